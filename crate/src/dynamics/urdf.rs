//! The dynamics of a robot imported from a URDF: the import
//! ([`crate::parsers::urdf`]) reads every `<inertial>` of the links a row
//! moves into the row's DH frame and lumps them (the spec's
//! `joints[k].inertial`); this module keeps which links went into each
//! row, and builds the [`Dynamics`].

use super::Dynamics;
use crate::error::FieldError;
use crate::kinematics::inertia::Inertial;
use crate::kinematics::{Robot, RobotSpec};
use crate::parsers::urdf::{UrdfOptions, robot_with_links};

pub use crate::parsers::urdf::link_inertial;

/// The bodies of an imported robot, one per DH row, in its DH frame.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfBodies {
    /// The imported spec (as [`crate::parsers::urdf::robot_from_urdf`]),
    /// with the rows' `inertial`.
    pub spec: RobotSpec,
    /// Per row: the lumped body, `None` when its links carry no mass.
    pub bodies: Vec<Option<Inertial>>,
    /// Per row: the URDF links lumped into it.
    pub links: Vec<Vec<String>>,
}

/// The imported robot and its bodies, one per row, in the DH frames.
///
/// # Errors
/// Everything [`robot_with_links`] refuses, bad `<inertial>` data
/// included ([`link_inertial`]).
pub fn urdf_bodies(xml: &str, options: &UrdfOptions) -> Result<UrdfBodies, FieldError> {
    let (spec, links) = robot_with_links(xml, options)?;
    let robot = Robot::from_spec(&spec)?;
    let mut names = vec![Vec::new(); robot.dof()];
    for link in links.iter().filter(|l| l.row >= 1 && l.row <= robot.dof()) {
        names[link.row - 1].push(link.name.clone());
    }
    Ok(UrdfBodies {
        bodies: robot.joints.iter().map(|j| j.inertial).collect(),
        spec,
        links: names,
    })
}

/// The dynamics of the robot imported from a URDF, with its inertial data.
///
/// # Errors
/// As [`urdf_bodies`], and `inertials: no inertial data for links …` when a
/// row's links carry no mass.
pub fn dynamics_from_urdf(xml: &str, options: &UrdfOptions) -> Result<Dynamics, FieldError> {
    let (spec, _) = robot_with_links(xml, options)?;
    Dynamics::from_robot(Robot::from_spec(&spec)?)
}
