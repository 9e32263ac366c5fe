//! A robot described by a URDF with its mesh files: the robot spec with
//! fitted volumes, and how well the volumes cover the collision meshes
//! before and after. The URDF and the meshes are read by
//! [`crate::parsers::urdf`] and [`crate::parsers::mesh`]; this module
//! places the meshes as bodies, chooses the tip and fits.

use std::collections::BTreeMap;

use serde::Serialize;

use super::{Body, Coverage, CoverageOptions, coverage, fit_volumes, rigid_segments};
use crate::error::FieldError;
use crate::kinematics::{Robot, RobotSpec};
use crate::mesh::TriMesh;
use crate::parsers::mesh::read_named;
use crate::parsers::urdf::{ChainLink, UrdfOptions, robot_with_links};

/// The result of [`fit_urdf`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct UrdfFit {
    /// The spec with fitted radii and extensions (as imported when no
    /// collision mesh could be read).
    pub robot: RobotSpec,
    /// Coverage of the collision meshes by the imported radii (primitive
    /// collision shapes or the 0.05 m default), `None` without meshes.
    pub before: Option<Coverage>,
    /// Coverage by the fitted radii.
    pub after: Option<Coverage>,
    /// One message per mesh that could not be found or read, naming it; the
    /// robot is fitted to the others.
    pub problems: Vec<String>,
    /// The collision bodies read (world frame at `q = 0`).
    #[serde(skip)]
    pub bodies: Vec<Body>,
}

/// The collision bodies of the links (base excluded) and one message per
/// mesh that could not be read.
fn read_bodies(links: &[ChainLink], files: &BTreeMap<String, Vec<u8>>) -> (Vec<Body>, Vec<String>) {
    let mut problems = Vec::new();
    let mut bodies = Vec::new();
    for link in links.iter().filter(|l| l.row > 0) {
        let mut mesh = TriMesh::default();
        for (k, m) in link.collision.iter().enumerate() {
            match read_named(&m.filename, files) {
                Ok(t) => mesh.append(&t.transformed(&(link.pose * m.origin), m.scale)),
                Err(e) => problems.push(format!("link \"{}\": collision[{k}]: {e}", link.name)),
            }
        }
        if !mesh.vertices.is_empty() {
            bodies.push(Body {
                name: link.name.clone(),
                link: link.row,
                mesh,
            });
        }
    }
    (bodies, problems)
}

/// Names of the bodies no skeleton segment moves with.
fn unplaced(spec: &RobotSpec, bodies: &[Body]) -> Result<Vec<String>, FieldError> {
    let robot = Robot::from_spec(spec)?;
    let rigid = rigid_segments(&robot, &vec![0.0; robot.dof()])?;
    Ok(bodies
        .iter()
        .filter(|b| rigid.get(b.link).is_none_or(Vec::is_empty))
        .map(|b| b.name.clone())
        .collect())
}

/// Imports a URDF ([`robot_with_links`]) and fits the volumes of its rows to
/// the collision meshes of the links they move ([`fit_volumes`]); `files`
/// maps paths (as dropped: `robot/meshes/link1.stl`) to bytes. Links fixed
/// to the base are not fitted (no segment moves with them).
///
/// Without `options.tip`, when the default tip leaves the last link with no
/// segment of its own (its origin on the last joint), a frame fixed to that
/// link (a flange, `ee_link`, `tool0`) is taken as the tip; a link no
/// segment moves with is named in the problems (its vertices count as
/// outside).
///
/// # Errors
/// A [`FieldError`] when the URDF cannot be imported; a mesh that cannot be
/// found or read is a message in [`UrdfFit::problems`] instead.
pub fn fit_urdf(
    xml: &str,
    options: &UrdfOptions,
    files: &BTreeMap<String, Vec<u8>>,
) -> Result<UrdfFit, FieldError> {
    let (spec, bodies, problems) = urdf_bodies(xml, options, files)?;
    let q = vec![0.0; spec.joints.len()];
    if bodies.is_empty() {
        return Ok(UrdfFit {
            robot: spec,
            before: None,
            after: None,
            problems,
            bodies,
        });
    }
    let o = CoverageOptions::default();
    let before = coverage(&spec, &q, &bodies, &o)?;
    let robot = fit_volumes(&spec, &q, &bodies)?;
    let after = coverage(&robot, &q, &bodies, &o)?;
    Ok(UrdfFit {
        robot,
        before: Some(before),
        after: Some(after),
        problems,
        bodies,
    })
}

/// The first half of [`fit_urdf`], without fitting or measuring: the
/// imported spec (radii as imported), its collision bodies (world frame at
/// `q = 0`) and the problems (meshes not found or not read, links no
/// segment moves with), the tip chosen as `fit_urdf` chooses it.
///
/// # Errors
/// A [`FieldError`] when the URDF cannot be imported.
pub fn urdf_bodies(
    xml: &str,
    options: &UrdfOptions,
    files: &BTreeMap<String, Vec<u8>>,
) -> Result<(RobotSpec, Vec<Body>, Vec<String>), FieldError> {
    let (mut spec, links) = robot_with_links(xml, options)?;
    let (mut bodies, mut problems) = read_bodies(&links, files);
    let mut loose = unplaced(&spec, &bodies)?;
    // A default tip at the last joint's origin leaves the last link without
    // a segment of its own: try the frames fixed to it (a flange, a tool).
    if !loose.is_empty() && options.tip.is_none() {
        let last = links.iter().map(|l| l.row).max().unwrap_or(0);
        let candidates: Vec<String> = links
            .iter()
            .filter(|l| l.row == last && !loose.contains(&l.name))
            .map(|l| l.name.clone())
            .collect();
        for tip in candidates {
            let o = UrdfOptions {
                tip: Some(tip),
                base: options.base.clone(),
                srdf: options.srdf.clone(),
                radii: options.radii.clone(),
            };
            let Ok((s2, l2)) = robot_with_links(xml, &o) else {
                continue;
            };
            let (b2, p2) = read_bodies(&l2, files);
            let still = unplaced(&s2, &b2)?;
            if still.is_empty() && s2.joints.len() == spec.joints.len() {
                (spec, bodies, problems, loose) = (s2, b2, p2, still);
                break;
            }
        }
    }
    for name in &loose {
        problems.push(format!(
            "link \"{name}\": no skeleton segment moves with it (its row has no length); choose a tip past it (a flange or tool frame)"
        ));
    }
    Ok((spec, bodies, problems))
}
