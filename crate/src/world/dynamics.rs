//! The arm as a rigid body in the world: its [`Dynamics`] (from the
//! inertial data of the robot spec), the torque mode's request, the joint
//! torques of every step held within `±maxTorque`, and the effective mass
//! at the control points.
//!
//! **Torque limits in every mode.** Whatever the controller, the motion
//! the limiter chooses needs the drive torques `τ = M(q) q̈ + C(q, q̇) q̇ +
//! g(q)`. When they would exceed a joint's `maxTorque` (less
//! [`TORQUE_MARGIN`]), the limiter is run again with every joint's
//! acceleration capped, at the largest cap (bisection) whose torques fit:
//! the motion is slowed, never driven beyond the data sheet. A step whose
//! torques already fit is left exactly as the limiter made it.

use glam::DVec3;

use super::ControlPointState;
use super::parts::{Model, State, StepData};
use crate::avoidance::limits::{self, JointMotion, StepOptions};
use crate::avoidance::protect::ProtectiveMode;
use crate::avoidance::{
    ActivePoint, ControllerConfig, Mode, TorqueInput, TorqueScratch, torque_control,
};
use crate::control_point::DhPoint;
use crate::dynamics::{Dynamics, MassFactor};
use crate::error::FieldError;
use crate::kinematics::Robot;

/// Fraction of `maxTorque` the limiter keeps to: the rest covers the
/// difference between the torques of one step and those an audit reads
/// from the sampled positions (finite differences).
pub const TORQUE_MARGIN: f64 = 0.98;

/// Steps of the bisection on the acceleration cap.
const BISECTION_STEPS: usize = 24;

/// What the dynamics of one step keep: the controller's buffers and the
/// drive torques of the motion chosen.
#[derive(Clone, Debug, Default)]
pub(super) struct DynamicsData {
    pub(super) scratch: TorqueScratch,
    /// `C q̇ + g` at the start of the step.
    bias: Vec<f64>,
    /// The motion before the limiter (for a second try).
    before: JointMotion,
    /// The drive torques of the last step (empty without dynamics).
    pub(super) torque: Vec<f64>,
}

/// The dynamics of `robot` from the inertial data of its rows, or the
/// error naming the links without any.
pub(super) fn model_dynamics(robot: &Robot) -> Result<Dynamics, FieldError> {
    Dynamics::from_robot(robot.clone())
}

/// Refuses a controller that needs the dynamics (torque mode) for a robot
/// without them: `mode: torque mode needs the robot's inertial data
/// (inertials: no inertial data for links …)`.
///
/// # Errors
/// As above.
pub(super) fn require_dynamics(
    config: &ControllerConfig,
    dynamics: &Result<Dynamics, FieldError>,
) -> Result<(), FieldError> {
    let Err(missing) = dynamics else {
        return Ok(());
    };
    let needs = |field: &str, what: &str| {
        FieldError::new(
            field,
            format!("{what} needs the robot's inertial data ({missing})"),
        )
        .within("controller")
    };
    if config.mode == Mode::Torque {
        return Err(needs("mode", "torque mode"));
    }
    if config.protective.mode == ProtectiveMode::Pfl {
        return Err(needs("protective.mode", "power and force limiting"));
    }
    Ok(())
}

/// The step's buffers for `dynamics`, if any.
pub(super) fn data_for(dynamics: &Result<Dynamics, FieldError>) -> DynamicsData {
    dynamics.as_ref().map_or_else(
        |_| DynamicsData::default(),
        |d| DynamicsData {
            scratch: TorqueScratch::new(d),
            ..DynamicsData::default()
        },
    )
}

/// The torque mode's requested joint velocities
/// ([`crate::avoidance::computed_torque`]).
///
/// # Errors
/// A robot without dynamics (refused before: a bug); an invalid task.
pub(super) fn torque_request(
    model: &Model,
    data: &mut StepData,
    active: &[ActivePoint],
    (q, qdot): (&[f64], &[f64]),
    dt: f64,
) -> Result<Vec<f64>, FieldError> {
    let dynamics = model.dynamics.as_ref().map_err(Clone::clone)?;
    let input = TorqueInput {
        dynamics,
        frames: &data.frames,
        q,
        qdot,
        points: active,
        tasks: &data.references,
        config: &model.scenario.controller,
        dt,
    };
    Ok(torque_control(&input, &mut data.dynamics.scratch)?.0)
}

/// The largest `|τᵢ| / (margin · maxTorqueᵢ)` of moving from `before` to
/// `after` in `dt`, with `M` and `C q̇ + g` given.
fn torque_ratio(
    robot: &Robot,
    (mass, bias): (&[f64], &[f64]),
    motion: (&[f64], &[f64]),
    dt: f64,
    tau: &mut Vec<f64>,
) -> f64 {
    let (before, after) = motion;
    let n = robot.dof();
    tau.clear();
    let mut worst = 0.0_f64;
    for (i, j) in robot.joints.iter().enumerate() {
        let t: f64 = (0..n)
            .map(|k| mass[i * n + k] * (after[k] - before[k]) / dt)
            .sum::<f64>()
            + bias[i];
        tau.push(t);
        worst = worst.max(t.abs() / (TORQUE_MARGIN * j.max_torque));
    }
    worst
}

/// Remembers the motion before the limiter (when the world has dynamics).
pub(super) fn before_limit(model: &Model, state: &State, data: &mut StepData) {
    if model.dynamics.is_ok() {
        data.dynamics.before.clone_from(&state.motion);
    }
}

/// After the limiter: the drive torques of its motion, and the limiter run
/// again with a capped acceleration when they exceed the torque limits
/// (see the module docs). Nothing without dynamics.
pub(super) fn hold_torque_limits(
    model: &Model,
    state: &mut State,
    data: &mut StepData,
    options: &StepOptions,
    dt: f64,
) {
    let Ok(dynamics) = model.dynamics.as_ref() else {
        return;
    };
    let robot = &model.robot;
    let dd = &mut data.dynamics;
    let n = robot.dof();
    dd.bias.resize(n, 0.0);
    let ws = &mut dd.scratch.workspace;
    let before = &dd.before;
    if dynamics
        .nonlinear_effects(ws, &state.q, &before.qdot, &mut dd.bias)
        .is_err()
        || dd.scratch.factor.update(dynamics, ws, &state.q).is_err()
    {
        return;
    }
    let terms = (dd.scratch.factor.mass(), dd.bias.as_slice());
    let mut tau = std::mem::take(&mut dd.torque);
    let ratio = torque_ratio(
        robot,
        terms,
        (&before.qdot, &state.motion.qdot),
        dt,
        &mut tau,
    );
    if ratio > 1.0 {
        let top = robot
            .joints
            .iter()
            .map(|j| j.max_acceleration)
            .fold(0.0, f64::max);
        let (mut lo, mut hi) = (
            0.0,
            top.min(options.max_acceleration)
                .min(options.stop_deceleration),
        );
        let try_cap = |cap: f64, motion: &mut JointMotion, tau: &mut Vec<f64>| {
            motion.clone_from(before);
            let capped = StepOptions {
                max_acceleration: cap,
                ..*options
            };
            limits::step_with(robot, &state.q, &data.request, motion, dt, &capped);
            torque_ratio(robot, terms, (&before.qdot, &motion.qdot), dt, tau)
        };
        for _ in 0..BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            if try_cap(mid, &mut state.motion, &mut tau) <= 1.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        try_cap(lo, &mut state.motion, &mut tau);
    }
    dd.torque = tau;
}

/// Fills each control point's effective mass along the direction from it
/// to its obstacle's witness (nothing without dynamics).
pub(super) fn effective_masses(
    model: &Model,
    data: &StepData,
    q: &[f64],
    points: &mut [ControlPointState],
) {
    let Ok(dynamics) = model.dynamics.as_ref() else {
        return;
    };
    let mut ws = dynamics.workspace();
    let mut factor = MassFactor::default();
    if points.is_empty() || factor.update(dynamics, &mut ws, q).is_err() {
        return;
    }
    for c in points {
        let u = (DVec3::from(c.witness) - DVec3::from(c.position)).normalize_or_zero();
        if u == DVec3::ZERO {
            continue;
        }
        let point = DhPoint {
            link: c.link,
            d: c.d,
            a: c.a,
        };
        let j = point.jacobians(&model.robot, &data.frames);
        let row: Vec<f64> = j.j_theta.iter().map(|col| col.dot(u)).collect();
        c.effective_mass = Some(factor.effective_mass(&row)).filter(|m| m.is_finite());
    }
}
