//! The assembler: the tasks' rows and the limits' inequalities stacked
//! into one problem of [`super::solve`] (the `constraints` avoidance,
//! [`crate::avoidance::constraints`]).
//!
//! The task rows `J q̇ ≈ v` ([`crate::avoidance::rows::Task`]) become the
//! objective `½ q̇ᵀ (JᵀJ + μW) q̇ − (Jᵀv)ᵀ q̇`; the limits
//! ([`crate::avoidance::rows::Limit`]) are stacked in the order given
//! into rows and the box. When that problem cannot be met, the soft
//! limits are dropped and the hard ones solved alone
//! ([`Outcome::relaxed`]).

use super::{Problem, Solution, Workspace, solve};
use crate::avoidance::ControllerConfig;
use crate::avoidance::rows::{Inequalities, Limit, LimitContext, TaskRows};
use crate::linalg::{Mat, cholesky_into};

/// Everything one solve stacks.
#[derive(Clone, Copy)]
pub struct Stack<'a> {
    /// The tasks' rows, stacked.
    pub tasks: &'a TaskRows,
    /// The limits, in stacking order.
    pub limits: &'a [&'a dyn Limit],
    /// What the limits are computed from.
    pub context: LimitContext<'a>,
    /// The controller (joint weights, damping).
    pub config: &'a ControllerConfig,
}

impl std::fmt::Debug for Stack<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stack")
            .field("tasks", &self.tasks.rhs.len())
            .field("limits", &self.limits.len())
            .finish_non_exhaustive()
    }
}

/// The joint velocity that best serves the stack's tasks under its limits,
/// into `out`: every limit first, the hard ones alone when that fails.
pub fn solve_stacked(stack: &Stack, ws: &mut Workspace, out: &mut Vec<f64>) -> Outcome {
    let (h, f) = objective(&stack.tasks.jac, &stack.tasks.rhs, stack.config);
    let mut solve_with = |keep: &dyn Fn(&dyn Limit) -> bool| {
        let rows = Inequalities::stack(stack.limits, &stack.context, keep);
        let problem = Problem {
            h: &h,
            f: &f,
            rows: &rows.rows,
            lo: &rows.lo,
            hi: &rows.hi,
        };
        solve(&problem, INFEASIBLE_TOLERANCE, ws, out)
    };
    let solution = solve_with(&|_| true);
    if solution.worst.is_none() {
        return Outcome {
            relaxed: false,
            solution,
        };
    }
    let solution = solve_with(&|l| !l.soft());
    Outcome {
        relaxed: true,
        solution,
    }
}

/// Violation of a protective bound (m/s) beyond which the arm is judged
/// unable to keep a pair safe: far above the solver's accuracy, far below
/// any speed that matters.
pub const INFEASIBLE_TOLERANCE: f64 = 1e-3;

/// `μ`, the weight of `q̇ᵀ W q̇` against the task (s²·m²/rad²): small
/// enough that a task away from singularities is tracked to within 0.1 %,
/// large enough to keep `H` well conditioned for the solver at a
/// singularity.
pub const REGULARISATION: f64 = 1e-4;

/// What [`solve_stacked`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outcome {
    /// Whether the soft limits had to be dropped (the dampers: dampers,
    /// protective bounds and the box could not all be met).
    pub relaxed: bool,
    /// The last solve.
    pub solution: Solution,
}

/// The Hessian `JᵀJ + μW` and the linear term `Jᵀv` of the tasks.
fn objective(jac: &Mat, rhs: &[f64], config: &ControllerConfig) -> (Mat, Vec<f64>) {
    let n = jac.cols;
    let mut h = Mat::zeros(n, n);
    let mut f = vec![0.0; n];
    for (row, target) in jac.data.chunks_exact(n).zip(rhs) {
        for i in 0..n {
            if row[i] == 0.0 {
                continue;
            }
            f[i] += row[i] * target;
            for j in 0..n {
                h.data[i * n + j] += row[i] * row[j];
            }
        }
    }
    let mu = REGULARISATION + singular_damping(jac, config);
    let weights = config.joint_weights.as_deref().unwrap_or(&[]);
    for i in 0..n {
        h.data[i * n + i] += mu * weights.get(i).copied().unwrap_or(1.0);
    }
    (h, f)
}

/// The damping of a singularity, `λ²`: zero while the task Jacobian's
/// smallest singular value `σ` is above `damping.epsilon`, rising to
/// `damping.lambdaMax²` as `σ → 0` (`λ² = (1 − σ²/ε²) λ_max²`, the
/// variable damping of the paper's DLS inverse). `σ²` is the smallest
/// eigenvalue of `J Jᵀ` (one row per task row: at most 6 per chain), found
/// by inverse iteration on its Cholesky factor.
fn singular_damping(jac: &Mat, config: &ControllerConfig) -> f64 {
    let (m, n) = (jac.rows, jac.cols);
    let eps = config.damping.epsilon;
    if m == 0 || eps <= 0.0 {
        return 0.0;
    }
    // G = J Jᵀ with the rows a task leaves at zero (a planar arm's z)
    // given a unit diagonal, so that they do not count as singular.
    let mut g = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..=i {
            let v: f64 = (0..n).map(|c| jac.get(i, c) * jac.get(j, c)).sum();
            g[i * m + j] = v;
            g[j * m + i] = v;
        }
        if g[i * m + i] < 1e-18 {
            g[i * m + i] = 1.0;
        }
    }
    let mut l = Vec::new();
    if !cholesky_into(&g, m, 1e-30, &mut l) {
        return config.damping.lambda_max.powi(2);
    }
    let mut x = vec![1.0; m];
    let mut largest = 0.0;
    for _ in 0..12 {
        // y = G⁻¹ x by the two triangular solves.
        for i in 0..m {
            let s: f64 = x[i] - (0..i).map(|k| l[i * m + k] * x[k]).sum::<f64>();
            x[i] = s / l[i * m + i];
        }
        for i in (0..m).rev() {
            let s: f64 = x[i] - (i + 1..m).map(|k| l[k * m + i] * x[k]).sum::<f64>();
            x[i] = s / l[i * m + i];
        }
        let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return config.damping.lambda_max.powi(2);
        }
        largest = norm;
        x.iter_mut().for_each(|v| *v /= norm);
    }
    let sigma2 = 1.0 / largest;
    if sigma2 >= eps * eps {
        0.0
    } else {
        (1.0 - sigma2 / (eps * eps)) * config.damping.lambda_max.powi(2)
    }
}
