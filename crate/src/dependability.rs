//! The dependability monitor (paper §IV): sensing errors, their propagation
//! into distances, detection of segment switches that the error can cause,
//! chattering, and time-to-collision against the transition delay.
//!
//! * **Sensing model** ([`SensorModel`]): each obstacle is seen displaced by
//!   a fixed bias drawn once per run (uniform in a ball of radius
//!   `biasBound`, the paper's `∂p_f`), a bounded error redrawn every step
//!   (uniform in a ball of radius `bound`), white Gaussian noise (`sigma`
//!   per axis) and correlated noise (first-order Gauss–Markov,
//!   `correlatedSigma`, `correlationTime`), and seen `latency` seconds late;
//!   everything is drawn from a seeded [`Rng`] so that a run is
//!   reproducible on every target.
//! * **Propagation** ([`distance_uncertainty`]): to first order a
//!   displacement `δp` of the obstacle changes the distance by `nᵀ δp`
//!   (`n` the unit normal of the closest pair), so the distance error is
//!   bounded by `bound + biasBound` and has standard deviation
//!   `σ = √(sigma² + correlatedSigma²)`. The safety margin is inflated by
//!   `bound + biasBound + 3 σ` ([`GAUSSIAN_COVERAGE`] standard deviations)
//!   plus `latency × the obstacle's speed`.
//! * **Switch risk**: if another part of the skeleton is within twice that
//!   margin of the closest one, an error inside the region can make the
//!   control point switch segment ([`EventKind::SwitchRisk`]).
//! * **Chattering** ([`SwitchCounter`]): segment switches of each control
//!   point are counted over a sliding window; more than `maxSwitches` in
//!   `switchWindow` seconds is chattering, and the configured policy applies:
//!   `stop` (joint velocities brought to zero with bounded deceleration while
//!   the chattering lasts) or `lock` (the control point held on its current
//!   segment for `lockTime`).
//! * **Time to collision**: clearance over the closing speed of the arm's
//!   material point and the obstacle (low-pass filtered), compared with the
//!   time a transition still needs ([`EventKind::TransitionTooSlow`]).
//!
//! Every such event goes into the trace with its time ([`Event`]).

use std::collections::VecDeque;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::error::{FieldError, non_negative, positive};
use crate::rng::Rng;

/// Standard deviations of Gaussian noise added to the safety margin.
pub const GAUSSIAN_COVERAGE: f64 = 3.0;

/// What to do when a control point chatters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ChatteringPolicy {
    /// Bring the joints to rest with bounded deceleration (default).
    #[default]
    Stop,
    /// Hold the control point on its current segment for `lockTime`.
    Lock,
}

/// Settings of the monitor (scenario field `dependability`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields, default)]
pub struct DependabilityConfig {
    /// Length of the sliding window in which switches are counted (s, > 0;
    /// default 0.5).
    pub switch_window: f64,
    /// Largest number of switches allowed in the window (default 3).
    pub max_switches: u32,
    /// Policy on chattering (default `stop`).
    pub on_chattering: ChatteringPolicy,
    /// How long a `lock` holds (s, > 0; default 1).
    pub lock_time: f64,
    /// Largest joint deceleration of a `stop` (rad/s² or m/s², > 0;
    /// default 10); a stop never exceeds the joints' own acceleration and
    /// jerk limits either (category 2: controlled, then held).
    pub max_deceleration: f64,
}

impl Default for DependabilityConfig {
    fn default() -> Self {
        Self {
            switch_window: 0.5,
            max_switches: 3,
            on_chattering: ChatteringPolicy::Stop,
            lock_time: 1.0,
            max_deceleration: 10.0,
        }
    }
}

impl DependabilityConfig {
    /// Checks every value.
    ///
    /// # Errors
    /// `switchWindow: must be > 0`, `lockTime: …`, `maxDeceleration: …`.
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("switchWindow", self.switch_window)?;
        positive("lockTime", self.lock_time)?;
        positive("maxDeceleration", self.max_deceleration)?;
        Ok(())
    }
}

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

/// Switch times of one control point over a sliding window.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SwitchCounter {
    times: VecDeque<f64>,
}

impl SwitchCounter {
    /// Records a switch at time `t` and forgets switches older than
    /// `window`; returns the count in the window.
    pub fn record(&mut self, t: f64, window: f64) -> usize {
        self.times.push_back(t);
        self.count(t, window)
    }

    /// The number of switches in `(t − window, t]`.
    pub fn count(&mut self, t: f64, window: f64) -> usize {
        while self.times.front().is_some_and(|&s| s <= t - window) {
            self.times.pop_front();
        }
        self.times.len()
    }

    /// Forgets every switch.
    pub fn clear(&mut self) {
        self.times.clear();
    }
}

/// Time to collision (s) from a distance (m) and the rate at which it
/// shrinks (m/s); infinite when the distance does not shrink.
#[must_use]
pub fn time_to_collision(distance: f64, closing_speed: f64) -> f64 {
    if closing_speed > 1e-9 && distance.is_finite() {
        (distance.max(0.0)) / closing_speed
    } else {
        f64::INFINITY
    }
}

/// One entry of the trace's event log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Event {
    /// Simulation time (s).
    pub t: f64,
    /// What happened.
    #[serde(flatten)]
    pub kind: EventKind,
}

/// What happened (the `kind` field of a trace event).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    tag = "kind",
    rename_all = "camelCase",
    rename_all_fields = "camelCase"
)]
#[non_exhaustive]
pub enum EventKind {
    /// The selected point of a control point moved to another segment,
    /// farther along the skeleton than the jump threshold.
    SegmentSwitch {
        /// Obstacle the control point answers (empty for pinned points).
        obstacle: String,
        /// Previous segment.
        from: usize,
        /// New segment.
        to: usize,
    },
    /// A control point started travelling along the skeleton.
    TransitionStart {
        /// Obstacle the control point answers.
        obstacle: String,
        /// Segment it leaves.
        from: usize,
        /// Segment it goes to.
        to: usize,
        /// Planned duration (s).
        duration: f64,
        /// Whether it replaced a transition under way.
        replan: bool,
    },
    /// A control point arrived.
    TransitionEnd {
        /// Obstacle the control point answers.
        obstacle: String,
        /// Segment it arrived on.
        segment: usize,
    },
    /// The sensing error region can switch the control point to another
    /// segment (raised when it starts).
    SwitchRisk {
        /// Obstacle concerned.
        obstacle: String,
        /// Closest segment.
        segment: usize,
        /// The other segment within reach of the error.
        alternative: usize,
        /// Difference of their distances (m).
        gap: f64,
        /// Inflated margin of the obstacle (m).
        margin: f64,
    },
    /// More than `maxSwitches` segment switches in `switchWindow`.
    Chattering {
        /// Obstacle concerned.
        obstacle: String,
        /// Switches counted in the window.
        switches: usize,
    },
    /// The robot is being stopped.
    Stop {
        /// Why.
        reason: String,
    },
    /// The robot resumes after a stop.
    Resume,
    /// A control point is held on one segment.
    Lock {
        /// Obstacle concerned.
        obstacle: String,
        /// Segment held.
        segment: usize,
        /// Until when (s).
        until: f64,
    },
    /// The protective layer cannot keep a pair's approach within what the
    /// arm can stop from (the obstacle closes in faster than the arm can
    /// retreat, or the arm is squeezed): the arm is stopped before contact.
    Unavoidable {
        /// Obstacle concerned (`self:<link>` for a self-collision pair).
        obstacle: String,
        /// Skeleton segment of the pair.
        segment: usize,
        /// Clearance of the pair (m).
        distance: f64,
        /// How much faster than allowed the pair closes in (m/s).
        excess: f64,
    },
    /// A lock ended.
    Unlock {
        /// Obstacle concerned.
        obstacle: String,
    },
    /// The time to collision is below the time the control point's
    /// transition still needs (raised when it starts).
    TransitionTooSlow {
        /// Obstacle concerned.
        obstacle: String,
        /// Time to collision (s).
        time_to_collision: f64,
        /// Remaining transition time (s).
        remaining: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counter_forgets_old_switches() {
        let mut c = SwitchCounter::default();
        assert_eq!(c.record(0.0, 0.5), 1);
        assert_eq!(c.record(0.2, 0.5), 2);
        assert_eq!(c.record(0.6, 0.5), 2);
        assert_eq!(c.count(1.2, 0.5), 0);
    }

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
