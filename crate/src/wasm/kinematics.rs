//! JS bindings of the kinematics contract: `robotPreset`, `presetNames`,
//! `forwardKinematics`, `skeleton`, `controlPoint`, `skeletonPoint`.

use glam::{DAffine3, DVec3};
use serde::{Deserialize, Serialize};
use wasm_bindgen::prelude::*;

use super::boundary::{count_arg, string_arg};
use super::convert::{joint_vec_named, js_error, object_from_js, robot_named, to_js};
use crate::control_point::DhPoint;
use crate::kinematics::{Robot, presets};
use crate::skeleton::{Skeleton, SpinePart};

type Rows = Vec<Vec<f64>>;

fn matrix4(t: &DAffine3) -> [[f64; 4]; 4] {
    let m = t.matrix3;
    let p = t.translation;
    [
        [m.x_axis.x, m.y_axis.x, m.z_axis.x, p.x],
        [m.x_axis.y, m.y_axis.y, m.z_axis.y, p.y],
        [m.x_axis.z, m.y_axis.z, m.z_axis.z, p.z],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

fn rows(cols: &[DVec3]) -> Rows {
    (0..3)
        .map(|r| cols.iter().map(|c| c[r]).collect())
        .collect()
}

fn frames_of(
    robot: &Robot,
    names: Option<&[String]>,
    q: &JsValue,
) -> Result<crate::kinematics::Frames, JsError> {
    let q = joint_vec_named("q", q, names)?;
    robot.forward(&q).map_err(|e| js_error(&e))
}

/// The robot spec of a preset: `"planar3"`, `"lwr4"`, `"iiwa14"`, `"panda"`,
/// `"ur5"`, `"dual-arm"`, `"stanford"`.
#[wasm_bindgen(js_name = robotPreset)]
pub fn robot_preset(name: JsValue) -> Result<JsValue, JsError> {
    let name = string_arg("name", &name)?;
    to_js(&presets::preset(&name).map_err(|e| js_error(&e))?)
}

/// Names of the presets.
#[wasm_bindgen(js_name = presetNames)]
#[must_use]
pub fn preset_names() -> Vec<String> {
    presets::NAMES.iter().map(|s| (*s).to_owned()).collect()
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct FkOut {
    origins: Vec<[f64; 3]>,
    frames: Vec<[[f64; 4]; 4]>,
    end_effector: [[f64; 4]; 4],
    end_effectors: Vec<[[f64; 4]; 4]>,
}

/// Forward kinematics: `{ origins, frames, endEffector, endEffectors }`:
/// origins of frames 0..n, every frame and the end effector as 4×4 rows, one
/// end effector per chain.
#[wasm_bindgen(js_name = forwardKinematics)]
pub fn forward_kinematics(robot_spec: JsValue, q: JsValue) -> Result<JsValue, JsError> {
    let (r, names) = robot_named(robot_spec)?;
    let f = frames_of(&r, names.as_deref(), &q)?;
    to_js(&FkOut {
        origins: f
            .transforms
            .iter()
            .map(|t| t.translation.to_array())
            .collect(),
        frames: f.transforms.iter().map(matrix4).collect(),
        end_effector: matrix4(&f.end_effector()),
        end_effectors: f.end_effectors.iter().map(matrix4).collect(),
    })
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct SegmentOut {
    from: usize,
    to: usize,
    link: usize,
    part: SpinePart,
    radius: [f64; 2],
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct SkeletonOut {
    nodes: Vec<[f64; 3]>,
    segments: Vec<SegmentOut>,
    frame_nodes: Vec<usize>,
}

/// The skeleton: `{ nodes, segments: [{ from, to, link, part, radius: [r0, r1] }],
/// frameNodes }`.
#[wasm_bindgen]
pub fn skeleton(robot_spec: JsValue, q: JsValue) -> Result<JsValue, JsError> {
    let (r, names) = robot_named(robot_spec)?;
    let f = frames_of(&r, names.as_deref(), &q)?;
    let s = Skeleton::build(&r, &f);
    to_js(&SkeletonOut {
        nodes: s.nodes.iter().map(|p| p.to_array()).collect(),
        segments: s
            .segments
            .iter()
            .map(|g| SegmentOut {
                from: g.from,
                to: g.to,
                link: g.link,
                part: g.part,
                radius: g.radius,
            })
            .collect(),
        frame_nodes: s.frame_nodes,
    })
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct PointIn {
    link: usize,
    d: f64,
    a: f64,
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct RatesIn {
    qdot: Vec<f64>,
    #[serde(default)]
    a_rate: f64,
    #[serde(default)]
    d_rate: f64,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct ControlPointOut {
    position: [f64; 3],
    j_theta: Rows,
    j_a: Rows,
    j_d: Rows,
    #[serde(skip_serializing_if = "Option::is_none")]
    segment: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    t: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    velocity: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    j_theta_dot: Option<Rows>,
    #[serde(skip_serializing_if = "Option::is_none")]
    j_a_dot: Option<Rows>,
    #[serde(skip_serializing_if = "Option::is_none")]
    j_d_dot: Option<Rows>,
}

/// A control point given by DH values `{ link, d, a }` (link 1-based):
/// `{ position, jTheta, jA, jD, segment, t }`, each Jacobian 3 × n as rows; with
/// `rates = { qdot, aRate?, dRate? }` also `velocity`, `jThetaDot`, `jADot`,
/// `jDDot`.
#[wasm_bindgen(js_name = controlPoint)]
pub fn control_point(
    robot_spec: JsValue,
    q: JsValue,
    point: JsValue,
    rates: JsValue,
) -> Result<JsValue, JsError> {
    let (r, names) = robot_named(robot_spec)?;
    let qv = joint_vec_named("q", &q, names.as_deref())?;
    let p: PointIn = object_from_js("point", point)?;
    let p = DhPoint {
        link: p.link,
        d: p.d,
        a: p.a,
    };
    let rates: Option<RatesIn> = if rates.is_undefined() || rates.is_null() {
        None
    } else {
        Some(object_from_js("rates", rates)?)
    };
    let frames = match &rates {
        Some(rt) => r.forward_with_velocity(&qv, &rt.qdot),
        None => r.forward(&qv),
    }
    .map_err(|e| js_error(&e))?;
    p.validate(&r, &frames)
        .map_err(|e| js_error(&e.within("point")))?;
    let jac = p.jacobians(&r, &frames);
    let skel = Skeleton::build(&r, &frames);
    let on_skeleton = p.to_skeleton(&r, &frames, &skel);
    let mut out = ControlPointOut {
        position: jac.position.to_array(),
        j_theta: rows(&jac.j_theta),
        j_a: rows(&jac.j_a),
        j_d: rows(&jac.j_d),
        segment: on_skeleton.map(|x| x.0),
        t: on_skeleton.map(|x| x.1),
        velocity: None,
        j_theta_dot: None,
        j_a_dot: None,
        j_d_dot: None,
    };
    if let Some(rt) = rates {
        let jr = p
            .jacobian_rates(&r, &frames, rt.a_rate, rt.d_rate)
            .map_err(|e| js_error(&e.within("rates")))?;
        out.velocity = Some(jr.velocity.to_array());
        out.j_theta_dot = Some(rows(&jr.j_theta_dot));
        out.j_a_dot = Some(rows(&jr.j_a_dot));
        out.j_d_dot = Some(rows(&jr.j_d_dot));
    }
    to_js(&out)
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct SkeletonPointIn {
    segment: usize,
    t: f64,
}

#[derive(Serialize)]
struct DhOut {
    link: usize,
    d: f64,
    a: f64,
    position: [f64; 3],
}

/// DH values `{ link, d, a, position }` of the point at fraction `t` along
/// skeleton segment `segment`.
#[wasm_bindgen(js_name = skeletonPoint)]
pub fn skeleton_point(robot_spec: JsValue, q: JsValue, at: JsValue) -> Result<JsValue, JsError> {
    let (r, names) = robot_named(robot_spec)?;
    let f = frames_of(&r, names.as_deref(), &q)?;
    let at: SkeletonPointIn = object_from_js("at", at)?;
    let s = Skeleton::build(&r, &f);
    let p = DhPoint::from_skeleton(&r, &f, &s, at.segment, at.t)
        .map_err(|e| js_error(&e.within("at")))?;
    to_js(&DhOut {
        link: p.link,
        d: p.d,
        a: p.a,
        position: p.position(&r, &f).to_array(),
    })
}

/// Runs the `KinematicsStep` benchmark workload (FK, skeleton, 8 control-point
/// Jacobians) `iterations` times for preset `name` inside wasm; returns a
/// checksum. Node times the call (`npm run bench`). Like the native bench's
/// batches (`benches/kinematics.rs`) it builds the workload once and runs it
/// on from call to call, so that a call's time holds only steps.
#[wasm_bindgen(js_name = benchKinematicsStep)]
pub fn bench_kinematics_step(name: JsValue, iterations: JsValue) -> Result<f64, JsError> {
    let name = string_arg("name", &name)?;
    let iterations = count_arg(
        "iterations",
        &iterations,
        None,
        super::world::MAX_BENCH_ITERATIONS,
    )?;
    let mut w = match BENCH_STEP.take() {
        Some((kept, w)) if kept == name => w,
        _ => crate::workloads::KinematicsStep::new(&name, 64).map_err(|e| js_error(&e))?,
    };
    let mut sum = 0.0;
    for _ in 0..iterations {
        sum += w.run();
    }
    BENCH_STEP.set(Some((name, w)));
    Ok(sum)
}

thread_local! {
    /// `benchKinematicsStep`'s workload and the preset it is for.
    static BENCH_STEP: std::cell::RefCell<Option<(String, crate::workloads::KinematicsStep)>> =
        const { std::cell::RefCell::new(None) };
}
