//! The drawn scene of a simulated world: the skeleton, every obstacle
//! primitive, the control points with their distance lines and repulsion
//! arrows, the sensing-margin regions, and the sliding points of point tasks.
//!
//! The input is [`DrawState`], the part of a world's state the viewer draws.
//! [`DrawState::from`] a [`WorldState`] moves the fields over (no copy of the
//! geometry, no JSON); [`DrawState`] also deserialises from a plain state
//! object (a recorded `World.state()`), where an obstacle given without its
//! `parts` is drawn from its `shape`.

use glam::DVec3;
use serde::Deserialize;

use super::drawing::{Capsule, Drawing, Line, Sphere};
use super::shapes::{Palette, UNCERTAINTY, draw_inflated, draw_shape, v};
use crate::distance::PrimitiveSpec;
use crate::scenario::ShapeSpec;
use crate::world::WorldState;

/// What the viewer draws of a world (a subset of the world's state; other
/// fields of a state object are ignored).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct DrawState {
    /// The robot's skeleton.
    pub skeleton: SkeletonView,
    /// The obstacles, each with its id and primitives.
    #[serde(default)]
    pub obstacles: Vec<ObstacleView>,
    /// The active control points.
    #[serde(default)]
    pub control_points: Vec<ControlPointView>,
    /// Sensing uncertainty around obstacles.
    #[serde(default)]
    pub uncertainty: Vec<UncertaintyView>,
    /// Where the sliding points of point tasks are now (m).
    #[serde(default)]
    pub sliding_points: Vec<[f64; 3]>,
    /// The joint vector (places the link meshes; empty: they stay where
    /// they were).
    #[serde(default)]
    pub q: Vec<f64>,
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

/// An obstacle: its id and the primitives it is made of.
#[derive(Clone, Debug, Deserialize)]
#[serde(from = "ObstacleWire")]
pub struct ObstacleView {
    /// The obstacle's id.
    pub id: String,
    /// Whether it is a human figure (drawn skin-coloured).
    pub human: bool,
    /// Its primitives at their current pose (one, or a human's parts).
    pub parts: Vec<PrimitiveSpec>,
}

/// An obstacle as a state object holds it: `{ id, shape, parts? }`.
#[derive(Deserialize)]
struct ObstacleWire {
    id: String,
    shape: serde_json::Value,
    #[serde(default)]
    parts: Option<Vec<PrimitiveSpec>>,
}

impl From<ObstacleWire> for ObstacleView {
    fn from(o: ObstacleWire) -> Self {
        let human = o.shape.get("type").and_then(|t| t.as_str()) == Some("human");
        // A shape that is no figure draws nothing rather than failing the
        // whole state: a recorded state may come from a newer version.
        let parts = o
            .parts
            .unwrap_or_else(|| match serde_json::from_value::<ShapeSpec>(o.shape) {
                Ok(ShapeSpec::Primitive(p)) => vec![p],
                Ok(ShapeSpec::Human(h)) => h.parts(),
                Err(_) => Vec::new(),
            });
        Self {
            id: o.id,
            human,
            parts,
        }
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
    /// The part of a human it answers, as `id:part` (`person:rightHand`;
    /// absent for other obstacles).
    #[serde(default)]
    pub part: Option<String>,
    /// Propagated standard deviations from the sensing error, when its
    /// obstacle is sensed with one.
    #[serde(default)]
    pub sigma: Option<SigmaView>,
}

/// The part of a control point's propagated deviations the view draws.
#[derive(Clone, Copy, Debug, Default, Deserialize)]
pub struct SigmaView {
    /// Of its witness's DH value `d'` (m).
    #[serde(default)]
    pub d: f64,
    /// Of its witness's DH value `a'` (m).
    #[serde(default)]
    pub a: f64,
}

impl SigmaView {
    /// Standard deviation of the witness's place along its link (m): its
    /// `d'` or its `a'` moves, the other is fixed by the segment.
    #[must_use]
    pub fn along(&self) -> f64 {
        (self.d * self.d + self.a * self.a).sqrt()
    }
}

/// The uncertainty region of a sensed obstacle.
#[derive(Clone, Debug, Deserialize)]
pub struct UncertaintyView {
    /// The obstacle's id.
    pub obstacle: String,
    /// Radius of the region (m).
    pub radius: f64,
}

impl From<WorldState> for DrawState {
    /// The drawn part of a world's state (the vectors are moved, not copied).
    fn from(state: WorldState) -> Self {
        let skeleton = SkeletonView {
            nodes: state.skeleton.nodes,
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
        };
        let obstacles = state
            .obstacles
            .into_iter()
            .map(|o| ObstacleView {
                human: matches!(o.shape, ShapeSpec::Human(_)),
                id: o.id,
                parts: o.parts,
            })
            .collect();
        let control_points = state
            .control_points
            .into_iter()
            .map(|c| ControlPointView {
                position: c.position,
                witness: Some(c.witness),
                repulsion: Some(c.repulsion),
                transitioning: c.transitioning,
                obstacle: c.obstacle,
                part: c.part,
                sigma: c.sigma.map(|s| SigmaView { d: s.d, a: s.a }),
            })
            .collect();
        let uncertainty = state
            .uncertainty
            .into_iter()
            .map(|u| UncertaintyView {
                obstacle: u.obstacle,
                radius: u.radius,
            })
            .collect();
        Self {
            skeleton,
            obstacles,
            control_points,
            uncertainty,
            sliding_points: state.sliding_points,
            q: state.q,
        }
    }
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

/// Colours and sizes of the robot and of the control-point marks.
pub mod style {
    /// Translucent volume around a skeleton segment.
    pub const VOLUME: [f32; 4] = [0.33, 0.55, 0.85, 0.45];
    /// The skeleton's spine.
    pub const SPINE: [f32; 4] = [0.20, 0.24, 0.32, 1.0];
    /// Skeleton nodes.
    pub const NODE: [f32; 4] = [0.95, 0.55, 0.15, 1.0];
    /// A control point at rest.
    pub const CONTROL_POINT: [f32; 4] = [0.80, 0.10, 0.55, 1.0];
    /// A control point travelling along the skeleton.
    pub const TRANSITIONING: [f32; 4] = [0.10, 0.70, 0.35, 1.0];
    /// The line from a control point to its witness.
    pub const DISTANCE_LINE: [f32; 4] = [0.62, 0.08, 0.45, 1.0];
    /// Repulsion arrows.
    pub const REPULSION: [f32; 4] = [0.0, 0.62, 0.62, 1.0];
    /// The sliding point of a point task.
    pub const SLIDING_POINT: [f32; 4] = [0.15, 0.35, 0.90, 1.0];
    /// The interval along the skeleton where a control point's witness may
    /// be, given the sensing error (± [`SIGMA_SPAN`] standard deviations).
    pub const WITNESS_INTERVAL: [f32; 4] = [0.95, 0.45, 0.05, 0.75];
    /// Half-length of the witness interval in standard deviations (about
    /// 95 % of a Gaussian).
    pub const SIGMA_SPAN: f64 = 2.0;
    /// Radius of the spine (m).
    pub const SPINE_RADIUS: f32 = 0.012;
    /// Radius of a node mark (m).
    pub const NODE_RADIUS: f32 = 0.022;
    /// Radius of a control-point mark (m).
    pub const CONTROL_POINT_RADIUS: f32 = 0.026;
    /// Longest repulsion arrow (m).
    pub const MAX_ARROW: f64 = 0.3;
}

/// Adds `state` to `scene`; the obstacle whose id is `selected` is
/// highlighted. `around` is the point near which infinite planes are drawn.
pub fn build_scene(
    scene: &mut Drawing,
    state: &DrawState,
    options: &DrawOptions,
    selected: Option<&str>,
    around: [f64; 3],
) {
    draw_skeleton(scene, &state.skeleton, options);
    for o in &state.obstacles {
        let palette = if selected == Some(o.id.as_str()) {
            Palette::SELECTED
        } else if o.human {
            Palette::HUMAN
        } else {
            Palette::OBSTACLE
        };
        for part in &o.parts {
            draw_shape(scene, part, &palette, around, options.plane_extent);
        }
    }
    draw_uncertainty(scene, state);
    for cp in &state.control_points {
        draw_control_point(scene, cp, options.arrow_scale);
        draw_witness_interval(scene, &state.skeleton, cp);
    }
    for p in &state.sliding_points {
        scene.spheres.push(Sphere {
            center: v(*p),
            radius: 0.8 * style::CONTROL_POINT_RADIUS,
            color: style::SLIDING_POINT,
        });
    }
}

/// The spine of every segment, its volume and the nodes, as `options` ask.
fn draw_skeleton(scene: &mut Drawing, skeleton: &SkeletonView, options: &DrawOptions) {
    for s in &skeleton.segments {
        let (Some(&a), Some(&b)) = (skeleton.nodes.get(s.from), skeleton.nodes.get(s.to)) else {
            continue;
        };
        let (a, b) = (v(a), v(b));
        scene.capsules.push(Capsule {
            a,
            b,
            radius: [style::SPINE_RADIUS; 2],
            color: style::SPINE,
        });
        if options.volumes {
            scene.capsules.push(Capsule {
                a,
                b,
                radius: [s.radius[0] as f32, s.radius[1] as f32],
                color: style::VOLUME,
            });
        }
    }
    if options.nodes {
        for &n in &skeleton.nodes {
            scene.spheres.push(Sphere {
                center: v(n),
                radius: style::NODE_RADIUS,
                color: style::NODE,
            });
        }
    }
}

/// The sensing margin of each obstacle: the inflated figure for round
/// primitives, a ball around each witness point for the flat ones (where the
/// true closest point may be). Of a human, only the parts that control
/// points answer get theirs: there the margin tells where the part the
/// controller reads may truly be. Shaded over all sixteen parts of a body
/// near the camera it cost a software renderer about 2 ms a frame (of
/// 26, `human-panda`) for a rim a centimetre wide.
fn draw_uncertainty(scene: &mut Drawing, state: &DrawState) {
    for u in &state.uncertainty {
        let m = u.radius;
        if !(m.is_finite() && m > 0.0) {
            continue;
        }
        let Some(o) = state.obstacles.iter().find(|o| o.id == u.obstacle) else {
            continue;
        };
        let answered = |k: usize| {
            let name = crate::human::PART_NAMES.get(k).copied();
            state.control_points.iter().any(|c| {
                let part = c
                    .part
                    .as_deref()
                    .and_then(|p| p.strip_prefix(o.id.as_str()));
                part.and_then(|p| p.strip_prefix(':')) == name
            })
        };
        let mut flat = false;
        for (k, part) in o.parts.iter().enumerate() {
            if o.human && !answered(k) {
                continue;
            }
            flat |= !draw_inflated(scene, part, m as f32);
        }
        if !flat {
            continue;
        }
        let witnesses = state
            .control_points
            .iter()
            .filter(|c| c.obstacle == o.id)
            .filter_map(|c| c.witness);
        for w in witnesses {
            scene.spheres.push(Sphere {
                center: v(w),
                radius: m as f32,
                color: UNCERTAINTY,
            });
        }
    }
}

/// The interval along the skeleton, around a control point, where its
/// witness may be given the sensing error: ± [`style::SIGMA_SPAN`]
/// propagated standard deviations along the segment the point is on,
/// clipped to that segment (a thick orange stretch of the spine).
fn draw_witness_interval(scene: &mut Drawing, skeleton: &SkeletonView, cp: &ControlPointView) {
    let Some(sigma) = cp.sigma.map(|s| s.along()) else {
        return;
    };
    if !(sigma.is_finite() && sigma > 0.0) {
        return;
    }
    let p = DVec3::from(cp.position);
    // The segment whose spine passes through the point.
    let mut best: Option<(f64, DVec3, DVec3, f64)> = None;
    for s in &skeleton.segments {
        let (Some(&a), Some(&b)) = (skeleton.nodes.get(s.from), skeleton.nodes.get(s.to)) else {
            continue;
        };
        let (a, b) = (DVec3::from(a), DVec3::from(b));
        let l2 = (b - a).length_squared();
        if l2 <= 0.0 {
            continue;
        }
        let t = ((p - a).dot(b - a) / l2).clamp(0.0, 1.0);
        let d = (a + (b - a) * t).distance(p);
        if best.is_none_or(|x| d < x.0) {
            best = Some((d, a, b, t));
        }
    }
    let Some((_, a, b, t)) = best else { return };
    let len = a.distance(b);
    let half = (style::SIGMA_SPAN * sigma / len).min(1.0);
    let (t0, t1) = ((t - half).max(0.0), (t + half).min(1.0));
    let r = 1.6 * style::SPINE_RADIUS;
    scene.capsules.push(Capsule {
        a: v((a + (b - a) * t0).to_array()),
        b: v((a + (b - a) * t1).to_array()),
        radius: [r, r],
        color: style::WITNESS_INTERVAL,
    });
}

/// A control point, the line to its witness and its repulsion arrow
/// (`arrow_scale` metres per unit of repulsion, at most
/// [`style::MAX_ARROW`]).
fn draw_control_point(scene: &mut Drawing, cp: &ControlPointView, arrow_scale: f64) {
    let color = if cp.transitioning {
        style::TRANSITIONING
    } else {
        style::CONTROL_POINT
    };
    scene.spheres.push(Sphere {
        center: v(cp.position),
        radius: style::CONTROL_POINT_RADIUS,
        color,
    });
    if let Some(w) = cp.witness {
        scene.lines.push(Line {
            a: v(cp.position),
            b: v(w),
            width: 2.5,
            color: style::DISTANCE_LINE,
        });
        scene.spheres.push(Sphere {
            center: v(w),
            radius: 0.4 * style::CONTROL_POINT_RADIUS,
            color: style::DISTANCE_LINE,
        });
    }
    if let Some(r) = cp.repulsion {
        let r = DVec3::from(r) * arrow_scale;
        let len = r.length();
        if len.is_finite() && len > 1e-4 {
            let r = r * (len.min(style::MAX_ARROW) / len);
            let from = DVec3::from(cp.position);
            scene.push_arrow(
                v(from.to_array()),
                v((from + r).to_array()),
                4.0,
                0.06,
                style::REPULSION,
            );
        }
    }
}
