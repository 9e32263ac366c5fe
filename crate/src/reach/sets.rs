//! The problem sets by name ([`problems`]), and a problem as plain data
//! (`{ name, scenario, goal: { position, orientation }, goalQ? }`: the
//! scenario, saved as JSON, opens in the playground as it is).
//!
//! **In JS: `reachProblems(set)`, plain JS over files, nothing in wasm.** An
//! export over [`problems`] from the wasm module was built and measured
//! first: the web module grew by 36 kB gzipped (1.793 → 1.829 MB), over the
//! budget; measured again on 2026-11-28, 1.812 → 1.849 MB. twiggy's diff of
//! the unoptimised modules (+119 kB) names what costs it: the built-in
//! `pr2.json` and the sets' strings (`.rodata`, +19 kB), the serde readers
//! monomorphised for the MotionBenchMaker scene file (`serde_path_to_error`
//! seeds, about +35 kB), the Panda set's generator (`panda_problems`,
//! +9.5 kB), `mbm_problems` (+8 kB), `pr2_builtin` and `pr2_problems`
//! (+10 kB), a second `Scenario` serialiser (+4.4 kB) and
//! `scenario_json` (+3 kB). The package ships the sets instead as JSON files
//! (`package/problems/<set>.json`: each set's shared scenario fields once,
//! each problem's own fields beside it), which `package/reach.js` expands;
//! `crate/tests/reach_problem_files.rs` checks that the files are these
//! functions' output and writes the native fixture the Node test compares
//! with. The wasm module is unchanged.
//!
//! What is built in, and why: the PR2 set is `pr2.json` beside this file,
//! the arm's spec (volumes as fitted) and the five scenes in their compact
//! form, a few kB gzipped; it is written by [`pr2_data`] from the URDF, the
//! meshes and NEO's scenes file, and a test checks that it still is what
//! they give. The Panda set is generated (seed [`PANDA_SEED`],
//! [`PANDA_COUNT`] problems). The MotionBenchMaker set is not built in
//! (see [`super::mbm`]): it takes the scene files as `data`.

use serde::Serialize as SerializeDerive;
use serde::ser::{Serialize, SerializeStruct, Serializer};

use super::pr2::{Pr2Scene, pr2_problems};
use super::{Problem, mbm, panda_problems};
use crate::error::FieldError;
use crate::kinematics::RobotSpec;

/// The names of the problem sets.
pub const SETS: [&str; 3] = ["pr2", "panda", "mbm"];
/// Seed of the `panda` set.
pub const PANDA_SEED: u64 = 1;
/// Problems in the `panda` set.
pub const PANDA_COUNT: usize = 100;

/// The built-in PR2 set (module docs).
const PR2_DATA: &str = include_str!("pr2.json");

/// The form of `pr2.json`.
#[derive(SerializeDerive)]
#[serde(rename_all = "camelCase")]
struct Pr2Data {
    about: String,
    robot: RobotSpec,
    scenes: Vec<Pr2Scene>,
}

const ABOUT: &str = "NEO's PR2 reach problems (crate/tests/data/neo/, MIT): the right arm \
    imported from crate/tests/data/urdf/pr2.urdf in base_footprint at torso lift 0.16825 m, \
    end effector r_wrist_roll_link; scenes: boxes in base_footprint, configurations, problems = \
    every ordered pair (i, j), i < j. Written by reach::pr2_data; do not edit by hand.";

/// The text of `pr2.json` for the arm `robot` (as [`super::pr2_arm`] gives
/// it) and NEO's scenes file.
///
/// # Errors
/// A scenes file [`super::pr2_scenes`] refuses.
pub fn pr2_data(robot: &RobotSpec, scenes_json: &str) -> Result<String, FieldError> {
    let data = Pr2Data {
        about: ABOUT.into(),
        robot: robot.clone(),
        scenes: super::pr2_scenes(scenes_json)?,
    };
    let mut text =
        serde_json::to_string(&data).map_err(|e| FieldError::new("data", e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// The built-in PR2 set's arm and scenes.
///
/// # Errors
/// Only through a bug (the file is built in and tested).
pub fn pr2_builtin() -> Result<(RobotSpec, Vec<Pr2Scene>), FieldError> {
    // Read as a JSON value first, the robot spec through the same reader as
    // a scenario's (one copy of the spec's reader in the wasm module, not
    // a second one for text).
    let bad = |e: String| FieldError::new("pr2.json", e);
    let mut data: serde_json::Value =
        serde_json::from_str(PR2_DATA).map_err(|e| bad(e.to_string()))?;
    let robot = serde_path_to_error::deserialize(data["robot"].take())
        .map_err(|e: serde_path_to_error::Error<_>| bad(e.to_string()))?;
    let scenes = serde_json::from_value(data["scenes"].take()).map_err(|e| bad(e.to_string()))?;
    Ok((robot, scenes))
}

/// The problems of the set `set` (`"pr2"`, `"panda"` or `"mbm"`): `data`
/// is the MotionBenchMaker scene files (JSON text: one file or an array of
/// them) for `"mbm"`, and must be absent for the built-in sets.
///
/// # Errors
/// `set: unknown problem set "x" (known: pr2, panda, mbm)`; `data: …` when
/// it is missing for `"mbm"`, given for another set, or not scene files.
pub fn problems(set: &str, data: Option<&str>) -> Result<Vec<Problem>, FieldError> {
    if !SETS.contains(&set) {
        return Err(FieldError::new(
            "set",
            format!("unknown problem set \"{set}\" (known: {})", SETS.join(", ")),
        ));
    }
    match (set, data) {
        ("mbm", Some(json)) => mbm::mbm_problems(json, "data"),
        ("mbm", None) => Err(FieldError::new(
            "data",
            "the MotionBenchMaker set is not built in: pass its scene files \
             (crate/tests/data/mbm/*.json, one file or an array of them)",
        )),
        (_, Some(_)) => Err(FieldError::new(
            "data",
            format!("the \"{set}\" set is built in and takes no data"),
        )),
        ("pr2", None) => {
            let (robot, scenes) = pr2_builtin()?;
            pr2_problems(&robot, &scenes)
        }
        _ => panda_problems(PANDA_SEED, PANDA_COUNT),
    }
}

impl Serialize for Problem {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(SerializeDerive)]
        struct Goal {
            position: [f64; 3],
            orientation: [f64; 4],
        }
        let mut out = s.serialize_struct("Problem", 4)?;
        out.serialize_field("name", &self.name)?;
        out.serialize_field("scenario", &self.scenario)?;
        out.serialize_field(
            "goal",
            &Goal {
                position: self.position.to_array(),
                orientation: self.orientation.to_array(),
            },
        )?;
        if let Some(q) = &self.goal_q {
            out.serialize_field("goalQ", q)?;
        } else {
            out.skip_field("goalQ")?;
        }
        out.end()
    }
}
