//! The reach report: each controller on each problem of a set, judged by
//! the one evaluator ([`super::run`]) with both criteria side by side —
//! the strict one (1 cm and 2° within 10 s, within every limit, no contact
//! beginning while the arm moves) and NEO's count (summed pose error below
//! 0.25 m + rad within 25 s) — per scene and over the set, with the strict
//! failures classified.
//!
//! The controllers ([`Controller`]): the library's default
//! `constraints`, the paper's `repulsion`, and NEO
//! ([`crate::avoidance::neo`]) as published (its command straight to the
//! joints) and through the library's limiter. Every one sees the same
//! model, volumes, obstacles, control period and evaluator; only
//! `controller.avoidance` (and `neo.limiter`) differ.

use super::{Outcome, Problem};
use crate::avoidance::Avoidance;
use crate::error::FieldError;
use crate::plan::{Plan, PlanOptions, plan_path};
use crate::scenario::Scenario;

/// A controller of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Controller {
    /// `constraints`, the library's default.
    Constraints,
    /// The paper's `repulsion`.
    Repulsion,
    /// NEO as published: its QP's command straight to the joints.
    Neo,
    /// NEO's command through the library's jerk-limited limiter.
    NeoLimited,
    /// `constraints` following a planned joint-space path to the problem's
    /// goal configuration ([`crate::plan`]); the goal pose alone when no
    /// path is found.
    Planned,
}

impl Controller {
    /// Every controller, in the report's order.
    pub const ALL: [Self; 5] = [
        Self::Constraints,
        Self::Repulsion,
        Self::Neo,
        Self::NeoLimited,
        Self::Planned,
    ];

    /// Its name in the report (and on the command line).
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Constraints => "constraints",
            Self::Repulsion => "repulsion",
            Self::Neo => "neo",
            Self::NeoLimited => "neo+limiter",
            Self::Planned => "constraints+plan",
        }
    }

    /// The controller named `name` ([`Self::label`]).
    #[must_use]
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.label() == name)
    }

    /// `scenario` driven by this controller (every other setting kept).
    pub fn apply(self, scenario: &mut Scenario) {
        let c = &mut scenario.controller;
        c.avoidance = match self {
            Self::Constraints | Self::Planned => Avoidance::Constraints,
            Self::Repulsion => Avoidance::Repulsion,
            Self::Neo | Self::NeoLimited => Avoidance::Neo,
        };
        c.neo.limiter = self == Self::NeoLimited;
    }

    /// `problem` driven by this controller.
    #[must_use]
    pub fn problem(self, problem: &Problem) -> Problem {
        self.guided(problem).0
    }

    /// `problem` driven by this controller, and for [`Self::Planned`] the
    /// plan it follows (or why there is none: the goal pose is then
    /// reached for reactively).
    #[must_use]
    pub fn guided(self, problem: &Problem) -> (Problem, Option<Result<Plan, FieldError>>) {
        let mut p = problem.clone();
        self.apply(&mut p.scenario);
        if self != Self::Planned {
            return (p, None);
        }
        let plan = match &p.goal_q {
            Some(goal) => plan_path(&p.scenario, goal, &PlanOptions::default()),
            None => Err(FieldError::new(
                "goalQ",
                "the problem has no goal configuration",
            )),
        };
        if let Ok(plan) = &plan {
            p.scenario.task = plan.task();
        }
        (p, Some(plan))
    }
}

/// Why a run failed the strict criterion: the first that applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The arm overlaps an obstacle (or itself) in its first step.
    StartInContact,
    /// At the goal configuration the arm is closer to an obstacle than the
    /// library's safety band (or overlaps it): unreachable by design.
    GoalInBand,
    /// Reached, but a contact began while the arm moved.
    MovingContact,
    /// Reached, but a joint exceeded its velocity, acceleration or jerk
    /// limit.
    OverLimit,
    /// Not reached, and the world stopped the arm at least once
    /// (`unavoidable` or chattering).
    Stopped,
    /// Not reached, the arm never stopped: it ended short, in a local
    /// minimum (or too slowly to arrive in time).
    LocalMinimum,
}

impl Failure {
    /// Every class, in the report's order.
    pub const ALL: [Self; 6] = [
        Self::StartInContact,
        Self::GoalInBand,
        Self::MovingContact,
        Self::OverLimit,
        Self::Stopped,
        Self::LocalMinimum,
    ];

    /// Its name in the report.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::StartInContact => "start in contact",
            Self::GoalInBand => "goal within the band",
            Self::MovingContact => "contact while moving",
            Self::OverLimit => "over a limit",
            Self::Stopped => "stop",
            Self::LocalMinimum => "local minimum",
        }
    }
}

/// The class of `outcome`'s strict failure (`None` for a success); `band`
/// is the safety band the goals are judged against (m).
#[must_use]
pub fn classify(outcome: &Outcome, band: f64) -> Option<Failure> {
    if outcome.success {
        return None;
    }
    Some(if outcome.start_clearance <= 0.0 {
        Failure::StartInContact
    } else if outcome.goal_clearance.is_some_and(|c| c < band) {
        Failure::GoalInBand
    } else if outcome.reached.is_some() {
        if outcome.audit.moving_contact.is_some() {
            Failure::MovingContact
        } else {
            Failure::OverLimit
        }
    } else if outcome.stopped {
        Failure::Stopped
    } else {
        Failure::LocalMinimum
    })
}

/// One row of the report: a controller over some runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Row {
    /// Problems.
    pub problems: usize,
    /// Strict successes.
    pub strict: usize,
    /// Runs that meet NEO's count.
    pub neo: usize,
    /// Median time to the goal of the strict successes (s; NaN: none).
    pub strict_time: f64,
    /// Median time to NEO's count of the runs that meet it (s; NaN: none).
    pub neo_time: f64,
    /// Smallest clearance over every run (m).
    pub min_clearance: f64,
    /// Peak `|q̇| / limit` over every run.
    pub peak_velocity: f64,
    /// Peak `|q̈| / limit` over every run.
    pub peak_acceleration: f64,
    /// Runs over a velocity, acceleration or jerk limit.
    pub over_limit: usize,
    /// Runs in which a contact began while the arm moved.
    pub moving_contact: usize,
    /// Strict failures per class, in the order of [`Failure::ALL`].
    pub failures: [usize; 6],
    /// Median time per control step (µs; NaN when not timed).
    pub step_us: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The [`Row`] of `runs` (each an outcome and its time per step in µs,
/// NaN when not timed), goals judged against `band` (m).
#[must_use]
pub fn row(runs: &[&(Outcome, f64)], band: f64) -> Row {
    let outcomes = runs.iter().map(|r| &r.0);
    let mut failures = [0; 6];
    for o in outcomes.clone() {
        if let Some(k) = classify(o, band).and_then(|f| Failure::ALL.iter().position(|c| *c == f)) {
            failures[k] += 1;
        }
    }
    let over = |o: &&Outcome| {
        let a = &o.audit;
        let with_contact = crate::scenario::MotionAudit {
            moving_contact: None,
            ..*a
        };
        !with_contact.admissible()
    };
    Row {
        problems: runs.len(),
        strict: outcomes.clone().filter(|o| o.success).count(),
        neo: outcomes.clone().filter(|o| o.neo_reached.is_some()).count(),
        strict_time: median(
            outcomes
                .clone()
                .filter(|o| o.success)
                .filter_map(|o| o.reached)
                .collect(),
        ),
        neo_time: median(outcomes.clone().filter_map(|o| o.neo_reached).collect()),
        min_clearance: outcomes
            .clone()
            .map(|o| o.audit.clearance)
            .fold(f64::INFINITY, f64::min),
        peak_velocity: outcomes
            .clone()
            .map(|o| o.audit.velocity)
            .fold(0.0, f64::max),
        peak_acceleration: outcomes
            .clone()
            .map(|o| o.audit.acceleration)
            .fold(0.0, f64::max),
        over_limit: outcomes.clone().filter(over).count(),
        moving_contact: outcomes
            .clone()
            .filter(|o| o.audit.moving_contact.is_some())
            .count(),
        failures,
        step_us: median(runs.iter().map(|r| r.1).filter(|v| v.is_finite()).collect()),
    }
}

/// The report's table header (Markdown).
#[must_use]
pub fn header() -> String {
    let classes: Vec<&str> = Failure::ALL.iter().map(|f| f.label()).collect();
    format!(
        "| set / scene | controller | problems | strict | NEO's count | time to goal (strict; NEO's) | min clearance | peak q̇/limit | peak q̈/limit | over a limit | contact while moving | strict failures: {} | µs/step |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|",
        classes.join(" / ")
    )
}

/// `row` as a line of the report's table.
#[must_use]
pub fn line(scene: &str, controller: Controller, row: &Row) -> String {
    let pct = |k: usize| 100.0 * k as f64 / row.problems.max(1) as f64;
    let failures: Vec<String> = row.failures.iter().map(ToString::to_string).collect();
    // A median over no run prints as "–", not "NaN s".
    let secs = |t: f64| {
        if t.is_nan() {
            "–".to_owned()
        } else {
            format!("{t:.2} s")
        }
    };
    format!(
        "| {scene} | {} | {} | {:.1} % ({}) | {:.1} % ({}) | {}; {} | {:.1} mm | {:.2} | {:.2} | {} | {} | {} | {:.1} |",
        controller.label(),
        row.problems,
        pct(row.strict),
        row.strict,
        pct(row.neo),
        row.neo,
        secs(row.strict_time),
        secs(row.neo_time),
        row.min_clearance * 1e3,
        row.peak_velocity,
        row.peak_acceleration,
        row.over_limit,
        row.moving_contact,
        failures.join(" / "),
        row.step_us,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::MotionAudit;

    fn outcome(success: bool) -> Outcome {
        Outcome {
            success,
            reached: success.then_some(1.0),
            neo_reached: Some(0.5),
            final_error: (0.0, 0.0),
            audit: MotionAudit {
                velocity: 0.5,
                acceleration: 0.9,
                jerk: 0.1,
                clearance: 0.03,
                moving_contact: None,
                torque: None,
            },
            steps: 100,
            stopped: false,
            start_clearance: 0.1,
            goal_clearance: Some(0.1),
        }
    }

    #[test]
    fn failures_are_classified_by_the_first_cause() {
        let band = 0.02;
        assert_eq!(classify(&outcome(true), band), None);
        let mut o = outcome(false);
        assert_eq!(classify(&o, band), Some(Failure::LocalMinimum));
        o.stopped = true;
        assert_eq!(classify(&o, band), Some(Failure::Stopped));
        o.reached = Some(2.0);
        o.audit.acceleration = 30.0;
        assert_eq!(classify(&o, band), Some(Failure::OverLimit));
        o.audit.moving_contact = Some(1.5);
        assert_eq!(classify(&o, band), Some(Failure::MovingContact));
        o.goal_clearance = Some(0.01);
        assert_eq!(classify(&o, band), Some(Failure::GoalInBand));
        o.start_clearance = -0.001;
        assert_eq!(classify(&o, band), Some(Failure::StartInContact));
    }

    #[test]
    fn a_row_counts_both_criteria_and_the_violations() {
        let mut over = outcome(false);
        over.reached = Some(3.0);
        over.audit.acceleration = 12.0;
        let runs = [(outcome(true), 10.0), (over, 20.0), (outcome(false), 30.0)];
        let refs: Vec<&(Outcome, f64)> = runs.iter().collect();
        let r = row(&refs, 0.02);
        assert_eq!((r.problems, r.strict, r.neo), (3, 1, 3));
        assert_eq!((r.over_limit, r.moving_contact), (1, 0));
        assert_eq!(r.failures, [0, 0, 0, 1, 0, 1]);
        assert_eq!(r.peak_acceleration, 12.0);
        assert_eq!((r.strict_time, r.step_us), (1.0, 20.0));
    }

    #[test]
    fn controllers_set_the_avoidance_and_the_limiter() {
        let mut s = Scenario::from_json(
            r#"{ "robot": { "preset": "planar3" }, "obstacles": [], "dt": 0.01, "duration": 1 }"#,
        )
        .unwrap();
        Controller::NeoLimited.apply(&mut s);
        assert!(s.controller.uses_neo() && s.controller.neo.limiter);
        Controller::Neo.apply(&mut s);
        assert!(s.controller.uses_neo() && !s.controller.neo.limiter);
        Controller::Repulsion.apply(&mut s);
        assert_eq!(s.controller.avoidance, Avoidance::Repulsion);
        assert_eq!(
            Controller::parse("neo+limiter"),
            Some(Controller::NeoLimited)
        );
        assert_eq!(Controller::parse("magnets"), None);
    }
}
