//! The protective bound of every guarded pair as a limit: the approach
//! speed from which the arm can still stop before the safety distance,
//! with the braking of the joints, the time-to-collision slowdown and the
//! escape from an obstacle that closes in faster than the arm could stop
//! already in each guard's bound ([`crate::avoidance::protect::prepare`]).
//! The row of a pair is `nᵀ J_θ` at the arm's witness; self pairs are
//! [`super::SelfPairs`].

use super::{Inequalities, Limit, LimitContext};
use crate::avoidance::protect::Guard;

/// One row per skeleton–obstacle guard at its protective bound (hard).
#[derive(Clone, Copy, Debug)]
pub struct ProtectiveBound<'g> {
    /// This step's guards.
    pub guards: &'g [Guard],
}

impl Limit for ProtectiveBound<'_> {
    fn compute_qp_inequalities<'a>(&'a self, _: &LimitContext, out: &mut Inequalities<'a>) {
        for (k, g) in self.guards.iter().enumerate() {
            if g.obstacle.is_some() {
                out.push_pair(k, &g.row, g.bound);
            }
        }
    }
}
