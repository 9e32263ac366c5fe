//! The scene query: every skeleton segment, with its volume, against a set
//! of obstacles, plus self-collision pairs between non-adjacent links; and
//! picking an obstacle with a ray.
//!
//! A bounding-volume hierarchy over the obstacles' axis-aligned boxes (built
//! once per [`Scene::new`] or edit, median split on the widest axis) keeps the
//! cost of a query close to the number of obstacles near the skeleton;
//! infinite planes are always tested. Each candidate's box is then checked
//! exactly against the segment's axis (a mid-phase) before the narrow phase.

use glam::DVec3;
use parry3d_f64::math::Pose;
use parry3d_f64::query::Ray;
use parry3d_f64::shape::{Ball, Capsule as ParryCapsule};

use super::cuboid::segment_aabb_distance2;
use super::generic::parry_shape;
use super::{
    Capsule, Distance, DistanceError, LineSegment, Primitive, TaperedCapsule, core_of, distance,
};
use crate::error::{FieldError, finite3, non_negative};
use crate::skeleton::Skeleton;

mod box_tree;
mod nearest;

pub use nearest::Nearest;

use box_tree::{Aabb, BoxTree, bounds_of};

/// An obstacle: a primitive with a caller-chosen id.
#[derive(Clone, Debug, PartialEq)]
pub struct Obstacle {
    /// Caller's id, reported back by queries and picks.
    pub id: u32,
    /// The figure (world frame).
    pub shape: Primitive,
}

/// What a skeleton segment was measured against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// Obstacle number `index` in the scene, with its id.
    Obstacle {
        /// Position in the scene's obstacle list.
        index: usize,
        /// The obstacle's id.
        id: u32,
    },
    /// Another skeleton segment (self-collision), by index.
    Segment(usize),
}

/// One segment–obstacle (or segment–segment) pair within the influence
/// distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairDistance {
    /// Index of the skeleton segment.
    pub segment: usize,
    /// What it was measured against.
    pub target: Target,
    /// Signed clearance between the segment's volume and the target (m).
    pub distance: f64,
    /// Witness on the segment's volume.
    pub point_segment: DVec3,
    /// Witness on the target.
    pub point_other: DVec3,
    /// Fraction along the segment (0 at `from`, 1 at `to`) of the core point
    /// closest to the target: where a control point would sit.
    pub fraction: f64,
    /// Unit direction from the segment towards the target.
    pub normal: DVec3,
    /// `false` when the closest point is one of a family (see
    /// [`Distance::unique`]).
    pub unique: bool,
}

/// Which candidates the query measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BroadPhase {
    /// Only obstacles whose bounding box is within reach (default).
    #[default]
    Hierarchy,
    /// Every obstacle (a reference for tests and benchmarks).
    BruteForce,
}

/// Options of [`Scene::query`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QueryOptions {
    /// Pairs with a clearance above this are not reported (m, ≥ 0).
    pub influence_distance: f64,
    /// Whether to report segment–segment pairs between non-adjacent links.
    pub self_collision: bool,
    /// Candidate selection.
    pub broad_phase: BroadPhase,
}

impl Default for QueryOptions {
    fn default() -> Self {
        Self {
            influence_distance: 0.3,
            self_collision: true,
            broad_phase: BroadPhase::Hierarchy,
        }
    }
}

/// The result of a pick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// Position in the scene's obstacle list.
    pub index: usize,
    /// The obstacle's id.
    pub id: u32,
    /// Where the ray first meets the obstacle.
    pub point: DVec3,
    /// Distance from the ray's origin to `point` (m).
    pub distance: f64,
}

/// Obstacles with a broad phase for skeleton queries.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    obstacles: Vec<Obstacle>,
    bounds: Vec<Aabb>,
    unbounded: Vec<usize>,
    tree: BoxTree,
}

impl Scene {
    /// A scene of `obstacles` (already validated primitives).
    #[must_use]
    pub fn new(obstacles: Vec<Obstacle>) -> Self {
        let mut s = Self {
            obstacles,
            ..Self::default()
        };
        s.rebuild();
        s
    }

    fn rebuild(&mut self) {
        self.bounds = self.obstacles.iter().map(|o| bounds_of(&o.shape)).collect();
        let (finite, unbounded): (Vec<usize>, Vec<usize>) =
            (0..self.obstacles.len()).partition(|&i| self.bounds[i].is_finite());
        self.unbounded = unbounded;
        self.tree = BoxTree::build(&self.bounds, finite);
    }

    /// The obstacles, in order.
    #[must_use]
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// Replaces the figure of obstacle `index` (e.g. after a drag) and
    /// rebuilds the hierarchy.
    ///
    /// # Errors
    /// `obstacles: no obstacle at index {index}`.
    pub fn set_shape(&mut self, index: usize, shape: Primitive) -> Result<(), FieldError> {
        let o = self
            .obstacles
            .get_mut(index)
            .ok_or_else(|| FieldError::new("obstacles", format!("no obstacle at index {index}")))?;
        o.shape = shape;
        self.rebuild();
        Ok(())
    }

    /// Every skeleton segment (with its tapered volume) against the
    /// obstacles, and, if asked, against the segments of non-adjacent links;
    /// the pairs whose clearance is at most the influence distance, ordered
    /// by segment then target.
    ///
    /// `adjacent(i, j)` tells whether links `i` and `j` (1-based DH rows)
    /// are adjacent, i.e. one is the parent of the other (see
    /// [`parent_adjacency`]); segments of the same link are never paired.
    ///
    /// # Errors
    /// `influenceDistance: …` when negative or not finite;
    /// `skeleton.nodes[k][j]: not a finite number`; an unsupported pair.
    ///
    /// # Example
    /// ```
    /// use glam::DVec3;
    /// use skeleton_avoidance::distance::{
    ///     parent_adjacency, Obstacle, Primitive, QueryOptions, Scene, Sphere,
    /// };
    /// use skeleton_avoidance::skeleton::{Segment, Skeleton, SpinePart};
    ///
    /// let arm = Skeleton {
    ///     nodes: vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 0.4), DVec3::new(0.3, 0.0, 0.4)],
    ///     segments: vec![
    ///         Segment { from: 0, to: 1, link: 1, part: SpinePart::D, radius: [0.05, 0.05] },
    ///         Segment { from: 1, to: 2, link: 2, part: SpinePart::A, radius: [0.05, 0.05] },
    ///     ],
    ///     ..Default::default()
    /// };
    /// let ball = Sphere::new(DVec3::new(0.15, 0.2, 0.4), 0.05).unwrap();
    /// let scene = Scene::new(vec![Obstacle { id: 1, shape: Primitive::Sphere(ball) }]);
    /// let parents = [0, 0, 1]; // link 1 on the base, link 2 on link 1
    /// let pairs = scene
    ///     .query(&arm, &QueryOptions::default(), parent_adjacency(&parents))
    ///     .unwrap();
    /// let near = pairs.iter().find(|p| p.segment == 1).unwrap();
    /// assert!((near.fraction - 0.5).abs() < 1e-6);
    /// ```
    pub fn query(
        &self,
        skeleton: &Skeleton,
        options: &QueryOptions,
        adjacent: impl Fn(usize, usize) -> bool,
    ) -> Result<Vec<PairDistance>, DistanceError> {
        let influence = non_negative("influenceDistance", options.influence_distance)?;
        let volumes = volumes(skeleton)?;
        let mut out = Vec::new();
        let mut candidates = Vec::new();
        for (i, vol) in volumes.iter().enumerate() {
            let reach = bounds_of(vol).grown(influence);
            candidates.clear();
            match options.broad_phase {
                BroadPhase::Hierarchy => {
                    self.tree.query(&reach, &mut candidates);
                    candidates.extend_from_slice(&self.unbounded);
                    candidates.sort_unstable();
                }
                BroadPhase::BruteForce => candidates.extend(0..self.obstacles.len()),
            }
            let (s0, s1, rmax) = axis_of(vol);
            let reach2 = (influence + rmax) * (influence + rmax);
            for &j in &candidates {
                let o = &self.obstacles[j];
                // Mid-phase: the exact distance from the axis to the
                // obstacle's box rules out most candidates of the box test
                // (not worth it for a ball or a point, whose exact distance
                // costs less than the box's).
                let b = &self.bounds[j];
                if options.broad_phase == BroadPhase::Hierarchy
                    && !matches!(o.shape, Primitive::Sphere(_) | Primitive::Point(_))
                    && b.is_finite()
                    && segment_aabb_distance2(s0, s1, b.min, b.max) > reach2
                {
                    continue;
                }
                let d = distance(vol, &o.shape)?;
                if d.distance <= influence {
                    out.push(pair(i, vol, Target::Obstacle { index: j, id: o.id }, d));
                }
            }
            if options.self_collision {
                let li = skeleton.segments[i].link;
                for (j, other) in volumes.iter().enumerate().skip(i + 1) {
                    let lj = skeleton.segments[j].link;
                    if li == lj || adjacent(li, lj) || !reach.overlaps(&bounds_of(other)) {
                        continue;
                    }
                    let d = distance(vol, other)?;
                    if d.distance <= influence {
                        out.push(pair(i, vol, Target::Segment(j), d));
                    }
                }
            }
        }
        Ok(out)
    }

    /// Segment `segment` of `skeleton` measured against obstacle `index` of
    /// the scene moved by `offset` (the same pair as [`Scene::query`] would
    /// report, whatever the influence distance): what uncertainty
    /// propagation differentiates ([`crate::dependability::propagate`]).
    ///
    /// # Errors
    /// An index out of range, non-finite input.
    pub fn pair_moved(
        &self,
        skeleton: &Skeleton,
        segment: usize,
        index: usize,
        offset: DVec3,
    ) -> Result<PairDistance, DistanceError> {
        let (Some(s), Some(o)) = (skeleton.segments.get(segment), self.obstacles.get(index)) else {
            return Err(FieldError::new("segment", "index out of range").into());
        };
        let (Some(a), Some(b)) = (skeleton.nodes.get(s.from), skeleton.nodes.get(s.to)) else {
            return Err(FieldError::new("segment", "node index out of range").into());
        };
        finite3("offset", offset)?;
        // Moving the obstacle by `offset` is moving the segment by `−offset`.
        let vol = volume(
            LineSegment {
                a: *a - offset,
                b: *b - offset,
            },
            s.radius,
        );
        let d = distance(&vol, &o.shape)?;
        let mut p = pair(segment, &vol, Target::Obstacle { index, id: o.id }, d);
        p.point_segment += offset;
        p.point_other += offset;
        Ok(p)
    }

    /// The first obstacle hit by the ray from `origin` along `direction`
    /// (parry ray casts; points and segments are picked within
    /// `pick_radius`, tapered capsules through the capsule of their larger
    /// radius).
    ///
    /// # Errors
    /// Non-finite input, `direction: must not be zero`, negative
    /// `pickRadius`.
    ///
    /// # Example
    /// ```
    /// use glam::DVec3;
    /// use skeleton_avoidance::distance::{Obstacle, Primitive, Scene, Sphere};
    /// let ball = Sphere::new(DVec3::new(0.0, 0.0, 2.0), 0.5).unwrap();
    /// let scene = Scene::new(vec![Obstacle { id: 4, shape: Primitive::Sphere(ball) }]);
    /// let hit = scene.pick(DVec3::ZERO, DVec3::Z, 0.01).unwrap().unwrap();
    /// assert_eq!(hit.id, 4);
    /// assert!((hit.point.z - 1.5).abs() < 1e-9);
    /// ```
    pub fn pick(
        &self,
        origin: DVec3,
        direction: DVec3,
        pick_radius: f64,
    ) -> Result<Option<Pick>, FieldError> {
        let origin = finite3("origin", origin)?;
        let dir = finite3("direction", direction)?;
        let pick_radius = non_negative("pickRadius", pick_radius)?;
        let len = dir.length();
        if len.is_nan() || len <= 0.0 {
            return Err(FieldError::new("direction", "must not be zero"));
        }
        let dir = dir / len;
        let ray = Ray::new(origin, dir);
        let mut best: Option<Pick> = None;
        for (index, o) in self.obstacles.iter().enumerate() {
            if let Some(t) = cast(&o.shape, &ray, pick_radius)
                && best.is_none_or(|b| t < b.distance)
            {
                best = Some(Pick {
                    index,
                    id: o.id,
                    point: origin + dir * t,
                    distance: t,
                });
            }
        }
        Ok(best)
    }
}

/// The time of impact of a unit ray with a primitive.
fn cast(shape: &Primitive, ray: &Ray, pick_radius: f64) -> Option<f64> {
    use parry3d_f64::query::RayCast;
    let max = f64::MAX;
    let capsule = |s: &LineSegment, r: f64| {
        if r > 0.0 {
            ParryCapsule::new(s.a, s.b, r).cast_ray(&Pose::IDENTITY, ray, max, true)
        } else {
            None
        }
    };
    let ball = |c: DVec3, r: f64| {
        if r > 0.0 {
            Ball::new(r).cast_ray(&Pose::from_translation(c), ray, max, true)
        } else {
            None
        }
    };
    match shape {
        Primitive::Point(p) => ball(*p, pick_radius),
        Primitive::Segment(s) => capsule(s, pick_radius),
        Primitive::Sphere(s) => ball(s.center, s.radius),
        Primitive::Capsule(c) => capsule(&c.segment, c.radius),
        Primitive::TaperedCapsule(c) => capsule(&c.segment, c.max_radius()),
        Primitive::Plane(p) => {
            let den = p.normal.dot(ray.dir);
            if den == 0.0 {
                return None;
            }
            let t = -p.signed_distance(ray.origin) / den;
            (t >= 0.0).then_some(t)
        }
        Primitive::Polygon(poly) => {
            let n = poly.normal();
            let den = n.dot(ray.dir);
            let (_, h) = poly.to_local(ray.origin);
            if den == 0.0 {
                return None;
            }
            let t = -h / den;
            let (q, _) = poly.to_local(ray.origin + ray.dir * t);
            (t >= 0.0 && poly.contains_local(q)).then_some(t)
        }
        _ => {
            let (core, _) = core_of(shape);
            let (pose, s) = parry_shape(core)?;
            s.cast_ray(&pose, ray, max, true)
        }
    }
}

/// The volume of a skeleton segment.
/// The volumes of `skeleton`'s segments, in order, after checking its
/// nodes are finite and its segments' node indices in range.
fn volumes(skeleton: &Skeleton) -> Result<Vec<Primitive>, DistanceError> {
    for (k, p) in skeleton.nodes.iter().enumerate() {
        // The field's name is formatted only for a bad node: this runs
        // every control step.
        if !p.is_finite() {
            finite3(&format!("skeleton.nodes[{k}]"), *p)?;
        }
    }
    let mut volumes = Vec::with_capacity(skeleton.segments.len());
    for (k, s) in skeleton.segments.iter().enumerate() {
        let (Some(a), Some(b)) = (skeleton.nodes.get(s.from), skeleton.nodes.get(s.to)) else {
            return Err(FieldError::new(
                format!("skeleton.segments[{k}]"),
                "node index out of range",
            )
            .into());
        };
        volumes.push(volume(LineSegment { a: *a, b: *b }, s.radius));
    }
    Ok(volumes)
}

/// A segment volume's axis and its largest radius (what the mid-phase
/// measures boxes against).
fn axis_of(vol: &Primitive) -> (DVec3, DVec3, f64) {
    match vol {
        Primitive::Capsule(c) => (c.segment.a, c.segment.b, c.radius),
        Primitive::TaperedCapsule(c) => (c.segment.a, c.segment.b, c.max_radius()),
        Primitive::Segment(s) => (s.a, s.b, 0.0),
        _ => (DVec3::ZERO, DVec3::ZERO, f64::INFINITY),
    }
}

fn volume(s: LineSegment, radius: [f64; 2]) -> Primitive {
    let [r0, r1] = radius;
    if !(r0 > 0.0 && r1 > 0.0) {
        Primitive::Segment(s)
    } else if r0 == r1 {
        Primitive::Capsule(Capsule {
            segment: s,
            radius: r0,
        })
    } else {
        Primitive::TaperedCapsule(TaperedCapsule { segment: s, radius })
    }
}

fn pair(i: usize, vol: &Primitive, target: Target, d: Distance) -> PairDistance {
    // The witness is c(t) + r(t)·normal with c(t) = a + t·(b − a) and
    // r(t) = r0 + t·(r1 − r0), so t follows from it exactly.
    let (a, b, r0, r1) = match vol {
        Primitive::Capsule(c) => (c.segment.a, c.segment.b, c.radius, c.radius),
        Primitive::TaperedCapsule(c) => (c.segment.a, c.segment.b, c.radius[0], c.radius[1]),
        Primitive::Segment(s) => (s.a, s.b, 0.0, 0.0),
        _ => (DVec3::ZERO, DVec3::ZERO, 0.0, 0.0),
    };
    let dir = (b - a) + d.normal * (r1 - r0);
    let l2 = dir.length_squared();
    let fraction = if l2 > 0.0 {
        ((d.point_a - a - d.normal * r0).dot(dir) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    PairDistance {
        segment: i,
        target,
        distance: d.distance,
        point_segment: d.point_a,
        point_other: d.point_b,
        fraction,
        normal: d.normal,
        unique: d.unique,
    }
}

/// The adjacency of links described by their parents: `parents[j]` is the
/// parent link of link `j` (0 for the base; index 0 unused). Links `i` and
/// `j` are adjacent when one is the parent of the other.
///
/// For a [`Robot`](crate::kinematics::Robot) use
/// `|i, j| robot.adjacent(i, j)` instead (the crate's one definition of
/// adjacent links): it skips rows that add no segment and counts sibling
/// chains starting from one node as adjacent.
pub fn parent_adjacency(parents: &[usize]) -> impl Fn(usize, usize) -> bool + '_ {
    move |i, j| parents.get(i) == Some(&j) || parents.get(j) == Some(&i)
}
