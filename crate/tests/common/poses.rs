//! Joint configurations shared by the tests that start from them.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

/// The Panda's "ready" pose (franka_ros' default).
pub const PANDA_READY: [f64; 7] = [
    0.0,
    -FRAC_PI_4,
    0.0,
    -3.0 * FRAC_PI_4,
    0.0,
    FRAC_PI_2,
    FRAC_PI_4,
];
