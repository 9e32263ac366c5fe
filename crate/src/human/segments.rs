//! A subject's own segment lengths ([`Segments`], the `segments` of a
//! human) and the dimensions a body is posed with ([`Dims`]).
//!
//! Without `segments` every length is Drillis & Contini's fraction of the
//! height ([`super::proportion`]). A recording measures its subject: the
//! track fit takes the median of each segment over the frames, the left and
//! right sides together ([`measure`]; the arm lengthened, both segments
//! alike, to the 95th percentile of the recorded shoulder–wrist distance
//! when that is longer), and keeps it within
//! [`PLAUSIBLE`] times the proportion's value at the body's height (a
//! tracker's outliers do not make a giant's forearm). The radii, the head,
//! the neck, the hands and the feet stay proportional to the height.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::body::{build, proportion};
use crate::error::{FieldError, finite};

/// Each segment may be this many times its proportional length, at least
/// and at most (the spread of adult segment proportions is well inside).
pub const PLAUSIBLE: (f64, f64) = (0.7, 1.4);

/// A subject's segment lengths (m): joint centre to joint centre.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Segments {
    /// Shoulder to elbow.
    pub upper_arm: f64,
    /// Elbow to wrist.
    pub forearm: f64,
    /// Hip to knee.
    pub thigh: f64,
    /// Knee to ankle.
    pub shank: f64,
    /// Between the shoulder joints.
    pub shoulder_width: f64,
    /// Between the hip joints.
    pub hip_width: f64,
    /// Middle of the hip joints to the middle of the shoulder joints,
    /// standing upright.
    pub trunk: f64,
}

impl Segments {
    /// Drillis & Contini's segments for a body of height `h` (m).
    #[must_use]
    pub fn proportional(h: f64) -> Self {
        use proportion::*;
        Self {
            upper_arm: UPPER_ARM * h,
            forearm: FOREARM * h,
            thigh: THIGH * h,
            shank: SHANK * h,
            shoulder_width: SHOULDER_WIDTH * h,
            hip_width: 2.0 * build::HIP_HALF * h,
            trunk: (SHOULDER_HEIGHT - HIP_HEIGHT) * h,
        }
    }

    fn named(&self) -> [(&'static str, f64); 7] {
        [
            ("upperArm", self.upper_arm),
            ("forearm", self.forearm),
            ("thigh", self.thigh),
            ("shank", self.shank),
            ("shoulderWidth", self.shoulder_width),
            ("hipWidth", self.hip_width),
            ("trunk", self.trunk),
        ]
    }

    fn from_values(v: [f64; 7]) -> Self {
        Self {
            upper_arm: v[0],
            forearm: v[1],
            thigh: v[2],
            shank: v[3],
            shoulder_width: v[4],
            hip_width: v[5],
            trunk: v[6],
        }
    }

    /// Checks each length against the plausible range for height `h`.
    ///
    /// # Errors
    /// `forearm: must be in [0.179, 0.358] m for a height of 1.75 m (got
    /// 0.6)` (or not a finite number).
    pub fn validate(&self, h: f64) -> Result<(), FieldError> {
        let base = Self::proportional(h).named();
        for ((name, x), (_, b)) in self.named().into_iter().zip(base) {
            finite(name, x)?;
            let (lo, hi) = (PLAUSIBLE.0 * b, PLAUSIBLE.1 * b);
            if !(lo..=hi).contains(&x) {
                return Err(FieldError::new(
                    name,
                    format!("must be in [{lo:.3}, {hi:.3}] m for a height of {h} m (got {x})"),
                ));
            }
        }
        Ok(())
    }

    /// Each length brought into the plausible range for height `h`.
    #[must_use]
    pub fn clamped(&self, h: f64) -> Self {
        let base = Self::proportional(h).named();
        let mut v = [0.0; 7];
        for (k, ((_, x), (_, b))) in self.named().into_iter().zip(base).enumerate() {
            let x = if x.is_finite() { x } else { b };
            v[k] = x.clamp(PLAUSIBLE.0 * b, PLAUSIBLE.1 * b);
        }
        Self::from_values(v)
    }
}

/// What a body is posed with (m): the height and the lengths that place
/// the joints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dims {
    /// Height.
    pub h: f64,
    /// Segment lengths.
    pub segments: Segments,
    /// Whether the segments are the subject's own (not proportional).
    pub own: bool,
}

impl Dims {
    /// A body of height `h` with `segments` (proportional when `None`).
    #[must_use]
    pub fn new(h: f64, segments: Option<&Segments>) -> Self {
        Self {
            h,
            segments: segments
                .copied()
                .unwrap_or_else(|| Segments::proportional(h)),
            own: segments.is_some(),
        }
    }

    /// The lumbar joint above the middle of the hip joints.
    #[must_use]
    pub fn lumbar(&self) -> f64 {
        build::LUMBAR * self.h
    }

    /// The shoulders' middle above the lumbar joint, along the trunk.
    #[must_use]
    pub fn shoulder_above_lumbar(&self) -> f64 {
        if self.own {
            (self.segments.trunk - self.lumbar()).max(0.0)
        } else {
            use proportion::*;
            (SHOULDER_HEIGHT - HIP_HEIGHT - build::LUMBAR) * self.h
        }
    }
}

/// The median of each segment over `frames` (the fit's fourteen joints,
/// [`crate::parsers::track::NEEDED`]), left and right together, kept in the
/// plausible range for height `h`.
#[must_use]
pub fn measure(frames: &[[DVec3; 14]], h: f64) -> Segments {
    let lumbar = build::LUMBAR * h;
    let mut series: [Vec<f64>; 7] = Default::default();
    for j in frames {
        let d = |a: usize, b: usize| (j[a] - j[b]).length();
        series[0].extend([d(0, 2), d(1, 3)]);
        series[1].extend([d(2, 4), d(3, 5)]);
        series[2].extend([d(6, 8), d(7, 9)]);
        series[3].extend([d(8, 10), d(9, 11)]);
        series[4].push(d(0, 1));
        series[5].push(d(6, 7));
        // The trunk is measured from the lumbar joint (straight above the
        // hips' middle), which is where the body bends it.
        let hips = 0.5 * (j[6] + j[7]);
        let shoulders = 0.5 * (j[0] + j[1]);
        series[6].push((shoulders - (hips + DVec3::Z * lumbar)).length() + lumbar);
    }
    let mut v = [f64::NAN; 7];
    for (k, s) in series.iter_mut().enumerate() {
        v[k] = quantile(s, 0.5);
    }
    // The arm reaches as far as the recorded wrist goes from the recorded
    // shoulder (95th percentile): a tracker's shoulder keypoint moves out
    // with a raised or outstretched arm, so the medians of the upper arm
    // and forearm fall short of the outstretched arm, where the hand is.
    let mut reach: Vec<f64> = frames
        .iter()
        .flat_map(|j| [(j[0] - j[4]).length(), (j[1] - j[5]).length()])
        .collect();
    let reach = quantile(&mut reach, 0.95);
    let arm = v[0] + v[1];
    if reach > arm && arm > 0.0 {
        v[0] *= reach / arm;
        v[1] *= reach / arm;
    }
    Segments::from_values(v).clamped(h)
}

/// The `q` quantile of the finite values of `s` (sorted in place; the
/// element at rank ⌊q·n⌋, NaN when none).
fn quantile(s: &mut Vec<f64>, q: f64) -> f64 {
    s.retain(|x| x.is_finite());
    s.sort_by(f64::total_cmp);
    let k = ((q * s.len() as f64) as usize).min(s.len().saturating_sub(1));
    s.get(k).copied().unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportional_segments_are_plausible_and_others_are_refused() {
        let s = Segments::proportional(1.75);
        assert!(s.validate(1.75).is_ok());
        let long = Segments { forearm: 0.6, ..s };
        let e = long.validate(1.75).unwrap_err();
        assert!(e.to_string().starts_with("forearm: must be in"), "{e}");
        assert_eq!(long.clamped(1.75).forearm, 1.4 * s.forearm);
        let nan = Segments {
            trunk: f64::NAN,
            ..s
        };
        assert!(
            nan.validate(1.75)
                .unwrap_err()
                .to_string()
                .starts_with("trunk")
        );
    }
}
