//! Tasks of a scenario (field `task`): what the arm does besides avoiding.
//!
//! `task` is one task or a list of them, at most one per chain, so a
//! two-arm torso can have a goal for each arm. A chain without a task is
//! free (the avoidance rows and the null-space damping drive it).
//!
//! | `type` | reference |
//! |---|---|
//! | `hold` (default) | the main chain's end effector stays where it starts (`hold` takes no `chain`) |
//! | `goal` | the end effector reaches `position` (and `orientation`) |
//! | `trajectory` | the end effector follows `points` at `times` (piecewise linear) |
//! | `point` | a control point at DH values moving from `from` to `to` over `duration` (a quintic: rest to rest, C2) holds `position` (default: where it is at `t = 0`) |
//!
//! The `point` task is eq. 4's purpose: the point slides along its link,
//! so holding it still needs the moving-point terms
//! `θ̇ = J_θ^† (ṗ_d + K (p_d − p) − J_a ȧ − J_d ḋ)`.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::{TimeOrder, check_timed_points, unit_quat};
use crate::avoidance::TaskReference;
use crate::control_point::{DhPoint, PointMotion};
use crate::error::{FieldError, finite3, non_negative, positive};
use crate::kinematics::{Frames, Robot};

/// DH values `(d', a')` of a point on its link.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DhValues {
    /// `d'` (m).
    pub d: f64,
    /// `a'` (m).
    pub a: f64,
}

/// One task. It is read through a flat struct of every key (see
/// `tagged.rs`), so that an error names the exact place (`task.position`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(
    tag = "type",
    rename_all = "camelCase",
    try_from = "super::tagged::TaskFields"
)]
pub enum TaskSpec {
    /// Keep the main chain's end effector where it starts (default): its
    /// position, and with the `constraints` avoidance its orientation too
    /// when the chain has six joints or more (a spatial arm that can; a
    /// planar arm holds its position only). The paper's controllers
    /// (`repulsion`, torque, `clik2`) hold the position, as in the paper:
    /// a pose task in the null space of the avoidance rows leaves a 7-joint
    /// arm none to avoid with.
    #[default]
    Hold,
    /// Reach `position` (m), and `orientation` (`[x, y, z, w]`) if given.
    Goal {
        /// Position (m, world frame).
        position: [f64; 3],
        /// Orientation as a unit quaternion `[x, y, z, w]`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        orientation: Option<[f64; 4]>,
        /// Chain whose end effector has the goal (0 = main chain; default 0).
        #[serde(default)]
        chain: usize,
    },
    /// Follow the piecewise-linear path through `points` at `times` (s);
    /// the first point before, the last point after.
    Trajectory {
        /// Positions (m).
        points: Vec<[f64; 3]>,
        /// Times (s, increasing).
        times: Vec<f64>,
        /// Chain whose end effector follows (default 0).
        #[serde(default)]
        chain: usize,
    },
    /// A control point on `link` whose DH values go from `from` to `to`
    /// between `start` and `start + duration`, holding `position`.
    Point {
        /// Link (1-based).
        link: usize,
        /// DH values at the start.
        from: DhValues,
        /// DH values at the end.
        to: DhValues,
        /// When the point starts to slide (s, ≥ 0; default 0).
        #[serde(default)]
        start: f64,
        /// How long it slides (s, > 0).
        duration: f64,
        /// Cartesian reference (m; default: the point's position at `t = 0`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        position: Option<[f64; 3]>,
    },
    /// Follow a path in joint space: be at `configurations[k]` at
    /// `times[k]` (s, on the path's clock, which waits while the arm lags),
    /// at rest there, on the straight segments between them (see
    /// `joint_path.rs`). Drives every joint, so it is the only task; the
    /// `constraints` avoidance only.
    Joints {
        /// Configurations, one value per joint (rad or m).
        configurations: Vec<Vec<f64>>,
        /// Times (s, ≥ 0, increasing), one per configuration.
        times: Vec<f64>,
    },
}

/// The scenario's `task` field: one task or a list (at most one per chain).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Tasks {
    /// One task.
    One(TaskSpec),
    /// Several tasks.
    Many(Vec<TaskSpec>),
}

impl Default for Tasks {
    fn default() -> Self {
        Self::One(TaskSpec::Hold)
    }
}

impl From<TaskSpec> for Tasks {
    fn from(t: TaskSpec) -> Self {
        Self::One(t)
    }
}

/// The quintic `s(u) = 10u³ − 15u⁴ + 6u⁵` and its first two derivatives in
/// time, for `u = (t − start) / duration` clamped into `[0, 1]`.
pub(super) fn quintic(t: f64, start: f64, duration: f64) -> (f64, f64, f64) {
    let u = ((t - start) / duration).clamp(0.0, 1.0);
    let (u2, u3) = (u * u, u * u * u);
    let s = u3 * (10.0 - 15.0 * u + 6.0 * u2);
    let ds = 30.0 * u2 * (1.0 - u) * (1.0 - u) / duration;
    let dds = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / (duration * duration);
    (s, ds, dds)
}

impl TaskSpec {
    /// The chain this task drives (a point task: the chain of its link).
    #[must_use]
    pub fn chain(&self, robot: &Robot) -> usize {
        match self {
            Self::Hold | Self::Joints { .. } => 0,
            Self::Goal { chain, .. } | Self::Trajectory { chain, .. } => *chain,
            Self::Point { link, .. } => robot
                .chains
                .iter()
                .position(|c| (c.first..=c.last).contains(link))
                .unwrap_or(0),
        }
    }

    /// Checks every value.
    ///
    /// # Errors
    /// `position[1]: not a finite number`, `orientation: …`, `times: …`,
    /// `from.a: 0.5 is outside the link's span [0, 0.3]`.
    pub fn validate(&self, robot: &Robot) -> Result<(), FieldError> {
        match self {
            Self::Hold => Ok(()),
            Self::Goal {
                position,
                orientation,
                chain,
            } => {
                check_chain(*chain, robot)?;
                finite3("position", DVec3::from_array(*position))?;
                if let Some(o) = orientation {
                    unit_quat("orientation", *o)?;
                }
                Ok(())
            }
            Self::Trajectory {
                points,
                times,
                chain,
            } => {
                check_chain(*chain, robot)?;
                check_timed_points(points, times, TimeOrder::Increasing)
            }
            Self::Joints {
                configurations,
                times,
            } => super::joint_path::validate(robot, configurations, times),
            Self::Point {
                link,
                from,
                to,
                start,
                duration,
                position,
            } => {
                let mut q = vec![0.0; robot.dof()];
                robot.clamp_to_limits(&mut q);
                let frames = robot.forward(&q)?;
                for (name, v) in [("from", from), ("to", to)] {
                    let p = DhPoint {
                        link: *link,
                        d: v.d,
                        a: v.a,
                    };
                    p.validate(robot, &frames)
                        .map_err(|e| if e.field == "link" { e } else { e.within(name) })?;
                }
                non_negative("start", *start)?;
                positive("duration", *duration)?;
                if let Some(p) = position {
                    finite3("position", DVec3::from_array(*p))?;
                }
                Ok(())
            }
        }
    }

    /// The DH point and its motion at time `t` (point tasks only).
    #[must_use]
    pub fn point_at(&self, t: f64) -> Option<(DhPoint, PointMotion)> {
        let Self::Point {
            link,
            from,
            to,
            start,
            duration,
            ..
        } = self
        else {
            return None;
        };
        let (s, ds, dds) = quintic(t, *start, *duration);
        let (dd, da) = (to.d - from.d, to.a - from.a);
        let dh = DhPoint {
            link: *link,
            d: from.d + dd * s,
            a: from.a + da * s,
        };
        let motion = PointMotion {
            a_rate: da * ds,
            d_rate: dd * ds,
            a_accel: da * dds,
            d_accel: dd * dds,
        };
        Some((dh, motion))
    }
}

fn check_chain(chain: usize, robot: &Robot) -> Result<(), FieldError> {
    if chain >= robot.chains.len() {
        return Err(FieldError::new(
            "chain",
            format!(
                "{chain} is not a chain of this robot (chains 0 to {})",
                robot.chains.len().saturating_sub(1)
            ),
        ));
    }
    Ok(())
}

impl Tasks {
    /// The tasks as a slice.
    #[must_use]
    pub fn as_slice(&self) -> &[TaskSpec] {
        match self {
            Self::One(t) => std::slice::from_ref(t),
            Self::Many(v) => v,
        }
    }

    /// Checks every task and that no chain has two.
    ///
    /// # Errors
    /// `[1].chain: chain 0 already has a task`, or a task's own error under
    /// its index.
    pub fn validate(&self, robot: &Robot) -> Result<(), FieldError> {
        let mut used = vec![false; robot.chains.len()];
        for (k, t) in self.as_slice().iter().enumerate() {
            let within = |e: FieldError| match self {
                Self::One(_) => e,
                Self::Many(_) => e.within(&format!("[{k}]")),
            };
            t.validate(robot).map_err(within)?;
            if matches!(t, TaskSpec::Joints { .. }) && self.as_slice().len() > 1 {
                return Err(within(FieldError::new(
                    "type",
                    "a joints task drives every joint: it must be the only task",
                )));
            }
            let c = t.chain(robot);
            if std::mem::replace(&mut used[c], true) {
                return Err(within(FieldError::new(
                    "chain",
                    format!("chain {c} already has a task"),
                )));
            }
        }
        Ok(())
    }

    /// Where each task anchors at the start: the end effector of its chain
    /// (hold: its position, and its orientation on a chain of six joints or
    /// more), or its point's position (point tasks without `position`).
    #[must_use]
    pub fn anchors(&self, robot: &Robot, frames: &Frames) -> Vec<(DVec3, Option<DQuat>)> {
        self.as_slice()
            .iter()
            .map(|t| match (t, t.point_at(0.0)) {
                (
                    TaskSpec::Point {
                        position: Some(p), ..
                    },
                    _,
                ) => (DVec3::from_array(*p), None),
                (_, Some((dh, _))) => (dh.position(robot, frames), None),
                _ => {
                    let chain = t.chain(robot);
                    let ee = frames.end_effectors.get(chain);
                    let spatial = chain_joints(robot, chain) >= 6;
                    (
                        ee.map_or(DVec3::ZERO, |e| e.translation),
                        ee.filter(|_| spatial && matches!(t, TaskSpec::Hold))
                            .map(|e| DQuat::from_mat3(&e.matrix3)),
                    )
                }
            })
            .collect()
    }

    /// The references of every task at time `t` (`anchors` from
    /// [`Tasks::anchors`]); a hold keeps its orientation only with
    /// `hold_orientation` (the `constraints` avoidance).
    pub fn references(
        &self,
        robot: &Robot,
        t: f64,
        anchors: &[(DVec3, Option<DQuat>)],
        hold_orientation: bool,
        out: &mut Vec<TaskReference>,
    ) {
        out.clear();
        for (k, task) in self.as_slice().iter().enumerate() {
            if matches!(task, TaskSpec::Joints { .. }) {
                // Not a Cartesian reference: see `joint_reference`.
                continue;
            }
            let (anchor, rotation) = anchors.get(k).copied().unwrap_or((DVec3::ZERO, None));
            let mut r = TaskReference {
                position: anchor,
                velocity: DVec3::ZERO,
                acceleration: DVec3::ZERO,
                orientation: None,
                chain: task.chain(robot),
                point: task.point_at(t),
            };
            match task {
                TaskSpec::Hold => r.orientation = rotation.filter(|_| hold_orientation),
                TaskSpec::Point { .. } | TaskSpec::Joints { .. } => {}
                TaskSpec::Goal {
                    position,
                    orientation,
                    ..
                } => {
                    r.position = DVec3::from_array(*position);
                    r.orientation = orientation.and_then(|o| unit_quat("orientation", o).ok());
                }
                TaskSpec::Trajectory { points, times, .. } => {
                    let v = |k: usize| DVec3::from_array(points[k]);
                    let k = times.partition_point(|&s| s <= t);
                    if k == 0 {
                        r.position = v(0);
                    } else if k >= times.len() {
                        r.position = v(times.len() - 1);
                    } else {
                        let (t0, t1) = (times[k - 1], times[k]);
                        let vel = (v(k) - v(k - 1)) / (t1 - t0);
                        r.position = v(k - 1) + vel * (t - t0);
                        r.velocity = vel;
                    }
                }
            }
            out.push(r);
        }
    }
}

impl Tasks {
    /// The `joints` task's reference at time `t` into `q` and `qdot`
    /// (see `joint_path.rs`); `false` (and both left empty) without one.
    pub fn joint_reference(&self, t: f64, q: &mut Vec<f64>, qdot: &mut Vec<f64>) -> bool {
        for task in self.as_slice() {
            if let TaskSpec::Joints {
                configurations,
                times,
            } = task
            {
                super::joint_path::reference_at(configurations, times, t, q, qdot);
                return true;
            }
        }
        q.clear();
        qdot.clear();
        false
    }

    /// Whether one of the tasks is a `joints` task.
    #[must_use]
    pub fn in_joint_space(&self) -> bool {
        self.as_slice()
            .iter()
            .any(|t| matches!(t, TaskSpec::Joints { .. }))
    }
}

/// The joints that move chain `chain`'s end effector (its rows and every
/// row it hangs from).
fn chain_joints(robot: &Robot, chain: usize) -> usize {
    let Some(c) = robot.chains.get(chain) else {
        return 0;
    };
    let mut k = c.last;
    let mut count = 0;
    while k >= 1 && count <= robot.dof() {
        count += 1;
        k = robot.joints[k - 1].parent;
    }
    count
}
