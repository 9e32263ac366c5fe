//! Builds the render [`Scene`] of a simulated world: the skeleton, every
//! obstacle primitive, the control points with their distance lines and
//! repulsion arrows, and the uncertainty regions.
//!
//! The input is [`DrawState`], the part of a world's state the viewer draws;
//! `Viewer.drawWorld` fills it in Rust from a `World` (no geometry crosses to
//! JS), `Viewer.drawState` from a plain object (a recorded state).

use glam::{DQuat, DVec3};
use serde::Deserialize;

use crate::render::{Capsule, Line, Scene, Sphere};

/// What the viewer draws of a world (a subset of the world's state; other
/// fields of a state object are ignored).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct DrawState {
    /// The robot's skeleton.
    pub skeleton: SkeletonView,
    /// The obstacles, each with its id and shape.
    #[serde(default)]
    pub obstacles: Vec<ObstacleView>,
    /// The active control points.
    #[serde(default)]
    pub control_points: Vec<ControlPointView>,
    /// Sensing uncertainty around obstacles.
    #[serde(default)]
    pub uncertainty: Vec<UncertaintyView>,
}

/// Skeleton nodes and segments (m, world frame).
#[derive(Clone, Debug, Default, Deserialize)]
pub struct SkeletonView {
    /// Node positions.
    pub nodes: Vec<[f64; 3]>,
    /// Segments between nodes.
    pub segments: Vec<SegmentView>,
}

/// One skeleton segment and the radii of its volume at each end.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct SegmentView {
    /// Index of the first node.
    pub from: usize,
    /// Index of the second node.
    pub to: usize,
    /// Radius of the volume at `from` and at `to` (m).
    pub radius: [f64; 2],
}

/// An obstacle: its id, its shape and the primitives it is made of.
#[derive(Clone, Debug, Deserialize)]
pub struct ObstacleView {
    /// The obstacle's id.
    pub id: String,
    /// Its current shape (world frame): a primitive, or a composite such as
    /// `{ type: "human", position, … }` whose primitives are in `parts`.
    pub shape: serde_json::Value,
    /// The primitives it is made of (one, or a human's parts); when missing,
    /// `shape` itself must be a primitive.
    #[serde(default)]
    pub parts: Option<Vec<ShapeView>>,
}

impl ObstacleView {
    /// The primitives to draw (empty when `shape` is no primitive and no
    /// parts are given).
    fn primitives(&self) -> Vec<ShapeView> {
        match &self.parts {
            Some(parts) => parts.clone(),
            None => serde_json::from_value(self.shape.clone())
                .map(|p| vec![p])
                .unwrap_or_default(),
        }
    }

    fn is_human(&self) -> bool {
        self.shape.get("type").and_then(|t| t.as_str()) == Some("human")
    }
}

/// An obstacle's shape, with the field names of the JS contract.
#[derive(Clone, Debug, Deserialize)]
#[serde(
    tag = "type",
    rename_all = "camelCase",
    rename_all_fields = "camelCase"
)]
pub enum ShapeView {
    /// A point.
    Point {
        /// Position (m).
        p: [f64; 3],
    },
    /// A segment.
    Segment {
        /// First end (m).
        a: [f64; 3],
        /// Second end (m).
        b: [f64; 3],
    },
    /// A ball.
    Sphere {
        /// Centre (m).
        center: [f64; 3],
        /// Radius (m).
        radius: f64,
    },
    /// A capsule.
    Capsule {
        /// First end (m).
        a: [f64; 3],
        /// Second end (m).
        b: [f64; 3],
        /// Radius (m).
        radius: f64,
    },
    /// A capsule whose radius varies linearly.
    TaperedCapsule {
        /// First end (m).
        a: [f64; 3],
        /// Second end (m).
        b: [f64; 3],
        /// Radius at `a` and at `b` (m).
        radius: [f64; 2],
    },
    /// The plane `normal · x + offset = 0`.
    Plane {
        /// Normal (any length).
        normal: [f64; 3],
        /// Offset (m, for a unit normal).
        offset: f64,
    },
    /// A rectangle.
    Rectangle {
        /// Centre (m).
        center: [f64; 3],
        /// Its two in-plane axes (unit, orthogonal).
        axes: [[f64; 3]; 2],
        /// Half sides along the axes (m).
        half_extents: [f64; 2],
    },
    /// A disk.
    Disk {
        /// Centre (m).
        center: [f64; 3],
        /// Normal of its plane.
        normal: [f64; 3],
        /// Radius (m).
        radius: f64,
    },
    /// A planar polygon.
    Polygon {
        /// Vertices in order (m).
        vertices: Vec<[f64; 3]>,
    },
    /// An oriented box.
    Box {
        /// Centre (m).
        center: [f64; 3],
        /// Half sides along its axes (m).
        half_extents: [f64; 3],
        /// Rotation as a quaternion `[x, y, z, w]` (identity when missing).
        #[serde(default)]
        rotation: Option<[f64; 4]>,
    },
    /// The convex hull of points (drawn as its points and their star).
    ConvexHull {
        /// The points (m).
        points: Vec<[f64; 3]>,
    },
}

/// A control point as drawn.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ControlPointView {
    /// Where it is (m).
    pub position: [f64; 3],
    /// The closest point of its obstacle (m), if any.
    #[serde(default)]
    pub witness: Option<[f64; 3]>,
    /// The repulsion acting on it (m/s in velocity mode, N in torque mode).
    #[serde(default)]
    pub repulsion: Option<[f64; 3]>,
    /// Whether it is travelling along the skeleton towards a new point.
    #[serde(default)]
    pub transitioning: bool,
    /// Id of the obstacle it answers.
    #[serde(default)]
    pub obstacle: String,
}

/// The uncertainty region of a sensed obstacle.
#[derive(Clone, Debug, Deserialize)]
pub struct UncertaintyView {
    /// The obstacle's id.
    pub obstacle: String,
    /// Radius of the region (m).
    pub radius: f64,
}

/// What to draw besides the obstacles.
#[derive(Clone, Copy, Debug)]
pub struct DrawOptions {
    /// Translucent volumes around the skeleton segments.
    pub volumes: bool,
    /// Skeleton nodes as small spheres.
    pub nodes: bool,
    /// Seconds of repulsion drawn per metre of arrow (velocity × scale = length).
    pub arrow_scale: f64,
    /// Half the side of the square that stands for an infinite plane (m).
    pub plane_extent: f64,
}

pub const VOLUME_COLOR: [f32; 4] = [0.33, 0.55, 0.85, 0.45];
pub const SPINE_COLOR: [f32; 4] = [0.20, 0.24, 0.32, 1.0];
pub const NODE_COLOR: [f32; 4] = [0.95, 0.55, 0.15, 1.0];
pub const SPINE_RADIUS: f32 = 0.012;
pub const NODE_RADIUS: f32 = 0.022;

const SOLID: [f32; 4] = [0.85, 0.33, 0.28, 1.0];
const FLAT: [f32; 4] = [0.85, 0.45, 0.30, 0.55];
const PLANE: [f32; 4] = [0.55, 0.62, 0.72, 0.25];
const OUTLINE: [f32; 4] = [0.45, 0.18, 0.12, 1.0];
const SELECTED: [f32; 4] = [0.98, 0.78, 0.10, 1.0];
const SELECTED_FLAT: [f32; 4] = [0.98, 0.78, 0.10, 0.6];
const SELECTED_OUTLINE: [f32; 4] = [0.70, 0.45, 0.0, 1.0];
const HUMAN: [f32; 4] = [0.90, 0.72, 0.58, 1.0];
const CONTROL_POINT: [f32; 4] = [0.80, 0.10, 0.55, 1.0];
const TRANSITIONING: [f32; 4] = [0.10, 0.70, 0.35, 1.0];
const DISTANCE_LINE: [f32; 4] = [0.62, 0.08, 0.45, 1.0];
const REPULSION: [f32; 4] = [0.10, 0.45, 0.85, 1.0];
const UNCERTAINTY: [f32; 4] = [0.95, 0.60, 0.10, 0.22];
/// Radius of a point obstacle and thickness of a segment obstacle (m).
const THIN: f32 = 0.012;
const CONTROL_POINT_RADIUS: f32 = 0.026;
/// Longest repulsion arrow (m).
const MAX_ARROW: f64 = 0.3;

fn v(p: [f64; 3]) -> [f32; 3] {
    [p[0] as f32, p[1] as f32, p[2] as f32]
}

/// Rebuilds `scene` from `state`; the obstacle whose id is `selected` is
/// highlighted. `around` is the point near which infinite planes are drawn.
pub fn build_scene(
    scene: &mut Scene,
    state: &DrawState,
    options: &DrawOptions,
    selected: Option<&str>,
    around: [f64; 3],
) {
    draw_skeleton(scene, &state.skeleton, options);
    for o in &state.obstacles {
        let is_selected = selected == Some(o.id.as_str());
        let human = o.is_human();
        for part in o.primitives() {
            let before = (scene.capsules.len(), scene.spheres.len());
            draw_shape(scene, &part, is_selected, around, options.plane_extent);
            if human && !is_selected {
                for c in &mut scene.capsules[before.0..] {
                    c.color = HUMAN;
                }
                for s in &mut scene.spheres[before.1..] {
                    s.color = HUMAN;
                }
            }
        }
    }
    for u in &state.uncertainty {
        let m = u.radius;
        if !(m.is_finite() && m > 0.0) {
            continue;
        }
        let Some(o) = state.obstacles.iter().find(|o| o.id == u.obstacle) else {
            continue;
        };
        let mut flat = false;
        for part in o.primitives() {
            draw_inflated(scene, &part, m as f32);
            flat |= matches!(
                part,
                ShapeView::Plane { .. }
                    | ShapeView::Rectangle { .. }
                    | ShapeView::Disk { .. }
                    | ShapeView::Polygon { .. }
                    | ShapeView::Box { .. }
                    | ShapeView::ConvexHull { .. }
            );
        }
        if flat {
            // Where the true closest point may be: a ball around each witness.
            for cp in state.control_points.iter().filter(|c| c.obstacle == o.id) {
                if let Some(w) = cp.witness {
                    scene.spheres.push(Sphere {
                        center: v(w),
                        radius: m as f32,
                        color: UNCERTAINTY,
                    });
                }
            }
        }
    }
    for cp in &state.control_points {
        let color = if cp.transitioning {
            TRANSITIONING
        } else {
            CONTROL_POINT
        };
        scene.spheres.push(Sphere {
            center: v(cp.position),
            radius: CONTROL_POINT_RADIUS,
            color,
        });
        if let Some(w) = cp.witness {
            scene.lines.push(Line {
                a: v(cp.position),
                b: v(w),
                width: 2.5,
                color: DISTANCE_LINE,
            });
            scene.spheres.push(Sphere {
                center: v(w),
                radius: 0.4 * CONTROL_POINT_RADIUS,
                color: DISTANCE_LINE,
            });
        }
        if let Some(r) = cp.repulsion {
            let r = DVec3::from(r) * options.arrow_scale;
            let len = r.length();
            if len.is_finite() && len > 1e-4 {
                let r = r * (len.min(MAX_ARROW) / len);
                let from = DVec3::from(cp.position);
                scene.push_arrow(
                    v(from.to_array()),
                    v((from + r).to_array()),
                    3.0,
                    0.05,
                    REPULSION,
                );
            }
        }
    }
}

fn draw_skeleton(scene: &mut Scene, skeleton: &SkeletonView, options: &DrawOptions) {
    for s in &skeleton.segments {
        let (Some(&a), Some(&b)) = (skeleton.nodes.get(s.from), skeleton.nodes.get(s.to)) else {
            continue;
        };
        let (a, b) = (v(a), v(b));
        scene.capsules.push(Capsule {
            a,
            b,
            radius: [SPINE_RADIUS; 2],
            color: SPINE_COLOR,
        });
        if options.volumes {
            scene.capsules.push(Capsule {
                a,
                b,
                radius: [s.radius[0] as f32, s.radius[1] as f32],
                color: VOLUME_COLOR,
            });
        }
    }
    if options.nodes {
        for &n in &skeleton.nodes {
            scene.spheres.push(Sphere {
                center: v(n),
                radius: NODE_RADIUS,
                color: NODE_COLOR,
            });
        }
    }
}

/// A representative point of a shape: its centre (the sensed position).
#[must_use]
pub fn anchor(shape: &ShapeView) -> [f64; 3] {
    let mean = |points: &[[f64; 3]]| {
        let sum = points
            .iter()
            .fold(DVec3::ZERO, |acc, p| acc + DVec3::from(*p));
        (sum / points.len().max(1) as f64).to_array()
    };
    match shape {
        ShapeView::Point { p } => *p,
        ShapeView::Segment { a, b }
        | ShapeView::Capsule { a, b, .. }
        | ShapeView::TaperedCapsule { a, b, .. } => mean(&[*a, *b]),
        ShapeView::Sphere { center, .. }
        | ShapeView::Rectangle { center, .. }
        | ShapeView::Disk { center, .. }
        | ShapeView::Box { center, .. } => *center,
        ShapeView::Plane { normal, offset } => {
            let n = DVec3::from(*normal);
            (n * (-offset / n.length_squared().max(1e-12))).to_array()
        }
        ShapeView::Polygon { vertices } => mean(vertices),
        ShapeView::ConvexHull { points } => mean(points),
    }
}

fn draw_shape(
    scene: &mut Scene,
    shape: &ShapeView,
    selected: bool,
    around: [f64; 3],
    plane_extent: f64,
) {
    let (solid, flat, outline) = if selected {
        (SELECTED, SELECTED_FLAT, SELECTED_OUTLINE)
    } else {
        (SOLID, FLAT, OUTLINE)
    };
    match shape {
        ShapeView::Point { p } => scene.spheres.push(Sphere {
            center: v(*p),
            radius: 1.5 * THIN,
            color: solid,
        }),
        ShapeView::Segment { a, b } => scene.capsules.push(Capsule {
            a: v(*a),
            b: v(*b),
            radius: [THIN; 2],
            color: solid,
        }),
        ShapeView::Sphere { center, radius } => scene.spheres.push(Sphere {
            center: v(*center),
            radius: *radius as f32,
            color: solid,
        }),
        ShapeView::Capsule { a, b, radius } => scene.capsules.push(Capsule {
            a: v(*a),
            b: v(*b),
            radius: [*radius as f32; 2],
            color: solid,
        }),
        ShapeView::TaperedCapsule { a, b, radius } => scene.capsules.push(Capsule {
            a: v(*a),
            b: v(*b),
            radius: [radius[0] as f32, radius[1] as f32],
            color: solid,
        }),
        ShapeView::Plane { normal, offset } => {
            let color = if selected { SELECTED_FLAT } else { PLANE };
            scene.push_plane(
                v(*normal),
                *offset as f32,
                v(around),
                plane_extent as f32,
                color,
                outline,
            );
        }
        ShapeView::Rectangle {
            center,
            axes,
            half_extents,
        } => scene.push_rectangle(
            v(*center),
            [v(axes[0]), v(axes[1])],
            [half_extents[0] as f32, half_extents[1] as f32],
            flat,
            outline,
        ),
        ShapeView::Disk {
            center,
            normal,
            radius,
        } => {
            let n = DVec3::from(*normal).normalize_or(DVec3::Z);
            scene.push_disk(v(*center), v(n.to_array()), *radius as f32, flat, outline);
        }
        ShapeView::Polygon { vertices } => {
            let points: Vec<[f32; 3]> = vertices.iter().map(|p| v(*p)).collect();
            let triangles = ear_clip(vertices);
            scene.push_polygon(&points, &triangles, flat, outline);
        }
        ShapeView::Box {
            center,
            half_extents,
            rotation,
        } => {
            let q = rotation
                .map(DQuat::from_array)
                .filter(|q| q.is_finite() && q.length() > 1e-9)
                .map_or(DQuat::IDENTITY, DQuat::normalize);
            let axes = [
                v((q * DVec3::X).to_array()),
                v((q * DVec3::Y).to_array()),
                v((q * DVec3::Z).to_array()),
            ];
            scene.push_box(v(*center), axes, v(*half_extents), solid, outline);
        }
        ShapeView::ConvexHull { points } => {
            let c = anchor(shape);
            for p in points {
                scene.spheres.push(Sphere {
                    center: v(*p),
                    radius: THIN,
                    color: solid,
                });
                scene.lines.push(Line {
                    a: v(c),
                    b: v(*p),
                    width: 1.5,
                    color: outline,
                });
            }
        }
    }
}

/// The region within `m` of a round primitive (point, segment, sphere,
/// capsule) as a translucent volume; nothing for the others.
fn draw_inflated(scene: &mut Scene, shape: &ShapeView, m: f32) {
    let capsule = |a: [f64; 3], b: [f64; 3], r: [f32; 2]| Capsule {
        a: v(a),
        b: v(b),
        radius: [r[0] + m, r[1] + m],
        color: UNCERTAINTY,
    };
    match shape {
        ShapeView::Point { p } => scene.spheres.push(Sphere {
            center: v(*p),
            radius: m,
            color: UNCERTAINTY,
        }),
        ShapeView::Sphere { center, radius } => scene.spheres.push(Sphere {
            center: v(*center),
            radius: *radius as f32 + m,
            color: UNCERTAINTY,
        }),
        ShapeView::Segment { a, b } => scene.capsules.push(capsule(*a, *b, [0.0; 2])),
        ShapeView::Capsule { a, b, radius } => {
            scene.capsules.push(capsule(*a, *b, [*radius as f32; 2]));
        }
        ShapeView::TaperedCapsule { a, b, radius } => {
            scene
                .capsules
                .push(capsule(*a, *b, [radius[0] as f32, radius[1] as f32]));
        }
        _ => {}
    }
}

/// Triangles of a planar, simple polygon (ear clipping in its own plane);
/// empty for fewer than three vertices or a degenerate polygon.
fn ear_clip(vertices: &[[f64; 3]]) -> Vec<[usize; 3]> {
    let n = vertices.len();
    if n < 3 {
        return Vec::new();
    }
    let p: Vec<DVec3> = vertices.iter().map(|x| DVec3::from(*x)).collect();
    // Newell's normal, then 2D coordinates in the polygon's plane.
    let mut normal = DVec3::ZERO;
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        normal += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let Some(normal) = normal.try_normalize() else {
        return Vec::new();
    };
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let q: Vec<(f64, f64)> = p.iter().map(|x| (x.dot(u), x.dot(w))).collect();
    let cross = |a: usize, b: usize, c: usize| {
        (q[b].0 - q[a].0) * (q[c].1 - q[a].1) - (q[b].1 - q[a].1) * (q[c].0 - q[a].0)
    };
    let inside = |a: usize, b: usize, c: usize, x: usize| {
        let s = |i: usize, j: usize| {
            (q[j].0 - q[i].0) * (q[x].1 - q[i].1) - (q[j].1 - q[i].1) * (q[x].0 - q[i].0)
        };
        s(a, b) >= 0.0 && s(b, c) >= 0.0 && s(c, a) >= 0.0
    };
    let mut remaining: Vec<usize> = (0..n).collect();
    let mut out = Vec::with_capacity(n - 2);
    let mut guard = 0;
    while remaining.len() > 3 && guard < 4 * n * n {
        guard += 1;
        let m = remaining.len();
        let mut clipped = false;
        for k in 0..m {
            let (a, b, c) = (
                remaining[(k + m - 1) % m],
                remaining[k],
                remaining[(k + 1) % m],
            );
            if cross(a, b, c) <= 0.0 {
                continue;
            }
            if remaining
                .iter()
                .any(|&x| x != a && x != b && x != c && inside(a, b, c, x))
            {
                continue;
            }
            out.push([a, b, c]);
            remaining.remove(k);
            clipped = true;
            break;
        }
        if !clipped {
            break;
        }
    }
    if remaining.len() == 3 {
        out.push([remaining[0], remaining[1], remaining[2]]);
    }
    if out.len() + 2 != n {
        return Vec::new();
    }
    out
}
