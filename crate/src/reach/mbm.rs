//! MotionBenchMaker's Panda problems (Chamzas et al., RA-L 2022; 700
//! problems in 7 scenes, boxes and cylinders around the Panda), read from
//! the scene files converted in `crate/tests/data/mbm/` (its README holds
//! the provenance and the format).
//!
//! **Not built into the library.** The 700 problems carry their own
//! obstacles (MotionBenchMaker moves every object per problem): 8 200
//! objects, 2.0 MB of JSON whose numbers are full-precision random poses
//! (0.39 MB gzipped, against a wasm budget with a few kB left), and no
//! encoding keeps them exact in a few kB. So the data stays a JSON file read
//! by the caller (`std::fs` natively; `fetch` or `fs` for a JS caller) and
//! handed to [`mbm_problems`], which builds the problems: one scene file, or
//! an array of them.
//!
//! **The grasped object is left out of its problem's scene.** Every
//! MotionBenchMaker goal is a grasp: the scene's queries file
//! (`configs/scenes/<scene>/*queries*.yaml` in KavrakiLab/motion_bench_maker)
//! names the object to grasp (`objects: ["Can1"]`) and the hand's offset
//! from it, and the goal configuration puts the open gripper around that
//! object (MotionBenchMaker's Panda holds its fingers 0.065 m from the hand
//! axis, so in MoveIt the fingers straddle a 3 cm can without touching it).
//! The library's Panda covers the hand and fingers with volumes that fill
//! the gap between the fingers, so with the object in the scene every goal
//! overlaps an obstacle and no problem can be reached strictly. The
//! converted files name the object per problem (`grasped`: the object
//! nearest to the point between the fingertips, 0.1034 m along
//! `panda_link8`'s z, at the goal: inside it in 671 problems, at most 1.7 mm
//! above a can's top in `box`, the next object at least 8 cm away; see
//! `convert_mbm.py`). Of the two ways to honour the grasp, this one was
//! taken: dropping the object for the whole run, rather than reproducing
//! an allowed collision between the gripper's volumes and that object
//! only. The library has no per-pair allowed-collision matrix (every
//! control point avoids every obstacle), and an allowance for the gripper
//! would still leave the arm's other links free to pass through the
//! object; leaving it out is the simple, stated approximation. The
//! scenes' own allowed-collision matrices (kept in the source files) list
//! robot links only, so nothing else in MotionBenchMaker's problems is
//! allowed to touch an obstacle.
//!
//! A cylinder becomes a capsule between its end faces' centres with the
//! cylinder's radius (the library has no cylinder obstacle): it covers the
//! cylinder and overshoots each end by the radius. The robot is the Panda
//! preset (its fitted volumes); its end effector is `panda_link8`, the
//! flange whose pose is the goal.

use glam::{DQuat, DVec3};
use serde::Deserialize;
use serde_json::{Value, json};

use super::{Problem, scenario_json};
use crate::error::FieldError;

/// The scenes, by the names of their files in `crate/tests/data/mbm/`.
pub const SCENES: [&str; 7] = [
    "bookshelf_small",
    "bookshelf_tall",
    "bookshelf_thin",
    "box",
    "cage",
    "table_pick",
    "table_under_pick",
];

#[derive(Deserialize)]
struct SceneFile {
    set: String,
    problems: Vec<MbmProblem>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct MbmProblem {
    name: String,
    start: Vec<f64>,
    goal_q: Vec<f64>,
    goal: Pose,
    grasped: String,
    obstacles: Objects,
}

#[derive(Deserialize)]
struct Pose {
    position: [f64; 3],
    rotation: [f64; 4],
}

#[derive(Deserialize)]
struct Objects {
    #[serde(default)]
    boxes: Vec<BoxObject>,
    #[serde(default)]
    cylinders: Vec<Cylinder>,
    #[serde(default)]
    spheres: Vec<Sphere>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct BoxObject {
    id: String,
    center: [f64; 3],
    half_extents: [f64; 3],
    rotation: [f64; 4],
}

#[derive(Deserialize)]
struct Cylinder {
    id: String,
    radius: f64,
    a: [f64; 3],
    b: [f64; 3],
}

#[derive(Deserialize)]
struct Sphere {
    id: String,
    center: [f64; 3],
    radius: f64,
}

/// The obstacles of one problem as scenario obstacles, the object with the
/// id `grasped` left out (module docs).
fn obstacles(o: &Objects, grasped: &str) -> Vec<Value> {
    let kept = |id: &String| id != grasped;
    let boxes = o.boxes.iter().filter(|b| kept(&b.id)).map(|b| {
        json!({ "id": b.id, "shape": { "type": "box", "center": b.center,
                "halfExtents": b.half_extents, "rotation": b.rotation } })
    });
    let cylinders = o.cylinders.iter().filter(|c| kept(&c.id)).map(|c| {
        json!({ "id": c.id, "shape": { "type": "capsule", "a": c.a, "b": c.b, "radius": c.radius } })
    });
    let spheres = o.spheres.iter().filter(|s| kept(&s.id)).map(|s| {
        json!({ "id": s.id, "shape": { "type": "sphere", "center": s.center, "radius": s.radius } })
    });
    boxes.chain(cylinders).chain(spheres).collect()
}

/// The problems of MotionBenchMaker scene files (module docs): `json` is
/// one scene file (`crate/tests/data/mbm/<scene>.json`) or an array of
/// them, as JSON text; `field` names it in errors.
///
/// # Errors
/// Text that is not such a file (`field[k]…: reason`), or a problem whose
/// scenario the library refuses.
pub fn mbm_problems(json: &str, field: &str) -> Result<Vec<Problem>, FieldError> {
    let value: Value =
        serde_json::from_str(json).map_err(|e| FieldError::new(field, format!("not JSON: {e}")))?;
    let files = match value {
        Value::Array(files) => files
            .into_iter()
            .enumerate()
            .map(|(k, f)| (format!("{field}[{k}]"), f))
            .collect(),
        file => vec![(field.to_owned(), file)],
    };
    let mut out = Vec::new();
    for (path, file) in files {
        let file: SceneFile = serde_path_to_error::deserialize(file).map_err(|e| {
            let inner =
                crate::error::from_serde_path(&e.path().to_string(), &e.inner().to_string());
            let at = if inner.field.is_empty() {
                path.clone()
            } else {
                format!("{path}.{}", inner.field)
            };
            FieldError::new(at, inner.reason)
        })?;
        if file.set != "mbm" {
            return Err(FieldError::new(
                format!("{path}.set"),
                format!("expected \"mbm\", got \"{}\"", file.set),
            ));
        }
        for p in file.problems {
            let orientation = DQuat::from_array(p.goal.rotation).normalize();
            let position = DVec3::from_array(p.goal.position);
            let scenario = scenario_json(
                json!({ "preset": "panda" }),
                &p.start,
                obstacles(&p.obstacles, &p.grasped),
                position,
                orientation,
            )
            .map_err(|e| FieldError::new(format!("{path}: {}", p.name), e.to_string()))?;
            out.push(Problem {
                name: p.name,
                scenario,
                position,
                orientation,
                goal_q: Some(p.goal_q),
            });
        }
    }
    Ok(out)
}
