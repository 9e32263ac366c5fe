//! A small dense convex QP: the joint velocity that best serves the tasks
//! under one-sided constraints.
//!
//! `minimise ½ xᵀ H x − fᵀ x  subject to  aₖᵀ x ≤ bₖ,  lo ≤ x ≤ hi`
//!
//! with `H` symmetric positive definite (`n × n`, `n` the number of joints:
//! 3 to 14 here) and a few dozen rows at most. The constraints' dual is
//! solved by Hildreth's coordinate ascent in the metric of `H⁻¹`: each row
//! in turn takes the multiplier that satisfies it exactly given the others,
//! clipped at zero. It needs no factorisation beyond one Cholesky of `H`,
//! allocates nothing per sweep, is exact at convergence (the KKT conditions
//! to the tolerance) and degrades gracefully: on an infeasible problem it
//! stops after [`MAX_SWEEPS`] with the rows violated least in the `H`
//! metric, which the caller reports.
//!
//! Rows join a working set only once the solution violates them, so the
//! ascent runs on the few rows that bind, not on every pair in reach
//! (hundreds among a thousand obstacles).

use crate::linalg::Mat;

/// Sweeps at most over every round of the working set (the problem is
/// then reported as violated).
pub const MAX_SWEEPS: usize = 200;

/// Outcome of [`solve`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Solution {
    /// Largest violation `aₖᵀ x − bₖ` over the rows (m/s; ≤ 0 when all hold).
    pub violation: f64,
    /// The row with the largest violation, when it exceeds `tolerance`.
    pub worst: Option<usize>,
    /// Sweeps used.
    pub sweeps: usize,
}

/// Scratch space reused from step to step (no allocation in steady state).
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    hinv: Vec<f64>,
    u: Vec<f64>,
    norms: Vec<f64>,
    lambda: Vec<f64>,
    up: Vec<f64>,
    down: Vec<f64>,
}

/// The inverse of the symmetric positive definite `h` (row-major `n × n`)
/// into `out`, by Cholesky; `false` when `h` is not positive definite.
fn spd_inverse(h: &[f64], n: usize, out: &mut Vec<f64>) -> bool {
    // L Lᵀ = H, then solve for each column of the identity.
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = h[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return false;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    out.clear();
    out.resize(n * n, 0.0);
    let mut y = vec![0.0; n];
    for c in 0..n {
        for i in 0..n {
            let mut s = if i == c { 1.0 } else { 0.0 };
            for k in 0..i {
                s -= l[i * n + k] * y[k];
            }
            y[i] = s / l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = y[i];
            for k in i + 1..n {
                s -= l[k * n + i] * out[k * n + c];
            }
            out[i * n + c] = s / l[i * n + i];
        }
    }
    true
}

/// The unconstrained optimum `H⁻¹ f` into `x`; `false` when `h` is not
/// positive definite.
pub fn unconstrained(h: &Mat, f: &[f64], ws: &mut Workspace, x: &mut Vec<f64>) -> bool {
    let n = f.len();
    if !spd_inverse(&h.data, n, &mut ws.hinv) {
        return false;
    }
    x.clear();
    x.extend((0..n).map(|i| (0..n).map(|k| ws.hinv[i * n + k] * f[k]).sum::<f64>()));
    true
}

/// Solves the QP of the module docs into `x`. `rows[k]` is `(aₖ, bₖ)`;
/// a row with `‖aₖ‖ ≈ 0` cannot be acted on and is skipped (reported as
/// violated when `bₖ < 0`). `tolerance` (m/s) is the violation beyond which
/// a row is reported in [`Solution::worst`].
///
/// Rows enter a working set only when the current solution violates them
/// (all violated rows at once, at most [`MAX_ROUNDS`] times): with a few
/// hundred pairs in reach only a handful bind, and the ascent then runs on
/// those alone. The optimum over the working set that violates no other
/// row is the optimum of the whole problem.
///
/// A non-positive-definite `h` (only a bug upstream) gives `x = 0`
/// clamped to the box.
#[allow(clippy::too_many_arguments)]
pub fn solve(
    h: &Mat,
    f: &[f64],
    rows: &[(&[f64], f64)],
    lo: &[f64],
    hi: &[f64],
    tolerance: f64,
    ws: &mut Workspace,
    x: &mut Vec<f64>,
) -> Solution {
    let n = f.len();
    x.clear();
    x.resize(n, 0.0);
    if !spd_inverse(&h.data, n, &mut ws.hinv) {
        for (xi, (l, u)) in x.iter_mut().zip(lo.iter().zip(hi)) {
            *xi = 0.0_f64.clamp(*l, *u);
        }
        return report(rows, x, tolerance, 0);
    }
    let mut set: Vec<usize> = Vec::new();
    let mut sub: Vec<(&[f64], f64)> = Vec::new();
    let mut sweeps = 0;
    ws.lambda.clear();
    ws.up.clear();
    ws.up.resize(n, 0.0);
    ws.down.clear();
    ws.down.resize(n, 0.0);
    for _ in 0..MAX_ROUNDS {
        sub.clear();
        sub.extend(set.iter().map(|&k| rows[k]));
        sweeps += hildreth(f, &sub, lo, hi, ws, x);
        if sweeps >= MAX_SWEEPS {
            break;
        }
        let before = set.len();
        for (k, (a, b)) in rows.iter().enumerate() {
            let ax: f64 = a.iter().zip(x.iter()).map(|(p, q)| p * q).sum();
            if ax - b > ENTER && !set.contains(&k) {
                set.push(k);
            }
        }
        if set.len() == before {
            break;
        }
    }
    for (xi, (l, u)) in x.iter_mut().zip(lo.iter().zip(hi)) {
        *xi = if xi.is_finite() {
            xi.clamp(*l, *u)
        } else {
            0.0_f64.clamp(*l, *u)
        };
    }
    report(rows, x, tolerance, sweeps)
}

/// Violation (m/s) beyond which a row enters the working set.
const ENTER: f64 = 1e-9;

/// Rounds of the working set at most.
pub const MAX_ROUNDS: usize = 12;

/// Hildreth's ascent over `rows` and the box (`ws.hinv` set), into `x`,
/// warm-started from the multipliers of the rows it had before (the
/// working set only grows: row k keeps its multiplier); returns the sweeps
/// used.
fn hildreth(
    f: &[f64],
    rows: &[(&[f64], f64)],
    lo: &[f64],
    hi: &[f64],
    ws: &mut Workspace,
    x: &mut [f64],
) -> usize {
    let n = f.len();
    let hinv = &ws.hinv;
    let m = rows.len();
    ws.u.clear();
    ws.u.resize(m * n, 0.0);
    ws.norms.clear();
    for (k, (a, _)) in rows.iter().enumerate() {
        let u = &mut ws.u[k * n..(k + 1) * n];
        for i in 0..n {
            u[i] = (0..n).map(|c| hinv[i * n + c] * a[c]).sum();
        }
        ws.norms
            .push(a.iter().zip(u.iter()).map(|(p, q)| p * q).sum());
    }
    ws.lambda.resize(m, 0.0);
    // x = H⁻¹ (f − Σ λₖ aₖ − Σ (upᵢ − downᵢ) eᵢ)
    for i in 0..n {
        let box_term: f64 = (0..n)
            .map(|c| hinv[i * n + c] * (ws.up[c] - ws.down[c]))
            .sum();
        let rows_term: f64 = (0..m).map(|k| ws.lambda[k] * ws.u[k * n + i]).sum();
        x[i] = (0..n).map(|k| hinv[i * n + k] * f[k]).sum::<f64>() - rows_term - box_term;
    }
    let mut sweeps = 0;
    while sweeps < MAX_SWEEPS {
        sweeps += 1;
        let mut change: f64 = 0.0;
        for (k, (a, b)) in rows.iter().enumerate() {
            let norm = ws.norms[k];
            if norm <= 1e-14 {
                continue;
            }
            let ax: f64 = a.iter().zip(x.iter()).map(|(p, q)| p * q).sum();
            let next = (ws.lambda[k] + (ax - b) / norm).max(0.0);
            let delta = next - ws.lambda[k];
            if delta != 0.0 {
                let u = &ws.u[k * n..(k + 1) * n];
                for (xi, ui) in x.iter_mut().zip(u) {
                    *xi -= ui * delta;
                }
                ws.lambda[k] = next;
                change = change.max((delta * norm).abs());
            }
        }
        for i in 0..n {
            let hii = hinv[i * n + i];
            // x_i ≤ hi_i (multiplier up[i]) and −x_i ≤ −lo_i (down[i]).
            let next = (ws.up[i] + (x[i] - hi[i]) / hii).max(0.0);
            let delta = next - ws.up[i];
            if delta != 0.0 {
                for (r, xr) in x.iter_mut().enumerate() {
                    *xr -= hinv[r * n + i] * delta;
                }
                ws.up[i] = next;
                change = change.max((delta * hii).abs());
            }
            let next = (ws.down[i] + (lo[i] - x[i]) / hii).max(0.0);
            let delta = next - ws.down[i];
            if delta != 0.0 {
                for (r, xr) in x.iter_mut().enumerate() {
                    *xr += hinv[r * n + i] * delta;
                }
                ws.down[i] = next;
                change = change.max((delta * hii).abs());
            }
        }
        if change < 1e-12 {
            break;
        }
    }
    sweeps
}

fn report(rows: &[(&[f64], f64)], x: &[f64], tolerance: f64, sweeps: usize) -> Solution {
    let mut out = Solution {
        sweeps,
        ..Solution::default()
    };
    for (k, (a, b)) in rows.iter().enumerate() {
        let v = a.iter().zip(x).map(|(p, q)| p * q).sum::<f64>() - b;
        if v > out.violation {
            out.violation = v;
            if v > tolerance {
                out.worst = Some(k);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat(n: usize, v: &[f64]) -> Mat {
        let mut m = Mat::zeros(n, n);
        m.data.copy_from_slice(v);
        m
    }

    #[test]
    fn unconstrained_is_the_newton_step_and_inverse_is_exact() {
        let h = mat(3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
        let mut inv = Vec::new();
        assert!(spd_inverse(&h.data, 3, &mut inv));
        for i in 0..3 {
            for j in 0..3 {
                let e: f64 = (0..3).map(|k| h.data[i * 3 + k] * inv[k * 3 + j]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((e - want).abs() < 1e-14, "{i} {j} {e}");
            }
        }
        let f = [1.0, -2.0, 0.5];
        let mut x = Vec::new();
        let mut ws = Workspace::default();
        let s = solve(&h, &f, &[], &[-9.0; 3], &[9.0; 3], 1e-9, &mut ws, &mut x);
        let hx = h.mul_vec(&x);
        for (a, b) in hx.iter().zip(&f) {
            assert!((a - b).abs() < 1e-12);
        }
        assert!(s.worst.is_none());
        assert!(!spd_inverse(&[1.0, 2.0, 2.0, 1.0], 2, &mut inv));
    }

    /// Against the closed form of one active row: `x = x* − H⁻¹a (aᵀx* − b)/(aᵀH⁻¹a)`.
    #[test]
    fn one_active_row_matches_the_closed_form_in_the_h_metric() {
        let h = mat(2, &[2.0, 0.5, 0.5, 1.0]);
        let f = [3.0, 1.0];
        let a = [1.0, 1.0];
        let b = 0.5;
        let mut x = Vec::new();
        let mut ws = Workspace::default();
        let s = solve(
            &h,
            &f,
            &[(&a, b)],
            &[-9.0; 2],
            &[9.0; 2],
            1e-9,
            &mut ws,
            &mut x,
        );
        let mut inv = Vec::new();
        spd_inverse(&h.data, 2, &mut inv);
        let star = [inv[0] * 3.0 + inv[1], inv[2] * 3.0 + inv[3]];
        let u = [inv[0] + inv[1], inv[2] + inv[3]];
        let t = (star[0] + star[1] - b) / (u[0] + u[1]);
        assert!((x[0] - (star[0] - u[0] * t)).abs() < 1e-10, "{x:?}");
        assert!((x[1] - (star[1] - u[1] * t)).abs() < 1e-10, "{x:?}");
        assert!(s.worst.is_none() && s.violation.abs() < 1e-10);
    }

    /// KKT on a random problem with box and rows active: stationarity with
    /// non-negative multipliers, recovered by a brute-force check that no
    /// feasible direction lowers the objective.
    #[test]
    fn solution_is_optimal_among_feasible_neighbours() {
        let h = mat(3, &[1.0, 0.2, 0.0, 0.2, 0.5, 0.1, 0.0, 0.1, 0.05]);
        let f = [2.0, -1.0, 0.3];
        let rows_a = [[1.0, 0.0, 1.0], [0.0, 1.0, -1.0]];
        let rows = [(&rows_a[0][..], 0.2), (&rows_a[1][..], -0.1)];
        let (lo, hi) = ([-1.0; 3], [1.0, 0.8, 1.0]);
        let mut x = Vec::new();
        let mut ws = Workspace::default();
        let s = solve(&h, &f, &rows, &lo, &hi, 1e-9, &mut ws, &mut x);
        assert!(s.worst.is_none(), "{s:?}");
        let obj = |y: &[f64]| {
            let hy = h.mul_vec(y);
            0.5 * y.iter().zip(&hy).map(|(a, b)| a * b).sum::<f64>()
                - y.iter().zip(&f).map(|(a, b)| a * b).sum::<f64>()
        };
        let feasible = |y: &[f64]| {
            rows.iter()
                .all(|(a, b)| a.iter().zip(y).map(|(p, q)| p * q).sum::<f64>() <= b + 1e-12)
                && y.iter()
                    .zip(lo.iter().zip(&hi))
                    .all(|(v, (l, u))| v >= l && v <= u)
        };
        assert!(feasible(&x));
        let best = obj(&x);
        let mut rng = crate::rng::Rng::new(7);
        for _ in 0..20_000 {
            let y: Vec<f64> = x.iter().map(|v| v + rng.range(-0.05, 0.05)).collect();
            if feasible(&y) {
                assert!(obj(&y) >= best - 1e-9, "{y:?} beats {x:?}");
            }
        }
    }

    #[test]
    fn infeasible_rows_are_reported() {
        let h = mat(2, &[1.0, 0.0, 0.0, 1.0]);
        let a = [1.0, 0.0];
        let mut x = Vec::new();
        let mut ws = Workspace::default();
        let s = solve(
            &h,
            &[0.0, 0.0],
            &[(&a, -3.0)],
            &[-2.0; 2],
            &[2.0; 2],
            1e-6,
            &mut ws,
            &mut x,
        );
        assert_eq!(s.worst, Some(0));
        assert!((s.violation - 1.0).abs() < 1e-6, "{s:?}");
    }
}
