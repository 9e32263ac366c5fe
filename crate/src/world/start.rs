//! The URDF import as a `World` would start it: [`import_urdf`] adds to the
//! kinematic import's report the pairs of links whose volumes overlap at
//! q = 0, found by the same self-collision query a `World` runs, named by
//! their URDF links and joints.

use std::collections::BTreeMap;

use crate::avoidance::ControllerConfig;
use crate::distance::{BroadPhase, QueryOptions, Scene, Target};
use crate::error::FieldError;
use crate::kinematics::{Robot, RobotSpec};
use crate::parsers::urdf::report::{JointReport, StartContact, UrdfImport};
use crate::parsers::urdf::{self, UrdfOptions};
use crate::skeleton::Skeleton;

/// [`urdf::import_urdf`] with `report.startContacts` filled in.
///
/// # Errors
/// As [`urdf::import_urdf`].
pub fn import_urdf(xml: &str, options: &UrdfOptions) -> Result<UrdfImport, FieldError> {
    let mut import = urdf::import_urdf(xml, options)?;
    import.report.start_contacts = start_contacts(&import.robot, &import.report.joints)?;
    Ok(import)
}

/// Non-adjacent rows whose volumes overlap at q = 0 (as a `World`'s
/// self-collision query pairs them), named by their URDF links and joints.
pub(super) fn start_contacts(
    spec: &RobotSpec,
    joints: &[JointReport],
) -> Result<Vec<StartContact>, FieldError> {
    let robot = Robot::from_spec(spec)?;
    let frames = robot.forward(&vec![0.0; robot.dof()])?;
    let skeleton = Skeleton::build(&robot, &frames);
    // The pairs a World leaves out: adjacent links, the SRDF's and those
    // no joint can move.
    let adjacency = super::self_pairs_left_out(&robot, &ControllerConfig::default())?;
    let options = QueryOptions {
        influence_distance: 0.0,
        self_collision: true,
        broad_phase: BroadPhase::BruteForce,
    };
    let pairs = Scene::new(Vec::new())
        .query(&skeleton, &options, |i, j| adjacency[i][j])
        .map_err(|e| FieldError::new("xml", e.to_string()))?;
    let mut worst: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    for p in pairs {
        let Target::Segment(other) = p.target else {
            continue;
        };
        if p.distance >= 0.0 {
            continue;
        }
        let (a, b) = (
            skeleton.segments[p.segment].link,
            skeleton.segments[other].link,
        );
        let key = (a.min(b), a.max(b));
        let d = worst.entry(key).or_insert(p.distance);
        *d = d.min(p.distance);
    }
    let name = |row: usize| -> (String, String) {
        joints.get(row.wrapping_sub(1)).map_or_else(
            || ("base".to_owned(), String::new()),
            |j| (j.links.first().cloned().unwrap_or_default(), j.name.clone()),
        )
    };
    Ok(worst
        .into_iter()
        .map(|((a, b), distance)| {
            let (la, ja) = name(a);
            let (lb, jb) = name(b);
            StartContact {
                links: [la, lb],
                joints: [ja, jb],
                distance,
            }
        })
        .collect())
}
