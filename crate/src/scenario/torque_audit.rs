//! The torques a trace's motion needs ([`audit_torque`]): `τ = M(q) q̈ +
//! C(q, q̇) q̇ + g(q)` at every sample from the sampled joint positions, as
//! the limiter computes them (`q̇ₖ = (qₖ − qₖ₋₁)/h`, `q̈ₖ = (q̇ₖ₊₁ − q̇ₖ)/h`),
//! against each joint's `maxTorque`.

use super::Trace;
use crate::dynamics::Dynamics;

/// Peak `|τᵢ| / maxTorqueᵢ` over the joints and the samples of `trace`
/// (sampled at every step: `sampleEvery = 1`) for the robot of
/// `dynamics`; 0 for a trace of fewer than three samples.
#[must_use]
pub fn audit_torque(dynamics: &Dynamics, trace: &Trace) -> f64 {
    let n = dynamics.dof();
    let joints = &dynamics.robot().joints;
    let mut ws = dynamics.workspace();
    let mut tau = vec![0.0; n];
    let s = &trace.samples;
    let mut peak = 0.0_f64;
    for k in 1..s.len().saturating_sub(1) {
        let (h0, h1) = (s[k].t - s[k - 1].t, s[k + 1].t - s[k].t);
        if !(h0 > 0.0 && h1 > 0.0) {
            continue;
        }
        let v0: Vec<f64> = s[k]
            .q
            .iter()
            .zip(&s[k - 1].q)
            .map(|(a, b)| (a - b) / h0)
            .collect();
        let acc: Vec<f64> = s[k + 1]
            .q
            .iter()
            .zip(&s[k].q)
            .zip(&v0)
            .map(|((a, b), v)| ((a - b) / h1 - v) / h1)
            .collect();
        if dynamics
            .inverse_dynamics(&mut ws, &s[k].q, (&v0, &acc), &mut tau)
            .is_err()
        {
            continue;
        }
        for (t, j) in tau.iter().zip(joints) {
            peak = peak.max(t.abs() / j.max_torque);
        }
    }
    peak
}
