//! Holding a pose while something passes close by: the end effector keeps
//! its pose (task `hold`) and the arm makes room with its redundancy — a
//! 7-joint arm has one direction of self-motion that leaves the flange in
//! place — rather than letting the flange go, within every joint limit.
//!
//! Each scene drives a 5 cm ball past one part of the arm (upper arm,
//! elbow, forearm) across the plane of the arm, at its middle (head-on)
//! or lifted so that it would miss the still arm's volume by a given
//! clearance (negative: it would go through it), or makes it appear 4.5 cm
//! from the part's volume and close in. The test asserts, per scene: the
//! largest drift of the flange (position and angle), every velocity,
//! acceleration and jerk within its limit, no contact while moving, and
//! for the scenes the arm can clear with room to spare, no stop and a
//! positive clearance throughout.
//!
//! Reference: NEO (Haviland & Corke 2021) on the Panda holding its flange,
//! as measured for issue 36: 0.9 mm with a ball driven at the elbow at
//! 0.25 m/s, 39 mm with one crossing over the forearm at 0.5 m/s, both
//! exceeding the acceleration limits 4–27×. Runs natively and, unchanged,
//! under `wasm-pack test --node`.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DQuat, DVec3};
use skeleton_avoidance::distance::{PrimitiveSpec, SphereSpec};
use skeleton_avoidance::kinematics::{Robot, presets};
use skeleton_avoidance::scenario::{
    Motion, MotionAudit, ObstacleSpec, RobotRef, Scenario, ShapeSpec, TaskSpec, Trace, audit,
};
use skeleton_avoidance::skeleton::Skeleton;
use skeleton_avoidance::world::World;

#[path = "common/poses.rs"]
mod poses;
use poses::PANDA_READY;

const IIWA_BENT: [f64; 7] = [0.0, 0.7, 0.0, -1.4, 0.0, 1.0, 0.0];
const BALL: f64 = 0.05;
const DT: f64 = 0.002;

/// How the ball passes.
#[derive(Clone, Copy, Debug)]
enum Pass {
    /// Across the arm's plane through the part's middle, at this speed.
    HeadOn(f64),
    /// Across the arm's plane at 0.5 m/s, lifted to miss the still arm's
    /// volume by this clearance (m; negative: through it).
    Miss(f64),
    /// Appears 4.5 cm from the part's volume at t = 0.2 s, then closes in
    /// at 0.2 m/s.
    Sudden,
}

/// One scene and what the arm must do in it.
struct Case {
    robot: &'static str,
    q0: &'static [f64],
    /// The part: skeleton nodes `from`, `to` (a node when equal).
    part: (&'static str, usize, usize),
    pass: Pass,
    /// Largest flange drift allowed (mm).
    drift: f64,
    /// Whether the arm must clear the ball: no stop, positive clearance.
    clears: bool,
}

/// What a run gave.
struct Measured {
    drift: f64,
    turn: f64,
    audit: MotionAudit,
    stopped: bool,
}

/// The ball's start and motion for `case`, and the run's duration.
fn ball(case: &Case, robot: &Robot) -> (DVec3, Motion, f64) {
    let frames = robot.forward(case.q0).unwrap();
    let sk = Skeleton::build(robot, &frames);
    let (_, from, to) = case.part;
    let nodes = &sk.nodes;
    // The arm's plane: shoulder, elbow, wrist; the ball crosses it.
    let across = (nodes[2] - nodes[1])
        .cross(nodes[nodes.len() - 2] - nodes[1])
        .normalize();
    let at = 0.5 * (nodes[from] + nodes[to]);
    let radius = sk
        .segments
        .iter()
        .filter(|s| s.from == from || s.to == to)
        .map(|s| s.radius[0].max(s.radius[1]))
        .fold(0.0, f64::max);
    match case.pass {
        Pass::HeadOn(speed) => (
            at - across * 0.6,
            Motion::Linear {
                velocity: (across * speed).to_array(),
            },
            1.2 / speed,
        ),
        Pass::Miss(clearance) => (
            at + DVec3::Z * (radius + BALL + clearance) - across * 0.6,
            Motion::Linear {
                velocity: (across * 0.5).to_array(),
            },
            2.4,
        ),
        Pass::Sudden => (
            at - across * (radius + BALL + 0.045),
            Motion::Waypoints {
                points: vec![[3.0; 3], [3.0; 3], [0.0; 3], (across * 0.2).to_array()],
                times: vec![0.0, 0.2, 0.2, 1.2],
                repeat: false,
            },
            1.5,
        ),
    }
}

fn run(case: &Case) -> Measured {
    let robot = Robot::from_spec(&presets::preset(case.robot).unwrap()).unwrap();
    let (center, motion, duration) = ball(case, &robot);
    let scenario = Scenario {
        robot: RobotRef::Preset(case.robot.to_owned()),
        q0: Some(case.q0.to_vec()),
        obstacles: vec![ObstacleSpec {
            id: "ball".into(),
            shape: ShapeSpec::Primitive(PrimitiveSpec::Sphere(SphereSpec {
                center: center.to_array(),
                radius: BALL,
            })),
            motion: Some(motion),
        }],
        task: TaskSpec::Hold.into(),
        controller: Default::default(),
        sensing: Default::default(),
        dependability: Default::default(),
        dt: DT,
        duration,
        sample_every: 1,
        camera: None,
    };
    let mut world = World::new(scenario).unwrap();
    let start = world.frames().end_effector();
    let (p0, r0) = (start.translation, DQuat::from_mat3(&start.matrix3));
    let mut trace = Trace::default();
    let mut out = Measured {
        drift: 0.0,
        turn: 0.0,
        audit: MotionAudit::default(),
        stopped: false,
    };
    for _ in 0..(duration / DT).round() as usize {
        world.step(DT);
        trace.samples.push(world.sample());
        let ee = world.frames().end_effector();
        out.drift = out.drift.max((ee.translation - p0).length());
        let turn = DQuat::from_mat3(&ee.matrix3).angle_between(r0);
        out.turn = out.turn.max(turn.to_degrees());
        out.stopped |= world.is_stopped();
    }
    out.audit = audit(&robot, &trace);
    out
}

fn check(cases: &[Case]) {
    let mut failures = Vec::new();
    for case in cases {
        let m = run(case);
        let a = &m.audit;
        let name = format!("{} {} {:?}", case.robot, case.part.0, case.pass);
        eprintln!(
            "{name:<34} drift {:7.2} mm {:5.2}°  |q̇|/lim {:.3} |q̈|/lim {:.3} jerk/lim {:.3}  min clearance {:7.4} m{}",
            m.drift * 1e3,
            m.turn,
            a.velocity,
            a.acceleration,
            a.jerk,
            a.clearance,
            if m.stopped { "  (stopped)" } else { "" }
        );
        if !a.admissible() {
            failures.push(format!(
                "{name}: outside the limits or contact while moving: {a:?}"
            ));
        }
        if m.drift * 1e3 > case.drift {
            failures.push(format!(
                "{name}: drift {:.2} mm > {} mm",
                m.drift * 1e3,
                case.drift
            ));
        }
        if case.clears && (m.stopped || a.clearance <= 0.0) {
            failures.push(format!(
                "{name}: not cleared (stopped {}, clearance {:.4})",
                m.stopped, a.clearance
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

const PANDA_UPPER: (&str, usize, usize) = ("upper arm", 1, 2);
const PANDA_ELBOW: (&str, usize, usize) = ("elbow", 3, 3);
const PANDA_FOREARM: (&str, usize, usize) = ("forearm", 4, 5);

/// The Panda in its ready pose. Where the elbow's self-motion alone makes
/// room (the elbow and the forearm passed slowly, a ball appearing beside
/// them, the upper arm grazed) the flange stays within 1 mm: what is left
/// is the task's own tracking error (gain 5/s) during the self-motion.
/// A ball driven at the elbow at 0.25 m/s — NEO: 0.9 mm — and at 0.5 m/s
/// is cleared by self-motion alone (0.05 and 0.15 mm measured). A ball
/// crossing over the forearm at 0.5 m/s, 5 cm into its volume, needs the
/// forearm lowered, which self-motion about the shoulder–wrist axis does
/// not do: 6.9 mm measured (NEO: 39 mm), bound 10 mm.
#[test]
fn the_panda_holds_its_flange_while_a_ball_passes() {
    let case = |part, pass, drift| Case {
        robot: "panda",
        q0: &PANDA_READY,
        part,
        pass,
        drift,
        clears: true,
    };
    check(&[
        case(PANDA_ELBOW, Pass::HeadOn(0.25), 0.5),
        case(PANDA_ELBOW, Pass::HeadOn(0.5), 0.5),
        case(PANDA_ELBOW, Pass::Miss(-0.05), 0.5),
        case(PANDA_ELBOW, Pass::Sudden, 0.5),
        case(PANDA_FOREARM, Pass::HeadOn(0.25), 1.0),
        case(PANDA_FOREARM, Pass::Miss(-0.05), 10.0),
        case(PANDA_FOREARM, Pass::Miss(0.0), 1.0),
        case(PANDA_FOREARM, Pass::Sudden, 1.0),
        case(PANDA_UPPER, Pass::Miss(0.0), 1.0),
    ]);
}

/// Where the Panda cannot make room: the forearm hit head-on at 0.5 m/s
/// moves the flange 47 mm to clear the ball (no stop, 5.8 cm clearance);
/// the upper arm, 0.3 m from the base, is hit head-on at 0.25 m/s by a
/// ball the joints cannot outrun within their limits: the arm stops and
/// the contact begins at rest (6.6 mm of drift in the braking). Bounds
/// 1.25× the measured drift.
#[test]
fn the_panda_gives_way_or_stops_where_it_must() {
    check(&[
        Case {
            robot: "panda",
            q0: &PANDA_READY,
            part: PANDA_FOREARM,
            pass: Pass::HeadOn(0.5),
            drift: 60.0,
            clears: true,
        },
        Case {
            robot: "panda",
            q0: &PANDA_READY,
            part: PANDA_UPPER,
            pass: Pass::HeadOn(0.25),
            drift: 8.5,
            clears: false,
        },
    ]);
}

const IIWA_UPPER: (&str, usize, usize) = ("upper arm", 1, 2);
const IIWA_ELBOW: (&str, usize, usize) = ("elbow", 2, 2);
const IIWA_FOREARM: (&str, usize, usize) = ("forearm", 2, 3);

/// The iiwa 14, bent: its elbow is cleared by self-motion alone (under
/// 0.5 mm) when the ball comes at 0.25 m/s, appears beside it, or grazes
/// it; 5 cm into the elbow's volume at 0.5 m/s the self-motion runs at the
/// speed limits and the flange gives 9 mm. Its 0.4 m forearm can only
/// swing about the wrist, so a ball crossing it moves the flange by
/// 44–123 mm, and one grazing the upper arm at 0.5 m/s by 56 mm: the arm
/// clears every one of them at full speed without a stop. Bounds 1.25×
/// the measured drift where it is above 1 mm.
#[test]
fn the_iiwa_holds_its_flange_while_a_ball_passes() {
    let case = |part, pass, drift| Case {
        robot: "iiwa14",
        q0: &IIWA_BENT,
        part,
        pass,
        drift,
        clears: true,
    };
    check(&[
        case(IIWA_ELBOW, Pass::HeadOn(0.25), 0.5),
        case(IIWA_ELBOW, Pass::Miss(-0.05), 11.5),
        case(IIWA_ELBOW, Pass::Miss(0.0), 0.5),
        case(IIWA_ELBOW, Pass::Sudden, 0.5),
        case(IIWA_FOREARM, Pass::HeadOn(0.25), 55.0),
        case(IIWA_FOREARM, Pass::Miss(0.0), 60.0),
        case(IIWA_FOREARM, Pass::Sudden, 155.0),
        case(IIWA_UPPER, Pass::Miss(0.0), 71.0),
    ]);
}
