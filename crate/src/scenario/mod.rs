//! Scenarios and traces: what a simulation is given and what it returns
//! (DESIGN "Scenario"; the format with every default is in
//! `docs/scenarios.md`).
//!
//! A [`Scenario`] names a robot (a spec or `{ "preset": name }`), its initial
//! joints, obstacles with motions, an end-effector task, the controller, the
//! sensing errors, the dependability monitor, the step `dt` and the
//! `duration`. [`Scenario::from_json`] reads one and reports the JSON path of
//! a bad value; [`Scenario::validate`] checks every value and reports the
//! path and the reason (`obstacles[2].shape.radius: must be > 0`).
//!
//! Obstacle motions translate the whole figure. A `human` shape is a
//! composite (head sphere, torso capsule, two arm capsules) that moves as one
//! body and answers to one id.
//!
//! Example scenarios ship with the crate ([`example`], [`EXAMPLE_NAMES`]).

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::avoidance::ControllerConfig;
use crate::dependability::DependabilityConfig;
use crate::error::{FieldError, positive};
use crate::kinematics::{Robot, RobotSpec, presets};

pub mod bounds;
mod camera;
mod examples;
pub mod joint_path;
mod obstacle;
mod sensing;
mod tagged;
mod task;
mod torque_audit;
mod trace;

pub use camera::{CameraSpec, MAX_FRAME_POINTS, MAX_PITCH};
pub use examples::{EXAMPLE_NAMES, example, example_json};
pub use obstacle::{
    HumanSpec, Motion, ObstacleSpec, ShapeSpec, primitives, reference_point, translated, unit_quat,
};
pub(crate) use obstacle::{TimeOrder, check_timed_points};
pub use sensing::SensingConfig;
pub use task::{DhValues, TaskSpec, Tasks};
pub use torque_audit::audit_torque;
pub use trace::{MotionAudit, Sample, Trace, TracePoint, audit};

/// Why a scenario (or an edit of a live world) was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// A value is missing, malformed or out of range: the JSON path and the
    /// reason.
    #[error(transparent)]
    Field(#[from] FieldError),
}

impl ScenarioError {
    /// The field error inside.
    #[must_use]
    pub fn field(&self) -> &FieldError {
        match self {
            Self::Field(e) => e,
        }
    }
}

/// The robot of a scenario: a preset by name or a full spec.
#[derive(Clone, Debug, PartialEq)]
pub enum RobotRef {
    /// `{ "preset": "lwr4" }`.
    Preset(String),
    /// A robot spec (DESIGN "Robot spec").
    Spec(Box<RobotSpec>),
}

impl RobotRef {
    /// The robot spec.
    ///
    /// # Errors
    /// `preset: unknown robot …`.
    pub fn spec(&self) -> Result<RobotSpec, FieldError> {
        match self {
            Self::Preset(name) => presets::preset(name),
            Self::Spec(s) => Ok((**s).clone()),
        }
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PresetRef {
    preset: String,
}

fn nested<T: serde::de::DeserializeOwned, E: serde::de::Error>(
    v: serde_json::Value,
) -> Result<T, E> {
    serde_path_to_error::deserialize(v).map_err(|e| {
        let path = e.path().to_string();
        if path == "." {
            E::custom(e.inner())
        } else {
            E::custom(crate::error::nested_message(&path, &e.inner().to_string()))
        }
    })
}

impl<'de> Deserialize<'de> for RobotRef {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        if !v.is_object() {
            return Err(serde::de::Error::custom(
                "expected a robot spec { convention, joints, … } or { preset: name }",
            ));
        }
        if v.get("preset").is_some() {
            let p: PresetRef = nested(v)?;
            Ok(Self::Preset(p.preset))
        } else {
            Ok(Self::Spec(Box::new(nested(v)?)))
        }
    }
}

impl Serialize for RobotRef {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Preset(name) => PresetRef {
                preset: name.clone(),
            }
            .serialize(s),
            Self::Spec(spec) => spec.serialize(s),
        }
    }
}

/// A simulation: robot, obstacles, task, controller, sensing, monitor,
/// step and duration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Scenario {
    /// A robot spec or `{ "preset": name }`.
    pub robot: RobotRef,
    /// Initial joint values (default all zero, clamped into the limits).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q0: Option<Vec<f64>>,
    /// Obstacles (ids unique).
    pub obstacles: Vec<ObstacleSpec>,
    /// Task: one, or a list with at most one per chain (default `hold`).
    #[serde(default)]
    pub task: Tasks,
    /// Controller (every field defaulted).
    #[serde(default)]
    pub controller: ControllerConfig,
    /// Sensing errors (default exact).
    #[serde(default)]
    pub sensing: SensingConfig,
    /// Dependability monitor (every field defaulted).
    #[serde(default)]
    pub dependability: DependabilityConfig,
    /// Control step (s, > 0, ≤ 0.1).
    pub dt: f64,
    /// Simulated time of [`crate::world::simulate`] (s, ≥ 0).
    pub duration: f64,
    /// Steps between two trace samples (≥ 1; default 1).
    #[serde(default = "one")]
    pub sample_every: usize,
    /// How viewers should look at it (the simulation ignores it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraSpec>,
}

fn one() -> usize {
    1
}

/// Largest accepted control step (s).
pub const MAX_DT: f64 = 0.1;

/// Largest number of steps [`crate::world::simulate`] accepts.
pub const MAX_STEPS: f64 = 1e7;

impl Scenario {
    /// Reads a scenario from JSON; errors name the JSON path.
    ///
    /// # Errors
    /// `obstacles[0].shape: missing field \`radius\``, then anything
    /// [`Scenario::validate`] reports.
    pub fn from_json(json: &str) -> Result<Self, ScenarioError> {
        let mut de = serde_json::Deserializer::from_str(json);
        let s: Self = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string())
        })?;
        s.validate()?;
        Ok(s)
    }

    /// The robot, built and checked.
    ///
    /// # Errors
    /// The robot spec's own errors, under `robot`.
    pub fn build_robot(&self) -> Result<Robot, FieldError> {
        let spec = self.robot.spec().map_err(|e| e.within("robot"))?;
        Robot::from_spec(&spec).map_err(|e| e.within("robot"))
    }

    /// Checks every value; the error names the JSON path and the reason.
    ///
    /// # Errors
    /// E.g. `obstacles[2].shape.radius: must be > 0`, `dt: must be > 0`,
    /// `sensing.ghost: no obstacle with this id`.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        bounds::check_value("", self)?;
        let robot = self.build_robot()?;
        if let Some(q0) = &self.q0 {
            crate::kinematics::check_vector("q0", q0, robot.dof())?;
        }
        let dt = positive("dt", self.dt)?;
        if dt > MAX_DT {
            return Err(FieldError::new("dt", format!("must be ≤ {MAX_DT} s")).into());
        }
        let duration = crate::error::non_negative("duration", self.duration)?;
        if duration / dt > MAX_STEPS {
            return Err(
                FieldError::new("duration", format!("more than {MAX_STEPS} steps of dt")).into(),
            );
        }
        if self.sample_every == 0 {
            return Err(FieldError::new("sampleEvery", "must be ≥ 1").into());
        }
        let mut ids = std::collections::BTreeSet::new();
        for (k, o) in self.obstacles.iter().enumerate() {
            o.validate()
                .map_err(|e| e.within(&format!("obstacles[{k}]")))?;
            if !ids.insert(o.id.as_str()) {
                return Err(FieldError::new(
                    format!("obstacles[{k}].id"),
                    format!("\"{}\" is used by an earlier obstacle", o.id),
                )
                .into());
            }
        }
        self.task.validate(&robot).map_err(|e| e.within("task"))?;
        validate_controller(&self.controller, &robot).map_err(|e| e.within("controller"))?;
        check_task_controller(&self.task, &self.controller)?;
        if let Some(d) = &self.sensing.default {
            d.validate().map_err(|e| e.within("sensing.default"))?;
        }
        for (id, s) in &self.sensing.obstacles {
            let field = format!("sensing.{id}");
            if !ids.contains(id.as_str()) {
                return Err(FieldError::new(field, "no obstacle with this id").into());
            }
            s.validate().map_err(|e| e.within(&field))?;
        }
        self.dependability
            .validate()
            .map_err(|e| e.within("dependability"))?;
        if let Some(c) = &self.camera {
            c.validate().map_err(|e| e.within("camera"))?;
        }
        Ok(())
    }
}

/// Checks that `controller` can drive `task`: a `joints` task needs the
/// `constraints` avoidance in velocity mode (the one controller with joint
/// rows).
///
/// # Errors
/// `task.type: a joints task needs controller.avoidance "constraints" …`.
pub fn check_task_controller(
    task: &Tasks,
    controller: &ControllerConfig,
) -> Result<(), FieldError> {
    if task.in_joint_space() && !controller.uses_constraints() {
        return Err(FieldError::new(
            "task.type",
            "a joints task needs controller.avoidance \"constraints\" (velocity mode)",
        ));
    }
    Ok(())
}

/// Checks a controller configuration, including its pinned points against
/// the robot.
///
/// # Errors
/// `influenceDistance: must be > 0`, `pinned[0].link: 9 is not a link of this robot (links 1 to 7)`, …
pub fn validate_controller(c: &ControllerConfig, robot: &Robot) -> Result<(), FieldError> {
    bounds::check_value("", c)?;
    c.validate()?;
    if let Some(w) = &c.joint_weights
        && w.len() != robot.dof()
    {
        return Err(FieldError::new(
            "jointWeights",
            format!(
                "expected {} values (one per joint), got {}",
                robot.dof(),
                w.len()
            ),
        ));
    }
    robot.link_pairs("selfCollisionExclude", &c.self_collision_exclude)?;
    for (k, p) in c.pinned.iter().enumerate() {
        p.validate_reachable(robot)
            .map_err(|e| e.within(&format!("pinned[{k}]")))?;
    }
    Ok(())
}
