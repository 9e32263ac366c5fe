//! [`Stage`]: everything a viewer shows except the GPU — the robot and its
//! pose, or a world's state, the selection, the display options, the camera
//! and the scene built from them.
//!
//! The wasm `Viewer` is a [`Stage`] and a renderer: it converts arguments,
//! asks the stage, and uploads the scene [`Stage::frame`] gives, when the
//! picture changed.
//!
//! A world handed to the stage every frame does not always change the
//! picture: a settled arm, a stopped robot and static obstacles give the
//! same scene step after step (in `sliding-point` 395 frames of 400, in
//! `planar-transition` and `dual-arm-self` about three quarters). Such a
//! frame is not drawn again: the canvas keeps the picture, and a settled
//! example or an idle embed costs the renderer nothing. The scene is
//! rebuilt and compared with the last one presented (and the camera with
//! its own), which costs far less than drawing it.

use glam::{DAffine3, DVec3, Vec3};
use serde::Deserialize;

use super::camera::{Camera, View};
use super::draw::{DrawOptions, DrawState, SegmentView, SkeletonView, build_scene};
use super::drawing::{Drawing, Grid};
use super::framing::{Reach, fit_points, is_planar};
use super::meshes::{Detail, LinkMesh, draw_meshes};
use crate::error::FieldError;
use crate::kinematics::Robot;
use crate::scenario::CameraSpec;
use crate::skeleton::Skeleton;

/// What can be switched on and off in the drawing (`setDisplay`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct Display {
    /// The translucent volumes around the skeleton segments.
    pub volumes: bool,
    /// The skeleton nodes as small spheres.
    pub nodes: bool,
    /// The DH frames' axes.
    pub axes: bool,
    /// The link meshes, when the robot has them ([`Stage::set_meshes`]).
    pub meshes: bool,
    /// The ground grid.
    pub grid: bool,
    /// Arrow length per unit of repulsion (s: metres of arrow per m/s).
    pub arrow_scale: f64,
}

impl Default for Display {
    fn default() -> Self {
        Self {
            volumes: true,
            nodes: true,
            axes: false,
            meshes: true,
            grid: true,
            arrow_scale: 0.4,
        }
    }
}

/// Parses a view name: `Some(view)` for `"3d"`, `"top"`, `"front"`,
/// `"side"` (and [`View::parse`]'s aliases), `None` for `"auto"`.
///
/// # Errors
/// `field: expected "auto", "3d", "top", "front" or "side", got "x"`.
pub fn parse_view(field: &str, name: &str) -> Result<Option<View>, FieldError> {
    if name == "auto" {
        return Ok(None);
    }
    View::parse(name).map(Some).ok_or_else(|| {
        FieldError::new(
            field,
            format!("expected \"auto\", \"3d\", \"top\", \"front\" or \"side\", got {name:?}"),
        )
    })
}

/// The viewer's state apart from the GPU.
#[derive(Clone, Debug)]
pub struct Stage {
    camera: Camera,
    scene: Drawing,
    display: Display,
    /// The view chosen at creation, if not `"auto"`.
    fixed_view: Option<View>,
    /// The view `"auto"` stands for with the current robot.
    auto_view: View,
    robot: Option<Robot>,
    q: Vec<f64>,
    skeleton: Skeleton,
    frames: Vec<DAffine3>,
    /// The world last drawn (replaces the robot's own skeleton while set).
    world: Option<DrawState>,
    /// Id of the highlighted obstacle.
    selected: Option<String>,
    reach: Reach,
    /// The robot's link meshes, in the frames of their rows.
    meshes: Vec<LinkMesh>,
    /// Points a fit keeps on screen besides the robot ([`Stage::set_camera`]).
    framed: Vec<DVec3>,
    dirty: bool,
    /// The scene and camera of the last frame presented (`None` after a
    /// resize, which needs a new frame whatever the scene).
    presented: Option<(Drawing, Camera)>,
    /// Frames presented, and frames due that were left out because their
    /// picture was the one on screen.
    counts: FrameCounts,
    /// The view's height and the tolerance (pixels) link meshes are drawn
    /// within ([`Stage::set_detail`]); `None`: full meshes.
    detail: Option<(f32, f32)>,
}

/// How many frames a stage had drawn ([`Stage::counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCounts {
    /// Frames presented.
    pub drawn: u64,
    /// Frames left out: something was handed to the stage, but the scene
    /// and the camera were those on screen.
    pub unchanged: u64,
}

impl Stage {
    /// An empty stage; `fixed_view` is the view to keep whatever the robot
    /// (`None`: the top view for a planar robot, else 3D).
    #[must_use]
    pub fn new(fixed_view: Option<View>) -> Self {
        Self {
            camera: Camera::framing(Vec3::ZERO, 1.0, fixed_view.unwrap_or(View::Orbit)),
            scene: Drawing::new(),
            display: Display::default(),
            fixed_view,
            auto_view: View::Orbit,
            robot: None,
            q: Vec::new(),
            skeleton: Skeleton::default(),
            frames: Vec::new(),
            world: None,
            selected: None,
            reach: Reach {
                center: DVec3::ZERO,
                radius: 1.0,
            },
            meshes: Vec::new(),
            framed: Vec::new(),
            dirty: true,
            presented: None,
            counts: FrameCounts::default(),
            detail: None,
        }
    }

    /// Sets the robot at zero (or the nearest pose within its joint limits),
    /// forgets the drawn world and, unless a view was fixed, frames the
    /// robot's reach (top view for a planar robot).
    ///
    /// # Errors
    /// Forward kinematics' own (not expected for a validated robot).
    pub fn set_robot(&mut self, robot: Robot) -> Result<(), FieldError> {
        let mut q = vec![0.0; robot.dof()];
        robot.clamp_to_limits(&mut q);
        let f = robot.forward(&q)?;
        self.skeleton = Skeleton::build(&robot, &f);
        self.reach = Reach::of(&robot, &f);
        self.auto_view = if is_planar(&f.transforms) {
            View::Top
        } else {
            View::Orbit
        };
        let view = self.fixed_view.unwrap_or(self.auto_view);
        self.camera = Camera::framing(self.reach.center.as_vec3(), self.reach.radius as f32, view);
        self.frames = f.transforms;
        self.robot = Some(robot);
        self.meshes.clear();
        self.framed.clear();
        self.q = q;
        self.world = None;
        self.dirty = true;
        Ok(())
    }

    /// The robot, once set.
    #[must_use]
    pub fn robot(&self) -> Option<&Robot> {
        self.robot.as_ref()
    }

    /// Sets the joint vector (rad, m) of the robot.
    ///
    /// # Errors
    /// `setJoints: no robot; call setRobot first`, or forward kinematics'
    /// (`q: expected 3 values, got 2`, `q[1]: not a finite number`).
    pub fn set_joints(&mut self, q: Vec<f64>) -> Result<(), FieldError> {
        self.require_robot()?;
        let Some(robot) = &self.robot else {
            return Ok(());
        };
        let f = robot.forward(&q)?;
        self.skeleton = Skeleton::build(robot, &f);
        self.frames = f.transforms;
        self.q = q;
        self.dirty = true;
        Ok(())
    }

    /// `Ok` once a robot is set.
    ///
    /// # Errors
    /// `setJoints: no robot; call setRobot first`.
    pub fn require_robot(&self) -> Result<(), FieldError> {
        if self.robot.is_some() {
            Ok(())
        } else {
            Err(FieldError::new(
                "setJoints",
                "no robot; call setRobot first",
            ))
        }
    }

    /// Draws `state` (a world's) instead of the robot's own skeleton until
    /// the next [`Stage::set_robot`].
    pub fn draw(&mut self, state: DrawState) {
        if let Some(robot) = &self.robot
            && state.q.len() == robot.dof()
            && let Ok(f) = robot.forward(&state.q)
        {
            self.frames = f.transforms;
        }
        self.world = Some(state);
        self.dirty = true;
    }

    /// Link meshes drawn with the current robot (each in the frame of its
    /// row; see [`link_meshes`](super::link_meshes)) until the next
    /// [`Stage::set_robot`].
    pub fn set_meshes(&mut self, meshes: Vec<LinkMesh>) {
        self.meshes = meshes;
        self.dirty = true;
    }

    /// Draws each link mesh with the coarsest level of detail whose error
    /// spans at most `tolerance` pixels on a view `height` pixels high
    /// (`view::meshes`).
    pub fn set_detail(&mut self, height: f32, tolerance: f32) {
        let detail = Some((height, tolerance));
        if detail != self.detail {
            self.detail = detail;
            self.dirty = true;
        }
    }

    /// Highlights the obstacle with this id (`None`: none).
    pub fn set_selected(&mut self, id: Option<String>) {
        self.selected = id;
        self.dirty = true;
    }

    /// Chooses what is drawn.
    pub fn set_display(&mut self, display: Display) {
        self.display = display;
        self.dirty = true;
    }

    /// Switches the view (`None`: the one `"auto"` stands for).
    pub fn set_view(&mut self, view: Option<View>) {
        self.camera.view = view.unwrap_or(self.auto_view);
        self.dirty = true;
    }

    /// Applies a scenario's camera: its yaw and pitch (those given; the 2D
    /// views keep their axis) and the points later fits keep on screen
    /// (replacing earlier ones). [`Stage::set_robot`] resets both.
    ///
    /// # Errors
    /// [`CameraSpec::validate`]'s (`pitch: must be within ±1.55 rad …`);
    /// the stage is then unchanged.
    pub fn set_camera(&mut self, spec: &CameraSpec) -> Result<(), FieldError> {
        spec.validate()?;
        if let Some(yaw) = spec.yaw {
            self.camera.yaw = yaw as f32;
        }
        if let Some(pitch) = spec.pitch {
            self.camera.pitch = pitch as f32;
        }
        self.framed = spec.frame.iter().map(|p| DVec3::from(*p)).collect();
        self.dirty = true;
        Ok(())
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Orbits the 3D camera by a drag of `dx`, `dy` pixels.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        self.camera.orbit(dx, dy);
        self.dirty = true;
    }

    /// Pans by a drag of `dx`, `dy` pixels in a buffer `height` pixels high.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        self.camera.pan(dx, dy, height);
        self.dirty = true;
    }

    /// Multiplies the camera distance by `factor` (> 1 zooms out).
    pub fn zoom(&mut self, factor: f32) {
        self.camera.zoom(factor);
        self.dirty = true;
    }

    /// Aims the camera, keeping its direction, at the skeleton and the
    /// obstacles within the robot's reach so that they fill `fill` of a
    /// drawing buffer of `aspect` = width / height.
    pub fn fit(&mut self, fill: f32, aspect: f32) {
        let points = self.fit_points();
        self.camera.fit(&points, aspect, fill);
        self.dirty = true;
    }

    /// [`Stage::fit`] into the part of a `width` × `height` drawing buffer
    /// below its top `top` pixels (where the page shows text over the view).
    pub fn fit_below(&mut self, fill: f32, size: (f32, f32), top: f32) {
        let points = self.fit_points();
        self.camera.fit_below(&points, size, top, fill);
        self.dirty = true;
    }

    /// What a fit frames: the skeleton, the obstacles within reach and the
    /// points of [`Stage::set_camera`].
    fn fit_points(&self) -> Vec<Vec3> {
        let points = match &self.world {
            Some(world) => fit_points(world, &self.reach),
            None => self.drawn_nodes(),
        };
        let points = points.iter().map(|p| DVec3::from(*p));
        points
            .chain(self.framed.iter().copied())
            .map(|p| p.as_vec3())
            .collect()
    }

    /// The robot's reach (the ball framed by [`Stage::set_robot`]).
    #[must_use]
    pub fn reach(&self) -> Reach {
        self.reach
    }

    /// The joint vector (empty before a robot is set).
    #[must_use]
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// The skeleton nodes currently drawn (m).
    #[must_use]
    pub fn drawn_nodes(&self) -> Vec<[f64; 3]> {
        match &self.world {
            Some(world) => world.skeleton.nodes.clone(),
            None => self.skeleton.nodes.iter().map(|n| n.to_array()).collect(),
        }
    }

    /// Whether anything changed since the scene was last drawn.
    #[must_use]
    pub fn is_dirty(&self) -> bool {
        self.dirty
    }

    /// The scene and camera of a new frame, or `None` when none is due:
    /// nothing changed since the last frame presented, or the scene, rebuilt,
    /// and the camera are the ones on screen (the stage is then clean). After
    /// `Some`, report with [`Stage::drawn`] whether it was presented.
    pub fn frame(&mut self) -> Option<(&Drawing, Camera)> {
        if !self.dirty {
            return None;
        }
        self.scene();
        if let Some((scene, camera)) = &self.presented
            && *scene == self.scene
            && *camera == self.camera
        {
            self.dirty = false;
            self.counts.unchanged += 1;
            return None;
        }
        Some((&self.scene, self.camera))
    }

    /// Records whether the frame [`Stage::frame`] gave reached the screen
    /// (a skipped frame leaves the stage dirty, to be drawn again).
    pub fn drawn(&mut self, presented: bool) {
        self.dirty = !presented;
        if presented {
            self.counts.drawn += 1;
            match &mut self.presented {
                Some((scene, camera)) => {
                    scene.clone_from(&self.scene);
                    *camera = self.camera;
                }
                None => self.presented = Some((self.scene.clone(), self.camera)),
            }
        }
    }

    /// Frames presented and frames left out as unchanged so far.
    #[must_use]
    pub fn counts(&self) -> FrameCounts {
        self.counts
    }

    /// Marks the stage as needing a new frame, even of the same scene
    /// (after a resize).
    pub fn touch(&mut self) {
        self.dirty = true;
        self.presented = None;
    }

    /// The scene to draw, rebuilt from the world (or the robot's own
    /// skeleton) and the display options.
    pub fn scene(&mut self) -> &Drawing {
        let scene = &mut self.scene;
        scene.clear();
        // The ground grid reaches well past the arm (whole metres, 1 … 10 m
        // from the origin), so that a framed view shows no edge of it; its
        // 0.1 m lines cover the arm's reach (to the next half metre, where a
        // 0.5 m line runs), beyond which only the 0.5 m lines go on.
        let half_extent = (2.0 * self.reach.radius).ceil().clamp(1.0, 10.0) as f32;
        let fine_extent = ((2.0 * self.reach.radius).ceil() / 2.0).clamp(0.5, 10.0) as f32;
        scene.grid = self.display.grid.then(|| Grid {
            half_extent,
            fine_extent: fine_extent.min(half_extent),
            ..Grid::default()
        });
        let options = DrawOptions {
            volumes: self.display.volumes,
            nodes: self.display.nodes,
            arrow_scale: self.display.arrow_scale,
            plane_extent: self.reach.plane_extent(),
        };
        let own;
        let state = match &self.world {
            Some(world) => world,
            None => {
                own = DrawState {
                    skeleton: skeleton_view(&self.skeleton),
                    ..DrawState::default()
                };
                &own
            }
        };
        let around = self.reach.center.to_array();
        if self.display.meshes {
            let detail = self.detail.map(|(height, tolerance)| Detail {
                camera: &self.camera,
                height,
                tolerance,
            });
            draw_meshes(scene, &self.meshes, &self.frames, detail);
        }
        build_scene(scene, state, &options, self.selected.as_deref(), around);
        if self.display.axes {
            for f in &self.frames {
                let m = f.matrix3.as_mat3();
                let axes = [m.x_axis, m.y_axis, m.z_axis].map(|a| a.to_array());
                scene.push_axes(f.translation.as_vec3().to_array(), axes, 0.08, 2.0);
            }
        }
        &self.scene
    }
}

/// The drawing's view of a core skeleton.
fn skeleton_view(skeleton: &Skeleton) -> SkeletonView {
    SkeletonView {
        nodes: skeleton.nodes.iter().map(|n| n.to_array()).collect(),
        segments: skeleton
            .segments
            .iter()
            .map(|s| SegmentView {
                from: s.from,
                to: s.to,
                radius: s.radius,
            })
            .collect(),
    }
}
