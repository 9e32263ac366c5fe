//! First-order propagation of sensing uncertainty through the
//! differentiable model (paper §IV: "the usual tools for uncertainty
//! propagation for the differentiable model can be used").
//!
//! The sensed position of an obstacle is `p + δp` with `δp` of zero mean
//! (over runs: the bias too is drawn at random) and covariance `Σ`
//! ([`Covariance`], from [`super::SensorModel::covariance`]). Any quantity
//! `y(p)` of the model — a pair's distance, the fraction of its witness
//! along the segment, the repulsion velocity, the joint command — then has,
//! to first order, the covariance `G Σ Gᵀ` with `G = ∂y/∂p`.
//!
//! * The distance gradient is exact and free: `∂d/∂p = n`, the unit normal
//!   from the arm towards the obstacle (moving the obstacle along `n` opens
//!   the gap by as much).
//! * Every other gradient is taken by central differences of the closed-form
//!   distance routines with the obstacle moved by `±h` along each axis
//!   ([`gradient`], [`FD_STEP`]). Where the model is not differentiable (a
//!   witness clamped at a segment end, two segments equally close) the
//!   difference quotient is the mean of the one-sided slopes, and the
//!   first-order figure is only indicative: the fig. 4 case, where the
//!   witness of a segment parallel to the obstacle is ill-conditioned,
//!   shows up as a very large standard deviation of `a'` or `d'`.
//! * Latency is not a random error: it shifts the sensed pose by the
//!   obstacle's own motion and stays in the safety margin only.
//!
//! **Switch probability** ([`switch_probability`]): with the per-segment
//! distances `dᵢ`, normals `nᵢ` and the closest segment `*`, the sensed
//! order of segments `i` and `*` flips when `(nᵢ − n_*)ᵀ δp < d_* − dᵢ`,
//! which has probability `Φ(−(dᵢ − d_*) / σᵢ)` with
//! `σᵢ² = (nᵢ − n_*)ᵀ Σ (nᵢ − n_*)`. The probability that the closest
//! segment differs from the ideal one is `1 − Πᵢ (1 − Pᵢ)`: exact for two
//! candidate segments (the paper's fig. 4), and between the largest `Pᵢ`
//! and their sum for more.

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

/// Step of the central differences (m): small against any obstacle's
/// distance to the arm and against the sensing errors worth modelling,
/// large against the round-off of the distance routines (~1e-15 m), so
/// that the difference quotient keeps ~8 significant digits.
pub const FD_STEP: f64 = 1e-6;

/// Covariance of an obstacle's sensed position (m²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Covariance(pub DMat3);

impl Covariance {
    /// No uncertainty.
    pub const ZERO: Self = Self(DMat3::ZERO);

    /// `variance` (m²) on each axis, no correlation between axes.
    #[must_use]
    pub fn isotropic(variance: f64) -> Self {
        Self(DMat3::from_diagonal(DVec3::splat(variance.max(0.0))))
    }

    /// Whether the position is known exactly.
    #[must_use]
    pub fn is_zero(&self) -> bool {
        self.0 == DMat3::ZERO
    }

    /// Variance of `gᵀ δp` (m² times the unit of `g` squared).
    #[must_use]
    pub fn variance_along(&self, g: DVec3) -> f64 {
        g.dot(self.0 * g).max(0.0)
    }

    /// Standard deviation of `gᵀ δp`.
    #[must_use]
    pub fn std_along(&self, g: DVec3) -> f64 {
        self.variance_along(g).sqrt()
    }

    /// Per-component standard deviations of `G δp`, where the columns of
    /// `G` are the derivatives along x, y and z (`G = [∂y/∂x ∂y/∂y ∂y/∂z]`
    /// for a vector `y` of any length, here given column by column).
    #[must_use]
    pub fn std_of(&self, columns: &[Vec<f64>; 3]) -> Vec<f64> {
        let n = columns[0].len();
        (0..n)
            .map(|i| self.std_along(DVec3::new(columns[0][i], columns[1][i], columns[2][i])))
            .collect()
    }
}

/// First-order standard deviations of one control point's quantities
/// caused by the sensing error of the obstacle it answers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct PointSigma {
    /// Of its clearance (m).
    pub distance: f64,
    /// Of the DH value `d'` of the selected witness on the arm (m; 0 for a
    /// pinned point, whose DH values are the user's).
    pub d: f64,
    /// Of the DH value `a'` of the selected witness on the arm (m).
    pub a: f64,
    /// Of each component of its repulsion (m/s, or N in torque mode).
    pub repulsion: [f64; 3],
}

/// Central-difference derivatives of `f` with respect to the obstacle's
/// position: `f(offset)` evaluates the model with the obstacle moved by
/// `offset`. Returns the three columns `∂f/∂x`, `∂f/∂y`, `∂f/∂z`, or
/// `None` when `f` fails at a probe.
pub fn gradient(mut f: impl FnMut(DVec3) -> Option<Vec<f64>>) -> Option<[Vec<f64>; 3]> {
    let mut column = |axis: DVec3| -> Option<Vec<f64>> {
        let plus = f(axis * FD_STEP)?;
        let minus = f(-axis * FD_STEP)?;
        Some(
            plus.iter()
                .zip(&minus)
                .map(|(p, m)| (p - m) / (2.0 * FD_STEP))
                .collect(),
        )
    };
    Some([column(DVec3::X)?, column(DVec3::Y)?, column(DVec3::Z)?])
}

/// The standard normal distribution function `Φ(x)` (the same bits on
/// every target: `libm`'s `erfc`).
#[must_use]
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / core::f64::consts::SQRT_2)
}

/// Probability that the segment sensed as closest differs from the ideal
/// one (see the module docs). `best` is the closest segment's `(distance,
/// normal)`, `others` those of every other candidate segment (each
/// segment's own closest pair, and only segments whose witness is far
/// enough along the skeleton to count as a switch).
#[must_use]
pub fn switch_probability(
    best: (f64, DVec3),
    others: impl IntoIterator<Item = (f64, DVec3)>,
    covariance: &Covariance,
) -> f64 {
    let mut stay = 1.0;
    for (d, n) in others {
        let gap = d - best.0;
        let sigma = covariance.std_along(n - best.1);
        let flip = if sigma > 0.0 {
            normal_cdf(-gap / sigma)
        } else if gap < 0.0 {
            1.0
        } else {
            0.0
        };
        stay *= 1.0 - flip;
    }
    (1.0 - stay).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_cdf_matches_known_values() {
        assert!((normal_cdf(0.0) - 0.5).abs() < 1e-16);
        assert!((normal_cdf(1.0) - 0.841_344_746_068_542_9).abs() < 1e-15);
        assert!((normal_cdf(-1.959_963_984_540_054) - 0.025).abs() < 1e-15);
        assert!(normal_cdf(-40.0) >= 0.0 && normal_cdf(40.0) == 1.0);
    }

    #[test]
    fn two_segments_flip_with_the_probability_of_their_gap() {
        let cov = Covariance::isotropic(0.01 * 0.01);
        let (n1, n2) = (DVec3::Y, -DVec3::X);
        // Equal distances: a coin toss.
        let p = switch_probability((0.1, n1), [(0.1, n2)], &cov);
        assert!((p - 0.5).abs() < 1e-15);
        // A gap of one σ of the difference (σ √2 for orthogonal normals).
        let gap = 0.01 * 2f64.sqrt();
        let p = switch_probability((0.1, n1), [(0.1 + gap, n2)], &cov);
        assert!((p - normal_cdf(-1.0)).abs() < 1e-15, "{p}");
        // Identical normals: the order cannot flip.
        assert_eq!(switch_probability((0.1, n1), [(0.1001, n1)], &cov), 0.0);
        // No uncertainty: never.
        assert_eq!(
            switch_probability((0.1, n1), [(0.1001, n2)], &Covariance::ZERO),
            0.0
        );
    }

    #[test]
    fn more_candidates_only_raise_the_probability() {
        let cov = Covariance::isotropic(1e-4);
        let one = switch_probability((0.1, DVec3::Y), [(0.11, DVec3::X)], &cov);
        let two = switch_probability((0.1, DVec3::Y), [(0.11, DVec3::X), (0.12, DVec3::Z)], &cov);
        assert!(two > one && two < 2.0 * one);
    }

    #[test]
    fn gradient_of_a_linear_map_is_its_matrix() {
        let g = gradient(|o| Some(vec![2.0 * o.x - o.z, 3.0 * o.y])).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-8;
        assert!(close(g[0][0], 2.0) && close(g[1][0], 0.0) && close(g[2][0], -1.0));
        assert!(close(g[1][1], 3.0) && close(g[0][1], 0.0));
        let cov = Covariance::isotropic(4.0);
        let s = cov.std_of(&g);
        assert!(close(s[0], 2.0 * 5f64.sqrt()) && close(s[1], 6.0));
        assert!(gradient(|_| None).is_none());
    }
}
