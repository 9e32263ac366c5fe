//! Robot presets, with DH values from the manufacturers' or the standard
//! literature's published tables.
//!
//! | name | robot | convention | source of the table |
//! |---|---|---|---|
//! | `planar3` | the paper's planar 3-link arm, links 0.4 / 0.3 / 0.2 m | standard | De Santis & Siciliano, §III-B, fig. 5 |
//! | `lwr4` | KUKA LWR4+ (DLR LWR III kinematics), 7 DOF | standard | Gaz, Flacco, Ficuciello, De Luca, ICRA 2016 (d₃ = 0.4, d₅ = 0.39 m); the 0.3105 m base column and the 0.078 m flange are folded into d₁ and d₇ so that the skeleton covers them; limits and speeds from KUKA's LWR4+ specification |
//! | `panda` | Franka Emika Panda, 7 DOF | modified (Craig) | Franka Control Interface documentation, "Robot and interface specifications"; the 0.107 m flange is folded into d₇ (a translation along z₇ commutes with θ₇) |
//! | `ur5` | Universal Robots UR5 (CB3), 6 DOF | standard | Universal Robots, "DH parameters for calculations of kinematics and dynamics" |
//! | `dual-arm` | a yawing torso carrying two LWR-like 7-DOF arms, in the spirit of DLR's Justin | standard | this project: torso column 0.9 m, shoulders 0.25 m either side of the chest, arms as `lwr4` |
//!
//! Link radii are sensible envelopes for each segment (m), not manufacturer
//! data.

use std::f64::consts::{FRAC_PI_2, PI};

use super::spec::{BranchSpec, Convention, JointSpec, JointType, RadiusSpec, RobotSpec};
use crate::error::FieldError;

/// Names accepted by [`preset`].
pub const NAMES: [&str; 5] = ["planar3", "lwr4", "panda", "ur5", "dual-arm"];

fn row(a: f64, alpha: f64, d: f64, radius: f64) -> JointSpec {
    JointSpec {
        a,
        alpha,
        d,
        theta: 0.0,
        kind: JointType::Revolute,
        min: None,
        max: None,
        max_velocity: None,
        radius: Some(RadiusSpec::Uniform(radius)),
        extension: None,
    }
}

fn limited(mut j: JointSpec, min: f64, max: f64, max_velocity: f64) -> JointSpec {
    j.min = Some(min);
    j.max = Some(max);
    j.max_velocity = Some(max_velocity);
    j
}

fn deg(x: f64) -> f64 {
    x.to_radians()
}

fn lwr_rows(d1: f64) -> Vec<JointSpec> {
    let l170 = deg(170.0);
    let l120 = deg(120.0);
    let v = deg(112.5);
    let v5 = deg(180.0);
    vec![
        limited(row(0.0, FRAC_PI_2, d1, 0.07), -l170, l170, v),
        limited(row(0.0, -FRAC_PI_2, 0.0, 0.07), -l120, l120, v),
        limited(row(0.0, -FRAC_PI_2, 0.4, 0.065), -l170, l170, v),
        limited(row(0.0, FRAC_PI_2, 0.0, 0.065), -l120, l120, v),
        limited(row(0.0, FRAC_PI_2, 0.39, 0.06), -l170, l170, v5),
        limited(row(0.0, -FRAC_PI_2, 0.0, 0.06), -l120, l120, v),
        limited(row(0.0, 0.0, 0.078, 0.045), -l170, l170, v),
    ]
}

fn spec(name: &str, convention: Convention, joints: Vec<JointSpec>) -> RobotSpec {
    RobotSpec {
        name: Some(name.to_owned()),
        convention,
        base: None,
        joints,
        tool: None,
        branches: Vec::new(),
    }
}

/// The robot spec of a preset.
///
/// # Errors
/// `preset: unknown robot "x" (known: planar3, lwr4, panda, ur5, dual-arm)`.
///
/// # Example
/// ```
/// use skeleton_avoidance::kinematics::{presets, Robot};
/// let robot = Robot::from_spec(&presets::preset("planar3")?)?;
/// let ee = robot.forward(&[0.0, 0.0, 0.0])?.end_effector();
/// assert!((ee.translation.x - 0.9).abs() < 1e-12);
/// # Ok::<(), skeleton_avoidance::FieldError>(())
/// ```
pub fn preset(name: &str) -> Result<RobotSpec, FieldError> {
    Ok(match name {
        "planar3" => spec(
            "planar3",
            Convention::Standard,
            vec![
                row(0.4, 0.0, 0.0, 0.04),
                row(0.3, 0.0, 0.0, 0.035),
                row(0.2, 0.0, 0.0, 0.03),
            ],
        ),
        "lwr4" => spec("lwr4", Convention::Standard, lwr_rows(0.3105)),
        "panda" => {
            let v = 2.175;
            let w = 2.61;
            spec(
                "panda",
                Convention::Modified,
                vec![
                    limited(row(0.0, 0.0, 0.333, 0.075), -2.8973, 2.8973, v),
                    limited(row(0.0, -FRAC_PI_2, 0.0, 0.075), -1.7628, 1.7628, v),
                    limited(row(0.0, FRAC_PI_2, 0.316, 0.065), -2.8973, 2.8973, v),
                    limited(row(0.0825, FRAC_PI_2, 0.0, 0.065), -3.0718, -0.0698, v),
                    limited(row(-0.0825, -FRAC_PI_2, 0.384, 0.06), -2.8973, 2.8973, w),
                    limited(row(0.0, FRAC_PI_2, 0.0, 0.06), -0.0175, 3.7525, w),
                    limited(row(0.088, FRAC_PI_2, 0.107, 0.05), -2.8973, 2.8973, w),
                ],
            )
        }
        "ur5" => {
            let l = 2.0 * PI;
            let v = PI;
            spec(
                "ur5",
                Convention::Standard,
                vec![
                    limited(row(0.0, FRAC_PI_2, 0.089159, 0.06), -l, l, v),
                    limited(row(-0.425, 0.0, 0.0, 0.055), -l, l, v),
                    limited(row(-0.39225, 0.0, 0.0, 0.05), -l, l, v),
                    limited(row(0.0, FRAC_PI_2, 0.10915, 0.045), -l, l, v),
                    limited(row(0.0, -FRAC_PI_2, 0.09465, 0.045), -l, l, v),
                    limited(row(0.0, 0.0, 0.0823, 0.04), -l, l, v),
                ],
            )
        }
        "dual-arm" => {
            let h = std::f64::consts::FRAC_1_SQRT_2;
            let mut torso = spec(
                "dual-arm",
                Convention::Standard,
                vec![limited(
                    row(0.0, 0.0, 0.9, 0.14),
                    -deg(170.0),
                    deg(170.0),
                    deg(90.0),
                )],
            );
            torso.branches = vec![
                BranchSpec {
                    name: Some("left".to_owned()),
                    parent: 1,
                    mount: [-h, 0.0, 0.0, h], // z of the arm base along +y
                    joints: lwr_rows(0.25),
                    tool: None,
                },
                BranchSpec {
                    name: Some("right".to_owned()),
                    parent: 1,
                    mount: [h, 0.0, 0.0, h], // along −y
                    joints: lwr_rows(0.25),
                    tool: None,
                },
            ];
            torso
        }
        other => {
            return Err(FieldError::new(
                "preset",
                format!("unknown robot \"{other}\" (known: {})", NAMES.join(", ")),
            ));
        }
    })
}
