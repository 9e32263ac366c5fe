//! Kinect v2 recordings (`tests/data/recordings/`), shared by the tests
//! that read them: which `kinect32` keypoint each recorded joint is.

/// Kinect v2 joint `JointType` index → the `kinect32` keypoint that names
/// the same joint (Azure Kinect numbers them differently: mapped by name).
pub const KINECT2: [(usize, &str); 19] = [
    (0, "pelvis"),
    (1, "spineNavel"),
    (2, "neck"),
    (3, "head"),
    (4, "leftShoulder"),
    (5, "leftElbow"),
    (6, "leftWrist"),
    (7, "leftHand"),
    (8, "rightShoulder"),
    (9, "rightElbow"),
    (10, "rightWrist"),
    (11, "rightHand"),
    (12, "leftHip"),
    (13, "leftKnee"),
    (14, "leftAnkle"),
    (15, "leftFoot"),
    (16, "rightHip"),
    (17, "rightKnee"),
    (18, "rightAnkle"),
];
