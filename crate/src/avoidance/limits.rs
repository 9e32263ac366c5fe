//! The *limit* stage: every joint command a real arm could execute.
//!
//! Whatever the controller and the protective layer ask for, the joints
//! move within their speed, acceleration and jerk limits
//! ([`crate::kinematics::Joint`]: `max_velocity`, `max_acceleration`,
//! `max_jerk`) and stop before their position limits.
//!
//! [`step`] is an online, jerk-limited velocity tracker, the
//! role Ruckig's velocity interface plays on real controllers, computed in
//! closed form per joint so that it costs a few hundred nanoseconds:
//!
//! 1. **Position limits with braking distance**: the commanded speed towards
//!    a limit is capped at `√(A (q_max − q))` (braking at half the
//!    acceleration limit, the other half kept for the jerk ramp), so the
//!    joint can always stop before the limit.
//! 2. **Synchronised, direction-preserving approach**: each joint `i` needs
//!    about `τᵢ = |eᵢ|/Aᵢ + Aᵢ/Jᵢ` to close its velocity error `eᵢ`; joint `i`
//!    uses the fraction `τᵢ/max τ` of its acceleration limit, so all joints
//!    arrive together and the velocity moves along the straight line from
//!    the current command to the requested one. This is what keeps the
//!    protective layer's linear constraints satisfied while the limiter
//!    catches up: every velocity on that line is a convex combination of two
//!    velocities that satisfy them.
//! 3. **Jerk-limited acceleration**: the acceleration heads for
//!    `sign(e) min(A', √(2 J' |e|), |e|/dt)` — the largest acceleration from
//!    which a jerk-limited ramp down reaches the target without overshoot —
//!    changing by at most `J dt` per step; the last term lets the velocity
//!    settle exactly instead of dithering around the target.
//!
//! The new velocity is `q̇ + q̈ dt`, so the accelerations and jerks read off
//! the sampled trajectory (`Δq̇/dt`, `Δq̈/dt`) are exactly the bounded ones.

use crate::kinematics::Robot;

/// Joint state the limiter carries from step to step.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointMotion {
    /// Joint velocities (rad/s or m/s).
    pub qdot: Vec<f64>,
    /// Joint accelerations (rad/s² or m/s²).
    pub qddot: Vec<f64>,
}

impl JointMotion {
    /// At rest, `n` joints.
    #[must_use]
    pub fn rest(n: usize) -> Self {
        Self {
            qdot: vec![0.0; n],
            qddot: vec![0.0; n],
        }
    }

    /// Whether every joint is still (velocity and acceleration zero).
    #[must_use]
    pub fn is_at_rest(&self) -> bool {
        self.qdot.iter().chain(&self.qddot).all(|v| *v == 0.0)
    }
}

/// The largest speed (≥ 0) at which joint `i` may move towards each of its
/// position limits now: `(towards min, towards max)`.
#[must_use]
pub fn braking_caps(robot: &Robot, q: &[f64]) -> Vec<(f64, f64)> {
    robot
        .joints
        .iter()
        .zip(q)
        .map(|(j, qi)| {
            let cap = |room: f64| {
                if room.is_finite() {
                    (j.max_acceleration * (room - LIMIT_MARGIN).max(0.0)).sqrt()
                } else {
                    f64::INFINITY
                }
            };
            (cap(qi - j.min), cap(j.max - qi))
        })
        .collect()
}

/// Admissible joint velocities now: the speed limits intersected with the
/// braking caps of the position limits, as `(lo, hi)` per joint.
#[must_use]
pub fn velocity_box(robot: &Robot, q: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let caps = braking_caps(robot, q);
    robot
        .joints
        .iter()
        .zip(caps)
        .map(|(j, (down, up))| (-j.max_velocity.min(down), j.max_velocity.min(up)))
        .unzip()
}

/// Narrows the velocity box `lo..hi` so that every joint can stop within
/// `time` seconds (see [`braking_time`]: a speed `v` needs `v / A` plus the
/// acceleration ramps, at most `2 A / J`): `|q̇ₖ| ≤ Aₖ (time − 2 Aₖ / Jₖ)`,
/// zero when even the ramps do not fit. An infinite `time` changes nothing.
pub fn cap_for_stop_time(robot: &Robot, time: f64, lo: &mut [f64], hi: &mut [f64]) {
    if !time.is_finite() {
        return;
    }
    for ((j, l), h) in robot.joints.iter().zip(lo).zip(hi) {
        let a = j.max_acceleration;
        let cap = (a * (time - 2.0 * a / j.max_jerk)).max(0.0);
        *l = l.max(-cap);
        *h = h.min(cap);
    }
}

/// Time the limiter needs to bring `motion` to rest (s): the slowest
/// joint's deceleration plus its acceleration ramp, plus one step.
#[must_use]
pub fn braking_time(robot: &Robot, motion: &JointMotion, dt: f64) -> f64 {
    robot
        .joints
        .iter()
        .zip(&motion.qdot)
        .zip(&motion.qddot)
        .map(|((j, v), a)| {
            v.abs() / j.max_acceleration + (a.abs() + j.max_acceleration) / j.max_jerk
        })
        .fold(0.0, f64::max)
        + dt
}

fn time_to_close(error: f64, a: f64, j: f64) -> f64 {
    let e = error.abs();
    if e <= 0.0 {
        0.0
    } else if e >= a * a / j {
        e / a + a / j
    } else {
        2.0 * (e / j).sqrt()
    }
}

/// The fraction `s` of its acceleration and jerk limits with which a joint
/// closes velocity error `e` in exactly `tau` (the inverse of
/// [`time_to_close`] for limits `s A`, `s J`): joints with the same ratio
/// `A/J` then follow profiles of the same shape, scaled by their errors.
/// A cap of zero on the acceleration (`A = 0`, `tau` infinite: the torque
/// limits leave no acceleration at all) has no share to scale: 1.
fn share_for(e: f64, a: f64, j: f64, tau: f64) -> f64 {
    let c = a / j;
    let s = if tau >= 2.0 * c {
        e.abs() / (a * (tau - c))
    } else {
        4.0 * e.abs() / (j * tau * tau)
    };
    if s.is_nan() {
        return 1.0;
    }
    s.clamp(1e-6, 1.0)
}

/// The velocity change of applying acceleration `a` for one step, then
/// ramping it down by `jerk_step` per step to zero.
fn landing(a: f64, jerk_step: f64, dt: f64) -> f64 {
    let m = (a / jerk_step).floor();
    dt * (a + m * a - jerk_step * m * (m + 1.0) / 2.0)
}

/// The largest acceleration in `[0, acc]` (and at most `e/dt`) from which
/// the discrete ramp down at `jerk_step` per step changes the velocity by
/// at most `e`: the velocity then lands on its target without overshoot.
fn landing_acceleration(e: f64, acc: f64, jerk_step: f64, dt: f64) -> f64 {
    let top = acc.min(e / dt);
    if top <= 0.0 || landing(top, jerk_step, dt) <= e {
        return top.max(0.0);
    }
    let (mut lo, mut hi): (f64, f64) = (0.0, top);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if landing(mid, jerk_step, dt) <= e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Room (rad or m) kept before a position limit for the discrete lag of
/// the braking profile.
const LIMIT_MARGIN: f64 = 1e-4;

/// Advances `motion` by one step of `dt` towards the requested velocities
/// `target` within every joint limit (see the module docs); returns the new
/// joint motion in place.
pub fn step(robot: &Robot, q: &[f64], target: &[f64], motion: &mut JointMotion, dt: f64) {
    step_with(robot, q, target, motion, dt, &StepOptions::default());
}

/// Options of [`step_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOptions {
    /// Every joint's acceleration further capped at this (the torque
    /// limits' share; default none).
    pub max_acceleration: f64,
    /// A stop's gentle deceleration (default none): every joint's
    /// acceleration capped at it too, except a joint held back by the
    /// braking cap of a position limit, which must not be carried past
    /// its limit by a gentle stop.
    pub stop_deceleration: f64,
    /// Whether the joints approach the target together along a straight
    /// line (default); `false` lets each joint use its full limits (an
    /// emergency brake of the protective layer: fastest, not straight).
    pub synchronise: bool,
}

impl Default for StepOptions {
    fn default() -> Self {
        Self {
            max_acceleration: f64::INFINITY,
            stop_deceleration: f64::INFINITY,
            synchronise: true,
        }
    }
}

/// [`step`] with options.
pub fn step_with(
    robot: &Robot,
    q: &[f64],
    target: &[f64],
    motion: &mut JointMotion,
    dt: f64,
    options: &StepOptions,
) {
    let n = robot.dof();
    if motion.qdot.len() != n || motion.qddot.len() != n {
        *motion = JointMotion::rest(n);
    }
    let (lo, hi) = velocity_box(robot, q);
    let caps = braking_caps(robot, q);
    // A joint held back by the braking cap of a position limit brakes with
    // its full acceleration, not its synchronised share nor a stop's.
    let mut braking = vec![false; n];
    let want: Vec<f64> = (0..n)
        .map(|i| {
            let t = target.get(i).copied().unwrap_or(0.0);
            let t = if t.is_finite() { t } else { 0.0 };
            let (down, up) = caps[i];
            braking[i] = t > up || t < -down || motion.qdot[i] > up || motion.qdot[i] < -down;
            t.clamp(lo[i], hi[i])
        })
        .collect();
    let cap = |i: usize| {
        if braking[i] {
            options.max_acceleration
        } else {
            options.max_acceleration.min(options.stop_deceleration)
        }
    };
    let longest = robot
        .joints
        .iter()
        .enumerate()
        .map(|(i, j)| {
            let acc = j.max_acceleration.min(cap(i));
            time_to_close(want[i] - motion.qdot[i], acc, j.max_jerk)
        })
        .fold(0.0, f64::max);
    for (i, j) in robot.joints.iter().enumerate() {
        let limit = j.max_acceleration.min(cap(i));
        let (v, a) = (motion.qdot[i], motion.qddot[i]);
        let e = want[i] - v;
        let share = if braking[i] || !options.synchronise {
            1.0
        } else if longest > 0.0 {
            share_for(e, limit, j.max_jerk, longest)
        } else {
            1.0
        };
        let (acc, jerk) = (limit * share, j.max_jerk * share);
        let reach = landing_acceleration(e.abs(), acc, jerk * dt, dt);
        // A joint builds up acceleration at its scaled jerk (the same shape
        // as the others) and takes it back at its full jerk limit, so that
        // a share that shrinks between steps never causes an overshoot.
        let goal = reach.copysign(e);
        let easing = goal.abs() < a.abs() || goal * a < 0.0;
        let step_jerk = if easing { j.max_jerk } else { jerk } * dt;
        let bound = limit.max(a.abs().min(j.max_acceleration));
        let mut a_next = goal
            .clamp(a - step_jerk, a + step_jerk)
            .clamp(-bound, bound);
        let mut v_next = v + a_next * dt;
        if v_next.abs() > j.max_velocity {
            v_next = v_next.clamp(-j.max_velocity, j.max_velocity);
            a_next = (v_next - v) / dt;
        }
        motion.qdot[i] = v_next;
        motion.qddot[i] = a_next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::presets;

    fn robot(name: &str) -> Robot {
        let spec = presets::preset(name).unwrap_or_else(|e| unreachable!("{e}"));
        Robot::from_spec(&spec).unwrap_or_else(|e| unreachable!("{e}"))
    }

    /// Runs the limiter towards `target` and checks every limit on the way.
    fn run(r: &Robot, q0: &[f64], target: &[f64], steps: usize) -> (Vec<f64>, JointMotion) {
        let dt = 0.001;
        let mut q = q0.to_vec();
        let mut m = JointMotion::rest(r.dof());
        for _ in 0..steps {
            let before = m.clone();
            step(r, &q, target, &mut m, dt);
            for (i, j) in r.joints.iter().enumerate() {
                assert!(m.qdot[i].abs() <= j.max_velocity * (1.0 + 1e-12));
                let acc = (m.qdot[i] - before.qdot[i]) / dt;
                assert!(acc.abs() <= j.max_acceleration * (1.0 + 1e-9), "{acc}");
                let jerk = (m.qddot[i] - before.qddot[i]) / dt;
                assert!(
                    jerk.abs() <= j.max_jerk * (1.0 + 1e-9),
                    "jerk {jerk} joint {i} v {} a {} before {:?}",
                    m.qdot[i],
                    m.qddot[i],
                    (before.qdot[i], before.qddot[i])
                );
            }
            for ((qi, v), j) in q.iter_mut().zip(&m.qdot).zip(&r.joints) {
                *qi += v * dt;
                assert!(*qi >= j.min - 1e-12 && *qi <= j.max + 1e-12, "{qi}");
            }
        }
        (q, m)
    }

    /// A gentle stop (a chattering stop's `maxDeceleration`) with a joint
    /// running towards its position limit: that joint brakes in time for
    /// the limit, within its acceleration limit; the others keep the
    /// gentle deceleration.
    #[test]
    fn a_gentle_stop_does_not_carry_a_joint_past_its_position_limit() {
        let r = robot("lwr4");
        let n = r.dof();
        let dt = 0.005;
        let gentle = 0.5;
        let options = StepOptions {
            stop_deceleration: gentle,
            ..StepOptions::default()
        };
        let j0 = &r.joints[0];
        // 0.3 rad/s towards the upper limit, 5 cm of room: a gentle stop
        // needs 9 cm, the joint's own acceleration about 1 mm.
        let mut q = vec![0.0; n];
        q[0] = j0.max - 0.05;
        let mut m = JointMotion::rest(n);
        m.qdot[0] = 0.3;
        m.qdot[1] = 0.3;
        for _ in 0..400 {
            let before = m.clone();
            step_with(&r, &q, &vec![0.0; n], &mut m, dt, &options);
            for (i, j) in r.joints.iter().enumerate() {
                let acc = (m.qdot[i] - before.qdot[i]) / dt;
                assert!(
                    acc.abs() <= j.max_acceleration * (1.0 + 1e-9),
                    "joint {i}: {acc}"
                );
                q[i] += m.qdot[i] * dt;
                assert!(
                    q[i] <= j.max && q[i] >= j.min,
                    "joint {i} at {} past its limit",
                    q[i]
                );
            }
            // The joint with room to spare keeps the gentle deceleration.
            assert!((m.qdot[1] - before.qdot[1]).abs() <= gentle * dt * (1.0 + 1e-9));
        }
        assert_eq!(m.qdot[0], 0.0);
    }

    #[test]
    fn a_zero_acceleration_cap_holds_the_velocity_without_nan() {
        let r = robot("lwr4");
        let n = r.dof();
        let options = StepOptions {
            max_acceleration: 0.0,
            ..StepOptions::default()
        };
        let mut m = JointMotion::rest(n);
        step_with(&r, &vec![0.1; n], &vec![0.5; n], &mut m, 0.005, &options);
        assert_eq!(m.qdot, vec![0.0; n]);
        assert_eq!(m.qddot, vec![0.0; n]);
    }

    #[test]
    fn reaches_the_target_within_every_limit_and_settles_exactly() {
        let r = robot("panda");
        let q0 = [0.0, 0.0, 0.0, -1.5, 0.0, 1.5, 0.0];
        let target = [1.0, -0.5, 0.3, 0.2, -2.0, 0.1, 5.0];
        let (_, m) = run(&r, &q0, &target, 400);
        for (i, v) in m.qdot.iter().enumerate() {
            let want = target[i].clamp(-r.joints[i].max_velocity, r.joints[i].max_velocity);
            assert!((v - want).abs() < 1e-9, "joint {i}: {v} vs {want}");
        }
        let (_, m) = run(&r, &q0, &[0.0; 7], 10);
        assert!(m.qdot.iter().all(|v| v.abs() < 0.1));
    }

    #[test]
    fn approach_keeps_the_direction_of_the_velocity_change() {
        let r = robot("lwr4");
        let target = [0.4, -0.2, 0.1, 0.3, 0.0, -0.1, 0.2];
        let dt = 0.001;
        let mut m = JointMotion::rest(7);
        let q = [0.0, 0.5, 0.0, -1.0, 0.0, 0.5, 0.0];
        for _ in 0..40 {
            step(&r, &q, &target, &mut m, dt);
            let s = m.qdot[0] / target[0];
            for i in 1..7 {
                assert!((m.qdot[i] - s * target[i]).abs() < 2e-3 * target[0].abs().max(1.0));
            }
        }
    }

    #[test]
    fn stops_before_position_limits() {
        let r = robot("planar3");
        let (q, m) = run(&r, &[2.5, 0.0, 0.0], &[2.0, 0.0, 0.0], 3000);
        assert!(q[0] <= r.joints[0].max + 1e-9, "{}", q[0]);
        assert!(m.qdot[0].abs() < 1e-6);
    }

    #[test]
    fn a_box_capped_for_a_stop_time_stops_within_it() {
        let r = robot("panda");
        let q = [0.0, 0.0, 0.0, -1.5, 0.0, 1.5, 0.0];
        let dt = 0.001;
        for time in [0.004, 0.05, 0.2] {
            let (mut lo, mut hi) = velocity_box(&r, &q);
            cap_for_stop_time(&r, time, &mut lo, &mut hi);
            // The fastest motion the box allows, decelerating at full rate.
            let mut m = JointMotion::rest(7);
            for (k, j) in r.joints.iter().enumerate() {
                m.qdot[k] = hi[k];
                m.qddot[k] = j.max_acceleration;
                let cap =
                    (j.max_acceleration * (time - 2.0 * j.max_acceleration / j.max_jerk)).max(0.0);
                assert!(lo[k] <= 0.0 && hi[k] >= 0.0 && -lo[k] <= cap && hi[k] <= cap);
            }
            let need = braking_time(&r, &m, dt);
            assert!(
                need <= time + dt + 1e-12,
                "{need} s to stop, {time} s allowed"
            );
            // And it does stop in that time.
            let mut t = 0.0;
            while !m.is_at_rest() {
                step(&r, &q, &[0.0; 7], &mut m, dt);
                t += dt;
                assert!(
                    t <= 1.1 * need + dt,
                    "still moving after {t} s (allowed {time} s)"
                );
            }
        }
        // Too little time for even the acceleration ramps: nothing may move.
        let (mut lo, mut hi) = velocity_box(&r, &q);
        cap_for_stop_time(&r, 1e-4, &mut lo, &mut hi);
        assert!(lo.iter().chain(&hi).all(|v| *v == 0.0));
        // No obstacle closing in: the box as it was.
        let (mut lo, mut hi) = velocity_box(&r, &q);
        cap_for_stop_time(&r, f64::INFINITY, &mut lo, &mut hi);
        assert_eq!((lo, hi), velocity_box(&r, &q));
    }

    #[test]
    fn braking_time_covers_a_stop() {
        let r = robot("panda");
        let q = [0.0, 0.0, 0.0, -1.5, 0.0, 1.5, 0.0];
        let (_, mut m) = run(&r, &q, &[1.5, -1.0, 1.0, 1.0, 2.0, -2.0, 2.0], 1000);
        let budget = braking_time(&r, &m, 0.001);
        let mut t = 0.0;
        while !m.is_at_rest() {
            step(&r, &q, &[0.0; 7], &mut m, 0.001);
            t += 0.001;
            assert!(
                t <= budget * 1.1,
                "still moving after {t} s (budget {budget} s)"
            );
        }
    }
}
