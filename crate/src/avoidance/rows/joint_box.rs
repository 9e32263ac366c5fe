//! The joint velocity box as a limit: each joint's speed limit, the
//! braking cap of its position limits (what its acceleration limit can
//! still shed before the limit), and the cap of the stop time
//! ([`crate::avoidance::protect::admissible_box`]).

use super::{Inequalities, Limit, LimitContext};
use crate::avoidance::protect::admissible_box;

/// The admissible velocity box (hard).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct JointBox;

impl Limit for JointBox {
    fn compute_qp_inequalities<'a>(&'a self, ctx: &LimitContext, out: &mut Inequalities<'a>) {
        let (lo, hi) = admissible_box(ctx.robot, ctx.q, ctx.stop_time);
        out.narrow_box(lo, hi);
    }
}
