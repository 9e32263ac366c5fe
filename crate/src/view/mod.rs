//! What the playground's viewer shows, as plain data: the drawn scene of a
//! robot or a simulated world, the framing of a robot, and the camera.
//!
//! Nothing here knows of the GPU or of JavaScript: the module builds and is
//! tested natively like the rest of the core. The wgpu renderer (`render`,
//! wasm32 only) uploads a [`Drawing`] as seen by a [`Camera`]; the wasm
//! `Viewer` converts its arguments and delegates to a [`Stage`].
//!
//! | file | what it holds |
//! |---|---|
//! | `scene.rs` | [`Drawing`]: capsules, spheres, lines, triangles, closed surfaces, a ground grid (f32, sRGB) |
//! | `camera.rs` | [`Camera`]: orbit / pan / zoom, perspective or the 2D views, projection and picking rays |
//! | `draw.rs` | [`DrawState`] and [`build_scene`]: skeleton, obstacles, control points, arrows, margins |
//! | `shapes.rs` | each obstacle primitive as scene items |
//! | `framing.rs` | [`Reach`], [`is_planar`], [`fit_points`] |
//! | `meshes.rs` | [`LinkMesh`]: a link's mesh in its row's frame (welded; closed surfaces turned outwards, drawn one-sided), placed each frame |
//! | `stage.rs` | [`Stage`]: robot, pose, world, selection, display and camera together |
//! | `occlusion.rs` | which triangles of a capsule or sphere lie inside an opaque one (not drawn) |
//! | `tessellation.rs` | the capsule template the renderer places for each capsule and sphere, and its level of detail from the size on screen |
//!
//! Data flow of one frame: `World` → [`crate::world::WorldState`] →
//! [`DrawState`] (moved, not copied) → [`build_scene`] → [`Drawing`] → GPU.

mod camera;
mod draw;
mod drawing;
mod framing;
mod meshes;
mod shapes;
mod stage;
// The solids' templates and level of detail, and which of their triangles
// opaque solids hide, for the renderer (wasm32).
#[cfg_attr(not(all(target_arch = "wasm32", feature = "render")), allow(dead_code))]
pub(crate) mod occlusion;
#[cfg_attr(not(all(target_arch = "wasm32", feature = "render")), allow(dead_code))]
pub(crate) mod tessellation;

pub use camera::{Camera, View};
pub use draw::{
    ControlPointView, DrawOptions, DrawState, ObstacleView, SegmentView, SigmaView, SkeletonView,
    UncertaintyView, build_scene, style,
};
pub use drawing::{Capsule, Drawing, Grid, Line, Sphere, Triangle};
pub use framing::{Reach, fit_points, is_planar};
pub use meshes::{
    Detail, LinkMesh, MAX_DRAWN_TRIANGLES, MESH_COLOR, MIN_LEVEL_TRIANGLES, MeshLevel, draw_meshes,
    link_meshes,
};
pub use shapes::{Palette, THIN, UNCERTAINTY};
pub use stage::{Display, FrameCounts, Stage, parse_view};
