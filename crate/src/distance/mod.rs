//! Distances between skeleton segments (and the volumes around them) and
//! environment primitives (paper §II, figs. 2–3).
//!
//! ## The parts
//!
//! * [`primitive`]: the figures with validated constructors, and
//!   [`PrimitiveSpec`], their description at the JavaScript boundary.
//! * One file per pair family with its closed form:
//!   `point` (a point against every figure), `segment_segment`,
//!   `plane` (a plane against every figure, through the figure's extreme
//!   points along the normal), `cuboid` (segment against rectangles and
//!   boxes: the squared distance along the segment is a convex piecewise
//!   quadratic whose pieces are minimised exactly), `disk` (segment against
//!   a disk: one monotone root of the derivative), `polygon` (segment against
//!   a planar, possibly non-convex polygon, and rectangles, polygons and disks
//!   against each other through their sides), `tapered` (the skeleton's tapered
//!   capsule), and `generic` (parry for the pairs with no closed form here:
//!   convex hulls, and disks or boxes against flat figures and boxes).
//! * [`distance`]: the one dispatcher, accepting either order.
//! * [`scene`]: every skeleton segment against a set of obstacles through a
//!   bounding-volume hierarchy, self-collision pairs, and picking by ray.
//!
//! ## Conventions
//!
//! A figure is a *core* (point, segment, plane, rectangle, disk, polygon, box,
//! hull) with a radius around it: a sphere is a point with a radius, a capsule
//! a segment with a radius. The distance between two figures is the distance
//! between their cores minus the radii, which is exact for separated figures
//! and for every overlap of rounded figures with flat cores.
//!
//! The result is *signed*: negative by the penetration depth when a solid
//! (sphere, capsule, tapered capsule, box, convex hull) and another figure
//! overlap, and 0 when figures without volume (point, segment, plane,
//! rectangle, disk, polygon) meet. In every case
//! `point_b − point_a = distance × normal`, where `normal` is the unit
//! direction in which moving B away from A increases the distance.
//!
//! When a whole family of point pairs is equally close (parallel segments, a
//! segment parallel to a plane, rectangle or disk above it), the witness is the
//! middle of that family (for example the middle of the overlap of two
//! parallel segments), so that it moves continuously as the obstacle moves, and
//! [`Distance::unique`] is `false`.
//!
//! Tapered capsules whose two radii differ: against a point or a sphere the
//! clearance is exact (closed form of the round cone). Against any other
//! figure it is the minimum over the segment of the clearance of the ball
//! centred there, found by a bracketing search on its slope that certifies a
//! lower bound, so it is never larger than the true clearance (and at most
//! ~1e-13 of the figure's size smaller); a non-convex polygon is the union of
//! its triangles.

mod cuboid;
mod disk;
pub mod domain;
mod generic;
mod plane;
mod point;
mod polygon;
pub mod primitive;
pub mod scene;
mod segment_segment;
mod tapered;

use glam::DVec3;

pub use primitive::{
    BoxSpec, Capsule, CapsuleSpec, ConvexHull, ConvexHullSpec, Disk, DiskSpec, LineSegment,
    OrientedBox, Plane, PlaneSpec, PointSpec, Polygon, PolygonSpec, Primitive, PrimitiveSpec,
    Rectangle, RectangleSpec, SegmentSpec, Sphere, SphereSpec, TaperedCapsule, TaperedCapsuleSpec,
};
pub use scene::{
    BroadPhase, Nearest, Obstacle, PairDistance, Pick, QueryOptions, Scene, Target,
    parent_adjacency,
};

use crate::error::FieldError;

/// Why a distance could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DistanceError {
    /// An input value was rejected.
    #[error(transparent)]
    Field(#[from] FieldError),
    /// No routine (closed form or parry) handles this pair.
    #[error("no distance between a {a} and a {b}")]
    UnsupportedPair {
        /// Type of the first figure.
        a: &'static str,
        /// Type of the second figure.
        b: &'static str,
    },
}

/// The signed distance between two figures and where it is attained.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distance {
    /// Signed distance (m): negative by the penetration depth when a solid
    /// overlaps the other figure, 0 when figures without volume meet.
    pub distance: f64,
    /// Witness on (or, in overlap, deepest in) the first figure.
    pub point_a: DVec3,
    /// Witness on the second figure; `point_b − point_a = distance × normal`.
    pub point_b: DVec3,
    /// Unit direction from A towards B in which separation grows.
    pub normal: DVec3,
    /// `false` when other witness pairs are equally close (then the
    /// witnesses are the middle of the family).
    pub unique: bool,
}

impl Distance {
    /// The same result with the roles of A and B exchanged.
    #[must_use]
    pub fn flipped(self) -> Self {
        Self {
            point_a: self.point_b,
            point_b: self.point_a,
            normal: -self.normal,
            ..self
        }
    }
}

/// Closest points between two cores; A is the first argument of the routine
/// that made it. `pb − pa = d × n`; `n` is zero when it is undefined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Closest {
    pub d: f64,
    pub pa: DVec3,
    pub pb: DVec3,
    pub n: DVec3,
    pub unique: bool,
}

impl Closest {
    /// The pair `pa`, `pb` at their Euclidean distance.
    #[inline(always)]
    pub fn between(pa: DVec3, pb: DVec3, unique: bool) -> Self {
        let v = pb - pa;
        let d = v.length();
        let n = if d > 0.0 { v / d } else { DVec3::ZERO };
        Self {
            d,
            pa,
            pb,
            n,
            unique,
        }
    }

    /// Sets the normal used when the witnesses coincide.
    pub fn or_normal(mut self, n: DVec3) -> Self {
        if self.n == DVec3::ZERO {
            self.n = n;
        }
        self
    }

    pub fn flipped(self) -> Self {
        Self {
            pa: self.pb,
            pb: self.pa,
            n: -self.n,
            ..self
        }
    }

    /// Grows the cores by radii `ra` and `rb`.
    #[inline(always)]
    pub fn inflate(self, ra: f64, rb: f64) -> Distance {
        let mut n = self.n;
        let mut unique = self.unique;
        if n == DVec3::ZERO {
            n = DVec3::Z;
            if ra + rb > 0.0 {
                unique = false;
            }
        }
        Distance {
            distance: self.d - ra - rb,
            point_a: self.pa + n * ra,
            point_b: self.pb - n * rb,
            normal: n,
            unique,
        }
    }
}

/// The innermost figure of a primitive, around which its radius is grown.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Core<'a> {
    Point(DVec3),
    Segment(DVec3, DVec3),
    Plane(&'a Plane),
    Rectangle(&'a Rectangle),
    Disk(&'a Disk),
    Polygon(&'a Polygon),
    Box(&'a OrientedBox),
    Hull(&'a ConvexHull),
}

impl Core<'_> {
    fn rank(&self) -> u8 {
        match self {
            Core::Point(_) => 0,
            Core::Segment(..) => 1,
            Core::Plane(_) => 2,
            Core::Rectangle(_) => 3,
            Core::Disk(_) => 4,
            Core::Polygon(_) => 5,
            Core::Box(_) => 6,
            Core::Hull(_) => 7,
        }
    }

    pub fn kind(&self) -> &'static str {
        match self {
            Core::Point(_) => "point",
            Core::Segment(..) => "segment",
            Core::Plane(_) => "plane",
            Core::Rectangle(_) => "rectangle",
            Core::Disk(_) => "disk",
            Core::Polygon(_) => "polygon",
            Core::Box(_) => "box",
            Core::Hull(_) => "convexHull",
        }
    }
}

/// A primitive's core and radius; a tapered capsule uses its larger radius
/// (callers treat tapered capsules with different radii themselves).
#[inline(always)]
pub(crate) fn core_of(p: &Primitive) -> (Core<'_>, f64) {
    let seg = |s: &LineSegment| {
        if s.a == s.b {
            Core::Point(s.a)
        } else {
            Core::Segment(s.a, s.b)
        }
    };
    match p {
        Primitive::Point(q) => (Core::Point(*q), 0.0),
        Primitive::Segment(s) => (seg(s), 0.0),
        Primitive::Sphere(s) => (Core::Point(s.center), s.radius),
        Primitive::Capsule(c) => (seg(&c.segment), c.radius),
        Primitive::TaperedCapsule(c) => (seg(&c.segment), c.max_radius()),
        Primitive::Plane(q) => (Core::Plane(q), 0.0),
        Primitive::Rectangle(r) => (Core::Rectangle(r), 0.0),
        Primitive::Disk(d) => (Core::Disk(d), 0.0),
        Primitive::Polygon(q) => (Core::Polygon(q), 0.0),
        Primitive::Box(b) => (Core::Box(b), 0.0),
        Primitive::ConvexHull(h) => (Core::Hull(h), 0.0),
    }
}

/// Closest points between two cores, either order.
pub(crate) fn core_distance(a: Core<'_>, b: Core<'_>) -> Result<Closest, DistanceError> {
    if a.rank() > b.rank() {
        return core_distance(b, a).map(Closest::flipped);
    }
    Ok(match (a, b) {
        (Core::Point(p), Core::Point(q)) => Closest::between(p, q, true),
        (Core::Point(p), Core::Segment(s0, s1)) => point::point_segment(p, s0, s1),
        (Core::Point(p), Core::Plane(q)) => point::point_plane(p, q),
        (Core::Point(p), Core::Rectangle(r)) => cuboid::point_rectangle(p, r),
        (Core::Point(p), Core::Disk(d)) => disk::point_disk(p, d),
        (Core::Point(p), Core::Polygon(q)) => polygon::point_polygon(p, q),
        (Core::Point(p), Core::Box(b)) => cuboid::point_box(p, b),
        (Core::Point(p), Core::Hull(h)) => generic::point_hull(p, h),
        (Core::Segment(a0, a1), Core::Segment(b0, b1)) => {
            segment_segment::segment_segment(a0, a1, b0, b1)
        }
        (Core::Segment(..), Core::Plane(q)) => plane::plane_core(q, a)?.flipped(),
        (Core::Segment(s0, s1), Core::Rectangle(r)) => cuboid::segment_rectangle(s0, s1, r),
        (Core::Segment(s0, s1), Core::Disk(d)) => disk::segment_disk(s0, s1, d),
        (Core::Segment(s0, s1), Core::Polygon(q)) => polygon::segment_polygon(s0, s1, q),
        (Core::Segment(s0, s1), Core::Box(b)) => cuboid::segment_box(s0, s1, b),
        (Core::Plane(q), _) => plane::plane_core(q, b)?,
        (Core::Rectangle(_), Core::Rectangle(_) | Core::Polygon(_))
        | (Core::Polygon(_), Core::Polygon(_)) => polygon::flat_flat(a, b),
        (Core::Rectangle(_), Core::Disk(d)) => polygon::flat_disk(a, d),
        (Core::Disk(d), Core::Polygon(_)) => polygon::flat_disk(b, d).flipped(),
        _ => generic::generic(a, b)?,
    })
}

/// The signed distance between two primitives, with witness points; either
/// order, every pair of figures.
///
/// Closed forms serve every pair with a point, sphere, segment, capsule,
/// tapered capsule or plane, and rectangles, polygons and disks against
/// each other (but disk–disk); parry serves convex hulls, disk–disk, and
/// boxes against flat figures and boxes.
///
/// # Errors
/// [`DistanceError::UnsupportedPair`] if parry declines a pair it should
/// serve (not expected for valid figures).
///
/// # Example
/// ```
/// use glam::DVec3;
/// use skeleton_avoidance::distance::{distance, Primitive, Sphere};
/// let a = Primitive::Sphere(Sphere::new(DVec3::ZERO, 1.0).unwrap());
/// let b = Primitive::Point(DVec3::new(3.0, 0.0, 0.0));
/// let d = distance(&a, &b).unwrap();
/// assert!((d.distance - 2.0).abs() < 1e-12);
/// assert_eq!(d.point_a, DVec3::X);
/// ```
///
/// See also [`Scene::query`] for many pairs at once.
pub fn distance(a: &Primitive, b: &Primitive) -> Result<Distance, DistanceError> {
    if let Primitive::TaperedCapsule(t) = a
        && t.radius[0] != t.radius[1]
        && t.segment.a != t.segment.b
    {
        return tapered::tapered_vs(t, b);
    }
    if let Primitive::TaperedCapsule(t) = b
        && t.radius[0] != t.radius[1]
        && t.segment.a != t.segment.b
    {
        return tapered::tapered_vs(t, a).map(Distance::flipped);
    }
    let (ca, ra) = core_of(a);
    let (cb, rb) = core_of(b);
    let c = core_distance(ca, cb).map_err(|e| match e {
        DistanceError::UnsupportedPair { .. } => DistanceError::UnsupportedPair {
            a: a.kind(),
            b: b.kind(),
        },
        other => other,
    })?;
    Ok(c.inflate(ra, rb))
}

/// Validates two descriptions and measures them (the JS `distance(a, b)`).
///
/// # Errors
/// The first invalid field, with its path prefixed by `a` or `b`, or
/// [`DistanceError::UnsupportedPair`].
pub fn distance_between_specs(
    a: &PrimitiveSpec,
    b: &PrimitiveSpec,
) -> Result<Distance, DistanceError> {
    let pa = Primitive::from_spec(a).map_err(|e| e.within("a"))?;
    let pb = Primitive::from_spec(b).map_err(|e| e.within("b"))?;
    distance(&pa, &pb)
}

/// Any unit vector orthogonal to `v` (zero `v` gives `Z`).
pub(crate) fn orthogonal_unit(v: DVec3) -> DVec3 {
    let n = v.normalize_or_zero();
    if n == DVec3::ZERO {
        DVec3::Z
    } else {
        n.any_orthonormal_vector()
    }
}
