//! The joint angles of a [`Pose`]: their names, their ranges and their JSON
//! form (an object with any subset of the names, the others zero).

use std::collections::BTreeMap;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::error::{FieldError, finite};

/// Number of joint angles of a [`Pose`].
pub const JOINT_COUNT: usize = 23;

/// A joint angle: its JSON name and the range of motion of the body
/// (rad; the active ranges of healthy adults, rounded, after the AAOS
/// tables, with the shoulder's elevation reaching overhead; the shoulder
/// girdle's, at the sternoclavicular joint, after Neumann, *Kinesiology of
/// the Musculoskeletal System*, ch. 5: elevation up to 45° and depression
/// 10°, protraction and retraction 15–20° each way, taken as 20°).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointRange {
    /// JSON name (`leftElbow`).
    pub name: &'static str,
    /// Smallest angle (rad).
    pub min: f64,
    /// Largest angle (rad).
    pub max: f64,
}

const fn j(name: &'static str, min: f64, max: f64) -> JointRange {
    JointRange { name, min, max }
}

/// Every joint angle of a [`Pose`], in the order of [`Pose::angles`].
///
/// Signs (body frame: x forward, y to the person's left, z up; every angle
/// is zero standing upright, arms hanging, legs straight):
/// - `spineFlexion` bends the trunk forward, `spineLateral` to the left,
///   `spineTwist` turns the chest to the left;
/// - `neckFlexion` tips the head forward, `neckTwist` turns it left;
/// - `*ShoulderFlexion` raises the arm forward (π/2: horizontal, pointing
///   ahead), `*ShoulderAbduction` raises it sideways away from the body,
///   `*ShoulderRotation` turns the upper arm about its own axis (positive
///   swings a bent forearm across the body, internal rotation);
/// - `*Elbow` bends the forearm towards the upper arm's front;
/// - `*HipFlexion` swings the thigh forward, `*HipAbduction` sideways away
///   from the body, `*Knee` bends the shin backwards;
/// - `*ShoulderElevation` turns the clavicle about the sternoclavicular
///   joint (the middle of the shoulders) raising the shoulder joint,
///   `*ShoulderProtraction` turns it bringing the shoulder joint forward
///   (negative: retraction); they move the shoulder joint, not the arm's
///   orientation (the arm's angles stay relative to the trunk).
pub const JOINTS: [JointRange; JOINT_COUNT] = [
    j("spineFlexion", -0.5, 1.6),
    j("spineLateral", -0.6, 0.6),
    j("spineTwist", -0.8, 0.8),
    j("neckFlexion", -1.0, 1.0),
    j("neckTwist", -1.4, 1.4),
    j("leftShoulderFlexion", -1.0, 3.15),
    j("leftShoulderAbduction", -0.9, 3.15),
    j("leftShoulderRotation", -1.6, 1.6),
    j("leftElbow", 0.0, 2.6),
    j("rightShoulderFlexion", -1.0, 3.15),
    j("rightShoulderAbduction", -0.9, 3.15),
    j("rightShoulderRotation", -1.6, 1.6),
    j("rightElbow", 0.0, 2.6),
    j("leftHipFlexion", -0.5, 2.1),
    j("leftHipAbduction", -0.5, 0.8),
    j("leftKnee", 0.0, 2.4),
    j("rightHipFlexion", -0.5, 2.1),
    j("rightHipAbduction", -0.5, 0.8),
    j("rightKnee", 0.0, 2.4),
    j("leftShoulderElevation", -0.17, 0.79),
    j("leftShoulderProtraction", -0.35, 0.35),
    j("rightShoulderElevation", -0.17, 0.79),
    j("rightShoulderProtraction", -0.35, 0.35),
];

/// Indices into [`Pose::angles`] by name.
#[allow(missing_docs)]
pub mod joint {
    pub const SPINE_FLEXION: usize = 0;
    pub const SPINE_LATERAL: usize = 1;
    pub const SPINE_TWIST: usize = 2;
    pub const NECK_FLEXION: usize = 3;
    pub const NECK_TWIST: usize = 4;
    /// First joint of the left arm (flexion, abduction, rotation, elbow).
    pub const LEFT_ARM: usize = 5;
    /// First joint of the right arm.
    pub const RIGHT_ARM: usize = 9;
    /// First joint of the left leg (hip flexion, hip abduction, knee).
    pub const LEFT_LEG: usize = 13;
    /// First joint of the right leg.
    pub const RIGHT_LEG: usize = 16;
    /// The left shoulder girdle (elevation, protraction).
    pub const LEFT_GIRDLE: usize = 19;
    /// The right shoulder girdle.
    pub const RIGHT_GIRDLE: usize = 21;
}

/// The index of joint `name` in [`JOINTS`].
#[must_use]
pub fn joint_index(name: &str) -> Option<usize> {
    JOINTS.iter().position(|j| j.name == name)
}

/// Joint angles of a human (rad), in the order of [`JOINTS`].
///
/// In JSON an object naming any subset of the joints
/// (`{ "leftElbow": 1.2 }`); the others are zero, an unknown name is refused.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// The angles (rad), in the order of [`JOINTS`].
    pub angles: [f64; JOINT_COUNT],
}

impl Pose {
    /// Checks that every angle is finite and within the body's range.
    ///
    /// # Errors
    /// `leftElbow: not a finite number`, `leftElbow: 3 is beyond the body's
    /// range [0, 2.6] rad`.
    pub fn validate(&self) -> Result<(), FieldError> {
        for (a, r) in self.angles.iter().zip(&JOINTS) {
            finite(r.name, *a)?;
            if *a < r.min || *a > r.max {
                return Err(FieldError::new(
                    r.name,
                    format!("{a} is beyond the body's range [{}, {}] rad", r.min, r.max),
                ));
            }
        }
        Ok(())
    }

    /// The same pose with every angle clamped into the body's range (NaN
    /// becomes 0).
    #[must_use]
    pub fn clamped(&self) -> Self {
        let mut out = *self;
        for (a, r) in out.angles.iter_mut().zip(&JOINTS) {
            *a = if a.is_nan() {
                0.0
            } else {
                a.clamp(r.min, r.max)
            };
        }
        out
    }
}

impl Serialize for Pose {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let map: BTreeMap<&str, f64> = JOINTS
            .iter()
            .zip(self.angles)
            .filter(|(_, a)| *a != 0.0)
            .map(|(j, a)| (j.name, a))
            .collect();
        map.serialize(s)
    }
}

impl<'de> Deserialize<'de> for Pose {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let map = BTreeMap::<String, f64>::deserialize(d)?;
        let mut pose = Self::default();
        for (name, a) in map {
            let Some(k) = joint_index(&name) else {
                return Err(serde::de::Error::custom(format!(
                    "unknown joint `{name}` (expected one of {})",
                    JOINTS.map(|j| j.name).join(", ")
                )));
            };
            pose.angles[k] = a;
        }
        Ok(pose)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_ranges_hold_zero() {
        for (k, r) in JOINTS.iter().enumerate() {
            assert_eq!(joint_index(r.name), Some(k));
            assert!(r.min <= 0.0 && r.max >= 0.0, "{}", r.name);
        }
    }

    #[test]
    fn json_names_the_joint() {
        let p: Pose = serde_json::from_str(r#"{ "leftElbow": 1.5 }"#).unwrap();
        assert_eq!(p.angles[joint::LEFT_ARM + 3], 1.5);
        let e = serde_json::from_str::<Pose>(r#"{ "leftElbo": 1.5 }"#).unwrap_err();
        assert!(e.to_string().contains("leftElbo"), "{e}");
        let p: Pose = serde_json::from_str(r#"{ "leftElbow": 3.0 }"#).unwrap();
        let e = p.validate().unwrap_err();
        assert_eq!(e.field, "leftElbow");
        assert_eq!(p.clamped().angles[8], 2.6);
    }
}
