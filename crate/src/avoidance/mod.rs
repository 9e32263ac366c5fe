//! Repulsion, control, the protective layer and the joint limits (paper
//! §II, §III-A; DESIGN parts 4 and 6). Four stages of the control step live
//! here, each in its own file:
//!
//! | stage | file | what it does |
//! |---|---|---|
//! | select | [`selection`] | control points from the scene query (pairs / per obstacle / pinned / self) |
//! | control | [`control`], [`computed_torque`] | repulsion and tasks → requested joint velocities (velocity, `clik2`; torque mode on the robot's `M(q)` with gravity and Coriolis compensated) |
//! | protect | [`protect`] | every pair's approach speed bounded so the arm can stop before contact (a small QP) |
//! | limit | [`limits`] | jerk-limited, synchronised tracking within velocity, acceleration, jerk and position limits |
//!
//! The rows the controllers stack — the limits (one-sided rows on `q̇`: the
//! joint box, the protective bounds, the dampers) and the tasks — are types
//! in [`rows`], one per file; [`qp::assemble`] stacks them for the
//! `constraints` avoidance's QP ([`constraints`]). The jerk limiter
//! [`limits`] is the *limit stage* that follows the controllers; a
//! [`rows::Limit`] is a bound inside the QP.
//!
//! * **Control-point selection** ([`Selection`]): one point per
//!   segment–obstacle pair within the influence distance, one per obstacle
//!   (the closest point over the whole skeleton, the paper's fig. 4), or
//!   points pinned by the user as `(link, d', a')`.
//! * **Repulsion** ([`repulsion_speed`]): the gradient of a potential that
//!   vanishes at the influence distance `ρ₀`,
//!   `v(d) = min(η (1/d − 1/ρ₀) / d², v_max)` for `0 < d < ρ₀`, `v_max` in
//!   contact, 0 beyond `ρ₀`. It prescribes the arm's own (material) velocity
//!   at the control point, away from the obstacle, as a velocity (velocity
//!   and `clik2` modes) or as a force `f = k_f v` (torque mode). `v_max`
//!   bounds how fast any point is pushed: heavy industrial arms want it low
//!   (paper §I). Rows fade in over the activation band ([`activation`]).
//! * **Tasks** ([`TaskReference`]): one per chain (end-effector goal or
//!   trajectory), or a control point at DH values that change in time with
//!   a Cartesian reference — the task where eq. 4's moving-point terms
//!   belong.
//!
//! The protective layer and the limits run after every mode, so whatever a
//! controller asks, the arm moves within its limits and never closes in on
//! an obstacle faster than it could stop.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::control_point::DhPoint;
use crate::control_point::PointMotion;
use crate::error::{FieldError, non_negative, positive};
use crate::kinematics::LinkRef;
use crate::linalg::Damping;

pub mod computed_torque;
pub mod constraints;
pub mod control;
pub mod limits;
pub mod neo;
pub mod protect;
pub mod qp;
pub mod rows;
pub mod selection;

pub use computed_torque::{TorqueInput, TorqueScratch, torque_control};
pub use control::{JointState, clik2_control, velocity_control};
pub use protect::ProtectiveConfig;

/// Which controller drives the joints.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Mode {
    /// Joint velocities from task-priority inverse kinematics (default).
    #[default]
    Velocity,
    /// Joint torques on the robot's own rigid-body dynamics
    /// ([`computed_torque`]).
    Torque,
    /// Second-order closed-loop inverse kinematics (joint accelerations).
    Clik2,
}

/// How the velocity controller avoids (scenario field
/// `controller.avoidance`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Avoidance {
    /// One-sided constraints in one QP with the tasks (default): the arm may
    /// not approach any pair faster than its velocity damper allows and is
    /// pushed away only inside the safety band or when an obstacle closes
    /// in ([`constraints`]).
    #[default]
    Constraints,
    /// The paper's potential-field repulsion: an equality row per control
    /// point within the influence distance, the tasks in its null space
    /// ([`control::velocity_control`]). The torque and `clik2` modes are the
    /// paper's controllers and always use it.
    Repulsion,
    /// NEO (Haviland & Corke 2021) as a baseline: its QP with a slack on
    /// the task, the manipulability term and velocity dampers, settings in
    /// `controller.neo` ([`neo`]).
    Neo,
}

/// How control points are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Selection {
    /// One per segment–obstacle pair within the influence distance.
    Pairs,
    /// One per obstacle: its closest point on the skeleton (default).
    #[default]
    PerObstacle,
    /// The points listed in `pinned`, each against its closest obstacle.
    Pinned,
}

/// Gains of the torque mode.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct TorqueGains {
    /// Cartesian stiffness of the task (N/m; default 300).
    pub stiffness: f64,
    /// Cartesian damping of the task (N·s/m; default 40).
    pub damping: f64,
    /// Joint damping `D` (N·m·s/rad; default 2).
    pub joint_damping: f64,
    /// Force per unit of repulsion speed, `k_f` (N·s/m; default 200).
    pub force_gain: f64,
}

impl Default for TorqueGains {
    fn default() -> Self {
        Self {
            stiffness: 300.0,
            damping: 40.0,
            joint_damping: 2.0,
            force_gain: 200.0,
        }
    }
}

/// Gains of the second-order CLIK.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct Clik2Gains {
    /// Position gain `K_p` (1/s²; default 100).
    pub kp: f64,
    /// Velocity gain `K_d` (1/s; default 20), also used by the avoidance
    /// rows to track the repulsion speed and to damp the null space.
    pub kd: f64,
}

impl Default for Clik2Gains {
    fn default() -> Self {
        Self {
            kp: 100.0,
            kd: 20.0,
        }
    }
}

/// Controller settings (scenario field `controller`; every field has a
/// default).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct ControllerConfig {
    /// `velocity` (default), `torque` or `clik2`.
    pub mode: Mode,
    /// `constraints` (default), the paper's `repulsion` or the `neo`
    /// baseline (velocity mode; the other modes always use the repulsion).
    pub avoidance: Avoidance,
    /// `pairs`, `perObstacle` (default) or `pinned`.
    pub selection: Selection,
    /// Points used by the `pinned` selection (default none).
    pub pinned: Vec<DhPoint>,
    /// Influence distance `ρ₀` (m, > 0; default 0.3).
    pub influence_distance: f64,
    /// Potential gain `η` (m³/s, ≥ 0; default 0.002).
    pub repulsion_gain: f64,
    /// Largest repulsion speed `v_max` (m/s, ≥ 0; default 0.5).
    pub max_repulsion_speed: f64,
    /// Time for one DH value of a transition (s, > 0; default 0.1).
    pub transition_time: f64,
    /// Largest move along the skeleton a control point makes without a
    /// transition (m, ≥ 0; default 0.02).
    pub jump_threshold: f64,
    /// How much closer (m, ≥ 0; default 0: always the closest, as in the
    /// paper) another segment must come to an obstacle before a
    /// `perObstacle` control point leaves its segment for it (see
    /// [`selection`]).
    pub switch_hysteresis: f64,
    /// Fraction of the influence distance over which an avoidance row fades
    /// in (in `(0, 1]`; default 0.5).
    pub activation_band: f64,
    /// Task gain `K` of velocity mode (1/s, ≥ 0; default 5).
    pub task_gain: f64,
    /// Damping of the pseudoinverses.
    pub damping: DampingConfig,
    /// Gains of torque mode.
    pub torque: TorqueGains,
    /// Gains of `clik2` mode.
    pub clik2: Clik2Gains,
    /// Clearance below which the `constraints` avoidance pushes the arm
    /// away (m, ≥ 0 and < `influenceDistance`; default 0.02). Between it and
    /// the influence distance a pair may only be approached at the damper's
    /// speed, `maxRepulsionSpeed · (d − band) / (ρ₀ − band)`, less the
    /// obstacle's own approach speed; the band grows with that speed by
    /// [`protect::DAMPER_HEADWAY`].
    pub safety_band: f64,
    /// Whether segments of non-adjacent links repel each other (default
    /// true). Pairs whose distance no joint can change are left out
    /// automatically.
    pub self_collision: bool,
    /// Further pairs of links kept out of the self-collision query (like
    /// MuJoCo's `exclude`; default none), e.g. `[[1, 4], ["panda_link1",
    /// "panda_link4"]]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub self_collision_exclude: Vec<[LinkRef; 2]>,
    /// Eq. 4's joint weights `W` (one positive value per joint; default
    /// none: unit weights). A heavier joint moves less.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_weights: Option<Vec<f64>>,
    /// Whether a point task subtracts its point's own motion on the arm,
    /// `J_a ȧ + J_d ḋ` (eq. 4; default true). Off only to see what eq. 4
    /// is for.
    pub moving_point_terms: bool,
    /// The protective layer beneath the repulsion.
    pub protective: ProtectiveConfig,
    /// NEO's settings (the `neo` avoidance).
    pub neo: neo::NeoConfig,
}

/// Damping of the damped least-squares inverse.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct DampingConfig {
    /// Singular value below which damping starts (default 0.04).
    pub epsilon: f64,
    /// Damping at a singularity (default 0.04).
    pub lambda_max: f64,
}

impl Default for DampingConfig {
    fn default() -> Self {
        let d = Damping::default();
        Self {
            epsilon: d.epsilon,
            lambda_max: d.lambda_max,
        }
    }
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            mode: Mode::Velocity,
            avoidance: Avoidance::Constraints,
            selection: Selection::PerObstacle,
            pinned: Vec::new(),
            influence_distance: 0.3,
            repulsion_gain: 0.002,
            max_repulsion_speed: 0.5,
            transition_time: crate::transition::DEFAULT_TIME_PER_VALUE,
            jump_threshold: crate::transition::DEFAULT_JUMP_THRESHOLD,
            switch_hysteresis: 0.0,
            activation_band: 0.5,
            task_gain: 5.0,
            damping: DampingConfig::default(),
            torque: TorqueGains::default(),
            clik2: Clik2Gains::default(),
            safety_band: 0.02,
            self_collision: true,
            self_collision_exclude: Vec::new(),
            joint_weights: None,
            moving_point_terms: true,
            protective: ProtectiveConfig::default(),
            neo: neo::NeoConfig::default(),
        }
    }
}

impl ControllerConfig {
    /// Checks every value (pinned points are checked against the robot by
    /// the scenario).
    ///
    /// # Errors
    /// The field and the reason, e.g. `influenceDistance: must be > 0`.
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("influenceDistance", self.influence_distance)?;
        non_negative("repulsionGain", self.repulsion_gain)?;
        non_negative("safetyBand", self.safety_band)?;
        if self.safety_band >= self.influence_distance {
            return Err(FieldError::new(
                "safetyBand",
                format!(
                    "must be < influenceDistance ({}), got {}",
                    self.influence_distance, self.safety_band
                ),
            ));
        }
        non_negative("maxRepulsionSpeed", self.max_repulsion_speed)?;
        positive("transitionTime", self.transition_time)?;
        non_negative("jumpThreshold", self.jump_threshold)?;
        non_negative("switchHysteresis", self.switch_hysteresis)?;
        positive("activationBand", self.activation_band)?;
        if self.activation_band > 1.0 {
            return Err(FieldError::new("activationBand", "must be ≤ 1"));
        }
        non_negative("taskGain", self.task_gain)?;
        non_negative("damping.epsilon", self.damping.epsilon)?;
        non_negative("damping.lambdaMax", self.damping.lambda_max)?;
        let t = &self.torque;
        non_negative("torque.stiffness", t.stiffness)?;
        non_negative("torque.damping", t.damping)?;
        non_negative("torque.jointDamping", t.joint_damping)?;
        non_negative("torque.forceGain", t.force_gain)?;
        non_negative("clik2.kp", self.clik2.kp)?;
        non_negative("clik2.kd", self.clik2.kd)?;
        self.protective.validate()?;
        self.neo.validate()?;
        if let Some(w) = &self.joint_weights {
            for (k, v) in w.iter().enumerate() {
                positive(&format!("jointWeights[{k}]"), *v)?;
            }
        }
        if self.selection == Selection::Pinned && self.pinned.is_empty() {
            return Err(FieldError::new(
                "pinned",
                "the pinned selection needs at least one point",
            ));
        }
        Ok(())
    }

    /// Whether a pair at clearance `distance` (m) lies beyond the influence
    /// distance in force ([`Self::influence`]; and is left out of
    /// selection and guards). The one influence test of the crate: a
    /// clearance that is not a number is not beyond it.
    #[must_use]
    pub fn beyond_influence(&self, distance: f64) -> bool {
        distance > self.influence()
    }

    /// The influence distance in force (m): NEO's `d_i` under the `neo`
    /// avoidance, `influenceDistance` otherwise. The scene query reaches
    /// it.
    #[must_use]
    pub fn influence(&self) -> f64 {
        if self.uses_neo() {
            self.neo.influence_distance
        } else {
            self.influence_distance
        }
    }

    /// Whether this controller solves NEO's programme (velocity mode with
    /// `avoidance: neo`).
    #[must_use]
    pub fn uses_neo(&self) -> bool {
        self.mode == Mode::Velocity && self.avoidance == Avoidance::Neo
    }

    /// Whether this controller solves the `constraints` avoidance (velocity
    /// mode with `avoidance: constraints`).
    #[must_use]
    pub fn uses_constraints(&self) -> bool {
        self.mode == Mode::Velocity && self.avoidance == Avoidance::Constraints
    }

    pub(crate) fn dls(&self) -> Damping {
        Damping {
            epsilon: self.damping.epsilon,
            lambda_max: self.damping.lambda_max,
        }
    }
}

/// Repulsion speed (m/s) at clearance `distance` (m): the potential's
/// gradient `η (1/d − 1/ρ₀) / d²`, bounded by `v_max`; `v_max` at or below
/// contact, 0 at or beyond the influence distance. Continuous in `d`.
#[must_use]
pub fn repulsion_speed(distance: f64, config: &ControllerConfig) -> f64 {
    let rho = config.influence_distance;
    let vmax = config.max_repulsion_speed;
    if distance.is_nan() || distance >= rho {
        return 0.0;
    }
    if distance <= 0.0 {
        return vmax;
    }
    let v = config.repulsion_gain * (1.0 / distance - 1.0 / rho) / (distance * distance);
    v.min(vmax)
}

/// Smooth activation of an avoidance row at clearance `distance`: 0 at or
/// beyond the influence distance, 1 within `ρ₀ (1 − band)`, a smoothstep in
/// between.
#[must_use]
pub fn activation(distance: f64, config: &ControllerConfig) -> f64 {
    let rho = config.influence_distance;
    let band = config.activation_band * rho;
    let x = ((rho - distance) / band).clamp(0.0, 1.0);
    if x.is_nan() {
        return 0.0;
    }
    x * x * (3.0 - 2.0 * x)
}

/// An active control point as the controllers see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActivePoint {
    /// Where it is on the arm.
    pub dh: DhPoint,
    /// Rates and accelerations of its own DH values (transitions).
    pub motion: PointMotion,
    /// Unit direction from the control point towards the obstacle.
    pub normal: DVec3,
    /// Clearance used by the controller (m): measured distance minus the
    /// sensing margin.
    pub distance: f64,
}

impl ActivePoint {
    /// The repulsion at this point: a velocity (m/s) away from the obstacle.
    #[must_use]
    pub fn repulsion(&self, config: &ControllerConfig) -> DVec3 {
        -self.normal * repulsion_speed(self.distance, config)
    }
}

/// One task's reference at one instant: the end effector of a chain, or
/// (when `point` is set) a control point of the arm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaskReference {
    /// Desired position (m).
    pub position: DVec3,
    /// Desired velocity (m/s).
    pub velocity: DVec3,
    /// Desired acceleration (m/s²).
    pub acceleration: DVec3,
    /// Desired orientation, if controlled.
    pub orientation: Option<DQuat>,
    /// Chain whose end effector is controlled (0 = main chain).
    pub chain: usize,
    /// A control point at DH values that change in time, with the rates of
    /// those values, instead of the end effector (position only).
    pub point: Option<(DhPoint, PointMotion)>,
}

impl TaskReference {
    /// Number of task rows: 3, or 6 for an end effector with orientation.
    #[must_use]
    pub fn rows(&self) -> usize {
        if self.orientation.is_some() && self.point.is_none() {
            6
        } else {
            3
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repulsion_is_bounded_and_vanishes_at_the_influence_distance() {
        let c = ControllerConfig::default();
        assert_eq!(repulsion_speed(0.3, &c), 0.0);
        assert_eq!(repulsion_speed(0.0, &c), c.max_repulsion_speed);
        assert_eq!(repulsion_speed(-0.1, &c), c.max_repulsion_speed);
        assert!(repulsion_speed(0.2999, &c) < 1e-3);
        let mut prev = 0.0;
        for k in 0..300 {
            let d = 0.3 - k as f64 * 0.001;
            let v = repulsion_speed(d, &c);
            assert!(v >= prev && v <= c.max_repulsion_speed);
            prev = v;
        }
    }

    #[test]
    fn activation_is_smooth() {
        let c = ControllerConfig::default();
        assert_eq!(activation(0.3, &c), 0.0);
        assert_eq!(activation(0.15, &c), 1.0);
        assert!((activation(0.225, &c) - 0.5).abs() < 1e-12);
    }
}
