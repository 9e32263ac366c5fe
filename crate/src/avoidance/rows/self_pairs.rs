//! The self pairs as a limit: two points of the arm may not approach each
//! other faster than the protective bound allows, with the row
//! `nᵀ (J_θ,a − J_θ,b)` (the guards with no obstacle,
//! [`crate::avoidance::protect::guards`]). A self pair's bound asks for no
//! retreat faster than `protective.withdrawSpeed`.

use super::{Inequalities, Limit, LimitContext};
use crate::avoidance::protect::Guard;

/// One row per self pair at its protective bound (hard).
#[derive(Clone, Copy, Debug)]
pub struct SelfPairs<'g> {
    /// This step's guards (only those without an obstacle are self pairs).
    pub guards: &'g [Guard],
}

impl Limit for SelfPairs<'_> {
    fn compute_qp_inequalities<'a>(&'a self, _: &LimitContext, out: &mut Inequalities<'a>) {
        for (k, g) in self.guards.iter().enumerate() {
            if g.obstacle.is_none() {
                out.push_pair(k, &g.row, g.bound);
            }
        }
    }
}
