//! Small dense linear algebra: the matrix type of the Jacobians, a symmetric
//! eigen-decomposition, the Cholesky factor, and the weighted damped least-squares pseudoinverse
//! that inverse kinematics and the avoidance controllers share.
//!
//! The pseudoinverse is `J_W^† = W⁻¹ Jᵀ (J W⁻¹ Jᵀ + Σ λ_i² u_i u_iᵀ)⁻¹` with
//! joint weights `W` (a larger weight moves a joint less), where `u_i` are the
//! left singular vectors of `J W^{-1/2}`. Each direction is damped only when
//! its singular value σ_i drops below `epsilon`,
//! `λ_i² = (1 − (σ_i/ε)²) λ_max²` (numerical filtering, Chiaverini 1997), so
//! the solution is exact where the arm is well conditioned, bounded at a
//! stretched arm, and unaffected by directions that are singular by design
//! (the z row of a planar arm's Jacobian). With `λ_max = ε` (the default) the
//! gain of the inverse never exceeds `1/ε`.
//!
//! This module depends on nothing else in the crate.

// Dense linear algebra on small matrices reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use glam::DVec3;

/// A small dense row-major matrix (Jacobians are 3 × n or 6 × n).
#[derive(Clone, Debug, PartialEq)]
pub struct Mat {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Row-major entries.
    pub data: Vec<f64>,
}

impl Mat {
    /// A zero matrix.
    #[must_use]
    pub fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            data: vec![0.0; rows * cols],
        }
    }

    /// The identity.
    #[must_use]
    pub fn identity(n: usize) -> Self {
        let mut m = Self::zeros(n, n);
        for i in 0..n {
            m.data[i * n + i] = 1.0;
        }
        m
    }

    /// A 3 × n matrix from n column vectors.
    #[must_use]
    pub fn from_columns3(cols: &[DVec3]) -> Self {
        let n = cols.len();
        let mut m = Self::zeros(3, n);
        for (k, c) in cols.iter().enumerate() {
            m.data[k] = c.x;
            m.data[n + k] = c.y;
            m.data[2 * n + k] = c.z;
        }
        m
    }

    /// Entry `(r, c)`.
    #[must_use]
    pub fn get(&self, r: usize, c: usize) -> f64 {
        self.data[r * self.cols + c]
    }

    /// Sets entry `(r, c)`.
    pub fn set(&mut self, r: usize, c: usize, v: f64) {
        self.data[r * self.cols + c] = v;
    }

    /// `self · x`.
    #[must_use]
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        (0..self.rows)
            .map(|r| {
                self.data[r * self.cols..(r + 1) * self.cols]
                    .iter()
                    .zip(x)
                    .map(|(a, b)| a * b)
                    .sum()
            })
            .collect()
    }

    /// `self · other`.
    #[must_use]
    pub fn mul(&self, other: &Self) -> Self {
        let mut out = Self::zeros(self.rows, other.cols);
        for r in 0..self.rows {
            for k in 0..self.cols {
                let a = self.get(r, k);
                if a == 0.0 {
                    continue;
                }
                for c in 0..other.cols {
                    out.data[r * other.cols + c] += a * other.get(k, c);
                }
            }
        }
        out
    }

    /// Rows as nested vectors (the JS layout).
    #[must_use]
    pub fn to_rows(&self) -> Vec<Vec<f64>> {
        self.data
            .chunks(self.cols.max(1))
            .map(<[f64]>::to_vec)
            .collect()
    }
}

/// Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations:
/// returns the eigenvalues and the eigenvectors as the columns of a matrix.
#[must_use]
pub fn symmetric_eigen(a: &Mat) -> (Vec<f64>, Mat) {
    let n = a.rows;
    let mut m = a.clone();
    let mut v = Mat::identity(n);
    for _sweep in 0..50 {
        let mut off = 0.0;
        for p in 0..n {
            for q in p + 1..n {
                off += m.get(p, q) * m.get(p, q);
            }
        }
        if off < 1e-30 {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = m.get(p, q);
                if apq.abs() < 1e-300 {
                    continue;
                }
                let theta = (m.get(q, q) - m.get(p, p)) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let mkp = m.get(k, p);
                    let mkq = m.get(k, q);
                    m.set(k, p, c * mkp - s * mkq);
                    m.set(k, q, s * mkp + c * mkq);
                }
                for k in 0..n {
                    let mpk = m.get(p, k);
                    let mqk = m.get(q, k);
                    m.set(p, k, c * mpk - s * mqk);
                    m.set(q, k, s * mpk + c * mqk);
                }
                for k in 0..n {
                    let vkp = v.get(k, p);
                    let vkq = v.get(k, q);
                    v.set(k, p, c * vkp - s * vkq);
                    v.set(k, q, s * vkp + c * vkq);
                }
            }
        }
    }
    ((0..n).map(|i| m.get(i, i)).collect(), v)
}

/// The joint weights and the damping of one weighted damped least-squares
/// inverse ([`dls_inverse`]), as the CLIK schemes take them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DlsSettings<'a> {
    /// Joint weights (`n` positive values; empty for unit weights).
    pub weights: &'a [f64],
    /// Damping near singularities.
    pub damping: Damping,
}

/// Parameters of the damped least-squares inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Damping {
    /// Singular value below which damping starts (same unit as `J`).
    pub epsilon: f64,
    /// Damping factor reached at an exact singularity.
    pub lambda_max: f64,
}

impl Default for Damping {
    fn default() -> Self {
        Self {
            epsilon: 0.04,
            lambda_max: 0.04,
        }
    }
}

/// A damped least-squares inverse `J_W^†` (n × m) with the conditioning it
/// was computed at.
#[derive(Clone, Debug, PartialEq)]
pub struct DlsInverse {
    /// The pseudoinverse, n × m.
    pub inverse: Mat,
    /// Smallest singular value of `J W^{-1/2}`.
    pub sigma_min: f64,
    /// Damping factor applied in the direction of the smallest singular value.
    pub lambda: f64,
}

/// The lower Cholesky factor `L` of the symmetric `n × n` row-major matrix
/// `a = L Lᵀ`, into `l` (row-major, zero above the diagonal). Returns
/// `false` when a pivot is not finite or not above `floor` (`a` is not
/// positive definite, or too close to singular for the caller): `l` is
/// then incomplete.
pub fn cholesky_into(a: &[f64], n: usize, floor: f64, l: &mut Vec<f64>) -> bool {
    l.clear();
    l.resize(n * n, 0.0);
    for i in 0..n {
        for j in 0..=i {
            let s = a[i * n + j] - (0..j).map(|k| l[i * n + k] * l[j * n + k]).sum::<f64>();
            if i == j {
                if !(s > floor && s.is_finite()) {
                    return false;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    true
}

/// The weighted damped least-squares inverse of `jac` (m × n) with joint
/// weights `weights` (n positive values; empty for unit weights).
#[must_use]
pub fn dls_inverse(jac: &Mat, weights: &[f64], damping: Damping) -> DlsInverse {
    let (m, n) = (jac.rows, jac.cols);
    let winv: Vec<f64> = (0..n)
        .map(|k| weights.get(k).map_or(1.0, |w| 1.0 / w))
        .collect();
    // A = J W⁻¹ Jᵀ
    let mut a = Mat::zeros(m, m);
    for r in 0..m {
        for c in r..m {
            let mut s = 0.0;
            for k in 0..n {
                s += jac.get(r, k) * winv[k] * jac.get(c, k);
            }
            a.set(r, c, s);
            a.set(c, r, s);
        }
    }
    let (eig, u) = symmetric_eigen(&a);
    let damp = |e: f64| {
        let sigma = e.max(0.0).sqrt();
        if sigma >= damping.epsilon {
            0.0
        } else {
            let ratio = sigma / damping.epsilon;
            (1.0 - ratio * ratio) * damping.lambda_max * damping.lambda_max
        }
    };
    let smallest = eig.iter().copied().fold(f64::INFINITY, f64::min).max(0.0);
    // (A + Σ λ_i² u_i u_iᵀ)⁻¹ = U diag(1 / (e_i + λ_i²)) Uᵀ: only the
    // directions whose singular value is below ε are damped. Directions with
    // e = 0 and no damping (only when ε = 0) are dropped.
    let mut ainv = Mat::zeros(m, m);
    for (i, e) in eig.iter().enumerate() {
        let den = e.max(0.0) + damp(*e);
        if den <= 1e-300 {
            continue;
        }
        for r in 0..m {
            for c in 0..m {
                let v = ainv.get(r, c) + u.get(r, i) * u.get(c, i) / den;
                ainv.set(r, c, v);
            }
        }
    }
    // W⁻¹ Jᵀ A⁻¹
    let mut inv = Mat::zeros(n, m);
    for k in 0..n {
        for c in 0..m {
            let mut s = 0.0;
            for r in 0..m {
                s += jac.get(r, k) * ainv.get(r, c);
            }
            inv.set(k, c, winv[k] * s);
        }
    }
    DlsInverse {
        inverse: inv,
        sigma_min: smallest.sqrt(),
        lambda: damp(smallest).sqrt(),
    }
}
