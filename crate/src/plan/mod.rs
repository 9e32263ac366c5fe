//! Global guidance for the reactive controller: a joint-space path from the
//! scenario's start to a goal configuration, every segment certified clear
//! of the obstacles (as they stand at `t = 0`) by the safety band and a
//! little more, timed within the joints' limits, to be followed as a
//! `joints` task ([`crate::scenario::TaskSpec::Joints`]).
//!
//! A reactive controller, the paper's or the `constraints` avoidance, stops
//! where the obstacles' push balances the goal's pull (a local minimum): an
//! arm reaching into a shelf past a board. A planner sees the whole free
//! space and finds the way round; the controller still runs every step
//! under every guard, so an obstacle that moves after planning is still
//! avoided. This is the usual split of a serious system (plan, then
//! follow reactively) and is kept apart from the controllers: a scenario
//! with a goal pose stays purely reactive unless its caller plans.
//!
//! The steps ([`plan_path`]):
//! 1. **Escape.** A start closer to an obstacle than the thresholds (the
//!    benchmark's fitted volumes overlap some of its starts) first climbs
//!    its clearance, opening every nearly-closest pair at once, and the
//!    climb is straightened to as few segments as keep its margin
//!    (`escape.rs`). A start between two boxes that no step frees further
//!    keeps each pair still short from closing further, as long as it is
//!    beyond the protective layer's safety distance and 2 mm; nearer (an
//!    arm wedged between boxes), the start is refused and left to the
//!    reactive controller.
//! 2. **Search.** RRT-Connect between the start and the goal (`rrt.rs`),
//!    with segments certified by a Lipschitz bound ([`checker`]), not
//!    sampled; when that finds no path, a second search whose trees creep
//!    and slide along the obstacles (a narrow passage between boxes).
//! 3. **Shorten.** Greedy (from each node kept, the farthest node in
//!    view), then random shortcuts kept only where they save time: the arm
//!    stops at every node, so a shortcut that adds two saves little.
//! 4. **Time.** Each segment is a rest-to-rest quintic whose duration keeps
//!    every joint within its velocity, acceleration and jerk limits, with
//!    [`PlanOptions::time_scale`] to spare for the controller's feedback.
//!
//! Files: `mod.rs` (the steps, the timing), `checker.rs`, `escape.rs`,
//! `rrt.rs`.

pub mod checker;
mod escape;
mod rrt;

use checker::{Checker, MIN_MARGIN, Thresholds};

use serde::{Deserialize, Serialize};

use crate::error::{FieldError, non_negative};
use crate::rng::Rng;
use crate::scenario::{Scenario, TaskSpec, Tasks};

/// Settings of [`plan_path`] (in JS, `planPath`'s `options`, camelCase,
/// every field optional).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct PlanOptions {
    /// Seed of the search.
    pub seed: u64,
    /// Clearance kept beyond the controller's safety band (m).
    pub extra_clearance: f64,
    /// Clearance kept between two of the arm's links (m).
    pub self_clearance: f64,
    /// Longest step of a tree (m that a point of the arm may move).
    pub step: f64,
    /// Rounds of each search before it gives up (a second search, which
    /// creeps along the obstacles, follows one that finds nothing).
    pub rounds: usize,
    /// Random shortcut attempts.
    pub shortcuts: usize,
    /// Each segment's duration over the shortest the limits allow (≥ 1).
    pub time_scale: f64,
}

impl PlanOptions {
    /// Checks every value.
    ///
    /// # Errors
    /// `step: must be > 0`, `rounds: must be in 1..=1000000`,
    /// `timeScale: must be ≥ 1`, …
    pub fn validate(&self) -> Result<(), FieldError> {
        non_negative("extraClearance", self.extra_clearance)?;
        non_negative("selfClearance", self.self_clearance)?;
        if !(MIN_STEP..=MAX_STEP).contains(&self.step) {
            return Err(FieldError::new(
                "step",
                format!("must be in [{MIN_STEP}, {MAX_STEP}] m"),
            ));
        }
        if !(1..=MAX_ROUNDS).contains(&self.rounds) {
            return Err(FieldError::new(
                "rounds",
                format!("must be in 1..={MAX_ROUNDS}"),
            ));
        }
        if self.shortcuts > MAX_ROUNDS {
            return Err(FieldError::new(
                "shortcuts",
                format!("must be in 0..={MAX_ROUNDS}"),
            ));
        }
        if !(self.time_scale >= 1.0 && self.time_scale.is_finite()) {
            return Err(FieldError::new("timeScale", "must be a finite number ≥ 1"));
        }
        Ok(())
    }
}

/// Shortest step of a search tree (m): a tree extends by steps, so a
/// shorter one would make a search of a metre take millions of them.
pub const MIN_STEP: f64 = 0.005;
/// Longest step of a search tree (m).
pub const MAX_STEP: f64 = 10.0;

/// Most rounds (or shortcut attempts) of one search.
pub const MAX_ROUNDS: usize = 1_000_000;

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            extra_clearance: 0.005,
            self_clearance: 0.005,
            step: 0.15,
            rounds: 4000,
            shortcuts: 200,
            time_scale: 1.0,
        }
    }
}

/// A timed joint-space path.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Plan {
    /// Configurations, the start first and the goal last.
    pub configurations: Vec<Vec<f64>>,
    /// When the arm is to be at each (s, from 0).
    pub times: Vec<f64>,
    /// How many of the first configurations are the escape from a start
    /// closer than the thresholds (0: the start was clear).
    pub escape: usize,
    /// The clearances every certified segment keeps (m).
    pub thresholds: Thresholds,
    /// Clearance evaluations spent.
    pub evaluations: usize,
}

impl Plan {
    /// The plan as a `joints` task.
    #[must_use]
    pub fn task(&self) -> Tasks {
        Tasks::One(TaskSpec::Joints {
            configurations: self.configurations.clone(),
            times: self.times.clone(),
        })
    }
}

/// A path for `scenario`'s robot from its start (`q0`) to `goal` among its
/// obstacles at `t = 0`, keeping the safety band plus
/// [`PlanOptions::extra_clearance`] (less near a goal closer than that,
/// never less than the band).
///
/// # Errors
/// Options out of range (`options.step: must be > 0`); a scenario a world
/// refuses; `goal` of the wrong length, not finite or
/// outside the limits; a goal within the safety band; a start that cannot
/// be freed; no path within [`PlanOptions::rounds`].
pub fn plan_path(
    scenario: &Scenario,
    goal: &[f64],
    options: &PlanOptions,
) -> Result<Plan, FieldError> {
    options.validate().map_err(|e| e.within("options"))?;
    let (mut checker, start) = Checker::for_scenario(scenario)?;
    crate::scenario::joint_path::validate(checker.robot(), &[goal.to_vec()], &[0.0])
        .map_err(|e| FieldError::new(e.field.replacen("configurations[0]", "goal", 1), e.reason))?;
    let controller = &scenario.controller;
    let band = controller.safety_band;
    let (goal_obstacles, goal_self) = checker.clearances(goal)?;
    if goal_obstacles < band {
        return Err(FieldError::new(
            "goal",
            format!(
                "its clearance, {:.1} mm, is within the safety band ({:.1} mm)",
                goal_obstacles * 1e3,
                band * 1e3
            ),
        ));
    }
    let thresholds = Thresholds {
        obstacles: (band + options.extra_clearance).min(goal_obstacles - 3.0 * MIN_MARGIN),
        self_pairs: options.self_clearance.min(goal_self - 6.0 * MIN_MARGIN),
    };
    let mut rng = Rng::new(options.seed);
    let floor = controller.protective.safety_distance + escape::FLOOR_ABOVE_SAFETY;
    let mut path = escape::escape(&mut checker, &start, (&thresholds, floor), &mut rng)?;
    let escape = path.len() - 1;
    let bounds: Vec<(f64, f64)> = checker
        .robot()
        .joints
        .iter()
        .zip(&start)
        .map(|(j, &q)| sampling_bounds(j.min, j.max, q))
        .collect();
    let mut problem = rrt::Problem {
        checker: &mut checker,
        thresholds,
        bounds: &bounds,
        search: rrt::Search {
            step: options.step,
            rounds: options.rounds,
            shortcuts: options.shortcuts,
            creep: false,
        },
    };
    let from = path.last().cloned().unwrap_or_else(|| start.clone());
    let mut found = problem.search(&from, goal, &mut rng)?;
    if found.is_none() {
        problem.search.creep = true;
        found = problem.search(&from, goal, &mut rng)?;
    }
    let found = found.ok_or_else(|| {
        FieldError::new(
            "goal",
            format!("no path found in two searches of {} rounds", options.rounds),
        )
    })?;
    let found = problem.shorten(found, &mut rng)?;
    path.extend(found.into_iter().skip(1));
    let times = timing(checker.robot(), &path, options.time_scale);
    Ok(Plan {
        configurations: path,
        times,
        escape,
        thresholds,
        evaluations: checker.evaluations,
    })
}

/// Where a joint is sampled: its limits, or a turn either side of the start
/// for a joint without.
fn sampling_bounds(min: f64, max: f64, start: f64) -> (f64, f64) {
    let pi = std::f64::consts::PI;
    (
        if min.is_finite() { min } else { start - pi },
        if max.is_finite() { max } else { start + pi },
    )
}

/// `path` with the nodes left out that a straight segment can skip: from
/// each node kept, the next is the farthest node `b` for which
/// `sees(a, b)` holds (tried from the last one down), else the next node.
/// Walking on only while the next node is seen stops at the first corner
/// a passage forces, and the arm stops at every node kept.
fn skip_nodes(
    path: Vec<Vec<f64>>,
    mut sees: impl FnMut(&[f64], &[f64]) -> Result<bool, FieldError>,
) -> Result<Vec<Vec<f64>>, FieldError> {
    let Some(first) = path.first() else {
        return Ok(path);
    };
    let mut out = vec![first.clone()];
    let mut i = 0;
    while i + 1 < path.len() {
        let mut j = i + 1;
        for k in (i + 2..path.len()).rev() {
            if sees(&path[i], &path[k])? {
                j = k;
                break;
            }
        }
        out.push(path[j].clone());
        i = j;
    }
    Ok(out)
}

/// The times of `path`'s configurations: each segment a rest-to-rest
/// quintic, as short as the joints' limits allow ([`segment_time`]),
/// times `scale`.
pub(crate) fn timing(robot: &crate::kinematics::Robot, path: &[Vec<f64>], scale: f64) -> Vec<f64> {
    let mut times = vec![0.0];
    let mut t = 0.0;
    for w in path.windows(2) {
        t += (segment_time(robot, &w[0], &w[1]) * scale.max(1.0)).max(MIN_SEGMENT_TIME);
        times.push(t);
    }
    times
}

/// Shortest duration of a path's segment (s).
pub(crate) const MIN_SEGMENT_TIME: f64 = 0.05;

/// The shortest rest-to-rest quintic from `a` to `b` within every joint's
/// velocity, acceleration and jerk limits (peaks `1.875 Δ/T`,
/// `5.774 Δ/T²`, `60 Δ/T³`; s).
pub(crate) fn segment_time(robot: &crate::kinematics::Robot, a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .zip(&robot.joints)
        .map(|((a, b), j)| {
            let d = (b - a).abs();
            (1.875 * d / j.max_velocity)
                .max((10.0 / 3f64.sqrt() * d / j.max_acceleration).sqrt())
                .max((60.0 * d / j.max_jerk).cbrt())
        })
        .fold(0.0, f64::max)
}
