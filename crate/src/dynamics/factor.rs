//! The mass matrix factored once per step, `M = L Lᵀ`, for what the
//! controllers ask of it: forward dynamics (`q̈ = M⁻¹ (τ − C q̇ − g)`) and
//! the effective mass of the arm along a direction at a point,
//! `(uᵀ J M⁻¹ Jᵀ u)⁻¹` (Khatib, *Inertial properties in robotic
//! manipulation*, 1995): with `r = Jᵀ u`, `rᵀ M⁻¹ r = |L⁻¹ r|²`.

use crate::error::FieldError;
use crate::linalg::cholesky_into;

use super::{Dynamics, Workspace};

/// `M(q)` and its Cholesky factor, with scratch for the solves (sized
/// once; no allocation per call after the first).
#[derive(Clone, Debug, Default)]
pub struct MassFactor {
    n: usize,
    /// `M(q)`, row-major.
    mass: Vec<f64>,
    /// Lower factor, row-major.
    l: Vec<f64>,
    scratch: Vec<f64>,
}

impl MassFactor {
    /// Computes and factors `M(q)` of `dynamics`.
    ///
    /// # Errors
    /// An invalid `q`; `dynamics: the mass matrix is not positive definite
    /// at q` (a joint that moves no mass).
    pub fn update(
        &mut self,
        dynamics: &Dynamics,
        ws: &mut Workspace,
        q: &[f64],
    ) -> Result<(), FieldError> {
        let n = dynamics.dof();
        self.n = n;
        self.mass.resize(n * n, 0.0);
        dynamics.mass_matrix(ws, q, &mut self.mass)?;
        if cholesky_into(&self.mass, n, 1e-12, &mut self.l) {
            Ok(())
        } else {
            Err(FieldError::new(
                "dynamics",
                "the mass matrix is not positive definite at q (a joint moves no mass)",
            ))
        }
    }

    /// `M(q)` (row-major `n × n`) of the last [`MassFactor::update`].
    #[must_use]
    pub fn mass(&self) -> &[f64] {
        &self.mass
    }

    /// `y = L⁻¹ b` into the scratch (forward substitution).
    fn forward(&mut self, b: &[f64]) {
        let n = self.n;
        self.scratch.clear();
        for (i, bi) in b.iter().enumerate().take(n) {
            let s: f64 = (0..i).map(|k| self.l[i * n + k] * self.scratch[k]).sum();
            self.scratch.push((bi - s) / self.l[i * n + i]);
        }
    }

    /// `x = M⁻¹ b` into `x`.
    pub fn solve(&mut self, b: &[f64], x: &mut [f64]) {
        let n = self.n;
        self.forward(b);
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|k| self.l[k * n + i] * x[k]).sum();
            x[i] = (self.scratch[i] - s) / self.l[i * n + i];
        }
    }

    /// `rᵀ M⁻¹ r` (1/kg for a row `r = Jᵀ u` of a unit direction `u`).
    pub fn inverse_quadratic(&mut self, r: &[f64]) -> f64 {
        self.forward(r);
        self.scratch.iter().map(|y| y * y).sum()
    }

    /// The effective mass `(rᵀ M⁻¹ r)⁻¹` (kg) along the row `r = Jᵀ u`;
    /// `+∞` where no joint moves the point along `u`.
    pub fn effective_mass(&mut self, r: &[f64]) -> f64 {
        let w = self.inverse_quadratic(r);
        if w > 1e-12 { 1.0 / w } else { f64::INFINITY }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::Inertial;
    use crate::kinematics::{Robot, presets};
    use glam::{DMat3, DVec3};

    fn planar() -> Dynamics {
        let spec = presets::preset("planar3").unwrap_or_else(|e| unreachable!("{e}"));
        let robot = Robot::from_spec(&spec).unwrap_or_else(|e| unreachable!("{e}"));
        let body = Inertial::new(
            1.5,
            DVec3::new(-0.1, 0.0, 0.0),
            DMat3::from_diagonal(DVec3::new(0.01, 0.02, 0.02)),
        )
        .unwrap_or_else(|e| unreachable!("{e}"));
        Dynamics::new(robot, vec![body; 3]).unwrap_or_else(|e| unreachable!("{e}"))
    }

    #[test]
    fn solve_inverts_the_mass_matrix() {
        let d = planar();
        let mut ws = d.workspace();
        let mut f = MassFactor::default();
        f.update(&d, &mut ws, &[0.3, -0.7, 1.1])
            .unwrap_or_else(|e| unreachable!("{e}"));
        let b = [0.4, -1.0, 2.5];
        let mut x = [0.0; 3];
        f.solve(&b, &mut x);
        let m = f.mass().to_vec();
        for i in 0..3 {
            let mx: f64 = (0..3).map(|k| m[i * 3 + k] * x[k]).sum();
            assert!((mx - b[i]).abs() < 1e-12, "{mx} vs {}", b[i]);
        }
        let quad = f.inverse_quadratic(&b);
        let direct: f64 = b.iter().zip(&x).map(|(a, c)| a * c).sum();
        assert!((quad - direct).abs() < 1e-12);
        assert!(f.effective_mass(&[0.0; 3]).is_infinite());
    }
}
