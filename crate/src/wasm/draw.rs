//! Builds the render [`Scene`] of a simulated world: the skeleton, every
//! obstacle primitive, the control points with their distance lines and
//! repulsion arrows, and the uncertainty regions.
//!
//! The input is [`DrawState`], the part of a world's state the viewer draws;
//! `Viewer.drawWorld` fills it in Rust from a `World` (no geometry crosses to
//! JS), `Viewer.drawState` from a plain object (a recorded state).

use glam::{DQuat, DVec3};
use serde::Deserialize;

use crate::distance::{
    BoxSpec, CapsuleSpec, DiskSpec, PlaneSpec, PointSpec, Polygon, PolygonSpec, PrimitiveSpec,
    RectangleSpec, SegmentSpec, SphereSpec, TaperedCapsuleSpec,
};
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
    pub parts: Option<Vec<PrimitiveSpec>>,
}

impl ObstacleView {
    /// The primitives to draw (empty when `shape` is no primitive and no
    /// parts are given).
    fn primitives(&self) -> Vec<PrimitiveSpec> {
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
const REPULSION: [f32; 4] = [0.0, 0.62, 0.62, 1.0];
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
            flat |= !matches!(
                part,
                PrimitiveSpec::Point(_)
                    | PrimitiveSpec::Segment(_)
                    | PrimitiveSpec::Sphere(_)
                    | PrimitiveSpec::Capsule(_)
                    | PrimitiveSpec::TaperedCapsule(_)
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
                    4.0,
                    0.06,
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

/// The points a view should frame: the skeleton's nodes and the centre of
/// every bounded obstacle part the robot can reach (within `reach` metres of
/// `base`). Infinite planes and parts out of reach (a large floor's centre,
/// a person walking in from afar) are left out so that the robot stays
/// large on screen.
#[must_use]
pub fn fit_points(state: &DrawState, base: [f64; 3], reach: f64) -> Vec<[f64; 3]> {
    let base = DVec3::from(base);
    let mut points = state.skeleton.nodes.clone();
    for o in &state.obstacles {
        for part in o.primitives() {
            if matches!(part, PrimitiveSpec::Plane(_)) {
                continue;
            }
            let p = anchor(&part);
            if DVec3::from(p).distance(base) <= reach {
                points.push(p);
            }
        }
    }
    points
}

/// A representative point of a shape: its centre (the sensed position).
#[must_use]
pub fn anchor(shape: &PrimitiveSpec) -> [f64; 3] {
    let mean = |points: &[[f64; 3]]| {
        let sum = points
            .iter()
            .fold(DVec3::ZERO, |acc, p| acc + DVec3::from(*p));
        (sum / points.len().max(1) as f64).to_array()
    };
    match shape {
        PrimitiveSpec::Point(PointSpec { p }) => *p,
        PrimitiveSpec::Segment(SegmentSpec { a, b })
        | PrimitiveSpec::Capsule(CapsuleSpec { a, b, .. })
        | PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec { a, b, .. }) => mean(&[*a, *b]),
        PrimitiveSpec::Sphere(SphereSpec { center, .. })
        | PrimitiveSpec::Rectangle(RectangleSpec { center, .. })
        | PrimitiveSpec::Disk(DiskSpec { center, .. })
        | PrimitiveSpec::Box(BoxSpec { center, .. }) => *center,
        PrimitiveSpec::Plane(PlaneSpec { normal, offset }) => {
            let n = DVec3::from(*normal);
            (n * (-offset / n.length_squared().max(1e-12))).to_array()
        }
        PrimitiveSpec::Polygon(PolygonSpec { vertices }) => mean(vertices),
        PrimitiveSpec::ConvexHull(crate::distance::ConvexHullSpec { points }) => mean(points),
    }
}

fn draw_shape(
    scene: &mut Scene,
    shape: &PrimitiveSpec,
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
        PrimitiveSpec::Point(PointSpec { p }) => scene.spheres.push(Sphere {
            center: v(*p),
            radius: 1.5 * THIN,
            color: solid,
        }),
        PrimitiveSpec::Segment(SegmentSpec { a, b }) => scene.capsules.push(Capsule {
            a: v(*a),
            b: v(*b),
            radius: [THIN; 2],
            color: solid,
        }),
        PrimitiveSpec::Sphere(SphereSpec { center, radius }) => scene.spheres.push(Sphere {
            center: v(*center),
            radius: *radius as f32,
            color: solid,
        }),
        PrimitiveSpec::Capsule(CapsuleSpec { a, b, radius }) => scene.capsules.push(Capsule {
            a: v(*a),
            b: v(*b),
            radius: [*radius as f32; 2],
            color: solid,
        }),
        PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec { a, b, radius }) => {
            scene.capsules.push(Capsule {
                a: v(*a),
                b: v(*b),
                radius: [radius[0] as f32, radius[1] as f32],
                color: solid,
            })
        }
        PrimitiveSpec::Plane(PlaneSpec { normal, offset }) => {
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
        PrimitiveSpec::Rectangle(RectangleSpec {
            center,
            axes,
            half_extents,
        }) => scene.push_rectangle(
            v(*center),
            [v(axes[0]), v(axes[1])],
            [half_extents[0] as f32, half_extents[1] as f32],
            flat,
            outline,
        ),
        PrimitiveSpec::Disk(DiskSpec {
            center,
            normal,
            radius,
        }) => {
            let n = DVec3::from(*normal).normalize_or(DVec3::Z);
            scene.push_disk(v(*center), v(n.to_array()), *radius as f32, flat, outline);
        }
        PrimitiveSpec::Polygon(PolygonSpec { vertices }) => {
            let points: Vec<[f32; 3]> = vertices.iter().map(|p| v(*p)).collect();
            // The library's triangulation; a fan when the polygon is refused.
            let triangles = Polygon::new(vertices.iter().map(|p| DVec3::from(*p)).collect())
                .map(|p| p.triangles())
                .unwrap_or_default();
            scene.push_polygon(&points, &triangles, flat, outline);
        }
        PrimitiveSpec::Box(BoxSpec {
            center,
            half_extents,
            rotation,
        }) => {
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
        PrimitiveSpec::ConvexHull(crate::distance::ConvexHullSpec { points }) => {
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
fn draw_inflated(scene: &mut Scene, shape: &PrimitiveSpec, m: f32) {
    let capsule = |a: [f64; 3], b: [f64; 3], r: [f32; 2]| Capsule {
        a: v(a),
        b: v(b),
        radius: [r[0] + m, r[1] + m],
        color: UNCERTAINTY,
    };
    match shape {
        PrimitiveSpec::Point(PointSpec { p }) => scene.spheres.push(Sphere {
            center: v(*p),
            radius: m,
            color: UNCERTAINTY,
        }),
        PrimitiveSpec::Sphere(SphereSpec { center, radius }) => scene.spheres.push(Sphere {
            center: v(*center),
            radius: *radius as f32 + m,
            color: UNCERTAINTY,
        }),
        PrimitiveSpec::Segment(SegmentSpec { a, b }) => {
            scene.capsules.push(capsule(*a, *b, [0.0; 2]))
        }
        PrimitiveSpec::Capsule(CapsuleSpec { a, b, radius }) => {
            scene.capsules.push(capsule(*a, *b, [*radius as f32; 2]));
        }
        PrimitiveSpec::TaperedCapsule(TaperedCapsuleSpec { a, b, radius }) => {
            scene
                .capsules
                .push(capsule(*a, *b, [radius[0] as f32, radius[1] as f32]));
        }
        _ => {}
    }
}

impl DrawState {
    /// The drawn part of a world's state, copied in Rust (nothing crosses to JS).
    #[must_use]
    pub fn from_world(state: &crate::world::WorldState) -> Self {
        Self {
            skeleton: SkeletonView {
                nodes: state.skeleton.nodes.clone(),
                segments: state
                    .skeleton
                    .segments
                    .iter()
                    .map(|s| SegmentView {
                        from: s.from,
                        to: s.to,
                        radius: s.radius,
                    })
                    .collect(),
            },
            obstacles: state
                .obstacles
                .iter()
                .map(|o| ObstacleView {
                    id: o.id.clone(),
                    shape: serde_json::to_value(&o.shape).unwrap_or(serde_json::Value::Null),
                    parts: Some(o.parts.clone()),
                })
                .collect(),
            control_points: state
                .control_points
                .iter()
                .map(|c| ControlPointView {
                    position: c.position,
                    witness: Some(c.witness),
                    repulsion: Some(c.repulsion),
                    transitioning: c.transitioning,
                    obstacle: c.obstacle.clone(),
                })
                .collect(),
            uncertainty: state
                .uncertainty
                .iter()
                .map(|u| UncertaintyView {
                    obstacle: u.obstacle.clone(),
                    radius: u.radius,
                })
                .collect(),
        }
    }
}
