//! Keypoint layouts: COCO-17, OpenPose BODY-25, Azure Kinect Body
//! Tracking (32 joints) and MediaPipe BlazePose (33 landmarks), their
//! keypoint names and where the joints the fit needs sit in each.

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
    /// MediaPipe BlazePose (`blazepose33`): 33 landmarks, COCO's joints
    /// plus the eyes' corners, the mouth, and per hand pinky, index and
    /// thumb, per foot heel and toe (`foot_index`).
    BlazePose33,
}

/// Every layout's name, as the errors list them.
pub const LAYOUT_NAMES: &str = "coco17, body25, kinect32 or blazepose33";

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

const BLAZEPOSE33: [&str; 33] = [
    "nose",
    "leftEyeInner",
    "leftEye",
    "leftEyeOuter",
    "rightEyeInner",
    "rightEye",
    "rightEyeOuter",
    "leftEar",
    "rightEar",
    "mouthLeft",
    "mouthRight",
    "leftShoulder",
    "rightShoulder",
    "leftElbow",
    "rightElbow",
    "leftWrist",
    "rightWrist",
    "leftPinky",
    "rightPinky",
    "leftIndex",
    "rightIndex",
    "leftThumb",
    "rightThumb",
    "leftHip",
    "rightHip",
    "leftKnee",
    "rightKnee",
    "leftAnkle",
    "rightAnkle",
    "leftHeel",
    "rightHeel",
    "leftFootIndex",
    "rightFootIndex",
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
    /// The layout named `name` (`coco17`, `body25`, `kinect32`,
    /// `blazepose33`).
    ///
    /// # Errors
    /// `layout: unknown layout …`.
    pub fn from_name(name: &str) -> Result<Self, FieldError> {
        match name {
            "coco17" => Ok(Self::Coco17),
            "body25" => Ok(Self::Body25),
            "kinect32" => Ok(Self::Kinect32),
            "blazepose33" => Ok(Self::BlazePose33),
            other => Err(FieldError::new(
                "layout",
                format!("unknown layout \"{other}\" (expected {LAYOUT_NAMES})"),
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
            Self::BlazePose33 => "blazepose33",
        }
    }

    /// The keypoint names, in the layout's order.
    #[must_use]
    pub fn names(self) -> &'static [&'static str] {
        match self {
            Self::Coco17 => &COCO17,
            Self::Body25 => &BODY25,
            Self::Kinect32 => &KINECT32,
            Self::BlazePose33 => &BLAZEPOSE33,
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
