//! JS bindings of the dynamics contract: `inverseDynamics`, `massMatrix`.
//!
//! Each call builds the robot and its [`Dynamics`] from the spec (the rows'
//! `inertial`), then one [`crate::dynamics::Workspace`]; a robot whose rows
//! lack inertial data is refused naming the links.

use wasm_bindgen::prelude::*;

use super::convert::{joint_vec_named, js_error, object_from_js, robot_named, to_js};
use crate::dynamics::{Dynamics, DynamicsOptions};

/// The robot's dynamics under the options' gravity, and its joint names.
fn dynamics_of(
    robot_spec: JsValue,
    options: JsValue,
) -> Result<(Dynamics, Option<Vec<String>>), JsError> {
    let (robot, names) = robot_named(robot_spec)?;
    let options: DynamicsOptions = if options.is_undefined() || options.is_null() {
        DynamicsOptions::default()
    } else {
        object_from_js("options", options)?
    };
    let dynamics = Dynamics::from_robot(robot).map_err(|e| js_error(&e))?;
    let dynamics = options
        .apply(dynamics)
        .map_err(|e| js_error(&e.within("options")))?;
    Ok((dynamics, names))
}

/// Inverse dynamics (recursive Newton–Euler): the joint torques (N·m) and
/// forces (N) `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` as a `Float64Array`.
/// `options`: `{ gravity?: [x, y, z] }` (m/s², world frame; default
/// `[0, 0, -9.81]`).
#[wasm_bindgen(js_name = inverseDynamics)]
pub fn inverse_dynamics(
    robot_spec: JsValue,
    q: JsValue,
    qdot: JsValue,
    qddot: JsValue,
    options: JsValue,
) -> Result<Vec<f64>, JsError> {
    let (dynamics, names) = dynamics_of(robot_spec, options)?;
    let q = joint_vec_named("q", &q, names.as_deref())?;
    let qdot = joint_vec_named("qdot", &qdot, names.as_deref())?;
    let qddot = joint_vec_named("qddot", &qddot, names.as_deref())?;
    let mut ws = dynamics.workspace();
    let mut tau = vec![0.0; dynamics.dof()];
    dynamics
        .inverse_dynamics(&mut ws, &q, (&qdot, &qddot), &mut tau)
        .map_err(|e| js_error(&e))?;
    Ok(tau)
}

/// The joint-space mass matrix `M(q)` (composite rigid bodies), `n × n` as
/// rows.
#[wasm_bindgen(js_name = massMatrix)]
pub fn mass_matrix(robot_spec: JsValue, q: JsValue) -> Result<JsValue, JsError> {
    let (dynamics, names) = dynamics_of(robot_spec, JsValue::UNDEFINED)?;
    let q = joint_vec_named("q", &q, names.as_deref())?;
    let n = dynamics.dof();
    let mut ws = dynamics.workspace();
    let mut m = vec![0.0; n * n];
    dynamics
        .mass_matrix(&mut ws, &q, &mut m)
        .map_err(|e| js_error(&e))?;
    let rows: Vec<&[f64]> = m.chunks(n).collect();
    to_js(&rows)
}
