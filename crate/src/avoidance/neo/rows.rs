//! NEO's limits as [`crate::avoidance::rows::Limit`]s: the joint-limit
//! damper with the velocity bounds (the box), the bounds of the task
//! slack (rows on `J q̇`), and the collision dampers (guards written with
//! NEO's bound and stacked by [`crate::avoidance::rows::VelocityDamper`]).

use super::NeoConfig;
use crate::avoidance::protect::{Guard, GuardPair, jacobian_at};
use crate::avoidance::rows::{Inequalities, Limit, LimitContext, TaskRows};
use crate::control_point::PointJacobians;
use crate::error::FieldError;
use crate::kinematics::{Frames, Robot};
use crate::skeleton::Skeleton;

/// The velocity bounds `|q̇ᵢ| ≤ q̇ᵢ,max` narrowed by NEO's joint-limit
/// damper: within `jointInfluence` (`ρᵢ`) of a position limit a joint may
/// approach it at most at `jointGain · (ρ − ρ_s) / (ρᵢ − ρ_s)`, `ρ` its
/// distance to the limit and `ρ_s` = `jointStop` (and must back away
/// below `ρ_s`), within the velocity bounds.
#[derive(Clone, Copy, Debug)]
pub struct JointLimitDamper<'c> {
    /// NEO's settings.
    pub config: &'c NeoConfig,
}

impl JointLimitDamper<'_> {
    /// The largest speed towards a limit `room` away (rad/s or m/s; `+∞`
    /// beyond the influence).
    #[must_use]
    pub fn bound(&self, room: f64) -> f64 {
        let c = self.config;
        if room.is_nan() || room > c.joint_influence {
            return f64::INFINITY;
        }
        c.joint_gain * (room - c.joint_stop) / (c.joint_influence - c.joint_stop)
    }

    /// The box `(lo, hi)` at `q`.
    #[must_use]
    pub fn velocity_box(&self, robot: &Robot, q: &[f64]) -> (Vec<f64>, Vec<f64>) {
        robot
            .joints
            .iter()
            .zip(q)
            .map(|(j, qi)| {
                let v = j.max_velocity;
                let lo = (-v).max(-self.bound(qi - j.min)).min(v);
                let hi = v.min(self.bound(j.max - qi)).max(-v);
                if lo > hi {
                    let mid = 0.5 * (lo + hi);
                    (mid, mid)
                } else {
                    (lo, hi)
                }
            })
            .unzip()
    }
}

impl Limit for JointLimitDamper<'_> {
    fn compute_qp_inequalities<'a>(&'a self, ctx: &LimitContext, out: &mut Inequalities<'a>) {
        let (lo, hi) = self.velocity_box(ctx.robot, ctx.q);
        out.narrow_box(lo, hi);
    }
}

/// The bounds of the task slack `δ = ν − J q̇`, `|δₖ| ≤ slackBound`, as
/// rows on `q̇`: `Jₖ q̇ ≤ νₖ + δ_max` and `−Jₖ q̇ ≤ δ_max − νₖ`.
#[derive(Clone, Debug)]
pub struct SlackBound<'t> {
    tasks: &'t TaskRows,
    negated: Vec<f64>,
    bound: f64,
}

impl<'t> SlackBound<'t> {
    /// The bounds of `tasks`' slack at `bound`.
    #[must_use]
    pub fn new(tasks: &'t TaskRows, bound: f64) -> Self {
        Self {
            tasks,
            negated: tasks.jac.data.iter().map(|v| -v).collect(),
            bound,
        }
    }
}

impl Limit for SlackBound<'_> {
    fn compute_qp_inequalities<'a>(&'a self, _: &LimitContext, out: &mut Inequalities<'a>) {
        let n = self.tasks.jac.cols.max(1);
        let rows = self.tasks.jac.data.chunks_exact(n);
        let negated = self.negated.chunks_exact(n);
        for ((row, neg), v) in rows.zip(negated).zip(&self.tasks.rhs) {
            out.push(row, v + self.bound);
            out.push(neg, self.bound - v);
        }
    }
}

/// NEO's collision damper of a pair at clearance `d` whose obstacle
/// approaches at `obstacle_speed`: the arm may approach at most at
/// `ξ (d − d_s) / (d_i − d_s)` less the obstacle's approach (more when it
/// recedes), and must back away below `d_s`.
#[must_use]
pub fn damper_bound(config: &NeoConfig, distance: f64, obstacle_speed: f64) -> f64 {
    let span = config.influence_distance - config.stopping_distance;
    config.damper_gain * (distance - config.stopping_distance) / span - obstacle_speed
}

/// What the collision dampers are computed from.
#[derive(Clone, Copy, Debug)]
pub struct DamperContext<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Its frames now.
    pub frames: &'a Frames,
    /// Its skeleton now.
    pub skeleton: &'a Skeleton,
    /// NEO's settings.
    pub config: &'a NeoConfig,
}

/// One guard per skeleton–obstacle pair of `pairs` within `d_i` (self
/// pairs left out, as NEO has none), its row `nᵀ J_θ` at the arm's
/// witness and its bound and `soft` both at [`damper_bound`], into `out`
/// (stacked by [`crate::avoidance::rows::VelocityDamper`]).
///
/// # Errors
/// A pair whose segment is not in the skeleton (a bug).
pub fn collision_dampers(
    ctx: &DamperContext,
    pairs: &[GuardPair],
    out: &mut Vec<Guard>,
) -> Result<(), FieldError> {
    out.clear();
    let mut jac = PointJacobians::default();
    for p in pairs {
        if p.obstacle.is_none() || p.distance > ctx.config.influence_distance {
            continue;
        }
        jacobian_at(
            ctx.robot,
            ctx.frames,
            ctx.skeleton,
            p.segment,
            p.fraction,
            &mut jac,
        )?;
        let bound = damper_bound(ctx.config, p.distance, p.obstacle_speed);
        out.push(Guard {
            row: jac.j_theta.iter().map(|c| p.normal.dot(*c)).collect(),
            bound,
            soft: bound,
            distance: p.distance,
            obstacle_speed: p.obstacle_speed,
            segment: p.segment,
            obstacle: p.obstacle,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avoidance::rows::VelocityDamper;
    use crate::kinematics::presets;

    fn panda() -> Robot {
        Robot::from_spec(&presets::preset("panda").unwrap()).unwrap()
    }

    #[test]
    fn the_collision_damper_is_neo_s() {
        let c = NeoConfig::default();
        assert!((damper_bound(&c, c.influence_distance, 0.0) - c.damper_gain).abs() < 1e-12);
        assert!(damper_bound(&c, c.stopping_distance, 0.0).abs() < 1e-12);
        assert!(
            damper_bound(&c, 0.0, 0.0) < 0.0,
            "below d_s the arm backs away"
        );
        // An obstacle closing in at 0.1 m/s takes its speed off the bound;
        // one receding adds it.
        assert!((damper_bound(&c, 0.2, 0.1) - (damper_bound(&c, 0.2, 0.0) - 0.1)).abs() < 1e-12);
        assert!(damper_bound(&c, 0.2, -0.1) > damper_bound(&c, 0.2, 0.0));
    }

    #[test]
    fn the_joint_damper_narrows_the_box_near_a_limit() {
        let r = panda();
        let c = NeoConfig::default();
        let damper = JointLimitDamper { config: &c };
        let mut q = vec![0.0, 0.0, 0.0, -1.5, 0.0, 1.8, 0.0];
        let (lo, hi) = damper.velocity_box(&r, &q);
        for (k, j) in r.joints.iter().enumerate() {
            let room = (q[k] - j.min).min(j.max - q[k]);
            if room > c.joint_influence {
                assert_eq!((lo[k], hi[k]), (-j.max_velocity, j.max_velocity));
            }
        }
        // Joint 1 halfway into its influence below the upper limit.
        let j = &r.joints[0];
        q[0] = j.max - 0.5 * (c.joint_influence + c.joint_stop);
        let (lo, hi) = damper.velocity_box(&r, &q);
        assert!((hi[0] - 0.5 * c.joint_gain).abs() < 1e-12, "{}", hi[0]);
        assert_eq!(lo[0], -j.max_velocity);
        // Past the stop angle it must back away, never faster than its limit.
        q[0] = j.max - 0.01;
        let (lo, hi) = damper.velocity_box(&r, &q);
        assert!(hi[0] < 0.0 && lo[0] == -j.max_velocity);
    }

    #[test]
    fn slack_rows_bound_the_task_slack_both_ways() {
        let mut tasks = TaskRows::new(2);
        tasks.add_rows(1);
        tasks.jac.data.copy_from_slice(&[1.0, 2.0]);
        tasks.rhs.push(0.5);
        let slack = SlackBound::new(&tasks, 10.0);
        let r = panda();
        let ctx = LimitContext {
            robot: &r,
            q: &[0.0; 7],
            stop_time: f64::INFINITY,
        };
        let rows = Inequalities::stack(&[&slack], &ctx, |_| true);
        assert_eq!(rows.rows.len(), 2);
        assert_eq!(rows.rows[0], (&[1.0, 2.0][..], 10.5));
        assert_eq!(rows.rows[1], (&[-1.0, -2.0][..], 9.5));
    }

    #[test]
    fn dampers_stack_one_row_per_pair_through_the_velocity_damper() {
        let guards = vec![
            Guard {
                row: vec![1.0, 0.0],
                bound: 0.4,
                soft: 0.4,
                obstacle: Some(0),
                ..Guard::default()
            },
            Guard {
                row: vec![0.0, 1.0],
                bound: -0.1,
                soft: -0.1,
                obstacle: Some(1),
                ..Guard::default()
            },
        ];
        let r = panda();
        let ctx = LimitContext {
            robot: &r,
            q: &[0.0; 7],
            stop_time: f64::INFINITY,
        };
        let damper = VelocityDamper { guards: &guards };
        let rows = Inequalities::stack(&[&damper], &ctx, |_| true);
        let bounds: Vec<f64> = rows.rows.iter().map(|r| r.1).collect();
        assert_eq!(bounds, vec![0.4, -0.1]);
    }
}
