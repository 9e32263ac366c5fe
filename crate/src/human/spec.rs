//! The JSON form of a human ([`HumanSpec`]: `{ "type": "human", … }`) and
//! its checked, ready-to-pose form ([`Human`]).

use std::collections::BTreeMap;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::animation::{Animation, Keyframe};
use super::body::{PART_NAMES, Posed, Root, pose_sized};
use super::library;
use super::pose::{JOINT_COUNT, Pose, joint};
use super::segments::{Dims, Segments};
use crate::error::{FieldError, finite, finite3, positive};

/// A person: an articulated body (pelvis, trunk, neck and head, arms with
/// hands, legs with feet) standing at `position`, facing `heading`, sized
/// by `height`, posed by `pose` and moved by `animation`.
///
/// The fields of the rigid figure of earlier versions (`position`,
/// `heading`, `height`, `reach`) keep their meaning: a scenario that gives
/// only those shows the same person at rest, arms raised forward by
/// `reach`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct HumanSpec {
    /// Point on the floor between the feet (m).
    pub position: [f64; 3],
    /// Direction the person faces, about z from +x (rad; default 0).
    #[serde(default)]
    pub heading: f64,
    /// Height (m, > 0, at most 3; default 1.75); the body scales with it.
    #[serde(default = "default_height")]
    pub height: f64,
    /// The subject's own segment lengths (default: Drillis & Contini's
    /// proportions of `height`; an imported track measures them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segments: Option<Segments>,
    /// Arm elevation of the rest pose when no `pose` is given: 0 hanging
    /// down, 1 straight forward (default 0.5; both shoulders flex by
    /// `reach · π/2`).
    #[serde(default = "default_reach")]
    pub reach: f64,
    /// Joint angles at rest (rad; replaces `reach` when given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose: Option<Box<Pose>>,
    /// Keyframes or a motion of the library.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<Box<AnimationSpec>>,
    /// Sensing error of single parts, by part name (`{ "rightHand": 0.04
    /// }`): the standard deviation per axis (m, ≥ 0, at most
    /// [`MAX_PART_SIGMA`]) of white Gaussian noise on the position of the
    /// keypoints that place the part, on top of the obstacle's own
    /// `sensing` (see `docs/scenarios.md`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub part_sigma: Option<BTreeMap<String, f64>>,
    /// What a Monte Carlo study draws for this person in each run (height,
    /// clip speed, motion, keypoint noise; `docs/monte-carlo.md`); ignored
    /// by a single simulation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vary: Option<Box<super::vary::HumanVariation>>,
}

/// Largest per-part sensing σ accepted (m).
pub const MAX_PART_SIGMA: f64 = 1.0;

fn default_height() -> f64 {
    1.75
}

fn default_reach() -> f64 {
    0.5
}

/// Tallest human accepted (m).
pub const MAX_HEIGHT: f64 = 3.0;

/// How a human moves its limbs: `keyframes` (with `loop`), or a `clip` of
/// the library ([`super::library`]) with its parameters.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct AnimationSpec {
    /// Keyframes (times in s from the start of the scenario).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub keyframes: Option<Vec<Keyframe>>,
    /// Repeat the keyframes (default false; clips set their own).
    #[serde(default, rename = "loop", skip_serializing_if = "Option::is_none")]
    pub repeat: Option<bool>,
    /// A motion of the library: `reach`, `wave`, `walk`, `bend`, `stepBack`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clip: Option<String>,
    /// `reach`: the point the hand reaches for (m, world frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<[f64; 3]>,
    /// `reach`, `wave`: which hand, `left` or `right` (default right).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side: Option<String>,
    /// `reach`: the hand's peak speed (m/s, default 1); `walk`: the
    /// walking speed the stride is sized for (m/s, default 1.4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<f64>,
    /// When the clip begins (s, default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<f64>,
}

/// A checked human, ready to pose at any time.
#[derive(Clone, Debug, PartialEq)]
pub struct Human {
    spec: HumanSpec,
    rest: Pose,
    animation: Option<Animation>,
    part_sigma: [f64; PART_NAMES.len()],
}

impl HumanSpec {
    /// The rest pose: `pose`, or both shoulders flexed by `reach · π/2`.
    #[must_use]
    pub fn rest_pose(&self) -> Pose {
        self.pose.as_deref().copied().unwrap_or_else(|| {
            let mut p = Pose::default();
            let f = self.reach.clamp(0.0, 1.0) * std::f64::consts::FRAC_PI_2;
            p.angles[joint::LEFT_ARM] = f;
            p.angles[joint::RIGHT_ARM] = f;
            p
        })
    }

    /// The height and the segment lengths the body is posed with.
    #[must_use]
    pub fn dims(&self) -> Dims {
        Dims::new(self.height, self.segments.as_ref())
    }

    /// The parts at rest (before any animation), as primitives.
    #[must_use]
    pub fn parts(&self) -> Vec<crate::distance::PrimitiveSpec> {
        let root = Root {
            position: DVec3::from_array(self.position),
            heading: self.heading,
            ..Root::default()
        };
        pose_sized(&self.dims(), &root, &self.rest_pose(), &[0.0; JOINT_COUNT])
            .parts
            .into_iter()
            .map(|p| p.shape)
            .collect()
    }

    /// Checks every value and prepares the animation.
    ///
    /// # Errors
    /// `position[1]: not a finite number`, `height: must be > 0`,
    /// `pose.leftElbow: … beyond the body's range …`,
    /// `animation.keyframes[2].t: must increase`, `animation.clip: unknown
    /// motion …`, …
    pub fn compile(&self) -> Result<Human, FieldError> {
        finite3("position", DVec3::from_array(self.position))?;
        finite("heading", self.heading)?;
        positive("height", self.height)?;
        if self.height > MAX_HEIGHT {
            return Err(FieldError::new(
                "height",
                format!("at most {MAX_HEIGHT} m (got {})", self.height),
            ));
        }
        if let Some(seg) = &self.segments {
            seg.validate(self.height)
                .map_err(|e| e.within("segments"))?;
        }
        finite("reach", self.reach)?;
        if let Some(p) = &self.pose {
            p.validate().map_err(|e| e.within("pose"))?;
        }
        let animation = match &self.animation {
            None => None,
            Some(a) => Some(self.animation_of(a).map_err(|e| e.within("animation"))?),
        };
        if let Some(v) = &self.vary {
            v.validate(self).map_err(|e| e.within("vary"))?;
        }
        let mut part_sigma = [0.0; PART_NAMES.len()];
        for (name, &sigma) in self.part_sigma.iter().flatten() {
            let field = format!("partSigma.{name}");
            let Some(k) = PART_NAMES.iter().position(|n| n == name) else {
                return Err(FieldError::new(
                    field,
                    format!("unknown part (expected one of {})", PART_NAMES.join(", ")),
                ));
            };
            finite(&field, sigma)?;
            if !(0.0..=MAX_PART_SIGMA).contains(&sigma) {
                return Err(FieldError::new(
                    field,
                    format!("must be in [0, {MAX_PART_SIGMA}] m (got {sigma})"),
                ));
            }
            part_sigma[k] = sigma;
        }
        Ok(Human {
            spec: self.clone(),
            rest: self.rest_pose(),
            animation,
            part_sigma,
        })
    }

    fn animation_of(&self, a: &AnimationSpec) -> Result<Animation, FieldError> {
        match (&a.keyframes, &a.clip) {
            (Some(_), Some(_)) => Err(FieldError::new(
                "clip",
                "give either keyframes or a clip, not both",
            )),
            (None, None) => Err(FieldError::new("keyframes", "give keyframes or a clip")),
            (Some(k), None) => Animation::new(k, a.repeat.unwrap_or(false)),
            (None, Some(name)) => {
                let (keys, repeat) = library::clip(self, name, a)?;
                Animation::new(&keys, a.repeat.unwrap_or(repeat))
            }
        }
    }
}

impl Human {
    /// The spec it was made from.
    #[must_use]
    pub fn spec(&self) -> &HumanSpec {
        &self.spec
    }

    /// The sensing σ of each part (m), in the order of [`PART_NAMES`]
    /// (zero where `partSigma` names none).
    #[must_use]
    pub fn part_sigma(&self) -> &[f64; PART_NAMES.len()] {
        &self.part_sigma
    }

    /// Whether some part has its own sensing σ.
    #[must_use]
    pub fn has_part_sigma(&self) -> bool {
        self.part_sigma.iter().any(|s| *s > 0.0)
    }

    /// Whether its limbs move.
    #[must_use]
    pub fn animated(&self) -> bool {
        self.animation.is_some()
    }

    /// The body at time `t` (s), its root displaced by `offset` (m) moving
    /// at `offset_velocity` (m/s, the obstacle's motion): every part with
    /// the velocities of its end points.
    #[must_use]
    pub fn posed_at(&self, t: f64, offset: DVec3, offset_velocity: DVec3) -> Posed {
        let (root, x) = self.sampled(t, offset, offset_velocity);
        pose_sized(&self.spec.dims(), &root, &x.pose, &x.rates)
    }

    /// The root and the joint angles at time `t` (s), before any motion
    /// of the obstacle.
    #[must_use]
    pub fn pose_at(&self, t: f64) -> (Root, Pose) {
        let (root, x) = self.sampled(t, DVec3::ZERO, DVec3::ZERO);
        (root, x.pose)
    }

    fn sampled(
        &self,
        t: f64,
        offset: DVec3,
        offset_velocity: DVec3,
    ) -> (Root, super::animation::Sampled) {
        let s = &self.spec;
        let turn = super::body::rotation(DVec3::Z, s.heading);
        let base = DVec3::from_array(s.position) + offset;
        let x = match &self.animation {
            Some(a) => a.sample(t),
            None => super::animation::Sampled {
                pose: self.rest,
                ..Default::default()
            },
        };
        let root = Root {
            position: base + turn * x.shift,
            heading: s.heading + x.turn,
            velocity: offset_velocity + turn * x.shift_rate,
            heading_rate: x.turn_rate,
        };
        (root, x)
    }
}
