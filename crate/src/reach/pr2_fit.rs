//! The PR2's right arm with its volumes fitted to the PR2's own collision
//! meshes, the gripper included ([`pr2_fitted_arm`]).
//!
//! The meshes are those `pr2.urdf` names for the links from
//! `r_shoulder_pan_link` to the gripper (`crate/tests/data/meshes/pr2/`,
//! BSD), with two additions the URDF alone does not give:
//! * the fingers (`r_gripper_{l,r}_finger_link` and their tips) hang on the
//!   gripper's joints (three of them mimic joints, which the importer
//!   refuses on a chain), off the arm's chain: those four joints are read
//!   as fixed at 0 (the gripper closed, as in NEO's runs), so that the
//!   importer hangs the fingers from the palm like any fixed part and the
//!   wrist roll's row carries them;
//! * `r_wrist_roll_link` has no `<collision>` in this `pr2.urdf` (an older
//!   xacro output); the current `pr2_description` gives it
//!   `forearm_v0/wrist_roll_L.stl` at the link's origin, added here so.
//!
//! The shoulder pan's mesh holds the shoulder housing and the counterbalance
//! below it, down to 0.49 m under the shoulder along the pan axis, while
//! the first row of the DH table only spans the 0.1 m from the pan axis to
//! the lift axis: a round cone around that spine would need a 0.5 m
//! radius. The pan axis is a spine too (its points do not move with the
//! pan, so a segment on it is rigid with the first row): frame 0 is
//! lowered along it by `h` and `d1` raised by the same `h`, which changes no
//! pose, and the fit keeps the `h` of [`SHOULDER_SPINES`] with the least
//! total volume (the paper's rule: segments on the spine of every
//! mechanical part, counterbalances included).
//!
//! The wrist roll's frame is where the wrist's axes cross, so a chain that
//! ends there gives its last row no length and no volume could carry the
//! gripper. The arm is therefore imported to `r_gripper_tool_frame`
//! (0.18 m along the roll axis, between the fingertips): the last row's
//! segment runs through the palm and the fingers. Its tool transform is
//! then moved back to `r_wrist_roll_link`, so the end effector, and the
//! goal, stay NEO's.

use std::collections::BTreeMap;

use glam::{DAffine3, DVec3};

use super::pr2::{ARM_BASE, GOAL_LINK, TORSO_LIFT, affine, compose, torso_pose};
use crate::error::FieldError;
use crate::fitting::{Body, Coverage, CoverageOptions, coverage, fit_volumes, urdf_bodies};
use crate::kinematics::{PoseSpec, RobotSpec};
use crate::parsers::mesh::read_named;
use crate::parsers::urdf::{UrdfOptions, robot_with_links};

/// The frame the arm is imported to (see the module docs).
const TOOL_LINK: &str = "r_gripper_tool_frame";
/// The gripper's finger joints, read as fixed (module docs).
const FINGER_JOINTS: [&str; 4] = [
    "r_gripper_l_finger_joint",
    "r_gripper_r_finger_joint",
    "r_gripper_l_finger_tip_joint",
    "r_gripper_r_finger_tip_joint",
];
/// The wrist roll's collision mesh (see the module docs).
const WRIST_ROLL_MESH: &str = "forearm_v0/wrist_roll_L.stl";

/// The result of [`pr2_fitted_arm`].
#[derive(Clone, Debug, PartialEq)]
pub struct Pr2Fit {
    /// The arm in `base_footprint` (as [`super::pr2_arm`] places it), end
    /// effector `r_wrist_roll_link`, volumes fitted.
    pub robot: RobotSpec,
    /// Coverage of the meshes by the importer's volumes (0.05 m capsules).
    pub before: Coverage,
    /// Coverage by the fitted volumes.
    pub after: Coverage,
    /// Meshes not found or not read, links no volume moves with.
    pub problems: Vec<String>,
}

fn options(tip: &str) -> UrdfOptions {
    UrdfOptions {
        tip: Some(tip.into()),
        base: Some(ARM_BASE.into()),
        srdf: None,
        radii: None,
    }
}

/// Lengths of the shoulder pan's spine below the shoulder tried (m; module
/// docs).
const SHOULDER_SPINES: [f64; 7] = [0.0, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45];

/// `spec` with its first row's `d` spine reaching `h` below the shoulder
/// along the pan axis: frame 0 lowered by `h` and `d1` raised by it, the
/// same kinematics (a translation along a revolute axis commutes with the
/// rotation about it).
fn shoulder_spine(spec: &RobotSpec, h: f64) -> RobotSpec {
    let mut s = spec.clone();
    let lowered = affine(spec.base.as_ref()) * DAffine3::from_translation(DVec3::new(0.0, 0.0, -h));
    s.base = Some(compose(lowered, None));
    if let Some(j) = s.joints.first_mut() {
        j.d += h;
    }
    s
}

/// `urdf` with the finger joints fixed at 0 (module docs).
fn fingers_fixed(urdf: &str) -> String {
    FINGER_JOINTS.iter().fold(urdf.to_owned(), |xml, j| {
        xml.replace(
            &format!("<joint name=\"{j}\" type=\"revolute\">"),
            &format!("<joint name=\"{j}\" type=\"fixed\">"),
        )
    })
}

/// The bodies of the arm (rows 1–7) and the gripper, in the imported
/// arm's frame at `q = 0`, and the problems met reading them.
fn bodies(
    urdf: &str,
    files: &BTreeMap<String, Vec<u8>>,
    rows: usize,
) -> Result<(Vec<Body>, Vec<String>), FieldError> {
    let (_, mut bodies, mut problems) = urdf_bodies(urdf, &options(TOOL_LINK), files)?;
    let (_, links) = robot_with_links(urdf, &options(TOOL_LINK))?;
    match (
        links.iter().find(|l| l.name == GOAL_LINK),
        read_named(WRIST_ROLL_MESH, files),
    ) {
        (Some(link), Ok(mesh)) => bodies.push(Body {
            name: GOAL_LINK.into(),
            link: rows,
            mesh: mesh.transformed(&link.pose, DVec3::ONE),
        }),
        (_, Err(e)) => problems.push(format!("link \"{GOAL_LINK}\": {e}")),
        (None, _) => problems.push(format!("link \"{GOAL_LINK}\": not on the chain")),
    }
    Ok((bodies, problems))
}

/// The tool transform that moves the end effector from the tool frame back
/// to the wrist roll's frame.
fn wrist_tool(urdf: &str, spec: &RobotSpec) -> Result<PoseSpec, FieldError> {
    let (_, links) = robot_with_links(urdf, &options(TOOL_LINK))?;
    let pose = |name: &str| {
        links
            .iter()
            .find(|l| l.name == name)
            .map(|l| l.pose)
            .ok_or_else(|| FieldError::new("xml", format!("link \"{name}\" is not on the chain")))
    };
    let offset = pose(TOOL_LINK)?.inverse() * pose(GOAL_LINK)?;
    Ok(compose(affine(spec.tool.as_ref()) * offset, None))
}

/// The PR2's right arm with its volumes fitted to its collision meshes and
/// the gripper's (module docs), in `base_footprint` at [`TORSO_LIFT`], end
/// effector `r_wrist_roll_link`. `files` maps the mesh files' paths (any
/// prefix: the lookup matches the longest common tail, e.g.
/// `pr2/collision/forearm_v0/forearm.stl`) to their bytes.
///
/// # Errors
/// A URDF that is not the PR2's; a mesh that cannot be read is named in
/// [`Pr2Fit::problems`] instead.
pub fn pr2_fitted_arm(urdf: &str, files: &BTreeMap<String, Vec<u8>>) -> Result<Pr2Fit, FieldError> {
    let urdf = &fingers_fixed(urdf);
    let (spec, _, _) = urdf_bodies(urdf, &options(TOOL_LINK), files)?;
    let rows = spec.joints.len();
    let (bodies, problems) = bodies(urdf, files, rows)?;
    let q = vec![0.0; rows];
    let o = CoverageOptions::default();
    let before = coverage(&spec, &q, &bodies, &o)?;
    let mut best: Option<(RobotSpec, Coverage)> = None;
    for h in SHOULDER_SPINES {
        let robot = fit_volumes(&shoulder_spine(&spec, h), &q, &bodies)?;
        let after = coverage(&robot, &q, &bodies, &o)?;
        if best
            .as_ref()
            .is_none_or(|(_, b)| after.robot.volumes_volume < b.robot.volumes_volume)
        {
            best = Some((robot, after));
        }
    }
    let (mut robot, after) = best.ok_or_else(|| FieldError::new("meshes", "nothing fitted"))?;
    robot.tool = Some(wrist_tool(urdf, &spec)?);
    robot.base = Some(compose(torso_pose(urdf, TORSO_LIFT)?, robot.base.as_ref()));
    Ok(Pr2Fit {
        robot,
        before,
        after,
        problems,
    })
}
