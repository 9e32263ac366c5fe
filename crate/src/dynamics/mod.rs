//! Rigid-body dynamics of a DH robot: inverse dynamics by the recursive
//! Newton–Euler algorithm, the joint-space mass matrix by the composite
//! rigid-body algorithm, gravity torques and Coriolis/centrifugal terms
//! (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 5 and 6).
//!
//! A [`Dynamics`] is a validated [`Robot`] with one [`Inertial`] per row
//! ([`Dynamics::from_robot`] takes them from the robot spec's
//! `joints[k].inertial`, which presets and the URDF import fill in):
//! the body moved by row `k` (everything rigidly attached to DH frame `k`),
//! its mass, centre of mass and inertia about the centre of mass, in DH
//! frame `k`. Both DH conventions, revolute and prismatic rows, branches
//! (rows whose parent is any earlier frame) and a moved base are handled:
//! the recursions run over [`Robot::forward`]'s frames, in the world's axes
//! with the base origin as reference point ([`spatial`]), so they never
//! depend on how a row's frame was built. Gravity is a vector in the world
//! frame (default [`DEFAULT_GRAVITY`], 9.81 m/s² along −z); the base is
//! fixed.
//!
//! Every computation takes a [`Workspace`] ([`Dynamics::workspace`]) and
//! writes into a caller's slice: no allocation per call.
//!
//! [`urdf`] maps a URDF's `<inertial>` elements into the DH frames of the
//! crate's URDF import; `crate/tests/dynamics_pinocchio.rs` compares the
//! results with Pinocchio's on published robots.

mod algorithms;
mod factor;
pub mod spatial;
pub mod urdf;

#[cfg(test)]
mod tests;

pub use crate::kinematics::inertia::{self, Inertial, InertialSpec};
pub use algorithms::Workspace;
pub use factor::MassFactor;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{FieldError, finite};
use crate::kinematics::Robot;

/// What a caller may set about a computation (the JS `options` of
/// `inverseDynamics`): the gravity vector.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct DynamicsOptions {
    /// Gravity (m/s², world frame); default [`DEFAULT_GRAVITY`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<[f64; 3]>,
}

impl DynamicsOptions {
    /// `dynamics` under these options.
    ///
    /// # Errors
    /// `gravity[k]: not a finite number`.
    pub fn apply(&self, dynamics: Dynamics) -> Result<Dynamics, FieldError> {
        match self.gravity {
            Some(g) => dynamics.with_gravity(DVec3::from_array(g)),
            None => Ok(dynamics),
        }
    }
}

/// Standard gravity along −z of the world frame (m/s²).
pub const DEFAULT_GRAVITY: DVec3 = DVec3::new(0.0, 0.0, -9.81);

/// A robot with the inertial parameters of the body each row moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamics {
    robot: Robot,
    bodies: Vec<Inertial>,
    gravity: DVec3,
}

impl Dynamics {
    /// The dynamics of `robot` with `bodies[k]` the body moved by row
    /// `k + 1`, in DH frame `k + 1`; gravity [`DEFAULT_GRAVITY`].
    ///
    /// # Errors
    /// `inertials: expected 7 bodies (one per joint), got 6`.
    pub fn new(robot: Robot, bodies: Vec<Inertial>) -> Result<Self, FieldError> {
        if bodies.len() != robot.dof() {
            return Err(FieldError::new(
                "inertials",
                format!(
                    "expected {} bodies (one per joint), got {}",
                    robot.dof(),
                    bodies.len()
                ),
            ));
        }
        Ok(Self {
            robot,
            bodies,
            gravity: DEFAULT_GRAVITY,
        })
    }

    /// [`Dynamics::new`] from per-row data some of which may be missing.
    ///
    /// # Errors
    /// As [`Dynamics::new`], and `inertials: no inertial data for links
    /// panda_link3, panda_link5` (the robot's link names, else `link k`)
    /// when any is missing.
    pub fn from_optional(robot: Robot, bodies: Vec<Option<Inertial>>) -> Result<Self, FieldError> {
        let missing: Vec<String> = bodies
            .iter()
            .enumerate()
            .filter(|(_, b)| b.is_none())
            .map(|(k, _)| robot.link_label(k + 1))
            .collect();
        if !missing.is_empty() {
            return Err(FieldError::new(
                "inertials",
                format!("no inertial data for links {}", missing.join(", ")),
            ));
        }
        Self::new(robot, bodies.into_iter().flatten().collect())
    }

    /// The dynamics of a robot whose rows carry their inertial parameters
    /// ([`crate::kinematics::JointSpec::inertial`]: given by hand, by a
    /// preset or read from a URDF's `<inertial>` elements).
    ///
    /// # Errors
    /// `inertials: no inertial data for links panda_link3, panda_link5`
    /// (the robot's link names, else `link k`) when any row has none.
    pub fn from_robot(robot: Robot) -> Result<Self, FieldError> {
        let bodies = robot.joints.iter().map(|j| j.inertial).collect();
        Self::from_optional(robot, bodies)
    }

    /// The same dynamics under gravity `g` (m/s², world frame).
    ///
    /// # Errors
    /// `gravity[k]: not a finite number`.
    pub fn with_gravity(mut self, g: DVec3) -> Result<Self, FieldError> {
        for (k, c) in g.to_array().iter().enumerate() {
            finite(&format!("gravity[{k}]"), *c)?;
        }
        self.gravity = g;
        Ok(self)
    }

    /// The robot.
    #[must_use]
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// The body of each row, in its DH frame.
    #[must_use]
    pub fn bodies(&self) -> &[Inertial] {
        &self.bodies
    }

    /// Gravity (m/s², world frame).
    #[must_use]
    pub fn gravity(&self) -> DVec3 {
        self.gravity
    }

    /// Number of joints.
    #[must_use]
    pub fn dof(&self) -> usize {
        self.robot.dof()
    }
}
