//! Keypoint layouts: COCO-17, OpenPose BODY-25 and Azure Kinect Body
//! Tracking (32 joints), their keypoint names and where the joints the fit
//! needs sit in each.

use glam::DVec3;

use crate::error::FieldError;

/// A keypoint layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// COCO-17 (`coco17`): nose, eyes, ears, shoulders, elbows, wrists, hips,
    /// knees, ankles.
    Coco17,
    /// OpenPose BODY-25 (`body25`): COCO's joints plus neck, mid-hip, toes
    /// and heels.
    Body25,
    /// Azure Kinect Body Tracking (`kinect32`): 32 joints from the pelvis
    /// to the hand tips.
    Kinect32,
}

const COCO17: [&str; 17] = [
    "nose",
    "leftEye",
    "rightEye",
    "leftEar",
    "rightEar",
    "leftShoulder",
    "rightShoulder",
    "leftElbow",
    "rightElbow",
    "leftWrist",
    "rightWrist",
    "leftHip",
    "rightHip",
    "leftKnee",
    "rightKnee",
    "leftAnkle",
    "rightAnkle",
];

const BODY25: [&str; 25] = [
    "nose",
    "neck",
    "rightShoulder",
    "rightElbow",
    "rightWrist",
    "leftShoulder",
    "leftElbow",
    "leftWrist",
    "midHip",
    "rightHip",
    "rightKnee",
    "rightAnkle",
    "leftHip",
    "leftKnee",
    "leftAnkle",
    "rightEye",
    "leftEye",
    "rightEar",
    "leftEar",
    "leftBigToe",
    "leftSmallToe",
    "leftHeel",
    "rightBigToe",
    "rightSmallToe",
    "rightHeel",
];

const KINECT32: [&str; 32] = [
    "pelvis",
    "spineNavel",
    "spineChest",
    "neck",
    "leftClavicle",
    "leftShoulder",
    "leftElbow",
    "leftWrist",
    "leftHand",
    "leftHandTip",
    "leftThumb",
    "rightClavicle",
    "rightShoulder",
    "rightElbow",
    "rightWrist",
    "rightHand",
    "rightHandTip",
    "rightThumb",
    "leftHip",
    "leftKnee",
    "leftAnkle",
    "leftFoot",
    "rightHip",
    "rightKnee",
    "rightAnkle",
    "rightFoot",
    "head",
    "nose",
    "leftEye",
    "leftEar",
    "rightEye",
    "rightEar",
];

/// The joints the fit reads, in this order ([`Layout::needed`]).
pub const NEEDED: [&str; 14] = [
    "leftShoulder",
    "rightShoulder",
    "leftElbow",
    "rightElbow",
    "leftWrist",
    "rightWrist",
    "leftHip",
    "rightHip",
    "leftKnee",
    "rightKnee",
    "leftAnkle",
    "rightAnkle",
    // The head's centre: the middle of the ears (COCO, BODY-25) or the
    // head joint (Kinect) — both entries name the keypoints averaged.
    "leftEar",
    "rightEar",
];

impl Layout {
    /// The layout named `name` (`coco17`, `body25`, `kinect32`).
    ///
    /// # Errors
    /// `layout: unknown layout …`.
    pub fn from_name(name: &str) -> Result<Self, FieldError> {
        match name {
            "coco17" => Ok(Self::Coco17),
            "body25" => Ok(Self::Body25),
            "kinect32" => Ok(Self::Kinect32),
            other => Err(FieldError::new(
                "layout",
                format!("unknown layout \"{other}\" (expected coco17, body25 or kinect32)"),
            )),
        }
    }

    /// Its name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Coco17 => "coco17",
            Self::Body25 => "body25",
            Self::Kinect32 => "kinect32",
        }
    }

    /// The keypoint names, in the layout's order.
    #[must_use]
    pub fn names(self) -> &'static [&'static str] {
        match self {
            Self::Coco17 => &COCO17,
            Self::Body25 => &BODY25,
            Self::Kinect32 => &KINECT32,
        }
    }

    /// The index of keypoint `name`.
    #[must_use]
    pub fn index(self, name: &str) -> Option<usize> {
        self.names().iter().position(|n| *n == name)
    }

    /// For each of [`NEEDED`], the keypoints (indices) averaged; the head
    /// of Kinect is its `head` joint (twice).
    #[must_use]
    pub fn needed(self) -> [usize; 14] {
        let mut out = [0; 14];
        for (o, n) in out.iter_mut().zip(NEEDED) {
            let n = match (self, n) {
                (Self::Kinect32, "leftEar" | "rightEar") => "head",
                _ => n,
            };
            *o = self.index(n).unwrap_or(0);
        }
        out
    }
}

/// Where every keypoint of `layout` sits on a body given its joints
/// (`j`: the [`NEEDED`] joints with the head's centre in both ear slots),
/// its hands' and feet's ends, its left and forward directions and its
/// height: the synthetic recordings' model of the joints the fit does not
/// read (eyes, toes, clavicles, …).
pub(crate) struct Anchors {
    pub j: [DVec3; 14],
    pub hand: [(DVec3, DVec3); 2],
    pub foot: [(DVec3, DVec3); 2],
    pub left: DVec3,
    pub forward: DVec3,
    pub height: f64,
}

impl Anchors {
    /// The position of keypoint `name`.
    pub(crate) fn at(&self, name: &str) -> DVec3 {
        let j = |n: &str| self.j[NEEDED.iter().position(|x| *x == n).unwrap_or(0)];
        let head = j("leftEar");
        let (l, f, h) = (self.left, self.forward, self.height);
        let neck = 0.5 * (j("leftShoulder") + j("rightShoulder"));
        let pelvis = 0.5 * (j("leftHip") + j("rightHip"));
        match name {
            "leftEar" => head + l * (0.06 * h),
            "rightEar" => head - l * (0.06 * h),
            "head" => head,
            "nose" => head + f * (0.055 * h),
            "leftEye" => head + f * (0.045 * h) + l * (0.02 * h) + DVec3::Z * (0.015 * h),
            "rightEye" => head + f * (0.045 * h) - l * (0.02 * h) + DVec3::Z * (0.015 * h),
            "neck" => neck,
            "midHip" | "pelvis" => pelvis,
            "spineNavel" => pelvis.lerp(neck, 0.35),
            "spineChest" => pelvis.lerp(neck, 0.7),
            "leftClavicle" => neck.lerp(j("leftShoulder"), 0.5),
            "rightClavicle" => neck.lerp(j("rightShoulder"), 0.5),
            "leftHand" | "leftThumb" => self.hand[0].0.lerp(self.hand[0].1, 0.5),
            "rightHand" | "rightThumb" => self.hand[1].0.lerp(self.hand[1].1, 0.5),
            "leftHandTip" => self.hand[0].1,
            "rightHandTip" => self.hand[1].1,
            "leftBigToe" | "leftFoot" => self.foot[0].1,
            "rightBigToe" | "rightFoot" => self.foot[1].1,
            "leftSmallToe" => self.foot[0].1 + l * (0.02 * h),
            "rightSmallToe" => self.foot[1].1 - l * (0.02 * h),
            "leftHeel" => self.foot[0].0,
            "rightHeel" => self.foot[1].0,
            other => j(other),
        }
    }
}
