//! A URDF's `<inertial>` elements carried into the DH frames of the import.
//!
//! The import lists every link it carries with the row that moves it and
//! its pose at `q = 0` ([`ChainLink`]: the links after each joint of the
//! path, and those hung from them by fixed joints). A link moved by row `k`
//! is rigidly attached to DH frame `k`, so its pose in that frame is
//! `T_k(0)⁻¹ · P_link(0)` for every `q`. Each `<inertial>` (mass, centre of
//! mass and inertia axes given by its `<origin>` in the link frame) is
//! carried through that pose into DH frame `k`, and the links of one row
//! are lumped into one body (masses add, tensors move to the common centre
//! of mass): the row's `inertial` in the spec. Links of row 0 (the base
//! and what is fixed to it) do not move and are left out.
//!
//! urdf-rs reads a missing `<inertial>` as zero mass: a row whose links all
//! have zero mass gets no `inertial` (the dynamics then name its link).

use glam::{DAffine3, DMat3, DVec3};

use super::{ChainLink, rpy_matrix};
use crate::error::{FieldError, finite};
use crate::kinematics::inertia::Inertial;
use crate::kinematics::{Robot, RobotSpec};

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
            finite(&format!("{what}[{k}]"), *c).map_err(|e| e.within(&prefix))?;
        }
    }
    let t = &i.inertia;
    let tensor = DMat3::from_cols(
        DVec3::new(t.ixx, t.ixy, t.ixz),
        DVec3::new(t.ixy, t.iyy, t.iyz),
        DVec3::new(t.ixz, t.iyz, t.izz),
    );
    let body = Inertial::new(i.mass.value, DVec3::ZERO, tensor).map_err(|e| e.within(&prefix))?;
    let pose = DAffine3::from_mat3_translation(
        rpy_matrix(DVec3::from_array(angles)),
        DVec3::from_array(xyz),
    );
    Ok(body.transformed(&pose))
}

/// Writes each row's lumped body into `spec.joints[k].inertial` (none for
/// a row whose links carry no mass).
///
/// # Errors
/// Bad `<inertial>` data ([`link_inertial`]); a spec the robot cannot be
/// built from (not expected: the import made it).
pub(super) fn fill_inertials(
    urdf: &urdf_rs::Robot,
    spec: &mut RobotSpec,
    links: &[ChainLink],
) -> Result<(), FieldError> {
    let robot = Robot::from_spec(spec)?;
    let n = robot.dof();
    let frames = robot.forward(&vec![0.0; n])?;
    let mut bodies = vec![Inertial::ZERO; n];
    for link in links.iter().filter(|l| l.row >= 1 && l.row <= n) {
        let Some(element) = urdf.links.iter().find(|l| l.name == link.name) else {
            continue;
        };
        let in_dh = frames.transforms[link.row].inverse() * link.pose;
        let body = link_inertial(element)?.transformed(&in_dh);
        bodies[link.row - 1] = bodies[link.row - 1].lumped(&body);
    }
    for (row, body) in spec.joints.iter_mut().zip(bodies) {
        row.inertial = (body.mass > 0.0).then(|| body.to_spec());
    }
    Ok(())
}
