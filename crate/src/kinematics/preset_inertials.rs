//! The presets' inertial parameters: for each row, the mass (kg), the
//! centre of mass (m) and the inertia tensor about it (kg·m²,
//! `[ixx, ixy, ixz, iyy, iyz, izz]`), in the preset's DH frame of the row
//! (the spec's `joints[k].inertial`).
//!
//! | preset | source | licence | in the preset's frames |
//! |---|---|---|---|
//! | `panda` | franka_ros `franka_description` (the identified parameters of Gaz, Cognetti, Oliva, Robuffo Giordano, De Luca, "Dynamic identification of the Franka Emika Panda robot with retrieval of feasible parameters using penalty-based optimization", IEEE RA-L 2019), via example-robot-data's `panda_collision.urdf` (`crate/tests/data/urdf/`) | Apache-2.0 | franka's link frames are the preset's (Craig) frames for rows 1–6; row 7 is link 7 and the massless flange, its centre of mass moved by the 0.107 m folded into d₇. The hand is not part of the preset (as for the volumes): a gripper is added by hand |
//! | `ur5` | ros-industrial `ur_description` (Universal Robots' masses and centres of mass; the tensors are the xacro's cylinder approximation, which gives the wrists 0.111 kg·m², as published), via example-robot-data's `ur5_robot.urdf` | BSD-3-Clause | each link frame carried onto the preset's DH frame |
//! | `iiwa14` | RobotLocomotion/models `iiwa_description` (from iiwa_stack), `iiwa14_primitive_collision.urdf` | BSD | each link frame carried onto the preset's DH frame |
//! | `lwr4` | Gaz, Flacco, De Luca, "Identifying the dynamic model used by the KUKA LWR: a reverse engineering approach", ICRA 2014, as tabulated (rounded) in Corke's Robotics Toolbox for MATLAB, `mdl_lwr` | the numbers are facts from the paper (RTB itself is LGPL-3; no code is used) | that table's standard DH frames are the preset's for rows 1–6 (its d₁ = 0 frame sits at the shoulder, where the preset's d₁ = 0.3105 m puts frame 1); row 7's centre of mass moved by the 0.078 m flange folded into d₇ |
//! | `dual-arm` | each arm as `lwr4` (the same frames: each arm's d₁ ends at its shoulder); the torso this project's choice: a 30 kg column 0.9 m high, a solid cylinder of radius 0.14 m | — | frame 1 at the top of the column |
//!
//! `planar3` and `stanford` carry none (asking for their dynamics names
//! the links that lack them; a spec may add them by hand).
//!
//! `crate/tests/preset_inertials.rs` derives the Panda's, the UR5's and the
//! iiwa's tables again from the URDFs (each link's `<inertial>` through the
//! two robots' frames, the base transform fitted on the tips) and checks
//! them to 1e-9, then checks that each preset's torques are the URDF
//! robot's; the values here are those, rounded to 11 significant digits
//! (the fit leaves dust below 1e-11 m).

use super::inertia::InertialSpec;

const fn body(mass: f64, com: [f64; 3], inertia: [f64; 6]) -> InertialSpec {
    InertialSpec { mass, com, inertia }
}

/// Franka Emika Panda (franka_description), rows 1–7 without the hand.
pub const PANDA: [InertialSpec; 7] = [
    body(
        4.970684,
        [0.003875, 0.002081, -0.04762],
        [0.70337, -0.000139, 0.006772, 0.70661, 0.019169, 0.009117],
    ),
    body(
        0.646926,
        [-0.003141, -0.02872, 0.003495],
        [0.007962, -0.003925, 0.010254, 0.02811, 0.000704, 0.025995],
    ),
    body(
        3.228604,
        [0.027518, 0.039252, -0.066502],
        [0.037242, -0.004761, -0.011396, 0.036155, -0.012805, 0.01083],
    ),
    body(
        3.587895,
        [-0.05317, 0.104419, 0.027454],
        [0.025853, 0.007796, -0.001332, 0.019552, 0.008641, 0.028323],
    ),
    body(
        1.225946,
        [-0.011953, 0.041065, -0.038437],
        [0.035549, -0.002117, -0.004037, 0.029474, 0.000229, 0.008627],
    ),
    body(
        1.666555,
        [0.060149, -0.014117, -0.010517],
        [0.001964, 0.000109, -0.001158, 0.004354, 0.000341, 0.005433],
    ),
    body(
        0.735522,
        [0.010517, -0.004252, -0.045403],
        [
            0.012516, -0.000428, -0.001196, 0.010027, -0.000741, 0.004815,
        ],
    ),
];

/// Universal Robots UR5 (ur_description).
pub const UR5: [InertialSpec; 6] = [
    body(
        3.7,
        [0.0, 0.0, 0.0],
        [0.010267495893, 0.0, 0.0, 0.00666, 0.0, 0.010267495893],
    ),
    body(
        8.393,
        [0.145, 0.0, 0.0],
        [0.0151074, 0.0, 0.0, 0.22689067591, 0.0, 0.22689067591],
    ),
    body(
        2.275,
        [0.14225, 0.0, 0.0],
        [0.004095, 0.0, 0.0, 0.049443313556, 0.0, 0.049443313556],
    ),
    body(
        1.219,
        [0.0, -0.093, 0.0],
        [0.111172755531, 0.0, 0.0, 0.111172755531, 0.0, 0.21942],
    ),
    body(
        1.219,
        [0.0, 0.09465, 0.0],
        [0.111172755531, 0.0, 0.0, 0.21942, 0.0, 0.111172755531],
    ),
    body(
        0.1879,
        [0.0, 0.0, -0.0823],
        [0.0171364731454, 0.0, 0.0, 0.033822, 0.0, 0.0171364731454],
    ),
];

/// KUKA LBR iiwa 14 R820 (iiwa_description).
pub const IIWA14: [InertialSpec; 7] = [
    body(
        5.76,
        [0.0, -0.0825, -0.03],
        [0.033, 0.0, 0.0, 0.0123, 0.0, 0.0333],
    ),
    body(
        6.35,
        [0.0003, -0.042, 0.059],
        [0.0305, 0.0, 0.0, 0.0304, 0.0, 0.011],
    ),
    body(
        3.5,
        [0.0, 0.0855, -0.03],
        [0.025, 0.0, 0.0, 0.0076, 0.0, 0.0238],
    ),
    body(
        3.5,
        [0.0, 0.034, 0.067],
        [0.017, 0.0, 0.0, 0.0164, 0.0, 0.006],
    ),
    body(
        3.5,
        [0.0001, -0.1395, -0.021],
        [0.01, 0.0, 0.0, 0.00449, 0.0, 0.0087],
    ),
    body(
        1.8,
        [0.0, -0.0004, 0.0006],
        [0.0049, 0.0, 0.0, 0.0036, 0.0, 0.0047],
    ),
    body(1.2, [0.0, 0.0, 0.02], [0.001, 0.0, 0.0, 0.001, 0.0, 0.001]),
];

/// KUKA LWR4+ (Gaz, Flacco, De Luca 2014, rounded as in RTB's `mdl_lwr`);
/// also each arm of `dual-arm`.
pub const LWR4: [InertialSpec; 7] = [
    body(
        4.0,
        [0.0, -0.03, 0.12],
        [0.0038166, 0.0, 0.0, 0.0038166, 0.0, 0.0036],
    ),
    body(
        4.0,
        [0.0003, 0.059, 0.042],
        [0.05, 0.0, 0.0, 0.018, 0.0, 0.044],
    ),
    body(3.0, [0.0, 0.03, 0.13], [0.08, 0.0, 0.0, 0.075, 0.0, 0.01]),
    body(2.7, [0.0, 0.007, 0.034], [0.03, 0.0, 0.0, 0.01, 0.0, 0.029]),
    body(
        1.7,
        [0.0001, 0.021, 0.076],
        [0.02, 0.0, 0.0, 0.018, 0.0, 0.005],
    ),
    body(
        1.8,
        [0.0, 0.0006, 0.0004],
        [0.005, 0.0, 0.0, 0.0036, 0.0, 0.0047],
    ),
    body(
        0.3,
        [0.0, 0.0, -0.058],
        [0.001, 0.0, 0.0, 0.001, 0.0, 0.001],
    ),
];

/// The dual arm's torso column: 30 kg, a solid cylinder of radius 0.14 m
/// and height 0.9 m whose top is frame 1 (`Izz = m r²/2`,
/// `Ixx = Iyy = m (3 r² + h²)/12`).
pub const TORSO: InertialSpec = body(
    30.0,
    [0.0, 0.0, -0.45],
    [2.172, 0.0, 0.0, 2.172, 0.0, 0.294],
);

/// `rows` with `inertials` written in, row by row.
pub(super) fn with_inertials(rows: &mut [super::spec::JointSpec], inertials: &[InertialSpec]) {
    for (row, body) in rows.iter_mut().zip(inertials) {
        row.inertial = Some(*body);
    }
}
