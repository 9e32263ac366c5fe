//! Reading the scenario's `{ type: …, … }` objects (motions and tasks) so
//! that an error names the exact place of the bad value.
//!
//! serde reads an internally tagged enum by buffering the whole object
//! first, and a path-tracking reader loses the path inside that buffer:
//! a bad waypoint used to be reported as `motion: invalid length 0`. Here
//! each such object is read as a flat struct of every key any variant uses
//! (so `motion.points[1]: expected [x, y, z], …` keeps its path), then the
//! keys are checked against the `type`.

use std::marker::PhantomData;

use serde::{Deserialize, Deserializer};

use super::nested;
use super::obstacle::Motion;
use super::task::{DhValues, TaskSpec, Tasks};

/// The accepted values of one `type` field.
pub(super) trait Kinds {
    /// What is tagged (`motion`, `task`).
    const WHAT: &'static str;
    /// The accepted `type` values.
    const KINDS: &'static [&'static str];
}

/// A `type` value, checked while reading so that the error names `type`.
pub(super) struct Tag<K> {
    name: String,
    kinds: PhantomData<K>,
}

impl<'de, K: Kinds> Deserialize<'de> for Tag<K> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        if K::KINDS.contains(&name.as_str()) {
            Ok(Self {
                name,
                kinds: PhantomData,
            })
        } else {
            Err(serde::de::Error::custom(format!(
                "unknown {} \"{name}\" (known: {})",
                K::WHAT,
                K::KINDS.join(", ")
            )))
        }
    }
}

/// Checks that the keys `present` fit a `what` of type `kind` that needs
/// `required` and accepts `optional`.
fn fit_fields(
    what: &str,
    kind: &str,
    present: &[(&str, bool)],
    required: &[&str],
    optional: &[&str],
) -> Result<(), String> {
    let fields = || {
        let all: Vec<&str> = required.iter().chain(optional).copied().collect();
        if all.is_empty() {
            "none besides `type`".to_owned()
        } else {
            all.join(", ")
        }
    };
    for &(name, is) in present {
        if is && !required.contains(&name) && !optional.contains(&name) {
            return Err(format!(
                "`{name}` is not a field of a {kind} {what} (its fields: {})",
                fields()
            ));
        }
        if !is && required.contains(&name) {
            return Err(format!(
                "missing `{name}` (a {kind} {what} needs {})",
                fields()
            ));
        }
    }
    Ok(())
}

const MISSING: &str = "internal: a required field went missing";

/// The `type` values of a motion.
pub(super) struct MotionKinds;

impl Kinds for MotionKinds {
    const WHAT: &'static str = "motion";
    const KINDS: &'static [&'static str] = &["static", "linear", "waypoints", "circular"];
}

/// Every key any motion uses; see [`Motion`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MotionFields {
    #[serde(rename = "type")]
    kind: Tag<MotionKinds>,
    velocity: Option<[f64; 3]>,
    points: Option<Vec<[f64; 3]>>,
    times: Option<Vec<f64>>,
    #[serde(rename = "loop")]
    repeat: Option<bool>,
    center: Option<[f64; 3]>,
    axis: Option<[f64; 3]>,
    period: Option<f64>,
}

impl TryFrom<MotionFields> for Motion {
    type Error = String;

    fn try_from(f: MotionFields) -> Result<Self, String> {
        let kind = f.kind.name.as_str();
        let present = [
            ("velocity", f.velocity.is_some()),
            ("points", f.points.is_some()),
            ("times", f.times.is_some()),
            ("loop", f.repeat.is_some()),
            ("center", f.center.is_some()),
            ("axis", f.axis.is_some()),
            ("period", f.period.is_some()),
        ];
        let (required, optional): (&[&str], &[&str]) = match kind {
            "static" => (&[], &[]),
            "linear" => (&["velocity"], &[]),
            "waypoints" => (&["points", "times"], &["loop"]),
            _ => (&["center", "axis", "period"], &[]),
        };
        fit_fields("motion", kind, &present, required, optional)?;
        Ok(match kind {
            "static" => Self::Static,
            "linear" => Self::Linear {
                velocity: f.velocity.ok_or(MISSING)?,
            },
            "waypoints" => Self::Waypoints {
                points: f.points.ok_or(MISSING)?,
                times: f.times.ok_or(MISSING)?,
                repeat: f.repeat.unwrap_or(false),
            },
            _ => Self::Circular {
                center: f.center.ok_or(MISSING)?,
                axis: f.axis.ok_or(MISSING)?,
                period: f.period.ok_or(MISSING)?,
            },
        })
    }
}

/// The `type` values of a task.
pub(super) struct TaskKinds;

impl Kinds for TaskKinds {
    const WHAT: &'static str = "task";
    const KINDS: &'static [&'static str] = &["hold", "goal", "trajectory", "point", "joints"];
}

/// Every key any task uses; see [`TaskSpec`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TaskFields {
    #[serde(rename = "type")]
    kind: Tag<TaskKinds>,
    position: Option<[f64; 3]>,
    orientation: Option<[f64; 4]>,
    chain: Option<usize>,
    points: Option<Vec<[f64; 3]>>,
    times: Option<Vec<f64>>,
    configurations: Option<Vec<Vec<f64>>>,
    link: Option<usize>,
    from: Option<DhValues>,
    to: Option<DhValues>,
    start: Option<f64>,
    duration: Option<f64>,
}

impl TryFrom<TaskFields> for TaskSpec {
    type Error = String;

    fn try_from(f: TaskFields) -> Result<Self, String> {
        let kind = f.kind.name.as_str();
        let present = [
            ("position", f.position.is_some()),
            ("orientation", f.orientation.is_some()),
            ("chain", f.chain.is_some()),
            ("points", f.points.is_some()),
            ("times", f.times.is_some()),
            ("configurations", f.configurations.is_some()),
            ("link", f.link.is_some()),
            ("from", f.from.is_some()),
            ("to", f.to.is_some()),
            ("start", f.start.is_some()),
            ("duration", f.duration.is_some()),
        ];
        let (required, optional): (&[&str], &[&str]) = match kind {
            "hold" => (&[], &[]),
            "goal" => (&["position"], &["orientation", "chain"]),
            "trajectory" => (&["points", "times"], &["chain"]),
            "joints" => (&["configurations", "times"], &[]),
            _ => (&["link", "from", "to", "duration"], &["start", "position"]),
        };
        fit_fields("task", kind, &present, required, optional)?;
        Ok(match kind {
            "hold" => Self::Hold,
            "goal" => Self::Goal {
                position: f.position.ok_or(MISSING)?,
                orientation: f.orientation,
                chain: f.chain.unwrap_or(0),
            },
            "trajectory" => Self::Trajectory {
                points: f.points.ok_or(MISSING)?,
                times: f.times.ok_or(MISSING)?,
                chain: f.chain.unwrap_or(0),
            },
            "joints" => Self::Joints {
                configurations: f.configurations.ok_or(MISSING)?,
                times: f.times.ok_or(MISSING)?,
            },
            _ => Self::Point {
                link: f.link.ok_or(MISSING)?,
                from: f.from.ok_or(MISSING)?,
                to: f.to.ok_or(MISSING)?,
                start: f.start.unwrap_or(0.0),
                duration: f.duration.ok_or(MISSING)?,
                position: f.position,
            },
        })
    }
}

/// `task` is one task object or a list of them.
impl<'de> Deserialize<'de> for Tasks {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        match v {
            serde_json::Value::Array(_) => Ok(Self::Many(nested(v)?)),
            serde_json::Value::Object(_) => Ok(Self::One(nested(v)?)),
            _ => Err(serde::de::Error::custom(
                "expected a task { type, … } or a list of tasks",
            )),
        }
    }
}
