//! Environment primitives with validated constructors, and their serde
//! description ([`PrimitiveSpec`]) as it crosses the JavaScript boundary.
//!
//! Every constructor checks its input (finite coordinates, positive radii,
//! non-zero normals, non-degenerate figures) and reports a [`FieldError`]
//! whose path uses the JavaScript field names (`radius`, `halfExtents[1]`), so
//! the wasm layer only has to put `a.` or `b.` in front.

//! One file per group of figures: [`round`] (segment, sphere, capsules),
//! [`flat`] (plane, rectangle, disk), [`polygon`], [`solid`] (box, convex
//! hull); [`spec`] holds [`PrimitiveSpec`] and its deserialisation. Every
//! type is re-exported here and from [`crate::distance`].

use glam::DVec3;

use crate::error::{FieldError, finite3};

pub mod flat;
pub mod polygon;
pub mod round;
pub mod solid;
pub mod spec;

pub use flat::{Disk, Plane, Rectangle};
pub use polygon::Polygon;
pub use round::{Capsule, LineSegment, Sphere, TaperedCapsule};
pub use solid::{ConvexHull, OrientedBox};
pub use spec::{
    BoxSpec, CapsuleSpec, ConvexHullSpec, DiskSpec, PlaneSpec, PointSpec, PolygonSpec,
    PrimitiveSpec, RectangleSpec, SegmentSpec, SphereSpec, TaperedCapsuleSpec,
};

/// Relative tolerance used to decide that a figure is degenerate (parallel
/// axes, non-planar polygon, …), scaled by the figure's size.
pub(crate) const REL_TOL: f64 = 1e-9;

/// A unit vector from `v`.
fn unit(field: &str, v: DVec3) -> Result<DVec3, FieldError> {
    let v = finite3(field, v)?;
    let len = v.length();
    if len > 0.0 && len.is_finite() {
        Ok(v / len)
    } else {
        Err(FieldError::new(field, "must not be zero"))
    }
}

/// A validated environment primitive (or skeleton volume).
#[derive(Clone, Debug, PartialEq)]
pub enum Primitive {
    /// A point.
    Point(DVec3),
    /// A segment.
    Segment(LineSegment),
    /// A solid ball.
    Sphere(Sphere),
    /// A solid capsule.
    Capsule(Capsule),
    /// A solid tapered capsule.
    TaperedCapsule(TaperedCapsule),
    /// An infinite plane (a surface, not a half-space).
    Plane(Plane),
    /// A flat rectangle.
    Rectangle(Rectangle),
    /// A flat disk.
    Disk(Disk),
    /// A flat simple polygon.
    Polygon(Polygon),
    /// A solid oriented box.
    Box(OrientedBox),
    /// A solid convex hull.
    ConvexHull(ConvexHull),
}

impl Primitive {
    /// The primitive's `type` name as JavaScript spells it.
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Point(_) => "point",
            Self::Segment(_) => "segment",
            Self::Sphere(_) => "sphere",
            Self::Capsule(_) => "capsule",
            Self::TaperedCapsule(_) => "taperedCapsule",
            Self::Plane(_) => "plane",
            Self::Rectangle(_) => "rectangle",
            Self::Disk(_) => "disk",
            Self::Polygon(_) => "polygon",
            Self::Box(_) => "box",
            Self::ConvexHull(_) => "convexHull",
        }
    }

    /// Whether the primitive is a solid (has an interior): sphere, capsule,
    /// tapered capsule, box, convex hull.
    #[must_use]
    pub fn is_solid(&self) -> bool {
        matches!(
            self,
            Self::Sphere(_)
                | Self::Capsule(_)
                | Self::TaperedCapsule(_)
                | Self::Box(_)
                | Self::ConvexHull(_)
        )
    }

    /// Validates a description into a primitive.
    ///
    /// # Errors
    /// The first invalid field, with its path inside the description.
    ///
    /// # Example
    /// ```
    /// use skeleton_avoidance::distance::{Primitive, PrimitiveSpec, SphereSpec};
    /// let spec = PrimitiveSpec::Sphere(SphereSpec { center: [0.0; 3], radius: 0.0 });
    /// let err = Primitive::from_spec(&spec).unwrap_err();
    /// assert_eq!(err.to_string(), "radius: must be > 0");
    /// ```
    pub fn from_spec(spec: &PrimitiveSpec) -> Result<Self, FieldError> {
        super::domain::check(spec)?;
        let v = |a: [f64; 3]| DVec3::from_array(a);
        Ok(match spec {
            PrimitiveSpec::Point(s) => Self::Point(finite3("p", v(s.p))?),
            PrimitiveSpec::Segment(s) => Self::Segment(LineSegment::new(v(s.a), v(s.b))?),
            PrimitiveSpec::Sphere(s) => Self::Sphere(Sphere::new(v(s.center), s.radius)?),
            PrimitiveSpec::Capsule(s) => Self::Capsule(Capsule::new(v(s.a), v(s.b), s.radius)?),
            PrimitiveSpec::TaperedCapsule(s) => {
                Self::TaperedCapsule(TaperedCapsule::new(v(s.a), v(s.b), s.radius)?)
            }
            PrimitiveSpec::Plane(s) => Self::Plane(Plane::new(v(s.normal), s.offset)?),
            PrimitiveSpec::Rectangle(s) => Self::Rectangle(Rectangle::new(
                v(s.center),
                [v(s.axes[0]), v(s.axes[1])],
                s.half_extents,
            )?),
            PrimitiveSpec::Disk(s) => Self::Disk(Disk::new(v(s.center), v(s.normal), s.radius)?),
            PrimitiveSpec::Polygon(s) => {
                Self::Polygon(Polygon::new(s.vertices.iter().map(|p| v(*p)).collect())?)
            }
            PrimitiveSpec::Box(s) => Self::Box(OrientedBox::new(
                v(s.center),
                v(s.half_extents),
                s.rotation.unwrap_or([0.0, 0.0, 0.0, 1.0]),
            )?),
            PrimitiveSpec::ConvexHull(s) => {
                Self::ConvexHull(ConvexHull::new(s.points.iter().map(|p| v(*p)).collect())?)
            }
        })
    }

    /// The same primitive translated by `t`.
    #[must_use]
    pub fn translated(&self, t: DVec3) -> Self {
        let seg = |s: &LineSegment| LineSegment {
            a: s.a + t,
            b: s.b + t,
        };
        match self {
            Self::Point(p) => Self::Point(*p + t),
            Self::Segment(s) => Self::Segment(seg(s)),
            Self::Sphere(s) => Self::Sphere(Sphere {
                center: s.center + t,
                ..*s
            }),
            Self::Capsule(c) => Self::Capsule(Capsule {
                segment: seg(&c.segment),
                ..*c
            }),
            Self::TaperedCapsule(c) => Self::TaperedCapsule(TaperedCapsule {
                segment: seg(&c.segment),
                ..*c
            }),
            Self::Plane(p) => Self::Plane(Plane {
                offset: p.offset - p.normal.dot(t),
                ..*p
            }),
            Self::Rectangle(r) => Self::Rectangle(Rectangle {
                center: r.center + t,
                ..*r
            }),
            Self::Disk(d) => Self::Disk(Disk {
                center: d.center + t,
                ..*d
            }),
            Self::Polygon(p) => {
                let mut q = p.clone();
                q.vertices.iter_mut().for_each(|v| *v += t);
                q.origin += t;
                Self::Polygon(q)
            }
            Self::Box(b) => Self::Box(OrientedBox {
                center: b.center + t,
                ..*b
            }),
            Self::ConvexHull(h) => {
                // Translating the hull's own vertices cannot make it degenerate.
                let pts: Vec<DVec3> = h.points.iter().map(|p| *p + t).collect();
                match ConvexHull::new(pts) {
                    Ok(moved) => Self::ConvexHull(moved),
                    Err(_) => self.clone(),
                }
            }
        }
    }
}
