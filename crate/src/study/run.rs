//! One run of a Monte Carlo study: the scenario with its own sensing
//! seeds, stepped to its duration, reduced to a [`RunRow`] as it goes (no
//! trace is built).

use serde::{Deserialize, Serialize};

use crate::dependability::EventKind;
use crate::rng::{Rng, derive_seed};
use crate::scenario::{Motion, Scenario, ScenarioError, ShapeSpec};
use crate::world::World;

/// Joint speed above which the arm counts as moving (rad/s or m/s): a
/// contact while some joint moves faster than this is a contact while
/// moving.
pub const MOVING_SPEED: f64 = 1e-3;

/// What one run of a study gives (one JSON line of the command-line
/// shards; serde camelCase).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct RunRow {
    /// Index of the run in the study (0-based).
    pub run: u64,
    /// The study's seed (the same on every row of one study).
    pub seed: u64,
    /// Smallest true clearance over every control step (m); `None` when
    /// nothing came within reach (the influence distance plus the sensing
    /// margin).
    pub min_clearance: Option<f64>,
    /// Whether the true clearance reached 0 while a joint moved faster
    /// than [`MOVING_SPEED`].
    pub contact_while_moving: bool,
    /// Whether the monitor stopped the arm (chattering or an unavoidable
    /// approach).
    pub stopped: bool,
    /// Whether a control point chattered.
    pub chattering: bool,
    /// Whether the monitor found a transition too slow
    /// (`transitionTooSlow`: the time to collision shorter than the
    /// remaining transition time, plus the braking time when the obstacle
    /// closes in).
    pub transition_too_slow: bool,
    /// Number of segment switches of every control point.
    pub switches: u64,
    /// Segment switches per second of simulated time (0 for a run of no
    /// duration).
    pub switches_per_second: f64,
    /// Smallest `time to collision − remaining transition time` (s) over
    /// the steps with a transition under way and something closing in
    /// (see [`crate::world::StepProbe::transition_slack`]); `None` when
    /// there was no such step.
    pub transition_slack: Option<f64>,
}

/// Where the streams of the humans' draws start (`derive_seed(seed, run,
/// VARY_STREAM + k)` for obstacle `k`), apart from the sensing seeds.
pub const VARY_STREAM: u64 = 1 << 32;

/// `scenario` as run `run` of a study seeded with `seed`: obstacle `k`
/// gets the sensing seed [`derive_seed`]`(seed, run, k)` (replacing the
/// scenario's own), and a human with `vary` the person drawn from
/// `derive_seed(seed, run, VARY_STREAM + k)` ([`crate::human::HumanVariation::draw`]; a
/// `linear` motion rescaled to a drawn clip speed); everything else as
/// given.
#[must_use]
pub fn run_scenario(scenario: &Scenario, seed: u64, run: u64) -> Scenario {
    let mut s = scenario.clone();
    for (k, o) in scenario.obstacles.iter().enumerate() {
        let mut spec = scenario.sensing.for_obstacle(&o.id);
        spec.seed = Some(derive_seed(seed, run, k as u64));
        s.sensing.obstacles.insert(o.id.clone(), spec);
    }
    for (k, o) in s.obstacles.iter_mut().enumerate() {
        let ShapeSpec::Human(h) = &o.shape else {
            continue;
        };
        let Some(v) = h.vary.as_deref() else {
            continue;
        };
        let mut rng = Rng::new(derive_seed(seed, run, VARY_STREAM + k as u64));
        let (drawn, speed) = v.draw(h, &mut rng);
        o.shape = ShapeSpec::Human(drawn);
        if let (Some(speed), Some(Motion::Linear { velocity })) = (speed, o.motion.as_mut()) {
            let v = glam::DVec3::from_array(*velocity);
            let n = v.length();
            if n > 0.0 {
                *velocity = (v * (speed / n)).to_array();
            }
        }
    }
    s
}

/// Runs run `run` of the study of `scenario` seeded with `seed`.
///
/// # Errors
/// Whatever [`World::new`] reports for the scenario.
pub fn run_one(scenario: &Scenario, seed: u64, run: u64) -> Result<RunRow, ScenarioError> {
    let s = run_scenario(scenario, seed, run);
    let steps = (s.duration / s.dt).round() as u64;
    let dt = s.dt;
    let mut world = World::new(s)?;
    let mut row = RunRow {
        run,
        seed,
        min_clearance: None,
        contact_while_moving: false,
        stopped: false,
        chattering: false,
        transition_too_slow: false,
        switches: 0,
        switches_per_second: 0.0,
        transition_slack: None,
    };
    let min = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    };
    let mut moving = false;
    let mut seen = world.event_count();
    for _ in 0..steps {
        world.step(dt);
        let p = world.probe();
        row.min_clearance = min(row.min_clearance, p.min_clearance);
        // The clearance of a step is measured before its motion: the arm
        // moves at the speed of the step before.
        if moving && p.min_clearance.is_some_and(|c| c <= 0.0) {
            row.contact_while_moving = true;
        }
        moving = p.joint_speed > MOVING_SPEED;
        row.transition_slack = min(row.transition_slack, p.transition_slack);
        let count = world.event_count();
        let events = world.events();
        let fresh = (count - seen).min(events.len());
        for e in &events[events.len() - fresh..] {
            match e.kind {
                EventKind::SegmentSwitch { .. } => row.switches += 1,
                EventKind::Stop { .. } => row.stopped = true,
                EventKind::Chattering { .. } => row.chattering = true,
                EventKind::TransitionTooSlow { .. } => row.transition_too_slow = true,
                _ => {}
            }
        }
        seen = count;
    }
    let duration = steps as f64 * dt;
    if duration > 0.0 {
        row.switches_per_second = row.switches as f64 / duration;
    }
    Ok(row)
}
