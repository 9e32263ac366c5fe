//! The guards' bounds in one step of the world: the time-to-collision
//! slowdown, the escape from an obstacle that closes in faster than the
//! arm could stop (or, when no escape is admissible, the *doomed* guard the
//! world stops for), the stop time that caps the joints' speed, and the
//! projection of a command onto the guards ([`protect`]).
//!
//! Every function here reads its inputs explicitly ([`GuardContext`]) and
//! returns what the world keeps; the world writes its own state and events.

use super::{Damper, Guard, GuardBounds, GuardPair, Projection, guards, project};
use crate::avoidance::ControllerConfig;
use crate::avoidance::constraints::INFEASIBLE_TOLERANCE;
use crate::avoidance::limits::{JointMotion, braking_time, cap_for_stop_time, velocity_box};
use crate::avoidance::qp;
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::linalg::Mat;
use crate::skeleton::Skeleton;

/// What the guards of one step are computed from.
#[derive(Clone, Copy, Debug)]
pub struct GuardContext<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Its frames at `q`.
    pub frames: &'a Frames,
    /// Its skeleton at `q`.
    pub skeleton: &'a Skeleton,
    /// Joint positions.
    pub q: &'a [f64],
    /// Joint velocities and accelerations.
    pub motion: &'a JointMotion,
    /// Whether the arm is stopping (or stopped).
    pub stopped: bool,
    /// The time within which the joints must be able to stop ([`stop_time`]).
    pub stop_time: f64,
    /// The step (s).
    pub dt: f64,
    /// The controller.
    pub config: &'a ControllerConfig,
}

/// The time within which the joints must be able to stop: for every
/// obstacle closing in at `v_h` with room `d − d_s` above the safety
/// distance, `(d − d_s) / v_h − T_r − dt`, the smallest of them (`∞`
/// when nothing closes in or during a stop).
///
/// The guards bound the arm's approach; this bounds its speed, so that
/// whatever the arm is doing — escaping an obstacle that appeared next
/// to it included — stopping still ends before the obstacle closes the
/// gap. Without it an escape at full speed that later ran out of room
/// (a joint limit, the row turning) ended in a stop that was still
/// braking when the obstacle arrived: contact while moving.
#[must_use]
pub fn stop_time(pairs: &[GuardPair], config: &ControllerConfig, stopped: bool, dt: f64) -> f64 {
    if stopped {
        return f64::INFINITY;
    }
    let p = config.protective;
    pairs
        .iter()
        .filter(|g| g.obstacle.is_some() && g.obstacle_speed > 0.0 && g.contact.is_none())
        .map(|g| (g.distance - p.safety_distance) / g.obstacle_speed - p.reaction_time - dt)
        .fold(f64::INFINITY, f64::min)
}

/// The admissible velocity box at `q`: the joints' speed limits, the
/// braking caps of their position limits, and the stop time of the
/// obstacles closing in ([`stop_time`]).
#[must_use]
pub fn admissible_box(robot: &Robot, q: &[f64], stop_time: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut lo, mut hi) = velocity_box(robot, q);
    cap_for_stop_time(robot, stop_time, &mut lo, &mut hi);
    (lo, hi)
}

/// The guards of this step into `out` (before the control stage; `bend`
/// keeps the bend reserve's frames from step to step): protective
/// bounds, dampers (in the `constraints` avoidance), the time-to-collision
/// `slowdown` of each obstacle, and the escape from obstacles that close
/// in faster than the arm could stop. Returns the first guard with no
/// admissible escape and its excess (m/s), if any.
///
/// # Errors
/// A pair whose segment is not in the skeleton (a bug).
pub fn prepare(
    ctx: &GuardContext,
    pairs: &[GuardPair],
    slowdown: &[f64],
    (out, bend): (&mut Vec<Guard>, &mut super::Bend),
) -> Result<Option<(usize, f64)>, FieldError> {
    let cfg = ctx.config;
    let p = cfg.protective;
    let bounds = GuardBounds {
        config: p,
        braking: braking_time(ctx.robot, ctx.motion, ctx.dt),
        floor: if ctx.stopped { 0.0 } else { f64::NEG_INFINITY },
        damper: cfg.uses_constraints().then_some(Damper {
            gain: cfg.max_repulsion_speed,
            band: cfg.safety_band,
            influence: cfg.influence_distance,
        }),
    };
    guards(ctx, pairs, &bounds, out, bend)?;
    let (lo, hi) = admissible_box(ctx.robot, ctx.q, ctx.stop_time);
    let mut doomed = None;
    for (k, g) in out.iter_mut().enumerate() {
        // Time to collision shorter than a transition plus braking: the
        // approach to that obstacle is slowed (retreat is left free).
        if let Some(o) = g.obstacle
            && g.bound > 0.0
        {
            g.bound *= slowdown.get(o).copied().unwrap_or(1.0);
        }
        // An obstacle closing in faster than the arm could stop: escape
        // along the row if the joints can outrun it, else stop now.
        if g.obstacle_speed > 0.0 && g.bound < 0.0 && !ctx.stopped {
            match g.escape(ctx.robot, &ctx.motion.qdot, &lo, &hi, &p) {
                Some(b) => g.bound = b,
                None if doomed.is_none() => {
                    let excess = g.approach(&ctx.motion.qdot) - g.bound;
                    doomed = Some((k, excess.max(0.0)));
                }
                None => {}
            }
        }
    }
    Ok(doomed)
}

/// What the protective layer decided in one step ([`protect`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Protection {
    /// The joints' stopping time now (s).
    pub braking_time: f64,
    /// Emergency brake: the arm already closes in faster than a guard
    /// allows (the request was zeroed).
    pub braking: bool,
    /// Whether every guard of an approaching obstacle holds with the arm
    /// at rest.
    pub all_hold: bool,
    /// The guard no admissible motion keeps safe, and its excess (m/s):
    /// the projection's infeasible guard, else the doomed guard of
    /// [`prepare`].
    pub doomed: Option<(usize, f64)>,
}

/// The protective layer's projection: `request` becomes the admissible
/// command closest to it under `guards` and the admissible box (zero
/// first under the emergency brake); `doomed` is [`prepare`]'s result.
pub fn protect(
    ctx: &GuardContext,
    pairs: &[GuardPair],
    guards: &[Guard],
    doomed: Option<(usize, f64)>,
    request: &mut Vec<f64>,
) -> Protection {
    let p = ctx.config.protective;
    let braking_time = braking_time(ctx.robot, ctx.motion, ctx.dt);
    // Emergency brake: the arm already closes in faster than a guard
    // allows (the limiter lags a sudden change of the guards).
    let braking = guards.iter().any(|g| g.breached(&ctx.motion.qdot));
    if braking {
        request.iter_mut().for_each(|v| *v = 0.0);
    }
    let all_hold = pairs.iter().all(|g| {
        g.obstacle_speed <= 0.0
            || g.contact_bound().is_some_and(|b| b >= 0.0)
            || p.bound(g.distance, g.obstacle_speed, braking_time) >= 0.0
    });
    let (lo, hi) = admissible_box(ctx.robot, ctx.q, ctx.stop_time);
    let weights = ctx.config.joint_weights.as_deref().unwrap_or(&[]);
    let mut out = Vec::with_capacity(request.len());
    let mut result = project(request.as_slice(), weights, &lo, &hi, guards, &mut out);
    if result.violation > INFEASIBLE_TOLERANCE
        && result
            .worst
            .is_some_and(|k| guards[k].obstacle_speed <= 0.0)
        && let Some((held, x)) = hold_ground(request, weights, &lo, &hi, guards)
    {
        (result, out) = (held, x);
    }
    *request = out;
    // A guard the joints cannot meet right now is no reason to stop
    // while the arm can still outrun its obstacle ([`Guard::escape`]):
    // the request is the closest admissible retreat.
    let infeasible = result
        .worst
        .filter(|_| result.violation > INFEASIBLE_TOLERANCE)
        .filter(|&k| {
            let g = &guards[k];
            g.obstacle_speed <= 0.0
                || g.escape(ctx.robot, &ctx.motion.qdot, &lo, &hi, &p)
                    .is_none()
        })
        .map(|k| (k, result.violation));
    Protection {
        braking_time,
        braking,
        all_hold,
        doomed: infeasible.or(doomed),
    }
}

/// The command closest to `desired` when every still obstacle's (and self
/// pair's) demand to retreat is dropped to holding its ground (bound 0),
/// if that is met; `None` when no guard demands a retreat or it is not.
///
/// Wedged between still obstacles (an arm that starts overlapping one box
/// and within the safety distance of another), no motion retreats from
/// all of them, and the projection is infeasible. Stopping then stops for
/// good: at rest the guards hold, the arm resumes, and the same retreat is
/// asked for again. Holding ground instead (closing in on none of them,
/// moving along them) is what a stopped arm does anyway (its guards' floor
/// is 0), and lets the arm slide out of the wedge. An obstacle that
/// closes in is not covered: its guard is escaped or stopped for as
/// before. Two guards whose rows nearly oppose leave a thin wedge of
/// commands, in which the projection's coordinate ascent crawls (1.7 mm/s
/// still violated after its 200 sweeps on a PR2 start between two boxes),
/// so this rarer problem is solved exactly by the active-set QP.
fn hold_ground(
    desired: &[f64],
    weights: &[f64],
    lo: &[f64],
    hi: &[f64],
    guards: &[Guard],
) -> Option<(Projection, Vec<f64>)> {
    let still = |g: &Guard| g.obstacle_speed <= 0.0 && g.bound < 0.0;
    if !guards.iter().any(still) {
        return None;
    }
    let n = desired.len();
    let w = |i: usize| weights.get(i).copied().unwrap_or(1.0);
    let mut h = Mat::zeros(n, n);
    for i in 0..n {
        h.data[i * n + i] = w(i);
    }
    let f: Vec<f64> = (0..n).map(|i| w(i) * desired[i]).collect();
    let rows: Vec<(&[f64], f64)> = guards
        .iter()
        .map(|g| (g.row.as_slice(), if still(g) { 0.0 } else { g.bound }))
        .collect();
    let problem = qp::Problem {
        h: &h,
        f: &f,
        rows: &rows,
        lo,
        hi,
    };
    let mut x = Vec::with_capacity(n);
    let solution = qp::solve(
        &problem,
        INFEASIBLE_TOLERANCE,
        &mut qp::Workspace::default(),
        &mut x,
    );
    (solution.worst.is_none()).then_some((
        Projection {
            violation: solution.violation,
            worst: None,
            sweeps: solution.steps,
        },
        x,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn guard(row: [f64; 3], bound: f64, obstacle_speed: f64) -> Guard {
        Guard {
            row: row.to_vec(),
            bound,
            obstacle_speed,
            ..Guard::default()
        }
    }

    #[test]
    fn wedged_between_still_obstacles_the_arm_holds_its_ground_and_slides() {
        // Two still obstacles on either side of one point, both asking for
        // a retreat of 5 cm/s: no command meets both.
        let guards = [
            guard([1.0, 0.0, 0.2], -0.05, 0.0),
            guard([-1.0, 0.0, -0.25], -0.05, 0.0),
        ];
        let desired = [0.3, 0.4, -0.1];
        let (lo, hi) = ([-1.0; 3], [1.0; 3]);
        let mut x = Vec::new();
        let plain = project(&desired, &[], &lo, &hi, &guards, &mut x);
        assert!(plain.violation > INFEASIBLE_TOLERANCE, "{plain:?}");
        // Test code: a `None` here is the failure this test looks for.
        let (held, x) = hold_ground(&desired, &[], &lo, &hi, &guards).unwrap();
        assert!(held.worst.is_none());
        for g in &guards {
            let approach: f64 = g.row.iter().zip(&x).map(|(r, v)| r * v).sum();
            assert!(approach <= 1e-9, "{approach}");
        }
        // It moves along both: the second joint, which neither row holds,
        // as asked.
        assert!((x[1] - 0.4).abs() < 1e-9, "{x:?}");
    }

    #[test]
    fn an_obstacle_closing_in_is_not_held_against() {
        let guards = [
            guard([1.0, 0.0, 0.0], 0.0, 0.0),
            guard([-1.0, 0.0, 0.0], -0.05, 0.2),
        ];
        assert!(hold_ground(&[0.1, 0.0, 0.0], &[], &[-1.0; 3], &[1.0; 3], &guards).is_none());
    }
}
