//! A URDF's `<inertial>` elements in the DH frames of the crate's URDF
//! import.
//!
//! The import ([`robot_with_links`]) turns the chain into a standard DH
//! table whose world frame is the base link's frame, and lists every link
//! it carries with the row that moves it and its pose at `q = 0` (the
//! links after each joint of the path, and those hung from them by fixed
//! joints). A link moved by row `k` is rigidly attached to DH frame `k`, so
//! its pose in that frame is `T_k(0)⁻¹ · P_link(0)` for every `q`. Each
//! `<inertial>` (mass, centre of mass and inertia axes given by its
//! `<origin>` in the link frame) is carried through that pose into DH frame
//! `k`, and the links of one row are lumped into one body (masses add,
//! tensors move to the common centre of mass). Links of row 0 (the base
//! and what is fixed to it) do not move and are left out.
//!
//! urdf-rs reads a missing `<inertial>` as zero mass: a row whose links
//! all have zero mass counts as having no inertial data.

use glam::{DAffine3, DMat3, DVec3};

use super::Dynamics;
use super::inertia::Inertial;
use crate::error::FieldError;
use crate::kinematics::{Robot, RobotSpec};
use crate::math;
use crate::parsers::urdf::{UrdfOptions, robot_with_links};

/// The bodies of an imported robot, one per DH row, in its DH frame.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfBodies {
    /// The imported spec (as [`crate::parsers::urdf::robot_from_urdf`]).
    pub spec: RobotSpec,
    /// Per row: the lumped body, `None` when its links carry no mass.
    pub bodies: Vec<Option<Inertial>>,
    /// Per row: the URDF links lumped into it.
    pub links: Vec<Vec<String>>,
}

/// `Rz(yaw) · Ry(pitch) · Rx(roll)`, URDF's `rpy`.
fn rpy(r: [f64; 3]) -> DMat3 {
    let (sr, cr) = math::sin_cos(r[0]);
    let (sp, cp) = math::sin_cos(r[1]);
    let (sy, cy) = math::sin_cos(r[2]);
    let rx = DMat3::from_cols(DVec3::X, DVec3::new(0.0, cr, sr), DVec3::new(0.0, -sr, cr));
    let ry = DMat3::from_cols(DVec3::new(cp, 0.0, -sp), DVec3::Y, DVec3::new(sp, 0.0, cp));
    let rz = DMat3::from_cols(DVec3::new(cy, sy, 0.0), DVec3::new(-sy, cy, 0.0), DVec3::Z);
    rz * ry * rx
}

/// A link's `<inertial>` in its own link frame.
///
/// # Errors
/// `link "l".inertial.mass: must be >= 0` and the like (see
/// [`Inertial::new`]), `link "l".inertial.origin.xyz[1]: not a finite
/// number`.
pub fn link_inertial(link: &urdf_rs::Link) -> Result<Inertial, FieldError> {
    let prefix = format!("link \"{}\".inertial", link.name);
    let i = &link.inertial;
    let (xyz, angles) = (i.origin.xyz.0, i.origin.rpy.0);
    for (what, v) in [("origin.xyz", xyz), ("origin.rpy", angles)] {
        for (k, c) in v.iter().enumerate() {
            crate::error::finite(&format!("{what}[{k}]"), *c).map_err(|e| e.within(&prefix))?;
        }
    }
    let t = &i.inertia;
    let tensor = DMat3::from_cols(
        DVec3::new(t.ixx, t.ixy, t.ixz),
        DVec3::new(t.ixy, t.iyy, t.iyz),
        DVec3::new(t.ixz, t.iyz, t.izz),
    );
    let body = Inertial::new(i.mass.value, DVec3::ZERO, tensor).map_err(|e| e.within(&prefix))?;
    let pose = DAffine3::from_mat3_translation(rpy(angles), DVec3::from_array(xyz));
    Ok(body.transformed(&pose))
}

/// The imported robot and its bodies, one per row, in the DH frames.
///
/// # Errors
/// Everything [`robot_with_links`] refuses, and bad `<inertial>` data
/// ([`link_inertial`]).
pub fn urdf_bodies(xml: &str, options: &UrdfOptions) -> Result<UrdfBodies, FieldError> {
    let (spec, links) = robot_with_links(xml, options)?;
    let urdf = urdf_rs::read_from_string(xml)
        .map_err(|e| FieldError::new("xml", format!("not a readable URDF: {e}")))?;
    let robot = Robot::from_spec(&spec)?;
    let n = robot.dof();
    let frames = robot.forward(&vec![0.0; n])?;
    let mut bodies = vec![Inertial::ZERO; n];
    let mut names = vec![Vec::new(); n];
    for link in links.iter().filter(|l| l.row >= 1) {
        let Some(element) = urdf.links.iter().find(|l| l.name == link.name) else {
            continue;
        };
        let in_dh = frames.transforms[link.row].inverse() * link.pose;
        let body = link_inertial(element)?.transformed(&in_dh);
        bodies[link.row - 1] = bodies[link.row - 1].lumped(&body);
        names[link.row - 1].push(link.name.clone());
    }
    Ok(UrdfBodies {
        spec,
        bodies: bodies
            .into_iter()
            .map(|b| (b.mass > 0.0).then_some(b))
            .collect(),
        links: names,
    })
}

/// The dynamics of the robot imported from a URDF, with its inertial data.
///
/// # Errors
/// As [`urdf_bodies`], and `inertials: no inertial data for links …` when a
/// row's links carry no mass.
pub fn dynamics_from_urdf(xml: &str, options: &UrdfOptions) -> Result<Dynamics, FieldError> {
    let imported = urdf_bodies(xml, options)?;
    let robot = Robot::from_spec(&imported.spec)?;
    Dynamics::from_optional(robot, imported.bodies)
}
