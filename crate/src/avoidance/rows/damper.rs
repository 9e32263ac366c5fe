//! The velocity damper of every guarded pair as a limit (Faverjon &
//! Tournassoud; NEO's form, [`crate::avoidance::protect::Damper`]): at the
//! influence distance the arm may approach at `maxRepulsionSpeed`, at the
//! safety band at zero, below it it is pushed away; an obstacle's own
//! approach speed is subtracted. Soft: dropped when it cannot be met
//! together with the hard limits.

use super::{Inequalities, Limit, LimitContext};
use crate::avoidance::protect::Guard;

/// Each guard's row at its damper bound ([`Guard::soft`]; soft).
#[derive(Clone, Copy, Debug)]
pub struct VelocityDamper<'g> {
    /// This step's guards.
    pub guards: &'g [Guard],
}

impl Limit for VelocityDamper<'_> {
    fn compute_qp_inequalities<'a>(&'a self, _: &LimitContext, out: &mut Inequalities<'a>) {
        for (k, g) in self.guards.iter().enumerate() {
            out.push_pair(k, &g.row, g.soft);
        }
    }

    fn soft(&self) -> bool {
        true
    }
}
