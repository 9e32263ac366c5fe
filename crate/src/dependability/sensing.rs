//! Sensing models: how an obstacle is seen (paper §IV, the error `∂p_f`).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::GAUSSIAN_COVERAGE;
use super::propagate::Covariance;
use crate::error::{FieldError, non_negative};
use crate::rng::Rng;

/// Default time constant of correlated sensing noise (s).
pub const DEFAULT_CORRELATION_TIME: f64 = 0.1;

/// Sensing error of one obstacle (scenario field `sensing`). Every field is
/// optional; an absent field is zero (exact sensing) unless said otherwise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct SensingSpec {
    /// Bound of a position error redrawn every step, uniform in the ball of
    /// this radius (m, ≥ 0; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
    /// Bound of a fixed offset drawn once per run, uniform in the ball of
    /// this radius: the paper's `∂p_f`, the real centroid being at the
    /// sensed one minus it (m, ≥ 0; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias_bound: Option<f64>,
    /// Standard deviation of white Gaussian noise per axis, drawn every
    /// step (m, ≥ 0; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// Stationary standard deviation per axis of correlated noise, a
    /// first-order Gauss–Markov process (m, ≥ 0; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlated_sigma: Option<f64>,
    /// Time constant of the correlated noise (s, ≥ 0; default
    /// [`DEFAULT_CORRELATION_TIME`]; 0 makes it white).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation_time: Option<f64>,
    /// Latency: the sensed pose is the true pose this long ago (s, ≥ 0;
    /// default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latency: Option<f64>,
    /// Seed of the noise (default: 1 + the obstacle's index).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
}

impl SensingSpec {
    /// Checks the values.
    ///
    /// # Errors
    /// `bound: must be >= 0`, `biasBound: …`, `sigma: …`,
    /// `correlatedSigma: …`, `correlationTime: …`, `latency: …` (also for
    /// NaN or infinite values).
    pub fn validate(&self) -> Result<(), FieldError> {
        let fields = [
            ("bound", self.bound),
            ("biasBound", self.bias_bound),
            ("sigma", self.sigma),
            ("correlatedSigma", self.correlated_sigma),
            ("correlationTime", self.correlation_time),
            ("latency", self.latency),
        ];
        for (name, value) in fields {
            if let Some(x) = value {
                non_negative(name, x)?;
            }
        }
        Ok(())
    }
}

/// The error model of one sensed obstacle, with its own random stream.
///
/// The error at a step is the sum of the fixed bias (drawn when the model is
/// made), a bounded error and white noise (drawn every step) and the state
/// of a Gauss–Markov process `x_{k+1} = a x_k + σ_c √(1 − a²) w_k`,
/// `a = exp(−Δt / τ)`, started from its stationary distribution. Latency is
/// applied by the caller, which knows the obstacle's motion
/// ([`SensorModel::latency`]).
#[derive(Clone, Debug)]
pub struct SensorModel {
    bound: f64,
    sigma: f64,
    bias_bound: f64,
    correlated_sigma: f64,
    correlation_time: f64,
    latency: f64,
    bias: DVec3,
    correlated: Option<(f64, DVec3)>,
    rng: Rng,
}

impl SensorModel {
    /// A model with error bound `bound` and Gaussian `sigma` (both m),
    /// seeded with `seed`.
    #[must_use]
    pub fn new(bound: f64, sigma: f64, seed: u64) -> Self {
        Self::from_spec(
            &SensingSpec {
                bound: Some(bound),
                sigma: Some(sigma),
                ..SensingSpec::default()
            },
            seed,
        )
    }

    /// A model from a (validated) spec, seeded with `seed` (the spec's own
    /// seed is the caller's business). The bias is drawn here, once.
    #[must_use]
    pub fn from_spec(spec: &SensingSpec, seed: u64) -> Self {
        let clean = |x: Option<f64>| x.filter(|v| v.is_finite()).unwrap_or(0.0).max(0.0);
        let mut rng = Rng::new(seed);
        let bias_bound = clean(spec.bias_bound);
        let bias = if bias_bound > 0.0 {
            ball(&mut rng) * bias_bound
        } else {
            DVec3::ZERO
        };
        Self {
            bound: clean(spec.bound),
            sigma: clean(spec.sigma),
            bias_bound,
            correlated_sigma: clean(spec.correlated_sigma),
            correlation_time: spec
                .correlation_time
                .filter(|v| v.is_finite() && *v >= 0.0)
                .unwrap_or(DEFAULT_CORRELATION_TIME),
            latency: clean(spec.latency),
            bias,
            correlated: None,
            rng,
        }
    }

    /// Whether the obstacle is sensed exactly.
    #[must_use]
    pub fn is_exact(&self) -> bool {
        self.bound == 0.0
            && self.sigma == 0.0
            && self.bias_bound == 0.0
            && self.correlated_sigma == 0.0
            && self.latency == 0.0
    }

    /// The latency of the sensed pose (s).
    #[must_use]
    pub fn latency(&self) -> f64 {
        self.latency
    }

    /// Sets the latency of the sensed pose (s; a live sensor's measured
    /// age of its frames). Not finite or negative counts as 0.
    pub fn set_latency(&mut self, latency: f64) {
        self.latency = if latency.is_finite() {
            latency.max(0.0)
        } else {
            0.0
        };
    }

    /// The fixed offset of this run (m).
    #[must_use]
    pub fn bias(&self) -> DVec3 {
        self.bias
    }

    /// The next sensing error (m) without the correlated part: uniform in
    /// the ball of radius `bound` plus Gaussian noise, plus the bias.
    pub fn sample(&mut self) -> DVec3 {
        let mut e = self.bias;
        if self.bound > 0.0 {
            e += ball(&mut self.rng) * self.bound;
        }
        if self.sigma > 0.0 {
            e += self.sigma * self.gaussian();
        }
        e
    }

    /// The sensing error at time `t` (m): [`SensorModel::sample`] plus the
    /// correlated noise advanced from the previous call's time.
    pub fn sample_at(&mut self, t: f64) -> DVec3 {
        let mut e = self.sample();
        if self.correlated_sigma > 0.0 {
            let s = self.correlated_sigma;
            let x = match self.correlated {
                None => s * self.gaussian(),
                Some((t0, x)) => {
                    let elapsed = (t - t0).max(0.0);
                    let a = if self.correlation_time > 0.0 {
                        crate::math::exp(-elapsed / self.correlation_time)
                    } else {
                        0.0
                    };
                    if a == 1.0 {
                        x
                    } else {
                        a * x + s * (1.0 - a * a).sqrt() * self.gaussian()
                    }
                }
            };
            self.correlated = Some((t, x));
            e += x;
        }
        e
    }

    fn gaussian(&mut self) -> DVec3 {
        DVec3::new(self.rng.normal(), self.rng.normal(), self.rng.normal())
    }

    /// Covariance of the sensing error over runs (m²), latency aside:
    /// isotropic, `sigma² + correlatedSigma² + (bound² + biasBound²) / 5`
    /// per axis (a point uniform in a ball of radius `R` has variance
    /// `R² / 5` along any axis; the bias is one draw per run, so across
    /// runs it is as random as the rest). See [`super::propagate`].
    #[must_use]
    pub fn covariance(&self) -> Covariance {
        let uniform = self.bound * self.bound + self.bias_bound * self.bias_bound;
        Covariance::isotropic(
            self.sigma * self.sigma + self.correlated_sigma * self.correlated_sigma + uniform / 5.0,
        )
    }

    /// The margin this error adds to a distance (m), latency aside: the
    /// bounded parts plus [`GAUSSIAN_COVERAGE`] times the total standard
    /// deviation, see [`distance_uncertainty`].
    #[must_use]
    pub fn margin(&self) -> f64 {
        // `sqrt` is correctly rounded on every target (`hypot` is not).
        let sigma = if self.correlated_sigma == 0.0 {
            self.sigma
        } else {
            (self.sigma * self.sigma + self.correlated_sigma * self.correlated_sigma).sqrt()
        };
        distance_uncertainty(DVec3::Z, self.bound + self.bias_bound, sigma)
    }
}

impl SensorModel {
    /// [`SensorModel::margin`] with white Gaussian noise of `extra` (m per
    /// axis) added to the model's own, as for one part of a body whose
    /// keypoints are seen with their own error: the same formula with
    /// `σ = √(sigma² + correlatedSigma² + extra²)` (equal to
    /// [`SensorModel::margin`] when `extra` is 0).
    #[must_use]
    pub fn margin_with(&self, extra: f64) -> f64 {
        if extra == 0.0 {
            return self.margin();
        }
        let sigma = (self.sigma * self.sigma
            + self.correlated_sigma * self.correlated_sigma
            + extra * extra)
            .sqrt();
        distance_uncertainty(DVec3::Z, self.bound + self.bias_bound, sigma)
    }

    /// [`SensorModel::covariance`] with white Gaussian noise of `extra`
    /// (m per axis) added.
    #[must_use]
    pub fn covariance_with(&self, extra: f64) -> Covariance {
        if extra == 0.0 {
            return self.covariance();
        }
        let c = self.covariance();
        Covariance::isotropic(c.variance_along(DVec3::X) + extra * extra)
    }

    /// A draw of white Gaussian noise of `sigma` per axis (m) from the
    /// model's random stream (a part's own sensing error).
    pub fn noise(&mut self, sigma: f64) -> DVec3 {
        sigma * self.gaussian()
    }
}

/// A point uniform in the unit ball (rejection sampling).
fn ball(rng: &mut Rng) -> DVec3 {
    loop {
        let v = rng.vec3(1.0);
        if v.length_squared() <= 1.0 {
            break v;
        }
    }
}

/// First-order propagation of an obstacle position error into the distance
/// along the unit normal `normal` of the closest pair: `|δd| ≤ |n| bound`
/// for the bounded part, `σ_d = |n| σ` for isotropic Gaussian noise; the
/// result is the inflated safety margin `|n| (bound + 3 σ)` (m).
#[must_use]
pub fn distance_uncertainty(normal: DVec3, bound: f64, sigma: f64) -> f64 {
    let g = normal.length();
    let g = if g.is_finite() { g } else { 1.0 };
    g * (bound + GAUSSIAN_COVERAGE * sigma)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_error_stays_in_its_ball() {
        let mut m = SensorModel::new(0.01, 0.0, 7);
        for _ in 0..1000 {
            assert!(m.sample().length() <= 0.01);
        }
        assert!((m.margin() - 0.01).abs() < 1e-15);
    }

    fn spec() -> SensingSpec {
        SensingSpec::default()
    }

    #[test]
    fn bias_is_drawn_once_and_stays_in_its_ball() {
        let s = SensingSpec {
            bias_bound: Some(0.05),
            ..spec()
        };
        let mut m = SensorModel::from_spec(&s, 3);
        let b = m.bias();
        assert!(b.length() <= 0.05 && b.length() > 0.0);
        for k in 0..100 {
            assert_eq!(m.sample_at(f64::from(k) * 0.01), b);
        }
        assert_eq!(SensorModel::from_spec(&s, 3).bias(), b);
        assert_ne!(SensorModel::from_spec(&s, 4).bias(), b);
        assert!((m.margin() - 0.05).abs() < 1e-15);
    }

    #[test]
    fn gauss_markov_noise_has_its_variance_and_correlation() {
        let (sigma, tau, dt) = (0.01, 0.1, 0.01);
        let s = SensingSpec {
            correlated_sigma: Some(sigma),
            correlation_time: Some(tau),
            ..spec()
        };
        let mut m = SensorModel::from_spec(&s, 11);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|k| m.sample_at(f64::from(k) * dt).x).collect();
        let var = xs.iter().map(|x| x * x).sum::<f64>() / f64::from(n);
        let lag = xs.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / f64::from(n - 1);
        let rho = lag / var;
        assert!(
            (var.sqrt() / sigma - 1.0).abs() < 0.05,
            "σ = {}",
            var.sqrt()
        );
        let expected = crate::math::exp(-dt / tau);
        assert!(
            (rho - expected).abs() < 0.01,
            "ρ = {rho}, expected {expected}"
        );
        assert!((m.margin() - 3.0 * sigma).abs() < 1e-15);
    }

    #[test]
    fn total_sigma_adds_in_quadrature() {
        let s = SensingSpec {
            bound: Some(0.01),
            bias_bound: Some(0.02),
            sigma: Some(0.003),
            correlated_sigma: Some(0.004),
            ..spec()
        };
        let m = SensorModel::from_spec(&s, 1);
        assert!((m.margin() - (0.03 + 3.0 * 0.005)).abs() < 1e-12);
        let var = 0.003f64.powi(2) + 0.004f64.powi(2) + (0.01f64.powi(2) + 0.02f64.powi(2)) / 5.0;
        assert!((m.covariance().variance_along(DVec3::X) - var).abs() < 1e-18);
        assert!(SensorModel::from_spec(&spec(), 1).covariance().is_zero());
        assert!(!m.is_exact());
        let lat = SensingSpec {
            latency: Some(0.1),
            ..spec()
        };
        assert!(!SensorModel::from_spec(&lat, 1).is_exact());
        assert!(SensorModel::from_spec(&spec(), 1).is_exact());
    }

    #[test]
    fn negative_or_nan_sensing_values_are_refused_with_the_field_named() {
        let cases: [(&str, SensingSpec); 6] = [
            (
                "bound",
                SensingSpec {
                    bound: Some(-1.0),
                    ..spec()
                },
            ),
            (
                "biasBound",
                SensingSpec {
                    bias_bound: Some(f64::NAN),
                    ..spec()
                },
            ),
            (
                "sigma",
                SensingSpec {
                    sigma: Some(-0.1),
                    ..spec()
                },
            ),
            (
                "correlatedSigma",
                SensingSpec {
                    correlated_sigma: Some(f64::NAN),
                    ..spec()
                },
            ),
            (
                "correlationTime",
                SensingSpec {
                    correlation_time: Some(-1.0),
                    ..spec()
                },
            ),
            (
                "latency",
                SensingSpec {
                    latency: Some(f64::NAN),
                    ..spec()
                },
            ),
        ];
        for (field, s) in cases {
            let e = s.validate().unwrap_err();
            assert!(e.to_string().starts_with(field), "{field}: {e}");
        }
        assert!(spec().validate().is_ok());
    }
}
