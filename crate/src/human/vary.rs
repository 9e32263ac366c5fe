//! How a Monte Carlo study varies a human from run to run (`vary` on the
//! human's shape): body height, the clip's speed, the motion of the
//! library, the keypoints' sensing σ. `simulate` and a `World` use the
//! human as given; only a study draws.

use serde::{Deserialize, Serialize};

use super::library::CLIP_NAMES;
use super::spec::{HumanSpec, MAX_HEIGHT, MAX_PART_SIGMA};
use crate::error::{FieldError, finite};
use crate::rng::Rng;

/// Fastest clip speed a study may draw (m/s).
pub const MAX_VARY_SPEED: f64 = 10.0;

/// What a study draws for a human in each run; every field optional.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct HumanVariation {
    /// Body height, uniform in `[min, max]` (m, in (0, 3]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<[f64; 2]>,
    /// The clip's `speed` (a reach's hand speed, a walk's pace), uniform in
    /// `[min, max]` (m/s, in (0, 10]); a `linear` motion of the obstacle
    /// is rescaled to the same speed (a walk's travel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<[f64; 2]>,
    /// Motions of the library, one drawn uniformly per run (replacing the
    /// animation's clip, its other parameters kept).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clips: Option<Vec<String>>,
    /// One σ for every part (keypoint noise of the run's sensor, m),
    /// uniform in `[min, max]` (in [0, 1]); replaces `partSigma`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub part_sigma: Option<[f64; 2]>,
}

fn range(field: &str, r: [f64; 2], lo: f64, hi: f64, open: bool) -> Result<(), FieldError> {
    for (k, x) in r.iter().enumerate() {
        finite(&format!("{field}[{k}]"), *x)?;
        let low = if open { *x <= lo } else { *x < lo };
        if low || *x > hi {
            let bracket = if open { "(" } else { "[" };
            return Err(FieldError::new(
                format!("{field}[{k}]"),
                format!("must be in {bracket}{lo}, {hi}] (got {x})"),
            ));
        }
    }
    if r[0] > r[1] {
        return Err(FieldError::new(field, "expected [min, max] with min ≤ max"));
    }
    Ok(())
}

impl HumanVariation {
    /// Checks the ranges and the clips against `human` (a `reach` needs
    /// the animation's `target`; a `speed` needs a clip).
    ///
    /// # Errors
    /// `height[1]: must be in (0, 3] …`, `speed: expected [min, max] …`,
    /// `clips[2]: unknown motion …`, `clips: needs at least one`,
    /// `clips[0]: reach needs the animation's target`, `speed: only a clip
    /// has a speed …`, `partSigma[0]: …`.
    pub fn validate(&self, human: &HumanSpec) -> Result<(), FieldError> {
        if let Some(h) = self.height {
            range("height", h, 0.0, MAX_HEIGHT, true)?;
        }
        if let Some(s) = self.part_sigma {
            range("partSigma", s, 0.0, MAX_PART_SIGMA, false)?;
        }
        let animation = human.animation.as_deref();
        if let Some(clips) = &self.clips {
            if clips.is_empty() {
                return Err(FieldError::new("clips", "needs at least one"));
            }
            for (k, c) in clips.iter().enumerate() {
                if !CLIP_NAMES.contains(&c.as_str()) {
                    return Err(FieldError::new(
                        format!("clips[{k}]"),
                        format!(
                            "unknown motion \"{c}\" (expected one of {})",
                            CLIP_NAMES.join(", ")
                        ),
                    ));
                }
                if c == "reach" && animation.and_then(|a| a.target).is_none() {
                    return Err(FieldError::new(
                        format!("clips[{k}]"),
                        "reach needs the animation's target",
                    ));
                }
            }
        }
        if let Some(s) = self.speed {
            range("speed", s, 0.0, MAX_VARY_SPEED, true)?;
            if self.clips.is_none() && animation.and_then(|a| a.clip.as_ref()).is_none() {
                return Err(FieldError::new(
                    "speed",
                    "only a clip has a speed (give the animation a clip, or clips)",
                ));
            }
        }
        Ok(())
    }

    /// `human` as drawn for one run from `rng`, and the speed drawn (if
    /// any). Four numbers are drawn whatever the fields, so that adding
    /// one leaves the others' draws as they were.
    #[must_use]
    pub fn draw(&self, human: &HumanSpec, rng: &mut Rng) -> (HumanSpec, Option<f64>) {
        let pick = |r: Option<[f64; 2]>, u: f64| r.map(|[lo, hi]| lo + (hi - lo) * u);
        let u: [f64; 4] = std::array::from_fn(|_| rng.uniform());
        let mut out = human.clone();
        out.vary = None;
        if let Some(h) = pick(self.height, u[0]) {
            out.height = h;
        }
        let speed = pick(self.speed, u[1]);
        if let Some(clips) = self.clips.as_ref().filter(|c| !c.is_empty()) {
            let k = ((u[2] * clips.len() as f64) as usize).min(clips.len() - 1);
            let a = out.animation.get_or_insert_with(Default::default);
            a.keyframes = None;
            a.clip = Some(clips[k].clone());
        }
        if let (Some(s), Some(a)) = (speed, out.animation.as_mut()) {
            a.speed = Some(s);
        }
        if let Some(s) = pick(self.part_sigma, u[3]) {
            out.part_sigma = Some(
                super::PART_NAMES
                    .iter()
                    .map(|n| ((*n).to_owned(), s))
                    .collect(),
            );
        }
        (out, speed)
    }
}
