//! Robot presets, with DH values from the manufacturers' or the standard
//! literature's published tables.
//!
//! | name | robot | convention | source of the table |
//! |---|---|---|---|
//! | `planar3` | the paper's planar 3-link arm, links 0.4 / 0.3 / 0.2 m | standard | De Santis & Siciliano, §III-B, fig. 5 |
//! | `lwr4` | KUKA LWR4+ (DLR LWR III kinematics), 7 DOF | standard | Gaz, Flacco, Ficuciello, De Luca, ICRA 2016 (d₃ = 0.4, d₅ = 0.39 m); the 0.3105 m base column and the 0.078 m flange are folded into d₁ and d₇ so that the skeleton covers them; limits and speeds from KUKA's LWR4+ specification |
//! | `iiwa14` | KUKA LBR iiwa 14 R820, 7 DOF | standard | the joint origins of iiwa_stack's `iiwa_description` (d₁ = 0.36, d₃ = 0.42, d₅ = 0.4, d₇ = 0.081 m; the 0.045 m flange as the tool), the same arm to 1e-6 m (`crate/tests/fitting_presets.rs`); limits from KUKA's LBR iiwa specification |
//! | `panda` | Franka Emika Panda, 7 DOF | modified (Craig) | Franka Control Interface documentation, "Robot and interface specifications"; the 0.107 m flange is folded into d₇ (a translation along z₇ commutes with θ₇) |
//! | `ur5` | Universal Robots UR5 (CB3), 6 DOF | standard | Universal Robots, "DH parameters for calculations of kinematics and dynamics"; the published d₄ = 0.10915 m is split into the three offsets it sums along the parallel axes 2–4 (d₂ = 0.13585, d₃ = −0.1197, d₄ = 0.093 m, ur_description's joint origins), so that the skeleton runs through the upper arm and the forearm (below) |
//! | `dual-arm` | a yawing torso carrying two LWR-like 7-DOF arms, in the spirit of DLR's Justin | standard | this project: torso column 0.9 m, shoulders 0.25 m either side of the chest, arms as `lwr4` |
//! | `stanford` | the Stanford arm: two revolute joints, a prismatic joint, a spherical wrist | standard | Siciliano, Sciavicco, Villani, Oriolo, *Robotics: Modelling, Planning and Control* (2009), §2.9 (the Stanford manipulator); lengths d₁ = 0.412, d₂ = 0.154, d₆ = 0.263 m as in the Stanford arm model of Corke's Robotics Toolbox |
//!
//! Link radii are sensible envelopes for each segment (m), except for
//! `iiwa14`, `panda` and `ur5`, whose radii are fitted to the published
//! collision meshes (below).
//!
//! ## Radii fitted to the collision meshes
//!
//! The paper asks the volumes to "approach the real volume" of each part
//! and the segments to cover the spine of every mechanical part. `iiwa14`,
//! `panda` and `ur5` carry the tapered radii [`crate::fitting::fit_volumes`]
//! finds on the published collision meshes (iiwa_stack's iiwa_description,
//! BSD-2; franka_description, Apache-2.0; ur_description via
//! example-robot-data, BSD-3; files and licences in
//! `crate/tests/data/meshes/`), carried into the preset's frames (the
//! transform that maps the URDF's tip onto the preset's last frame; the two
//! kinematics agree to 1e-6 m) and rounded up to the millimetre. Every
//! collision-mesh vertex is inside the volumes that move with its link:
//! `crate/tests/fitting_presets.rs` checks it with the coverage measure,
//! natively and in wasm, and prints this table. The Panda's hand is not
//! part of the preset. Vertices: share of the mesh vertices inside;
//! surface: share of the mesh area at most 1 mm outside; excess: volume of
//! the volumes over the meshes' volume ([`crate::fitting::Coverage`]).
//!
//! | preset | radii | vertices | surface | excess |
//! |---|---|---|---|---|
//! | `iiwa14` | hand-set envelopes, 0.07 … 0.045 m (as `lwr4`'s) | 14.0 % | 33.4 % | 0.98 |
//! | `iiwa14` | now: fitted, 0.056 … 0.133 m | 100 % | 100 % | 2.93 |
//! | `panda` | before: hand-set, 0.075 … 0.05 m | 44.2 % | 60.0 % | 1.14 |
//! | `panda` | now: fitted, 0.002 … 0.134 m | 100 % | 100 % | 3.15 |
//! | `ur5` | before: hand-set, 0.06 … 0.04 m, published DH table | 43.9 % | 39.0 % | 0.99 |
//! | `ur5` | fitted on the published DH table | 100 % | 100 % | 9.57 |
//! | `ur5` | now: fitted, offsets where the parts are, 0.036 … 0.081 m | 100 % | 100 % | 2.14 |
//!
//! Hand-set radii left more than half of each arm's mesh vertices outside
//! its volumes: a real arm would have touched an obstacle the algorithm saw
//! at a safe distance. The UR5 row shows the paper's remark that covering
//! the spines "has a reflex on DH tables": the published table folds the
//! shoulder and elbow offsets into d₄, so its spine for the upper arm runs
//! 0.136 m beside the part and a round cone around it needs a 0.206 m
//! radius. With each offset on the row where the part is, the spine runs
//! through the upper arm, the end effector's pose is unchanged (the offsets
//! lie along parallel axes) and the radius drops to 0.081 m.
//!
//! The Panda's and the iiwa's excess comes from their joint housings: each
//! housing is a cylinder across the spine, so the round cone around the
//! spine must reach its rims. A tighter fit needs segments along the joint axes, which DH rows
//! of zero length do not give; the volumes stay conservative.
//!
//! ## Inertial parameters
//!
//! `panda`, `ur5`, `iiwa14`, `lwr4` and `dual-arm` carry every row's
//! `inertial` (mass, centre of mass, inertia tensor in the row's DH frame):
//! the manufacturers' URDFs and the identified LWR4 parameters, carried
//! into the presets' frames; sources, licences and how each was carried
//! in the docs of `preset_inertials.rs` ([`super::preset_inertials`]).
//! `planar3` and `stanford` carry none.
//!
//! ## Motion limits
//!
//! Every preset joint carries `min`, `max`, `maxVelocity`,
//! `maxAcceleration`, `maxJerk` and `maxTorque`; [`preset`] fills all of
//! them, branches included.
//!
//! * `panda`: Franka's published joint limits (Franka Control Interface,
//!   "Robot and interface specifications"): q̇ 2.175 rad/s (joints 1–4),
//!   2.61 (5–7); q̈ 15, 7.5, 10, 12.5, 15, 20, 20 rad/s²; jerk 7500, 3750,
//!   5000, 6250, 7500, 10 000, 10 000 rad/s³; torque 87 N·m (1–4), 12 (5–7).
//! * `lwr4`: KUKA's LWR 4+ specification: ±170° (A1, A3, A5, A7), ±120°
//!   (A2, A4, A6); 110, 110, 128, 128, 204, 184, 184 °/s; 176, 176, 100,
//!   100, 100, 38, 38 N·m. KUKA publishes no acceleration or jerk limits:
//!   this project uses 10 rad/s² (A1–A4) and 15 rad/s² (A5–A7), the order
//!   of the Panda's, with the Panda's jerk-to-acceleration ratio (500/s).
//! * `iiwa14`: KUKA's LBR iiwa 14 R820 specification: ±170° (A1, A3, A5),
//!   ±120° (A2, A4, A6), ±175° (A7); 85, 85, 100, 75, 130, 135, 135 °/s;
//!   320, 320, 176, 176, 110, 40, 40 N·m. KUKA publishes no acceleration
//!   limit: 8.57, 8.57, 8.74, 11.36, 12.23, 15.72, 15.72 rad/s², the values
//!   of Drake's iiwa 14 model (RobotLocomotion/models), jerk 500/s × that.
//! * `ur5`: Universal Robots' UR5 (CB3) specification: ±360°, 180 °/s on
//!   every joint; 150 N·m (base, shoulder, elbow: size-3 joints), 28 N·m
//!   (wrists). UR publishes no hardware acceleration limit: 15 rad/s²
//!   (base, shoulder, elbow) and 25 rad/s² (wrists), jerk 500/s × that,
//!   this project's choice.
//! * `planar3`: this project's choice for a table-top arm of the paper's
//!   size: ±170°, 2 rad/s, 10 rad/s², 5000 rad/s³, 50 / 30 / 15 N·m.
//! * `dual-arm`: the torso joint ±170°, 90 °/s, 5 rad/s², 2500 rad/s³,
//!   300 N·m (a slow, heavy axis); each arm as `lwr4`.
//! * `stanford`: this project's choice (the original arm's controller
//!   limits are not published in SI): 1.5 rad/s, 8 rad/s² on joints 1–2;
//!   the prismatic joint 0.3–1.2 m, 0.5 m/s, 2 m/s², 1000 m/s³, 400 N;
//!   the wrist 3 rad/s, 15 rad/s².

use std::f64::consts::{FRAC_PI_2, PI};

use super::preset_inertials::{IIWA14, LWR4, PANDA, TORSO, UR5, with_inertials};
use super::spec::{BranchSpec, Convention, JointSpec, JointType, RadiusSpec, RobotSpec};
use crate::error::FieldError;

/// Names accepted by [`preset`].
pub const NAMES: [&str; 7] = [
    "planar3", "lwr4", "iiwa14", "panda", "ur5", "dual-arm", "stanford",
];

fn row(a: f64, alpha: f64, d: f64, radius: f64) -> JointSpec {
    JointSpec {
        a,
        alpha,
        d,
        radius: Some(RadiusSpec::Uniform(radius)),
        ..JointSpec::default()
    }
}

/// Position, velocity and acceleration limits; jerk and torque follow.
fn limited(mut j: JointSpec, range: [f64; 2], velocity: f64, acceleration: f64) -> JointSpec {
    j.min = Some(range[0]);
    j.max = Some(range[1]);
    j.max_velocity = Some(velocity);
    j.max_acceleration = Some(acceleration);
    j.max_jerk = Some(500.0 * acceleration);
    j
}

fn torque(mut j: JointSpec, max_torque: f64) -> JointSpec {
    j.max_torque = Some(max_torque);
    j
}

fn deg(x: f64) -> f64 {
    x.to_radians()
}

fn lwr_rows(d1: f64) -> Vec<JointSpec> {
    let l170 = [-deg(170.0), deg(170.0)];
    let l120 = [-deg(120.0), deg(120.0)];
    let rows = [
        (row(0.0, FRAC_PI_2, d1, 0.07), l170, 110.0, 10.0, 176.0),
        (row(0.0, -FRAC_PI_2, 0.0, 0.07), l120, 110.0, 10.0, 176.0),
        (row(0.0, -FRAC_PI_2, 0.4, 0.065), l170, 128.0, 10.0, 100.0),
        (row(0.0, FRAC_PI_2, 0.0, 0.065), l120, 128.0, 10.0, 100.0),
        (row(0.0, FRAC_PI_2, 0.39, 0.06), l170, 204.0, 15.0, 100.0),
        (row(0.0, -FRAC_PI_2, 0.0, 0.06), l120, 184.0, 15.0, 38.0),
        (row(0.0, 0.0, 0.078, 0.045), l170, 184.0, 15.0, 38.0),
    ];
    let mut joints: Vec<JointSpec> = rows
        .into_iter()
        .map(|(j, range, v, acc, tau)| torque(limited(j, range, deg(v), acc), tau))
        .collect();
    with_inertials(&mut joints, &LWR4);
    joints
}

/// KUKA LBR iiwa 14 R820: the lwr4's kinematic pattern with its own
/// lengths (d₁ = 0.36, d₃ = 0.42, d₅ = 0.4, d₇ = 0.081 m to the last joint
/// frame, the 0.045 m flange as the tool).
fn iiwa14() -> RobotSpec {
    let l170 = [-deg(170.0), deg(170.0)];
    let l120 = [-deg(120.0), deg(120.0)];
    let rows = [
        (row(0.0, FRAC_PI_2, 0.36, 0.07), l170, 85.0, 8.57, 320.0),
        (row(0.0, -FRAC_PI_2, 0.0, 0.07), l120, 85.0, 8.57, 320.0),
        (row(0.0, -FRAC_PI_2, 0.42, 0.065), l170, 100.0, 8.74, 176.0),
        (row(0.0, FRAC_PI_2, 0.0, 0.065), l120, 75.0, 11.36, 176.0),
        (row(0.0, FRAC_PI_2, 0.4, 0.06), l170, 130.0, 12.23, 110.0),
        (row(0.0, -FRAC_PI_2, 0.0, 0.06), l120, 135.0, 15.72, 40.0),
        (
            row(0.0, 0.0, 0.081, 0.045),
            [-deg(175.0), deg(175.0)],
            135.0,
            15.72,
            40.0,
        ),
    ];
    let mut joints: Vec<JointSpec> = rows
        .into_iter()
        .map(|(j, range, v, acc, tau)| torque(limited(j, range, deg(v), acc), tau))
        .collect();
    with_inertials(&mut joints, &IIWA14);
    let mut s = fitted(spec("iiwa14", Convention::Standard, joints), &IIWA14_RADII);
    s.tool = Some(super::spec::PoseSpec {
        position: [0.0, 0.0, 0.045],
        rotation: [0.0, 0.0, 0.0, 1.0],
    });
    s
}

fn spec(name: &str, convention: Convention, joints: Vec<JointSpec>) -> RobotSpec {
    RobotSpec {
        name: Some(name.to_owned()),
        convention,
        base: None,
        joints,
        tool: None,
        branches: Vec::new(),
        joint_names: None,
        link_names: None,
        self_collision_exclude: Vec::new(),
    }
}

fn panda() -> RobotSpec {
    let l = 2.8973;
    let rows = [
        (row(0.0, 0.0, 0.333, 0.075), [-l, l], 2.175, 15.0, 87.0),
        (
            row(0.0, -FRAC_PI_2, 0.0, 0.075),
            [-1.7628, 1.7628],
            2.175,
            7.5,
            87.0,
        ),
        (
            row(0.0, FRAC_PI_2, 0.316, 0.065),
            [-l, l],
            2.175,
            10.0,
            87.0,
        ),
        (
            row(0.0825, FRAC_PI_2, 0.0, 0.065),
            [-3.0718, -0.0698],
            2.175,
            12.5,
            87.0,
        ),
        (
            row(-0.0825, -FRAC_PI_2, 0.384, 0.06),
            [-l, l],
            2.61,
            15.0,
            12.0,
        ),
        (
            row(0.0, FRAC_PI_2, 0.0, 0.06),
            [-0.0175, 3.7525],
            2.61,
            20.0,
            12.0,
        ),
        (
            row(0.088, FRAC_PI_2, 0.107, 0.05),
            [-l, l],
            2.61,
            20.0,
            12.0,
        ),
    ];
    let mut joints: Vec<JointSpec> = rows
        .into_iter()
        .map(|(j, range, v, acc, tau)| torque(limited(j, range, v, acc), tau))
        .collect();
    with_inertials(&mut joints, &PANDA);
    fitted(spec("panda", Convention::Modified, joints), &PANDA_RADII)
}

/// The Panda's radii fitted to franka_description's collision meshes
/// (module docs), rounded up to the millimetre; rows 2 and 6 span no
/// segment and keep their envelope.
const PANDA_RADII: [Option<[f64; 2]>; 7] = [
    Some([0.002, 0.134]),
    None,
    Some([0.130, 0.110]),
    Some([0.083, 0.116]),
    Some([0.112, 0.131]),
    None,
    Some([0.060, 0.101]),
];

/// The UR5's radii fitted to ur_description's collision meshes (module
/// docs), rounded up to the millimetre.
const UR5_RADII: [Option<[f64; 2]>; 6] = [
    Some([0.051, 0.080]),
    Some([0.081, 0.081]),
    Some([0.058, 0.064]),
    Some([0.036, 0.069]),
    Some([0.038, 0.069]),
    Some([0.037, 0.046]),
];

/// The iiwa 14's radii fitted to iiwa_stack's collision meshes (module
/// docs), rounded up to the millimetre; rows 2, 4 and 6 span no segment.
const IIWA14_RADII: [Option<[f64; 2]>; 7] = [
    Some([0.058, 0.123]),
    None,
    Some([0.133, 0.119]),
    None,
    Some([0.115, 0.115]),
    None,
    Some([0.093, 0.056]),
];

/// `spec` with the rows' radii replaced by `radii` where given.
fn fitted(mut spec: RobotSpec, radii: &[Option<[f64; 2]>]) -> RobotSpec {
    for (j, r) in spec.joints.iter_mut().zip(radii) {
        if let Some(r) = r {
            j.radius = Some(RadiusSpec::Tapered(*r));
        }
    }
    spec
}

fn ur5() -> RobotSpec {
    let l = [-2.0 * PI, 2.0 * PI];
    let rows = [
        (row(0.0, FRAC_PI_2, 0.089159, 0.06), 15.0, 150.0),
        (row(-0.425, 0.0, 0.13585, 0.055), 15.0, 150.0),
        (row(-0.39225, 0.0, -0.1197, 0.05), 15.0, 150.0),
        (row(0.0, FRAC_PI_2, 0.093, 0.045), 25.0, 28.0),
        (row(0.0, -FRAC_PI_2, 0.09465, 0.045), 25.0, 28.0),
        (row(0.0, 0.0, 0.0823, 0.04), 25.0, 28.0),
    ];
    let mut joints: Vec<JointSpec> = rows
        .into_iter()
        .map(|(j, acc, tau)| torque(limited(j, l, PI, acc), tau))
        .collect();
    with_inertials(&mut joints, &UR5);
    fitted(spec("ur5", Convention::Standard, joints), &UR5_RADII)
}

fn planar3() -> RobotSpec {
    let l = [-deg(170.0), deg(170.0)];
    let rows = [(0.4, 0.04, 50.0), (0.3, 0.035, 30.0), (0.2, 0.03, 15.0)];
    let joints = rows
        .into_iter()
        .map(|(a, r, tau)| torque(limited(row(a, 0.0, 0.0, r), l, 2.0, 10.0), tau))
        .collect();
    spec("planar3", Convention::Standard, joints)
}

fn dual_arm() -> RobotSpec {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let mut column = limited(
        row(0.0, 0.0, 0.9, 0.14),
        [-deg(170.0), deg(170.0)],
        deg(90.0),
        5.0,
    );
    column.inertial = Some(TORSO);
    let mut torso = spec(
        "dual-arm",
        Convention::Standard,
        vec![torque(column, 300.0)],
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

fn stanford() -> RobotSpec {
    let full = [-deg(170.0), deg(170.0)];
    let mut slide = limited(row(0.0, 0.0, 0.0, 0.05), [0.3, 1.2], 0.5, 2.0);
    slide.kind = JointType::Prismatic;
    slide.max_jerk = Some(1000.0);
    let joints = vec![
        torque(
            limited(row(0.0, -FRAC_PI_2, 0.412, 0.09), full, 1.5, 8.0),
            200.0,
        ),
        torque(
            limited(
                row(0.0, FRAC_PI_2, 0.154, 0.08),
                [-deg(100.0), deg(100.0)],
                1.5,
                8.0,
            ),
            200.0,
        ),
        torque(slide, 400.0),
        torque(
            limited(row(0.0, -FRAC_PI_2, 0.0, 0.045), full, 3.0, 15.0),
            20.0,
        ),
        torque(
            limited(
                row(0.0, FRAC_PI_2, 0.0, 0.045),
                [-deg(100.0), deg(100.0)],
                3.0,
                15.0,
            ),
            20.0,
        ),
        torque(limited(row(0.0, 0.0, 0.263, 0.035), full, 3.0, 15.0), 20.0),
    ];
    spec("stanford", Convention::Standard, joints)
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
        "planar3" => planar3(),
        "lwr4" => spec("lwr4", Convention::Standard, lwr_rows(0.3105)),
        "iiwa14" => iiwa14(),
        "panda" => panda(),
        "ur5" => ur5(),
        "dual-arm" => dual_arm(),
        "stanford" => stanford(),
        other => {
            return Err(FieldError::new(
                "preset",
                format!("unknown robot \"{other}\" (known: {})", NAMES.join(", ")),
            ));
        }
    })
}
