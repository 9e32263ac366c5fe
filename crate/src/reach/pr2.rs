//! NEO's PR2 problems: the right arm as the benchmark models it, the five
//! scenes in a compact form, and the problems built from them.
//!
//! The arm is imported from the PR2's URDF from `torso_lift_link` on; the
//! importer places the arm's first frame in `torso_lift_link` (the right
//! shoulder sits 0.188 m to the right of the torso's axis), and [`pr2_arm`]
//! composes that pose with the torso's own pose in `base_footprint` at the
//! benchmark's lift (read from the same URDF), so that the arm, its goals
//! and the boxes share `base_footprint` as the scenes define it.

use glam::{DAffine3, DQuat, DVec3};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::{Problem, scenario_json};
use crate::error::FieldError;
use crate::kinematics::{PoseSpec, Robot, RobotSpec};
use crate::parsers::urdf::{UrdfOptions, robot_from_urdf};

/// The torso lift of every scene of the benchmark (m).
pub const TORSO_LIFT: f64 = 0.16825;

/// The link the arm is imported from, and the one whose pose is the goal.
pub(super) const ARM_BASE: &str = "torso_lift_link";
pub(super) const GOAL_LINK: &str = "r_wrist_roll_link";

/// One scene in the compact form the problem sets carry: boxes in
/// `base_footprint`, the arm's configurations; the problems are every
/// ordered pair `(i, j)`, `i < j`, start `configurations[i]`, goal
/// `configurations[j]` (the benchmark's definition).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct Pr2Scene {
    /// Scene name (`bookshelf`, `counter`, …).
    pub name: String,
    /// Boxes: `{ center, halfExtents, rotation }` in `base_footprint`.
    pub boxes: Vec<Pr2Box>,
    /// Arm configurations (7 joints, `r_shoulder_pan_joint` first).
    pub configurations: Vec<Vec<f64>>,
}

/// A box of a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Pr2Box {
    /// Centre (m).
    pub center: [f64; 3],
    /// Half extents (m).
    pub half_extents: [f64; 3],
    /// Rotation `[x, y, z, w]`.
    pub rotation: [f64; 4],
}

/// The scenes file `crate/tests/data/neo/pr2-scenes.json` as far as it is
/// read here.
#[derive(Deserialize)]
struct NeoFile {
    scenes: Vec<NeoScene>,
}

#[derive(Deserialize)]
struct NeoScene {
    name: String,
    torso_lift: f64,
    configurations: Vec<Vec<f64>>,
    boxes: Vec<Pr2Box>,
    problems: Vec<NeoProblem>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct NeoProblem {
    start_index: usize,
    goal_index: usize,
    start: Vec<f64>,
    goal: Vec<f64>,
}

/// The compact scenes of NEO's scenes file (`pr2-scenes.json`), checked:
/// every scene at [`TORSO_LIFT`], its problems exactly the ordered pairs
/// of its configurations.
///
/// # Errors
/// A file that does not parse or breaks one of these rules (`scenes[k]…`).
pub fn pr2_scenes(scenes_json: &str) -> Result<Vec<Pr2Scene>, FieldError> {
    let file: NeoFile = serde_json::from_str(scenes_json)
        .map_err(|e| FieldError::new("scenes", format!("not a scenes file: {e}")))?;
    let mut out = Vec::new();
    for (k, s) in file.scenes.into_iter().enumerate() {
        let field = format!("scenes[{k}]");
        if s.torso_lift != TORSO_LIFT {
            return Err(FieldError::new(
                format!("{field}.torso_lift"),
                format!("expected {TORSO_LIFT}"),
            ));
        }
        let n = s.configurations.len();
        let pairs = (0..n).flat_map(|i| (i + 1..n).map(move |j| (i, j)));
        let same = s.problems.len() == n * n.saturating_sub(1) / 2
            && pairs.zip(&s.problems).all(|((i, j), p)| {
                (p.start_index, p.goal_index) == (i, j)
                    && p.start == s.configurations[i]
                    && p.goal == s.configurations[j]
            });
        if !same {
            return Err(FieldError::new(
                format!("{field}.problems"),
                "not the ordered pairs of the configurations",
            ));
        }
        out.push(Pr2Scene {
            name: s.name,
            boxes: s.boxes,
            configurations: s.configurations,
        });
    }
    Ok(out)
}

/// Pose of `torso_lift_link` in `base_footprint` at `lift` (m), from the
/// URDF's `base_footprint_joint` and `torso_lift_joint`.
pub(super) fn torso_pose(urdf: &str, lift: f64) -> Result<DAffine3, FieldError> {
    let options = UrdfOptions {
        tip: Some(ARM_BASE.into()),
        base: Some("base_footprint".into()),
        srdf: None,
        radii: None,
    };
    let torso = Robot::from_spec(&robot_from_urdf(urdf, &options)?)?;
    let frames = torso.forward(&[lift])?;
    let ee = frames.end_effector();
    Ok(DAffine3::from_mat3_translation(ee.matrix3, ee.translation))
}

/// A pose as a transform (absent: the identity).
pub(super) fn affine(pose: Option<&PoseSpec>) -> DAffine3 {
    pose.map_or(DAffine3::IDENTITY, |p| {
        DAffine3::from_rotation_translation(
            DQuat::from_array(p.rotation).normalize(),
            DVec3::from_array(p.position),
        )
    })
}

/// `outer` then `inner` (`inner` absent: the identity).
pub(super) fn compose(outer: DAffine3, inner: Option<&PoseSpec>) -> PoseSpec {
    let (_, rotation, position) = (outer * affine(inner)).to_scale_rotation_translation();
    PoseSpec {
        position: position.to_array(),
        rotation: rotation.normalize().to_array(),
    }
}

/// The PR2's right arm in `base_footprint` at [`TORSO_LIFT`]: imported from
/// `torso_lift_link` to `r_wrist_roll_link` (the goal link, the end
/// effector), the importer's base pose composed with the torso's.
///
/// # Errors
/// A URDF that is not the PR2's.
pub fn pr2_arm(urdf: &str) -> Result<RobotSpec, FieldError> {
    let options = UrdfOptions {
        tip: Some(GOAL_LINK.into()),
        base: Some(ARM_BASE.into()),
        srdf: None,
        radii: None,
    };
    let mut spec = robot_from_urdf(urdf, &options)?;
    spec.base = Some(compose(torso_pose(urdf, TORSO_LIFT)?, spec.base.as_ref()));
    Ok(spec)
}

/// NEO's PR2 problems (see the module docs of [`crate::reach`]) for the
/// arm `robot` (as [`pr2_arm`] gives it) among `scenes`.
///
/// The problems' arm leaves out the rows' inertial data: the PR2's arm
/// hangs on a spring counterbalance (shoulder lift, upper-arm roll) that
/// the URDF does not model, so with the links' weight on the motors the
/// gravity torque alone reaches 1.59× the shoulder lift's 30 N·m effort at
/// the benchmark's start configurations, and the world's torque limits
/// would hold the arm still. The benchmark is kinematic, as NEO's is.
///
/// # Errors
/// A robot that does not take the scenes' configurations.
pub fn pr2_problems(robot: &RobotSpec, scenes: &[Pr2Scene]) -> Result<Vec<Problem>, FieldError> {
    let mut robot = robot.clone();
    for j in &mut robot.joints {
        j.inertial = None;
    }
    let robot = &robot;
    let model = Robot::from_spec(robot)?;
    let robot_json =
        serde_json::to_value(robot).map_err(|e| FieldError::new("robot", e.to_string()))?;
    let mut out = Vec::new();
    for scene in scenes {
        let obstacles: Vec<Value> = scene
            .boxes
            .iter()
            .enumerate()
            .map(|(k, b)| {
                json!({ "id": format!("box{k}"), "shape": {
                    "type": "box", "center": b.center, "halfExtents": b.half_extents, "rotation": b.rotation } })
            })
            .collect();
        let c = &scene.configurations;
        let mut k = 0;
        for i in 0..c.len() {
            for goal_q in &c[i + 1..] {
                let goal = model.forward(goal_q)?.end_effector();
                let orientation = DQuat::from_mat3(&goal.matrix3);
                let scenario = scenario_json(
                    robot_json.clone(),
                    &c[i],
                    obstacles.clone(),
                    goal.translation,
                    orientation,
                )?;
                out.push(Problem {
                    name: format!("pr2/{}/{k}", scene.name),
                    scenario,
                    position: goal.translation,
                    orientation,
                    goal_q: Some(goal_q.clone()),
                });
                k += 1;
            }
        }
    }
    Ok(out)
}
