//! Tests of the QP solver: closed forms, KKT conditions checked
//! independently of the solver, dependent and infeasible rows. Compiled
//! only under `cfg(test)` (`#[cfg(test)] mod tests;` in `mod.rs`), so the
//! `expect`s here stop a failing test and are unreachable from JavaScript.
use super::*;

fn mat(n: usize, v: &[f64]) -> Mat {
    let mut m = Mat::zeros(n, n);
    m.data.copy_from_slice(v);
    m
}

/// `H⁻¹ = J Jᵀ` from the solver's factor (`None` when `h` is not positive
/// definite).
fn inverse(h: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut ws = Workspace::default();
    factor(h, n, &mut ws).then(|| {
        (0..n * n)
            .map(|e| {
                (0..n)
                    .map(|k| ws.j[(e / n) * n + k] * ws.j[(e % n) * n + k])
                    .sum()
            })
            .collect()
    })
}

#[test]
fn unconstrained_is_the_newton_step_and_the_factor_is_exact() {
    let h = mat(3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
    let inv = inverse(&h.data, 3).expect("positive definite");
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
    let s = solve(
        &problem(&h, &f, &[], &[-9.0; 3], &[9.0; 3]),
        1e-9,
        &mut ws,
        &mut x,
    );
    let hx = h.mul_vec(&x);
    for (a, b) in hx.iter().zip(&f) {
        assert!((a - b).abs() < 1e-12);
    }
    assert!(s.worst.is_none());
    assert!(inverse(&[1.0, 2.0, 2.0, 1.0], 2).is_none());
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
        &problem(&h, &f, &[(&a, b)], &[-9.0; 2], &[9.0; 2]),
        1e-9,
        &mut ws,
        &mut x,
    );
    let inv = inverse(&h.data, 2).expect("positive definite");
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
    let s = solve(&problem(&h, &f, &rows, &lo, &hi), 1e-9, &mut ws, &mut x);
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
        &problem(&h, &[0.0, 0.0], &[(&a, -3.0)], &[-2.0; 2], &[2.0; 2]),
        1e-6,
        &mut ws,
        &mut x,
    );
    assert_eq!(s.worst, Some(0));
    assert!((s.violation - 1.0).abs() < 1e-6, "{s:?}");
}

/// Solves the square system `a y = b` (row-major) by elimination with
/// partial pivoting; `None` when singular.
fn solve_square(mut a: Vec<f64>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i * n + c].abs().total_cmp(&a[j * n + c].abs()))?;
        if a[p * n + c].abs() < 1e-12 {
            return None;
        }
        for k in 0..n {
            a.swap(c * n + k, p * n + k);
        }
        b.swap(c, p);
        for r in c + 1..n {
            let m = a[r * n + c] / a[c * n + c];
            for k in c..n {
                a[r * n + k] -= m * a[c * n + k];
            }
            b[r] -= m * b[c];
        }
    }
    let mut y = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r * n + k] * y[k]).sum();
        y[r] = (b[r] - s) / a[r * n + r];
    }
    Some(y)
}

/// The problem of `h`, `f`, `rows` and the box `lo..hi`.
fn problem<'a>(
    h: &'a Mat,
    f: &'a [f64],
    rows: &'a [(&'a [f64], f64)],
    lo: &'a [f64],
    hi: &'a [f64],
) -> Problem<'a> {
    Problem { h, f, rows, lo, hi }
}

/// The KKT conditions, checked independently of the solver: the
/// constraints active at `x` (slack under 1e-9) get multipliers by least
/// squares on `H x − f + Σ λₖ aₖ = 0`; the residual must vanish and
/// every multiplier be non-negative.
fn assert_kkt(h: &Mat, f: &[f64], rows: &[(Vec<f64>, f64)], lo: &[f64], hi: &[f64], x: &[f64]) {
    let n = f.len();
    let mut normals: Vec<Vec<f64>> = Vec::new();
    for (a, b) in rows {
        let ax: f64 = a.iter().zip(x).map(|(p, q)| p * q).sum();
        assert!(ax <= b + 1e-9, "row violated by {}", ax - b);
        if ax > b - 1e-9 {
            normals.push(a.clone());
        }
    }
    for i in 0..n {
        assert!(x[i] >= lo[i] - 1e-12 && x[i] <= hi[i] + 1e-12);
        let mut e = vec![0.0; n];
        if x[i] > hi[i] - 1e-9 {
            e[i] = 1.0;
            normals.push(e);
        } else if x[i] < lo[i] + 1e-9 {
            e[i] = -1.0;
            normals.push(e);
        }
    }
    let g: Vec<f64> = h.mul_vec(x).iter().zip(f).map(|(hx, fi)| fi - hx).collect();
    let k = normals.len();
    let lambda = if k == 0 {
        Vec::new()
    } else {
        let gram = (0..k * k)
            .map(|e| {
                normals[e / k]
                    .iter()
                    .zip(&normals[e % k])
                    .map(|(p, q)| p * q)
                    .sum()
            })
            .collect();
        let rhs = normals
            .iter()
            .map(|a| a.iter().zip(&g).map(|(p, q)| p * q).sum())
            .collect();
        solve_square(gram, rhs).expect("independent active normals")
    };
    for i in 0..n {
        let r = g[i] - (0..k).map(|j| lambda[j] * normals[j][i]).sum::<f64>();
        assert!(r.abs() < 1e-8, "stationarity residual {r} at {i}");
    }
    assert!(
        lambda.iter().all(|l| *l > -1e-8),
        "negative multiplier {lambda:?}"
    );
}

/// Random problems shaped like the avoidance's: `H = JᵀJ + 10⁻⁴ I` with
/// a task of rank 3 on up to 8 joints (the ill conditioning that stalled
/// coordinate ascent), up to 12 rows and the box, `x = 0` feasible.
/// Every solution meets the KKT conditions to 1e-8.
#[test]
fn random_ill_conditioned_problems_meet_the_kkt_conditions() {
    let mut rng = crate::rng::Rng::new(3);
    let mut active_total = 0;
    for trial in 0..400 {
        let n = 3 + trial % 6;
        let jac: Vec<f64> = (0..3 * n).map(|_| rng.range(-1.0, 1.0)).collect();
        let mut h = Mat::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                h.data[i * n + j] = (0..3).map(|r| jac[r * n + i] * jac[r * n + j]).sum();
            }
            h.data[i * n + i] += 1e-4;
        }
        let f: Vec<f64> = (0..n).map(|_| rng.range(-2.0, 2.0)).collect();
        let m = trial % 13;
        let rows: Vec<(Vec<f64>, f64)> = (0..m)
            .map(|_| {
                (
                    (0..n).map(|_| rng.range(-1.0, 1.0)).collect(),
                    rng.range(0.0, 0.5),
                )
            })
            .collect();
        let lo: Vec<f64> = (0..n).map(|_| rng.range(-1.5, -0.2)).collect();
        let hi: Vec<f64> = (0..n).map(|_| rng.range(0.2, 1.5)).collect();
        let view: Vec<(&[f64], f64)> = rows.iter().map(|(a, b)| (a.as_slice(), *b)).collect();
        let mut x = Vec::new();
        let mut ws = Workspace::default();
        let s = solve(&problem(&h, &f, &view, &lo, &hi), 1e-9, &mut ws, &mut x);
        assert!(s.worst.is_none(), "trial {trial}: {s:?}");
        assert_kkt(&h, &f, &rows, &lo, &hi, &x);
        active_total += ws.active.len();
    }
    // The problems bind: on average more than two constraints active.
    assert!(
        active_total > 800,
        "{active_total} active constraints in all"
    );
}

/// Duplicated and dependent rows (two pairs on one segment, a row equal
/// to a box bound) are handled: the solution is still optimal.
#[test]
fn dependent_rows_are_handled() {
    let h = mat(3, &[1.0, 0.2, 0.0, 0.2, 0.5, 0.1, 0.0, 0.1, 0.05]);
    let f = [2.0, -1.0, 0.3];
    let rows = [
        (vec![1.0, 0.0, 1.0], 0.2),
        (vec![1.0, 0.0, 1.0], 0.2),
        (vec![2.0, 0.0, 2.0], 0.4),
        (vec![1.0, 0.0, 0.0], 0.5),
        (vec![0.0, 0.0, 0.0], 1.0),
    ];
    let view: Vec<(&[f64], f64)> = rows.iter().map(|(a, b)| (a.as_slice(), *b)).collect();
    let (lo, hi) = ([-1.0; 3], [0.5, 0.8, 1.0]);
    let mut x = Vec::new();
    let mut ws = Workspace::default();
    let s = solve(&problem(&h, &f, &view, &lo, &hi), 1e-9, &mut ws, &mut x);
    assert!(s.worst.is_none(), "{s:?}");
    let independent = [rows[0].clone(), rows[3].clone()];
    assert_kkt(&h, &f, &independent, &lo, &[f64::INFINITY, 0.8, 1.0], &x);
}
