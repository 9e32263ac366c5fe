//! Keyframed motion of a human: poses (and a shift of the root) at times,
//! interpolated by shape-preserving cubics.
//!
//! Every channel (each joint angle, each coordinate of the shift) is a
//! piecewise cubic Hermite through the keyframes whose slopes are the
//! harmonic mean of the neighbouring secants, zero where the secants
//! change sign (Fritsch & Butland's monotone rule). The curve never leaves
//! the range of its two neighbouring keyframes, so keyframes within the
//! body's range give motion within it; velocities are continuous. Without
//! `loop` the first and last keyframes have zero slope and the pose holds
//! outside them; with `loop` the sequence repeats with period
//! `t[last] − t[0]` and the slopes wrap around (make the last pose equal
//! the first for a seamless cycle).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::pose::{JOINT_COUNT, Pose};
use crate::error::{FieldError, bounded, finite};

/// Most keyframes an animation (or an imported track) may hold.
pub const MAX_KEYFRAMES: usize = 100_000;

/// Largest shift of the root a keyframe may ask (m).
pub const MAX_SHIFT: f64 = 1000.0;

/// One keyframe.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Keyframe {
    /// Time (s).
    pub t: f64,
    /// Joint angles (absent ones zero).
    #[serde(default)]
    pub pose: Pose,
    /// Displacement of the root in the body's frame at rest: forward, left,
    /// up (m; default zero).
    #[serde(default, skip_serializing_if = "is_zero3")]
    pub shift: [f64; 3],
    /// Turn of the root about z, added to the heading (rad; default zero).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub turn: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_zero3(v: &[f64; 3]) -> bool {
    *v == [0.0; 3]
}

const CHANNELS: usize = JOINT_COUNT + 4;

/// Largest turn a keyframe may ask (rad).
pub const MAX_TURN: f64 = 1000.0;

/// A validated, ready-to-sample animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    times: Vec<f64>,
    values: Vec<[f64; CHANNELS]>,
    slopes: Vec<[f64; CHANNELS]>,
    repeat: bool,
}

/// The state of an animation at one time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sampled {
    /// Joint angles.
    pub pose: Pose,
    /// Their rates (rad/s).
    pub rates: [f64; JOINT_COUNT],
    /// Shift of the root (body frame at rest, m).
    pub shift: DVec3,
    /// Its rate (m/s).
    pub shift_rate: DVec3,
    /// Turn of the root about z (rad).
    pub turn: f64,
    /// Its rate (rad/s).
    pub turn_rate: f64,
}

fn harmonic(a: f64, b: f64) -> f64 {
    if a * b <= 0.0 {
        0.0
    } else {
        2.0 * a * b / (a + b)
    }
}

impl Animation {
    /// Checks and prepares `keyframes`.
    ///
    /// # Errors
    /// `keyframes: needs at least one keyframe`, `keyframes: at most 100000
    /// keyframes (got …)`, `keyframes[3].t: must increase`,
    /// `keyframes[2].pose.leftElbow: … beyond the body's range …`,
    /// `keyframes[1].shift[0]: …`, `loop: …`.
    pub fn new(keyframes: &[Keyframe], repeat: bool) -> Result<Self, FieldError> {
        if keyframes.is_empty() {
            return Err(FieldError::new("keyframes", "needs at least one keyframe"));
        }
        if keyframes.len() > MAX_KEYFRAMES {
            return Err(FieldError::new(
                "keyframes",
                format!(
                    "at most {MAX_KEYFRAMES} keyframes (got {})",
                    keyframes.len()
                ),
            ));
        }
        let mut times = Vec::with_capacity(keyframes.len());
        let mut values = Vec::with_capacity(keyframes.len());
        for (k, f) in keyframes.iter().enumerate() {
            let at = |field: &str| format!("keyframes[{k}].{field}");
            finite(&at("t"), f.t)?;
            if k > 0 && f.t <= keyframes[k - 1].t {
                return Err(FieldError::new(at("t"), "must increase"));
            }
            f.pose.validate().map_err(|e| e.within(&at("pose")))?;
            for (i, s) in f.shift.iter().enumerate() {
                bounded(&at(&format!("shift[{i}]")), *s, MAX_SHIFT)?;
            }
            bounded(&at("turn"), f.turn, MAX_TURN)?;
            let mut v = [0.0; CHANNELS];
            v[..JOINT_COUNT].copy_from_slice(&f.pose.angles);
            v[JOINT_COUNT..JOINT_COUNT + 3].copy_from_slice(&f.shift);
            v[JOINT_COUNT + 3] = f.turn;
            times.push(f.t);
            values.push(v);
        }
        if repeat && keyframes.len() < 2 {
            return Err(FieldError::new(
                "loop",
                "a looping animation needs at least two keyframes",
            ));
        }
        let slopes = slopes(&times, &values, repeat);
        Ok(Self {
            times,
            values,
            slopes,
            repeat,
        })
    }

    /// Time of the first keyframe (s).
    #[must_use]
    pub fn start(&self) -> f64 {
        self.times[0]
    }

    /// Time of the last keyframe (s).
    #[must_use]
    pub fn end(&self) -> f64 {
        self.times[self.times.len() - 1]
    }

    /// Whether it repeats.
    #[must_use]
    pub fn repeats(&self) -> bool {
        self.repeat
    }

    /// The pose, the shift and their rates at time `t` (s).
    #[must_use]
    pub fn sample(&self, t: f64) -> Sampled {
        let (first, last) = (self.start(), self.end());
        let mut t = if t.is_finite() { t } else { first };
        if self.repeat && last > first {
            t = first + (t - first).rem_euclid(last - first);
        }
        let n = self.times.len();
        let mut out = [0.0; CHANNELS];
        let mut rate = [0.0; CHANNELS];
        if t <= first || n == 1 {
            out = self.values[0];
        } else if t >= last {
            out = self.values[n - 1];
        } else {
            let k = self.times.partition_point(|&s| s <= t) - 1;
            let (t0, t1) = (self.times[k], self.times[k + 1]);
            let h = t1 - t0;
            let u = (t - t0) / h;
            let (u2, u3) = (u * u, u * u * u);
            let (h00, h10, h01, h11) = (
                2.0 * u3 - 3.0 * u2 + 1.0,
                u3 - 2.0 * u2 + u,
                -2.0 * u3 + 3.0 * u2,
                u3 - u2,
            );
            let (d00, d10, d01, d11) = (
                6.0 * u2 - 6.0 * u,
                3.0 * u2 - 4.0 * u + 1.0,
                -6.0 * u2 + 6.0 * u,
                3.0 * u2 - 2.0 * u,
            );
            let (p0, p1) = (&self.values[k], &self.values[k + 1]);
            let (m0, m1) = (&self.slopes[k], &self.slopes[k + 1]);
            for c in 0..CHANNELS {
                out[c] = h00 * p0[c] + h10 * h * m0[c] + h01 * p1[c] + h11 * h * m1[c];
                rate[c] = (d00 * p0[c] + d01 * p1[c]) / h + d10 * m0[c] + d11 * m1[c];
            }
        }
        let mut s = Sampled::default();
        s.pose.angles.copy_from_slice(&out[..JOINT_COUNT]);
        s.rates.copy_from_slice(&rate[..JOINT_COUNT]);
        s.shift = DVec3::new(out[JOINT_COUNT], out[JOINT_COUNT + 1], out[JOINT_COUNT + 2]);
        s.shift_rate = DVec3::new(
            rate[JOINT_COUNT],
            rate[JOINT_COUNT + 1],
            rate[JOINT_COUNT + 2],
        );
        s.turn = out[JOINT_COUNT + 3];
        s.turn_rate = rate[JOINT_COUNT + 3];
        s
    }
}

/// The monotone slopes of every channel at every keyframe.
fn slopes(times: &[f64], values: &[[f64; CHANNELS]], repeat: bool) -> Vec<[f64; CHANNELS]> {
    let n = times.len();
    let mut out = vec![[0.0; CHANNELS]; n];
    if n < 2 {
        return out;
    }
    let secant = |k: usize, c: usize| (values[k + 1][c] - values[k][c]) / (times[k + 1] - times[k]);
    for (k, slope) in out.iter_mut().enumerate().take(n - 1).skip(1) {
        for (c, m) in slope.iter_mut().enumerate() {
            *m = harmonic(secant(k - 1, c), secant(k, c));
        }
    }
    if repeat {
        let wrap: [f64; CHANNELS] =
            std::array::from_fn(|c| harmonic(secant(n - 2, c), secant(0, c)));
        out[0] = wrap;
        out[n - 1] = wrap;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(t: f64, elbow: f64) -> Keyframe {
        let mut f = Keyframe {
            t,
            ..Keyframe::default()
        };
        f.pose.angles[8] = elbow;
        f
    }

    #[test]
    fn stays_between_keyframes_and_rates_match_differences() {
        let a = Animation::new(
            &[key(0.0, 0.0), key(0.5, 2.0), key(0.7, 2.5), key(2.0, 0.1)],
            false,
        )
        .unwrap();
        let mut t = -0.1;
        while t < 2.2 {
            let s = a.sample(t);
            let e = s.pose.angles[8];
            assert!((0.0..=2.5).contains(&e), "{t}: {e}");
            let h = 1e-6;
            let fd = (a.sample(t + h).pose.angles[8] - a.sample(t - h).pose.angles[8]) / (2.0 * h);
            assert!(
                (fd - s.rates[8]).abs() < 1e-5,
                "{t}: {fd} vs {}",
                s.rates[8]
            );
            t += 0.013;
        }
        assert_eq!(a.sample(0.5).pose.angles[8], 2.0);
    }

    #[test]
    fn refuses_bad_keyframes_naming_the_field() {
        let e = Animation::new(&[key(0.0, 0.0), key(0.0, 1.0)], false).unwrap_err();
        assert_eq!(e.field, "keyframes[1].t");
        let e = Animation::new(&[key(0.0, 3.0)], false).unwrap_err();
        assert_eq!(e.field, "keyframes[0].pose.leftElbow");
        let e = Animation::new(&[key(f64::NAN, 0.0)], false).unwrap_err();
        assert_eq!(e.field, "keyframes[0].t");
        assert!(Animation::new(&[], false).is_err());
        assert!(Animation::new(&[key(0.0, 0.0)], true).is_err());
    }
}
