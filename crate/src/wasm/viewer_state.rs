//! The plain values `Viewer` reads from JavaScript (`Viewer.create`'s
//! options) and hands back (`state()`, `rayAt`): serde structs, no logic.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::render::Renderer;
use crate::view::Stage;

/// Options of `Viewer.create`.
#[derive(Debug, Default, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(super) struct ViewerOptions {
    /// `"auto"` (default), `"webgpu"` or `"webgl2"`.
    pub(super) backend: Option<String>,
    /// `"auto"` (default: 2D top view for planar robots, else 3D), `"3d"`,
    /// `"top"`, `"front"`, `"side"`.
    pub(super) view: Option<String>,
    /// 4× multisampling (default: on unless the adapter is a software
    /// rasteriser).
    pub(super) antialias: Option<bool>,
    /// Draw through the canvas's `OffscreenCanvas` (default: false).
    pub(super) offscreen: Option<bool>,
}

/// What `state()` reports (for tests and tooling, not for every frame).
#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct ViewerState {
    backend: &'static str,
    adapter: String,
    surface_format: String,
    sample_count: u32,
    /// Whether the canvas is drawn through its `OffscreenCanvas`.
    offscreen_canvas: bool,
    /// Triangles the last upload draws (solids at their level of detail,
    /// facing the eye; flat figures and line quads; grid hairlines not
    /// counted).
    triangles: u64,
    /// Triangles of the capsules and spheres at their level of detail,
    /// back faces included (what the level of detail alone decides).
    solid_triangles: u64,
    /// Frames presented so far.
    frames_drawn: u64,
    /// Frames left out so far because their scene and camera were those on
    /// screen.
    frames_unchanged: u64,
    view: &'static str,
    /// The camera: eye azimuth and elevation (rad), distance to the target
    /// (m) and the target (m, world frame).
    camera: CameraState,
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

/// The camera in `state()`.
#[derive(Debug, Serialize)]
pub(super) struct CameraState {
    yaw: f64,
    pitch: f64,
    distance: f64,
    target: [f64; 3],
}

/// A picking ray (m, world frame).
#[derive(Debug, Serialize)]
pub(super) struct Ray {
    pub(super) origin: [f64; 3],
    pub(super) direction: [f64; 3],
}

/// What `state()` reports of `renderer` and `stage` now.
pub(super) fn snapshot(renderer: &Renderer, stage: &Stage) -> ViewerState {
    let (width, height) = renderer.size();
    let nodes = stage.drawn_nodes();
    let camera = stage.camera();
    ViewerState {
        backend: renderer.backend().name(),
        adapter: renderer.adapter_name().to_owned(),
        surface_format: format!("{:?}", renderer.surface_format()),
        sample_count: renderer.sample_count(),
        offscreen_canvas: renderer.is_offscreen(),
        triangles: renderer.triangles(),
        solid_triangles: renderer.solid_triangles(),
        frames_drawn: stage.counts().drawn,
        frames_unchanged: stage.counts().unchanged,
        view: camera.view.name(),
        camera: CameraState {
            yaw: f64::from(camera.yaw),
            pitch: f64::from(camera.pitch),
            distance: f64::from(camera.distance),
            target: camera.target.as_dvec3().to_array(),
        },
        width,
        height,
        dof: stage.q().len(),
        q: stage.q().to_vec(),
        screen_nodes: nodes
            .iter()
            .map(|n| camera.project(DVec3::from(*n).as_vec3(), width as f32, height as f32))
            .collect(),
        nodes,
    }
}
