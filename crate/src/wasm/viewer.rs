//! `Viewer`: a canvas drawing a robot's skeleton with the wgpu renderer.
//!
//! JS owns the viewer (and frees it); it sets the robot and the joint vector,
//! forwards pointer input to the camera, and calls `render()` once per
//! animation frame. The per-frame geometry is built here, from the skeleton,
//! and never crosses to JS.

use glam::{DAffine3, Vec3};
use serde::{Deserialize, Serialize};
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use super::convert::{f64_vec, finite_arg, js_error, object_from_js, robot as robot_from_js};
use crate::kinematics::{Frames, Robot};
use crate::render::{BackendRequest, Camera, Capsule, Renderer, Scene, Sphere, View};
use crate::skeleton::Skeleton;

/// Options of `Viewer.create`.
#[derive(Debug, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct ViewerOptions {
    /// `"auto"` (default), `"webgpu"` or `"webgl2"`.
    backend: Option<String>,
    /// `"auto"` (default: 2D top view for planar robots, else 3D), `"3d"`,
    /// `"top"`, `"front"`, `"side"`.
    view: Option<String>,
}

/// What `setDisplay` toggles.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct Display {
    /// The translucent volumes around the skeleton segments.
    volumes: bool,
    /// The skeleton nodes as small spheres.
    nodes: bool,
    /// The DH frames' axes.
    axes: bool,
    /// The ground grid.
    grid: bool,
}

impl Default for Display {
    fn default() -> Self {
        Self {
            volumes: true,
            nodes: true,
            axes: false,
            grid: true,
        }
    }
}

/// What `state()` reports (for tests and tooling, not for every frame).
#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
struct ViewerState {
    backend: &'static str,
    surface_format: String,
    sample_count: u32,
    view: &'static str,
    width: u32,
    height: u32,
    dof: usize,
    q: Vec<f64>,
    /// Skeleton nodes (m, world frame).
    nodes: Vec<[f64; 3]>,
    /// The same nodes in drawing-buffer pixels from the top-left corner
    /// (`null` when behind the eye).
    screen_nodes: Vec<Option<[f32; 2]>>,
}

/// A picking ray (m, world frame).
#[derive(Debug, Serialize)]
struct Ray {
    origin: [f64; 3],
    direction: [f64; 3],
}

const VOLUME_COLOR: [f32; 4] = [0.33, 0.55, 0.85, 0.45];
const SPINE_COLOR: [f32; 4] = [0.20, 0.24, 0.32, 1.0];
const NODE_COLOR: [f32; 4] = [0.95, 0.55, 0.15, 1.0];
const SPINE_RADIUS: f32 = 0.012;
const NODE_RADIUS: f32 = 0.022;

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
    camera: Camera,
    scene: Scene,
    display: Display,
    fixed_view: Option<View>,
    /// The view `"auto"` stands for with the current robot.
    auto_view: View,
    robot: Option<Robot>,
    q: Vec<f64>,
    skeleton: Skeleton,
    frames: Vec<DAffine3>,
    dirty: bool,
}

#[wasm_bindgen]
impl Viewer {
    /// Starts a viewer on `canvas` (an `HTMLCanvasElement`).
    ///
    /// `options`: `{ backend?: "auto" | "webgpu" | "webgl2", view?: "auto" |
    /// "3d" | "top" | "front" | "side" }`.
    ///
    /// # Errors
    /// Rejects with an `Error` when `canvas` is not a canvas, an option is
    /// unknown, or the browser offers neither WebGPU nor WebGL2 (the message
    /// says so in words a person can act on).
    pub async fn create(canvas: JsValue, options: JsValue) -> Result<Viewer, JsError> {
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
            None | Some("auto") => None,
            Some(name) => Some(View::parse(name).ok_or_else(|| view_error("options.view", name))?),
        };
        let renderer = Renderer::new(canvas, request)
            .await
            .map_err(|e| JsError::new(&e.to_string()))?;
        let camera = Camera::framing(Vec3::ZERO, 1.0, fixed_view.unwrap_or(View::Orbit));
        Ok(Viewer {
            renderer,
            camera,
            scene: Scene::new(),
            display: Display::default(),
            fixed_view,
            auto_view: View::Orbit,
            robot: None,
            q: Vec::new(),
            skeleton: Skeleton::default(),
            frames: Vec::new(),
            dirty: true,
        })
    }

    /// The backend drawing the canvas: `"webgpu"` or `"webgl2"`.
    #[wasm_bindgen(getter)]
    pub fn backend(&self) -> String {
        self.renderer.backend().name().to_owned()
    }

    /// Number of joints of the current robot (0 before `setRobot`).
    #[wasm_bindgen(getter)]
    pub fn dof(&self) -> usize {
        self.q.len()
    }

    /// Sets the robot: a robot spec object (see the JS contract) or
    /// `{ preset: name }`. The joints go to zero and, unless a view was fixed
    /// at creation, the camera frames the robot (top view for a planar robot).
    ///
    /// # Errors
    /// An `Error` naming the field and the reason when the spec is invalid.
    #[wasm_bindgen(js_name = setRobot)]
    pub fn set_robot(&mut self, spec: JsValue) -> Result<(), JsError> {
        let robot = robot_from_js(spec)?;
        // Zero, or the nearest value within the joint limits.
        let mut q = vec![0.0; robot.dof()];
        robot.clamp_to_limits(&mut q);
        let f = robot.forward(&q).map_err(|e| js_error(&e))?;
        let skeleton = Skeleton::build(&robot, &f);
        let (center, reach) = reach(&robot, &f);
        let frames = f.transforms;
        self.auto_view = if is_planar(&frames) {
            View::Top
        } else {
            View::Orbit
        };
        let view = self.fixed_view.unwrap_or(self.auto_view);
        self.camera = Camera::framing(center.as_vec3(), reach as f32, view);
        self.robot = Some(robot);
        self.q = q;
        self.frames = frames;
        self.skeleton = skeleton;
        self.dirty = true;
        Ok(())
    }

    /// Sets the joint vector (rad for revolute joints, m for prismatic ones)
    /// from an array or a `Float64Array` of `dof` numbers.
    ///
    /// # Errors
    /// An `Error` when no robot is set, the length is not `dof`, or a value
    /// is not a finite number (`q[2]: not a finite number`).
    #[wasm_bindgen(js_name = setJoints)]
    pub fn set_joints(&mut self, q: JsValue) -> Result<(), JsError> {
        let Some(robot) = &self.robot else {
            return Err(JsError::new("setJoints: no robot; call setRobot first"));
        };
        let q = f64_vec("q", &q)?;
        let f = robot.forward(&q).map_err(|e| js_error(&e))?;
        self.skeleton = Skeleton::build(robot, &f);
        self.frames = f.transforms;
        self.q = q;
        self.dirty = true;
        Ok(())
    }

    /// Chooses what is drawn: `{ volumes?, nodes?, axes?, grid? }` (booleans;
    /// missing fields take their defaults: volumes, nodes and grid on, axes off).
    ///
    /// # Errors
    /// An `Error` naming an unknown or mistyped field.
    #[wasm_bindgen(js_name = setDisplay)]
    pub fn set_display(&mut self, display: JsValue) -> Result<(), JsError> {
        self.display = object_from_js("display", display)?;
        self.dirty = true;
        Ok(())
    }

    /// Switches the view: `"3d"`, `"top"`, `"front"`, `"side"`, or `"auto"`
    /// (the 2D top view for a planar robot, else 3D).
    ///
    /// # Errors
    /// An `Error` for any other name.
    #[wasm_bindgen(js_name = setView)]
    pub fn set_view(&mut self, name: &str) -> Result<(), JsError> {
        self.camera.view = match name {
            "auto" => self.auto_view,
            _ => View::parse(name).ok_or_else(|| view_error("view", name))?,
        };
        self.dirty = true;
        Ok(())
    }

    /// The current view's name.
    #[wasm_bindgen(getter)]
    pub fn view(&self) -> String {
        self.camera.view.name().to_owned()
    }

    /// Orbits the 3D camera by a pointer drag of `dx`, `dy` pixels (ignored
    /// in the 2D views).
    ///
    /// # Errors
    /// An `Error` when a delta is not finite.
    pub fn orbit(&mut self, dx: f64, dy: f64) -> Result<(), JsError> {
        let (dx, dy) = (finite_arg("orbit.dx", dx)?, finite_arg("orbit.dy", dy)?);
        self.camera.orbit(dx as f32, dy as f32);
        self.dirty = true;
        Ok(())
    }

    /// Pans so that the scene follows a pointer drag of `dx`, `dy` pixels.
    ///
    /// # Errors
    /// An `Error` when a delta is not finite.
    pub fn pan(&mut self, dx: f64, dy: f64) -> Result<(), JsError> {
        let (dx, dy) = (finite_arg("pan.dx", dx)?, finite_arg("pan.dy", dy)?);
        let height = self.renderer.size().1 as f32;
        self.camera.pan(dx as f32, dy as f32, height);
        self.dirty = true;
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
        self.camera.zoom(factor as f32);
        self.dirty = true;
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
        self.dirty = true;
        Ok(())
    }

    /// Draws one frame; call it from `requestAnimationFrame`.
    ///
    /// # Errors
    /// An `Error` when the drawing surface is lost for good.
    pub fn render(&mut self) -> Result<(), JsError> {
        if self.dirty {
            self.rebuild_scene();
            self.renderer.update(&self.scene, &self.camera);
            self.dirty = false;
        }
        self.renderer
            .render()
            .map_err(|e| JsError::new(&e.to_string()))
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
            .camera
            .ray(x as f32, y as f32, width as f32, height as f32)
            .ok_or_else(|| JsError::new("rayAt: the camera is degenerate"))?;
        let ray = Ray {
            origin: origin.as_dvec3().to_array(),
            direction: direction.as_dvec3().to_array(),
        };
        serde_wasm_bindgen::to_value(&ray).map_err(|e| JsError::new(&e.to_string()))
    }

    /// A snapshot for tests and tools: `{ backend, surfaceFormat,
    /// sampleCount, view, width, height, dof, q, nodes, screenNodes }`, where
    /// `screenNodes` are the skeleton nodes in drawing-buffer pixels.
    ///
    /// # Errors
    /// Only if the snapshot cannot be converted (not expected).
    pub fn state(&self) -> Result<JsValue, JsError> {
        let (width, height) = self.renderer.size();
        let state = ViewerState {
            backend: self.renderer.backend().name(),
            surface_format: format!("{:?}", self.renderer.surface_format()),
            sample_count: self.renderer.sample_count(),
            view: self.camera.view.name(),
            width,
            height,
            dof: self.q.len(),
            q: self.q.clone(),
            nodes: self.skeleton.nodes.iter().map(|n| n.to_array()).collect(),
            screen_nodes: self
                .skeleton
                .nodes
                .iter()
                .map(|n| {
                    self.camera
                        .project(n.as_vec3(), width as f32, height as f32)
                })
                .collect(),
        };
        serde_wasm_bindgen::to_value(&state).map_err(|e| JsError::new(&e.to_string()))
    }
}

impl Viewer {
    /// Rebuilds the scene from the skeleton and the display options.
    fn rebuild_scene(&mut self) {
        let scene = &mut self.scene;
        scene.clear();
        scene.grid = self.display.grid.then(crate::render::Grid::default);
        for s in &self.skeleton.segments {
            let (a, b) = self.skeleton.endpoints(s);
            let (a, b) = (a.as_vec3().to_array(), b.as_vec3().to_array());
            scene.capsules.push(Capsule {
                a,
                b,
                radius: [SPINE_RADIUS; 2],
                color: SPINE_COLOR,
            });
            if self.display.volumes {
                let radius = [s.radius[0] as f32, s.radius[1] as f32];
                scene.capsules.push(Capsule {
                    a,
                    b,
                    radius,
                    color: VOLUME_COLOR,
                });
            }
        }
        if self.display.nodes {
            for n in &self.skeleton.nodes {
                let center = n.as_vec3().to_array();
                scene.spheres.push(Sphere {
                    center,
                    radius: NODE_RADIUS,
                    color: NODE_COLOR,
                });
            }
        }
        if self.display.axes {
            for f in &self.frames {
                let m = f.matrix3.as_mat3();
                let axes = [
                    m.x_axis.to_array(),
                    m.y_axis.to_array(),
                    m.z_axis.to_array(),
                ];
                scene.push_axes(f.translation.as_vec3().to_array(), axes, 0.08, 2.0);
            }
        }
    }
}

/// A robot is drawn in 2D when every joint axis is the world z axis and every
/// frame origin lies in one horizontal plane.
fn is_planar(frames: &[DAffine3]) -> bool {
    let Some(first) = frames.first() else {
        return false;
    };
    frames.iter().all(|f| {
        f.matrix3.z_axis.normalize_or_zero().z.abs() > 1.0 - 1e-9
            && (f.translation.z - first.translation.z).abs() < 1e-9
    })
}

fn view_error(field: &str, name: &str) -> JsError {
    JsError::new(&format!(
        "{field}: expected \"auto\", \"3d\", \"top\", \"front\" or \"side\", got {name:?}"
    ))
}

/// Centre and radius of a ball that holds the robot in any pose: the base and
/// the sum of every row's translations, extensions, radii and tools.
fn reach(robot: &Robot, frames: &Frames) -> (glam::DVec3, f64) {
    let base = frames.origin(0);
    let rows: f64 = robot
        .joints
        .iter()
        .zip(&frames.d)
        .map(|(j, d)| j.a.abs() + d.abs() + j.extension + j.radius[0].max(j.radius[1]))
        .sum();
    let tools: f64 = robot
        .chains
        .iter()
        .map(|c| c.tool.translation.length())
        .sum();
    (base, (rows + tools).max(0.1))
}
