//! A small dense convex QP: the joint velocity that best serves the tasks
//! under one-sided constraints.
//!
//! `minimise ½ xᵀ H x − fᵀ x  subject to  aₖᵀ x ≤ bₖ,  lo ≤ x ≤ hi`
//!
//! with `H` symmetric positive definite (`n × n`, `n` the number of joints:
//! 3 to 14 here) and a few dozen rows at most.
//!
//! **Method: the dual active-set method of Goldfarb & Idnani (1983)**, the
//! method of `quadprog`, which reactive controllers such as NEO call by
//! default. It starts at the unconstrained optimum `H⁻¹f` and adds the most
//! violated constraint at a time, each step keeping the active constraints
//! exact and their multipliers non-negative (a constraint whose multiplier
//! would turn negative leaves the set). The factors are `J = L⁻ᵀ Q` and the
//! triangular `R` of `L⁻¹ N = Q R` (`H = L Lᵀ`, `N` the active normals),
//! updated by Givens rotations as constraints come and go, so a step costs
//! `O(n²)`. It ends in finitely many steps, exactly (to rounding) at the
//! optimum, or with a proof of infeasibility: a violated constraint that no
//! step of the primal or the dual can satisfy.
//!
//! Why not a first-order method: the task Hessian `JᵀJ + μW` has the
//! eigenvalue `μ = 10⁻⁴` in the task's null space, so coordinate ascent on
//! the dual (Hildreth's method, used here before) took its cap of 200
//! sweeps on most steps of an arm at its velocity limits and then reported
//! feasible problems as violated. The active-set method is insensitive to
//! that conditioning and measured at a few microseconds per solve.
//!
//! Rows with `‖aₖ‖ ≈ 0` cannot be acted on and are skipped (and reported as
//! violated when `bₖ < 0`); on an infeasible problem the solver returns the
//! last iterate clamped to the box, and [`Solution::worst`] names the row
//! violated most, which the caller reports.

use crate::linalg::{Mat, cholesky_into};

pub mod assemble;

/// Active-set steps at most per solve, beyond `3 (m + 2n)`: a guard against
/// cycling on degenerate problems (never reached in the tests and
/// benchmarks).
pub const MAX_STEPS: usize = 50;

/// Outcome of [`solve`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Solution {
    /// Largest violation `aₖᵀ x − bₖ` over the rows (m/s; ≤ 0 when all hold).
    pub violation: f64,
    /// The row with the largest violation, when it exceeds `tolerance`.
    pub worst: Option<usize>,
    /// Active-set steps used (a constraint added or dropped).
    pub steps: usize,
}

/// Scratch space reused from step to step (no allocation in steady state).
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    /// The Cholesky factor `L` of `H`.
    l: Vec<f64>,
    /// `J = L⁻ᵀ Q`, row-major `n × n`.
    j: Vec<f64>,
    /// `R`, upper triangular, row-major `n × n` (the first `q` columns used).
    r: Vec<f64>,
    d: Vec<f64>,
    z: Vec<f64>,
    dual: Vec<f64>,
    /// Multipliers of the active constraints (and of the candidate, last).
    u: Vec<f64>,
    /// Active constraints (see [`Constraints`]).
    active: Vec<usize>,
    /// Per constraint: active, or a row that cannot be acted on (not a
    /// candidate either way).
    skip: Vec<bool>,
}

/// One constraint `nᵀx ≥ c` of the solver: index `k < m` is the row
/// `aₖᵀx ≤ bₖ` (`n = −aₖ`), `m + i` the bound `xᵢ ≤ hiᵢ`, `m + n + i` the
/// bound `xᵢ ≥ loᵢ`.
struct Constraints<'a> {
    rows: &'a [(&'a [f64], f64)],
    lo: &'a [f64],
    hi: &'a [f64],
}

impl Constraints<'_> {
    fn count(&self) -> usize {
        self.rows.len() + 2 * self.lo.len()
    }

    /// `nₖᵀ v` for `v` read through `at` (`v[i] = at(i)`).
    fn normal_dot(&self, k: usize, at: impl Fn(usize) -> f64) -> f64 {
        let (m, n) = (self.rows.len(), self.lo.len());
        if k < m {
            -self.rows[k]
                .0
                .iter()
                .enumerate()
                .map(|(i, a)| a * at(i))
                .sum::<f64>()
        } else if k < m + n {
            -at(k - m)
        } else {
            at(k - m - n)
        }
    }

    /// The slack `nₖᵀx − cₖ` (negative when violated).
    fn slack(&self, k: usize, x: &[f64]) -> f64 {
        let (m, n) = (self.rows.len(), self.lo.len());
        let c = if k < m {
            -self.rows[k].1
        } else if k < m + n {
            -self.hi[k - m]
        } else {
            self.lo[k - m - n]
        };
        self.normal_dot(k, |i| x[i]) - c
    }

    /// Whether constraint `k` can be acted on (a row of zeros cannot).
    fn usable(&self, k: usize) -> bool {
        k >= self.rows.len() || self.rows[k].0.iter().any(|a| a.abs() > 1e-12)
    }

    /// The most violated constraint not in `skip` (slack below
    /// [`VIOLATED`]), read row by row, then the box.
    fn most_violated(&self, skip: &[bool], x: &[f64]) -> Option<usize> {
        let mut best = None;
        let mut lowest = VIOLATED;
        let mut consider = |k: usize, s: f64| {
            if s < lowest && !skip[k] {
                lowest = s;
                best = Some(k);
            }
        };
        for (k, (a, b)) in self.rows.iter().enumerate() {
            let ax: f64 = a.iter().zip(x).map(|(p, q)| p * q).sum();
            consider(k, b - ax);
        }
        let (m, n) = (self.rows.len(), x.len());
        for (i, xi) in x.iter().enumerate() {
            consider(m + i, self.hi[i] - xi);
            consider(m + n + i, xi - self.lo[i]);
        }
        best
    }
}

/// `J = L⁻ᵀ` of `h = L Lᵀ` into `ws.j`; `false` when `h` is not positive
/// definite.
fn factor(h: &[f64], n: usize, ws: &mut Workspace) -> bool {
    if !cholesky_into(h, n, 0.0, &mut ws.l) {
        return false;
    }
    let l = &ws.l;
    // Column c of L⁻¹ by forward substitution; J = (L⁻¹)ᵀ, so it is row c of J.
    ws.j.clear();
    ws.j.resize(n * n, 0.0);
    for c in 0..n {
        for i in c..n {
            let e = if i == c { 1.0 } else { 0.0 };
            let s = e - (c..i).map(|k| l[i * n + k] * ws.j[c * n + k]).sum::<f64>();
            ws.j[c * n + i] = s / l[i * n + i];
        }
    }
    true
}

/// Rotates columns `a` and `b` of the row-major `n`-column matrix `m` by
/// `(c, s)`: `col_a ← c col_a + s col_b`, `col_b ← −s col_a + c col_b`.
fn rotate_columns(m: &mut [f64], n: usize, a: usize, b: usize, c: f64, s: f64) {
    for row in m.chunks_exact_mut(n) {
        let (x, y) = (row[a], row[b]);
        row[a] = c * x + s * y;
        row[b] = -s * x + c * y;
    }
}

/// One problem of the module docs: `minimise ½ xᵀ H x − fᵀ x` subject to
/// `aₖᵀ x ≤ bₖ` for every `(aₖ, bₖ)` in `rows` and `lo ≤ x ≤ hi`.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a> {
    /// `H`, symmetric positive definite (`n × n`).
    pub h: &'a Mat,
    /// `f` (`n` values).
    pub f: &'a [f64],
    /// The rows `(aₖ, bₖ)`.
    pub rows: &'a [(&'a [f64], f64)],
    /// Lower bounds of `x`.
    pub lo: &'a [f64],
    /// Upper bounds of `x`.
    pub hi: &'a [f64],
}

/// Solves `problem` into `x`; `tolerance` (m/s) is the violation beyond
/// which a row is reported in [`Solution::worst`].
///
/// A non-positive-definite `h` (only a bug upstream) gives `x = 0`
/// clamped to the box.
pub fn solve(problem: &Problem, tolerance: f64, ws: &mut Workspace, x: &mut Vec<f64>) -> Solution {
    let Problem { h, f, rows, lo, hi } = *problem;
    let n = f.len();
    x.clear();
    x.resize(n, 0.0);
    let cons = Constraints { rows, lo, hi };
    let mut steps = 0;
    if factor(&h.data, n, ws) {
        // The unconstrained optimum H⁻¹f = J Jᵀ f.
        ws.d.clear();
        ws.d.extend((0..n).map(|c| (0..n).map(|r| ws.j[r * n + c] * f[r]).sum::<f64>()));
        for (i, xi) in x.iter_mut().enumerate() {
            *xi = (0..n).map(|c| ws.j[i * n + c] * ws.d[c]).sum();
        }
        steps = active_set(&cons, ws, x);
    }
    for (xi, (l, u)) in x.iter_mut().zip(lo.iter().zip(hi)) {
        *xi = if xi.is_finite() {
            xi.clamp(*l, *u)
        } else {
            0.0_f64.clamp(*l, *u)
        };
    }
    report(rows, x, tolerance, steps)
}

/// Slack below which a constraint counts as violated.
const VIOLATED: f64 = -1e-12;

/// Goldfarb–Idnani from the unconstrained optimum in `x` (`ws.j` set);
/// returns the steps used. Stops at the optimum, at a proof of
/// infeasibility, or after the step cap, leaving the last iterate in `x`.
fn active_set(cons: &Constraints, ws: &mut Workspace, x: &mut [f64]) -> usize {
    let n = x.len();
    ws.r.clear();
    ws.r.resize(n * n, 0.0);
    for v in [&mut ws.d, &mut ws.z, &mut ws.dual] {
        v.clear();
        v.resize(n, 0.0);
    }
    ws.u.clear();
    ws.active.clear();
    ws.skip.clear();
    ws.skip.extend((0..cons.count()).map(|k| !cons.usable(k)));
    let cap = MAX_STEPS + 3 * cons.count();
    let mut steps = 0;
    loop {
        let Some(p) = cons.most_violated(&ws.skip, x) else {
            return steps;
        };
        ws.u.push(0.0);
        loop {
            steps += 1;
            if steps > cap {
                return steps;
            }
            match step_towards(cons, p, ws, x) {
                Step::Added => break,
                Step::Dropped => {}
                Step::Infeasible => return steps,
            }
        }
    }
}

enum Step {
    Added,
    Dropped,
    Infeasible,
}

/// One step of the method towards satisfying constraint `p` (its
/// multiplier last in `ws.u`): the largest step along the primal direction
/// `z` and the dual direction `r` that keeps the active multipliers
/// non-negative; either `p` is satisfied (and joins the set), or an active
/// constraint's multiplier reaches zero (and it leaves the set).
fn step_towards(cons: &Constraints, p: usize, ws: &mut Workspace, x: &mut [f64]) -> Step {
    let n = x.len();
    let q = ws.active.len();
    // d = Jᵀ n_p, z = J₂ d₂, r = R⁻¹ d₁.
    for c in 0..n {
        ws.d[c] = cons.normal_dot(p, |r| ws.j[r * n + c]);
    }
    for i in 0..n {
        ws.z[i] = (q..n).map(|c| ws.j[i * n + c] * ws.d[c]).sum();
    }
    for i in (0..q).rev() {
        let s = ws.d[i]
            - (i + 1..q)
                .map(|k| ws.r[i * n + k] * ws.dual[k])
                .sum::<f64>();
        ws.dual[i] = s / ws.r[i * n + i];
    }
    // Partial step: the first active multiplier to reach zero.
    let mut t1 = f64::INFINITY;
    let mut leaving = None;
    for k in 0..q {
        if ws.dual[k] > 0.0 {
            let t = ws.u[k] / ws.dual[k];
            if t < t1 {
                t1 = t;
                leaving = Some(k);
            }
        }
    }
    // Full step: p satisfied exactly (zᵀn_p = ‖d₂‖²).
    let dd: f64 = ws.d.iter().map(|v| v * v).sum();
    let zz: f64 = ws.d[q..].iter().map(|v| v * v).sum();
    let t2 = if zz > 1e-20 * dd {
        -cons.slack(p, x) / zz
    } else {
        f64::INFINITY
    };
    let t = t1.min(t2);
    if !t.is_finite() {
        return Step::Infeasible;
    }
    for k in 0..q {
        ws.u[k] -= t * ws.dual[k];
    }
    ws.u[q] += t;
    if t2.is_finite() {
        for (xi, zi) in x.iter_mut().zip(&ws.z) {
            *xi += t * zi;
        }
    }
    if t2 <= t1 {
        add(p, ws, n);
        Step::Added
    } else {
        drop_active(leaving.unwrap_or(0), ws, n);
        Step::Dropped
    }
}

/// Adds `p` (with `ws.d = Jᵀ n_p`) to the active set: rotations zero
/// `d[q+1..]` into `d[q]`, the same rotations turn `J`, and `d[..=q]`
/// becomes column `q` of `R`.
fn add(p: usize, ws: &mut Workspace, n: usize) {
    let q = ws.active.len();
    for j in (q + 1..n).rev() {
        let (a, b) = (ws.d[j - 1], ws.d[j]);
        if b == 0.0 {
            continue;
        }
        let h = (a * a + b * b).sqrt();
        let (c, s) = (a / h, b / h);
        ws.d[j - 1] = h;
        ws.d[j] = 0.0;
        rotate_columns(&mut ws.j, n, j - 1, j, c, s);
    }
    for i in 0..=q {
        ws.r[i * n + q] = ws.d[i];
    }
    ws.active.push(p);
    ws.skip[p] = true;
}

/// Removes the active constraint at position `k`: its column leaves `R`,
/// and rotations of the rows of `R` (and the columns of `J`) restore the
/// triangle.
fn drop_active(k: usize, ws: &mut Workspace, n: usize) {
    let q = ws.active.len();
    let leaving = ws.active.remove(k);
    ws.skip[leaving] = false;
    ws.u.remove(k);
    for c in k..q - 1 {
        for i in 0..q {
            ws.r[i * n + c] = ws.r[i * n + c + 1];
        }
    }
    for i in 0..q {
        ws.r[i * n + q - 1] = 0.0;
    }
    for j in k..q - 1 {
        let (a, b) = (ws.r[j * n + j], ws.r[(j + 1) * n + j]);
        if b == 0.0 {
            continue;
        }
        let h = (a * a + b * b).sqrt();
        let (c, s) = (a / h, b / h);
        for col in j..q - 1 {
            let (top, bottom) = (ws.r[j * n + col], ws.r[(j + 1) * n + col]);
            ws.r[j * n + col] = c * top + s * bottom;
            ws.r[(j + 1) * n + col] = -s * top + c * bottom;
        }
        rotate_columns(&mut ws.j, n, j, j + 1, c, s);
    }
}

fn report(rows: &[(&[f64], f64)], x: &[f64], tolerance: f64, steps: usize) -> Solution {
    let mut out = Solution {
        steps,
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
mod tests;
