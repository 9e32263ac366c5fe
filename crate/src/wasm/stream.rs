//! JS binding of a sensor stream: `World.pushHumanFrame(obstacleId,
//! frame)` (the second `impl` of the `World` class; the work is in
//! `crate::world::stream`).

use wasm_bindgen::prelude::*;

use super::boundary::{number_arg, string_arg};
use super::convert::object_from_js;
use super::world::{WorldHandle, scenario_error};
use crate::world::HumanFrame;

#[wasm_bindgen(js_class = World)]
impl WorldHandle {
    /// Takes one frame of a sensed person, `{ t, layout, keypoints,
    /// confidence? }` (`t` in s on the world's clock, `layout` one of
    /// `coco17`, `body25`, `kinect32`, `blazepose33`, `keypoints` `[x, y,
    /// z]` in metres in the world frame), into human obstacle
    /// `obstacleId`: the body is fitted to it as an imported track is.
    ///
    /// # Errors
    /// `obstacleId: no obstacle "x"`, `frame.t: must be after the
    /// previous frame's …`, `frame.layout: unknown layout …`,
    /// `frame.keypoints: expected 33 keypoints …`,
    /// `frame.keypoints[4][0]: not a finite number`, …; the world is
    /// unchanged.
    #[wasm_bindgen(js_name = pushHumanFrame)]
    pub fn push_human_frame(
        &mut self,
        obstacle_id: JsValue,
        frame: JsValue,
    ) -> Result<(), JsError> {
        let id = string_arg("obstacleId", &obstacle_id)?;
        let frame: HumanFrame = object_from_js("frame", frame)?;
        self.inner
            .push_human_frame(&id, &frame)
            .map_err(|e| scenario_error(&e))
    }

    /// Sets the sensing latency of obstacle `obstacleId` (s, in [0, 2]):
    /// its sensed pose is its pose this long ago; a live feed sets its
    /// measured capture-to-pose latency here so that its frames are aged
    /// from when they were seen, not from when they arrived.
    ///
    /// # Errors
    /// `obstacleId: no obstacle "x"`, `latency: must be a finite number in
    /// [0, 2] s, got …`; the world is unchanged.
    #[wasm_bindgen(js_name = setSensingLatency)]
    pub fn set_sensing_latency(
        &mut self,
        obstacle_id: JsValue,
        latency: JsValue,
    ) -> Result<(), JsError> {
        let id = string_arg("obstacleId", &obstacle_id)?;
        let latency = number_arg("latency", &latency)?;
        self.inner
            .set_sensing_latency(&id, latency)
            .map_err(|e| scenario_error(&e))
    }
}
