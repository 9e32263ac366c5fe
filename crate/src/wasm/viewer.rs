//! `Viewer`: a canvas drawing a robot's skeleton with the wgpu renderer.
//!
//! JS owns the viewer (and frees it); it sets the robot and the joint vector,
//! forwards pointer input to the camera, and calls `render()` once per
//! animation frame. This file converts and checks the arguments; what is
//! drawn and how the camera moves is [`crate::view::Stage`]'s, the GPU is
//! [`Renderer`]'s. The per-frame geometry never crosses to JS.

use glam::DVec3;
use serde::Serialize;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use super::convert::{f64_vec, finite_arg, from_js, js_error, object_from_js, robot_named, to_js};
use super::viewer_state::{Ray, ViewerOptions, snapshot};
use crate::render::{BackendRequest, CanvasOptions, Renderer};
use crate::view::{DrawState, Stage, parse_view};

/// A canvas that draws a robot's skeleton over a ground grid, through WebGPU
/// or WebGL2.
///
/// ```js
/// const viewer = await Viewer.create(canvas, { backend: "auto" });
/// viewer.setRobot({ preset: "planar3" });
/// viewer.setJoints([0.3, -0.5, 0.8]);
/// (function frame() { viewer.render(); requestAnimationFrame(frame); })();
/// ```
#[wasm_bindgen]
#[derive(Debug)]
pub struct Viewer {
    renderer: Renderer,
    stage: Stage,
}

#[wasm_bindgen]
impl Viewer {
    /// Starts a viewer on `canvas` (an `HTMLCanvasElement`).
    ///
    /// `options`: `{ backend?: "auto" | "webgpu" | "webgl2", view?: "auto" |
    /// "3d" | "top" | "front" | "side", antialias?: boolean, offscreen?:
    /// boolean }` (antialias: 4× multisampling; by default on unless the
    /// adapter is a software rasteriser. offscreen: draw through the
    /// canvas's `OffscreenCanvas` (`transferControlToOffscreen`), which the
    /// browser composites more cheaply (about 5 ms less a frame on
    /// Chromium's software compositor); the canvas then belongs to the
    /// viewer: it can give no other context, its `width` and `height` can
    /// no longer be set, and a second viewer cannot draw on it. Default
    /// false; ignored where the browser cannot hand the canvas over).
    ///
    /// # Errors
    /// Rejects with an `Error` when `canvas` is not a canvas, an option is
    /// unknown, or the browser offers neither WebGPU nor WebGL2 (the message
    /// says so in words a person can act on).
    #[wasm_bindgen(unchecked_return_type = "Viewer")]
    pub async fn create(canvas: JsValue, options: JsValue) -> Result<JsValue, JsError> {
        let canvas: web_sys::HtmlCanvasElement = canvas
            .dyn_into()
            .map_err(|_| JsError::new("canvas: not an HTMLCanvasElement"))?;
        let options: ViewerOptions = if options.is_undefined() || options.is_null() {
            ViewerOptions::default()
        } else {
            object_from_js("options", options)?
        };
        let request = match options.backend.as_deref() {
            None => BackendRequest::Auto,
            Some(name) => BackendRequest::parse(name).ok_or_else(|| {
                JsError::new(&format!(
                    "options.backend: expected \"auto\", \"webgpu\" or \"webgl2\", got {name:?}"
                ))
            })?,
        };
        let fixed_view = match options.view.as_deref() {
            None => None,
            Some(name) => parse_view("options.view", name).map_err(|e| js_error(&e))?,
        };
        let canvas_options = CanvasOptions {
            antialias: options.antialias,
            offscreen: options.offscreen.unwrap_or(false),
        };
        let renderer = Renderer::new(canvas, request, canvas_options)
            .await
            .map_err(|e| JsError::new(&e.to_string()))?;
        let mut viewer = Viewer {
            renderer,
            stage: Stage::new(fixed_view),
        };
        viewer.follow_size();
        Ok(super::boundary::guarded_viewer(viewer))
    }

    /// The backend drawing the canvas: `"webgpu"` or `"webgl2"`.
    #[wasm_bindgen(getter)]
    pub fn backend(&self) -> String {
        self.renderer.backend().name().to_owned()
    }

    /// Number of joints of the current robot (0 before `setRobot`).
    #[wasm_bindgen(getter)]
    pub fn dof(&self) -> usize {
        self.stage.q().len()
    }

    /// Sets the robot: a robot spec object (see the JS contract) or
    /// `{ preset: name }`. The joints go to zero and, unless a view was fixed
    /// at creation, the camera frames the robot (top view for a planar robot).
    ///
    /// # Errors
    /// An `Error` naming the field and the reason when the spec is invalid.
    #[wasm_bindgen(js_name = setRobot)]
    pub fn set_robot(&mut self, spec: JsValue) -> Result<(), JsError> {
        let (robot, _) = robot_named(spec)?;
        self.stage.set_robot(robot).map_err(|e| js_error(&e))
    }

    /// Draws a world state given as a plain object: `{ skeleton: { nodes,
    /// segments }, obstacles?: [{ id, shape, parts? }], controlPoints?: [{
    /// position, witness?, repulsion?, transitioning? }], uncertainty?: [{
    /// obstacle, radius }], slidingPoints?: [[x, y, z]] }` (the shape of
    /// `World.state()`; other fields are ignored). Replaces the robot's own
    /// skeleton until the next `setRobot`. For a live world prefer
    /// `drawWorld`, which copies nothing through JS.
    ///
    /// # Errors
    /// An `Error` naming the field when the object does not have that shape.
    #[wasm_bindgen(js_name = drawState)]
    pub fn draw_state(&mut self, state: JsValue) -> Result<(), JsError> {
        let state: DrawState = from_js("state", state)?;
        self.stage.draw(state);
        Ok(())
    }

    /// Draws the current state of a simulated `World`: its skeleton,
    /// obstacles, control points, distance lines, repulsion arrows,
    /// uncertainty regions and the sliding points of point tasks. Call it
    /// once per frame after stepping; the geometry is read in Rust and never
    /// crosses to JS. Replaces the robot's own skeleton until the next
    /// `setRobot`.
    ///
    /// ```js
    /// world.advance(0.001, 16);
    /// viewer.drawWorld(world);
    /// viewer.render();
    /// ```
    #[wasm_bindgen(js_name = drawWorld)]
    pub fn draw_world(&mut self, world: &super::world::WorldHandle) {
        let core = world.world();
        // Without events: the viewer does not draw them.
        let state = core.state_since(core.event_count());
        self.stage.draw(DrawState::from(state));
    }

    /// Sets the robot from a URDF and its mesh files, and draws its
    /// collision meshes (lit, under the translucent volumes; `setDisplay({
    /// meshes, volumes })` switches either off). `options` are `fitUrdf`'s
    /// (`{ tip?, base?, meshes }`), and so is the result (`{ robot, before,
    /// after, problems }`): give `result.robot` to `new World(…)` and draw
    /// the world as usual; the meshes follow its joints.
    ///
    /// # Errors
    /// `fitUrdf`'s; the viewer is unchanged after one.
    #[wasm_bindgen(js_name = setUrdf)]
    pub fn set_urdf(&mut self, xml: JsValue, options: JsValue) -> Result<JsValue, JsError> {
        let fit = super::urdf::fit_from_js(xml, options)?;
        let robot = crate::kinematics::Robot::from_spec(&fit.robot).map_err(|e| js_error(&e))?;
        let zero = robot
            .forward(&vec![0.0; robot.dof()])
            .map_err(|e| js_error(&e))?;
        let meshes = crate::view::link_meshes(&fit.bodies, &zero.transforms);
        let report = to_js(&fit)?;
        self.stage.set_robot(robot).map_err(|e| js_error(&e))?;
        self.stage.set_meshes(meshes);
        Ok(report)
    }

    /// Draws a URDF's collision meshes on the current robot, which must be
    /// the same arm in another description (a preset's DH table): the tips
    /// agree, after one rigid base transform, to 1 µm over sampled
    /// configurations; the robot and its volumes stay as they are.
    /// `options` are `setUrdf`'s; the result is `{ problems }` (the meshes
    /// that could not be found or read); nothing is fitted or measured. The
    /// meshes go with the next `setRobot`.
    ///
    /// # Errors
    /// `fitUrdf`'s; `setMeshesFromUrdf: no robot; call setRobot first`;
    /// `setMeshesFromUrdf: the URDF's kinematics are not the robot's: …`
    /// (or its joint count differs). The viewer is unchanged after one.
    #[wasm_bindgen(js_name = setMeshesFromUrdf)]
    pub fn set_meshes_from_urdf(
        &mut self,
        xml: JsValue,
        options: JsValue,
    ) -> Result<JsValue, JsError> {
        let (spec, bodies, problems) = super::urdf::bodies_from_js(xml, options)?;
        let from = crate::kinematics::Robot::from_spec(&spec).map_err(|e| js_error(&e))?;
        let Some(onto) = self.stage.robot() else {
            return Err(JsError::new(
                "setMeshesFromUrdf: no robot; call setRobot first",
            ));
        };
        let bodies = crate::fitting::bodies_onto(&from, onto, &bodies)
            .map_err(|e| JsError::new(&format!("setMeshesFromUrdf: {e}")))?;
        let zero = onto
            .forward(&vec![0.0; onto.dof()])
            .map_err(|e| js_error(&e))?;
        let meshes = crate::view::link_meshes(&bodies, &zero.transforms);
        #[derive(Serialize)]
        struct Report {
            problems: Vec<String>,
        }
        let report = to_js(&Report { problems })?;
        self.stage.set_meshes(meshes);
        Ok(report)
    }

    /// Highlights the obstacle with this id (`null` or `undefined`: none).
    ///
    /// # Errors
    /// An `Error` when `id` is neither a string nor null.
    #[wasm_bindgen(js_name = setSelected)]
    pub fn set_selected(&mut self, id: JsValue) -> Result<(), JsError> {
        let id = if id.is_null() || id.is_undefined() {
            None
        } else {
            Some(
                id.as_string()
                    .ok_or_else(|| JsError::new("setSelected: expected a string id or null"))?,
            )
        };
        self.stage.set_selected(id);
        Ok(())
    }

    /// Where the world point `[x, y, z]` (m) lands on the canvas, in
    /// drawing-buffer pixels from the top-left corner, or `null` when it is
    /// behind the eye.
    ///
    /// # Errors
    /// An `Error` unless `point` is three finite numbers.
    #[wasm_bindgen(js_name = projectPoint)]
    pub fn project_point(&self, point: JsValue) -> Result<JsValue, JsError> {
        let p = f64_vec("point", &point)?;
        let [x, y, z] = p[..] else {
            return Err(JsError::new("point: expected 3 numbers"));
        };
        for (k, c) in [x, y, z].into_iter().enumerate() {
            finite_arg(&format!("point[{k}]"), c)?;
        }
        let (width, height) = self.renderer.size();
        let projected =
            self.stage
                .camera()
                .project(DVec3::new(x, y, z).as_vec3(), width as f32, height as f32);
        to_js(&projected)
    }

    /// The camera's viewing direction (unit vector from the eye towards the
    /// target, world frame): the normal of the view-aligned drag plane.
    #[wasm_bindgen(js_name = viewDirection)]
    pub fn view_direction(&self) -> Vec<f64> {
        (-self.stage.camera().backward())
            .as_dvec3()
            .to_array()
            .to_vec()
    }

    /// Sets the joint vector (rad for revolute joints, m for prismatic ones)
    /// from an array or a `Float64Array` of `dof` numbers.
    ///
    /// # Errors
    /// An `Error` when no robot is set, the length is not `dof`, or a value
    /// is not a finite number (`q[2]: not a finite number`).
    #[wasm_bindgen(js_name = setJoints)]
    pub fn set_joints(&mut self, q: JsValue) -> Result<(), JsError> {
        // Checked first so that the message names the missing robot.
        self.stage.require_robot().map_err(|e| js_error(&e))?;
        let q = f64_vec("q", &q)?;
        self.stage.set_joints(q).map_err(|e| js_error(&e))
    }

    /// Chooses what is drawn: `{ volumes?, nodes?, axes?, grid?,
    /// arrowScale? }` (booleans, and metres of repulsion arrow per m/s;
    /// missing fields take their defaults: volumes, nodes and grid on, axes
    /// off, arrowScale 0.4).
    ///
    /// # Errors
    /// An `Error` naming an unknown or mistyped field.
    #[wasm_bindgen(js_name = setDisplay)]
    pub fn set_display(&mut self, display: JsValue) -> Result<(), JsError> {
        self.stage.set_display(object_from_js("display", display)?);
        Ok(())
    }

    /// Switches the view: `"3d"`, `"top"`, `"front"`, `"side"`, or `"auto"`
    /// (the 2D top view for a planar robot, else 3D).
    ///
    /// # Errors
    /// An `Error` for any other name.
    #[wasm_bindgen(js_name = setView)]
    pub fn set_view(&mut self, name: JsValue) -> Result<(), JsError> {
        let name = super::boundary::string_arg("view", &name)?;
        let view = parse_view("view", &name).map_err(|e| js_error(&e))?;
        self.stage.set_view(view);
        Ok(())
    }

    /// Applies a scenario's `camera`: `{ yaw?, pitch?, frame? }` (rad, rad,
    /// world points in m that `fit` keeps on screen besides the robot;
    /// `docs/scenarios.md`). Call it after `setRobot`, which resets both,
    /// and before `fit`.
    ///
    /// # Errors
    /// An `Error` naming the field (`camera.pitch: must be within ±1.55 rad
    /// (got 2)`); the camera is then unchanged.
    #[wasm_bindgen(js_name = setCamera)]
    pub fn set_camera(&mut self, camera: JsValue) -> Result<(), JsError> {
        let spec: crate::scenario::CameraSpec = object_from_js("camera", camera)?;
        self.stage
            .set_camera(&spec)
            .map_err(|e| js_error(&e.within("camera")))
    }

    /// The current view's name.
    #[wasm_bindgen(getter)]
    pub fn view(&self) -> String {
        self.stage.camera().view.name().to_owned()
    }

    /// Orbits the 3D camera by a pointer drag of `dx`, `dy` pixels (ignored
    /// in the 2D views).
    ///
    /// # Errors
    /// An `Error` when a delta is not finite.
    pub fn orbit(&mut self, dx: f64, dy: f64) -> Result<(), JsError> {
        let (dx, dy) = (finite_arg("orbit.dx", dx)?, finite_arg("orbit.dy", dy)?);
        self.stage.orbit(dx as f32, dy as f32);
        Ok(())
    }

    /// Pans so that the scene follows a pointer drag of `dx`, `dy` pixels.
    ///
    /// # Errors
    /// An `Error` when a delta is not finite.
    pub fn pan(&mut self, dx: f64, dy: f64) -> Result<(), JsError> {
        let (dx, dy) = (finite_arg("pan.dx", dx)?, finite_arg("pan.dy", dy)?);
        let height = self.renderer.size().1 as f32;
        self.stage.pan(dx as f32, dy as f32, height);
        Ok(())
    }

    /// Multiplies the camera distance by `factor` (> 1 zooms out); a wheel
    /// handler can pass `Math.exp(event.deltaY * 0.001)`.
    ///
    /// # Errors
    /// An `Error` unless `factor` is finite and > 0.
    pub fn zoom(&mut self, factor: f64) -> Result<(), JsError> {
        let factor = finite_arg("zoom.factor", factor)?;
        if factor <= 0.0 {
            return Err(JsError::new("zoom.factor: must be > 0"));
        }
        self.stage.zoom(factor as f32);
        Ok(())
    }

    /// Frames the scene: the camera keeps its direction and aims at the
    /// robot's skeleton and the obstacles it can reach (centres within its
    /// reach from the base) so that they fill about `fill` of the view's
    /// width or height (default 0.6). With `top` (drawing-buffer pixels,
    /// default 0) they are framed in the part of the view below its top
    /// `top` pixels, where a page lays text over it (at most half the view).
    ///
    /// # Errors
    /// An `Error` unless `fill` is undefined or a number in (0, 1], and
    /// `top` undefined or a number ≥ 0.
    pub fn fit(&mut self, fill: Option<f64>, top: Option<f64>) -> Result<(), JsError> {
        let fill = finite_arg("fit.fill", fill.unwrap_or(0.6))?;
        if !(fill > 0.0 && fill <= 1.0) {
            return Err(JsError::new("fit.fill: must be in (0, 1]"));
        }
        let top = finite_arg("fit.top", top.unwrap_or(0.0))?;
        if top < 0.0 {
            return Err(JsError::new("fit.top: must be ≥ 0"));
        }
        let (width, height) = self.renderer.size();
        self.stage.fit_below(
            fill as f32,
            (width as f32, height.max(1) as f32),
            top as f32,
        );
        Ok(())
    }

    /// Sets the drawing-buffer size in pixels (CSS size × devicePixelRatio).
    ///
    /// # Errors
    /// An `Error` unless both are finite and ≥ 1.
    pub fn resize(&mut self, width: f64, height: f64) -> Result<(), JsError> {
        let (width, height) = (finite_arg("width", width)?, finite_arg("height", height)?);
        if width < 1.0 || height < 1.0 {
            return Err(JsError::new("resize: width and height must be >= 1"));
        }
        self.renderer
            .resize(width.round() as u32, height.round() as u32);
        self.follow_size();
        self.stage.touch();
        Ok(())
    }

    /// Draws one frame when the picture changed since the last one (the
    /// canvas keeps its picture otherwise: an unchanged scene and camera
    /// are not drawn again); call it from `requestAnimationFrame`.
    ///
    /// # Errors
    /// An `Error` when the drawing surface is lost for good.
    pub fn render(&mut self) -> Result<(), JsError> {
        let Some((scene, camera)) = self.stage.frame() else {
            return Ok(());
        };
        self.renderer.update(scene, &camera);
        let presented = self
            .renderer
            .render()
            .map_err(|e| JsError::new(&e.to_string()))?;
        self.stage.drawn(presented);
        Ok(())
    }

    /// The picking ray through canvas pixel (`x`, `y`) (drawing-buffer
    /// pixels from the top-left corner): `{ origin: [x, y, z], direction:
    /// [x, y, z] }` in the world frame (m), `direction` a unit vector.
    ///
    /// # Errors
    /// An `Error` when a coordinate is not finite.
    #[wasm_bindgen(js_name = rayAt)]
    pub fn ray_at(&self, x: f64, y: f64) -> Result<JsValue, JsError> {
        let (x, y) = (finite_arg("x", x)?, finite_arg("y", y)?);
        let (width, height) = self.renderer.size();
        let (origin, direction) = self
            .stage
            .camera()
            .ray(x as f32, y as f32, width as f32, height as f32)
            .ok_or_else(|| JsError::new("rayAt: the camera is degenerate"))?;
        let ray = Ray {
            origin: origin.as_dvec3().to_array(),
            direction: direction.as_dvec3().to_array(),
        };
        serde_wasm_bindgen::to_value(&ray).map_err(|e| JsError::new(&e.to_string()))
    }

    /// A snapshot for tests and tools: `{ backend, surfaceFormat,
    /// sampleCount, triangles, solidTriangles, framesDrawn, framesUnchanged,
    /// view, width, height, dof, q,
    /// nodes, screenNodes }`, where `triangles` are those drawn (the solids'
    /// faces turned away left out), `solidTriangles` those of the capsules
    /// and spheres at their level of detail, back faces included, and
    /// `screenNodes` the skeleton nodes in drawing-buffer pixels.
    ///
    /// # Errors
    /// Only if the snapshot cannot be converted (not expected).
    pub fn state(&self) -> Result<JsValue, JsError> {
        let state = snapshot(&self.renderer, &self.stage);
        serde_wasm_bindgen::to_value(&state).map_err(|e| JsError::new(&e.to_string()))
    }
}

impl Viewer {
    /// Tells the stage the drawing buffer's height and the renderer's
    /// tolerance, for the link meshes' level of detail.
    fn follow_size(&mut self) {
        let (_, height) = self.renderer.size();
        let tolerance = crate::view::tessellation::tolerance(self.renderer.is_software());
        self.stage.set_detail(height as f32, tolerance);
    }
}
