//! Segments and round solids: [`LineSegment`], [`Sphere`], [`Capsule`],
//! [`TaperedCapsule`].

use glam::DVec3;

use crate::error::{FieldError, finite3, positive};

/// A segment between two points (m). A zero-length segment is allowed and
/// behaves as a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineSegment {
    /// Start point.
    pub a: DVec3,
    /// End point.
    pub b: DVec3,
}

impl LineSegment {
    /// A segment from `a` to `b`.
    ///
    /// # Errors
    /// `a[k]` / `b[k]: not a finite number`.
    pub fn new(a: DVec3, b: DVec3) -> Result<Self, FieldError> {
        Ok(Self {
            a: finite3("a", a)?,
            b: finite3("b", b)?,
        })
    }

    /// The point at fraction `t` (0 at `a`, 1 at `b`).
    #[must_use]
    pub fn at(&self, t: f64) -> DVec3 {
        self.a + (self.b - self.a) * t
    }
}

/// A solid ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (m).
    pub center: DVec3,
    /// Radius (m, > 0).
    pub radius: f64,
}

impl Sphere {
    /// A ball of `radius` around `center`.
    ///
    /// # Errors
    /// `center[k]: not a finite number`, `radius: must be > 0`.
    pub fn new(center: DVec3, radius: f64) -> Result<Self, FieldError> {
        Ok(Self {
            center: finite3("center", center)?,
            radius: positive("radius", radius)?,
        })
    }
}

/// A solid capsule: the points within `radius` of the segment `a`–`b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// The core segment.
    pub segment: LineSegment,
    /// Radius (m, > 0).
    pub radius: f64,
}

impl Capsule {
    /// A capsule of `radius` around the segment `a`–`b`.
    ///
    /// # Errors
    /// Non-finite end points, `radius: must be > 0`.
    pub fn new(a: DVec3, b: DVec3, radius: f64) -> Result<Self, FieldError> {
        Ok(Self {
            segment: LineSegment::new(a, b)?,
            radius: positive("radius", radius)?,
        })
    }
}

/// A tapered capsule (the skeleton's volume): the convex hull of the ball of
/// radius `radius[0]` at `a` and the ball of radius `radius[1]` at `b`, which
/// is also the union of the balls centred on the segment whose radius varies
/// linearly from `radius[0]` to `radius[1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaperedCapsule {
    /// The core segment.
    pub segment: LineSegment,
    /// Radius at `a` and at `b` (m, > 0).
    pub radius: [f64; 2],
}

impl TaperedCapsule {
    /// A tapered capsule from `a` (radius `radius[0]`) to `b` (`radius[1]`).
    ///
    /// # Errors
    /// Non-finite end points, `radius[k]: must be > 0`.
    pub fn new(a: DVec3, b: DVec3, radius: [f64; 2]) -> Result<Self, FieldError> {
        Ok(Self {
            segment: LineSegment::new(a, b)?,
            radius: [
                positive("radius[0]", radius[0])?,
                positive("radius[1]", radius[1])?,
            ],
        })
    }

    /// Radius of the ball centred at fraction `t` along the segment.
    #[must_use]
    pub fn radius_at(&self, t: f64) -> f64 {
        self.radius[0] + (self.radius[1] - self.radius[0]) * t
    }

    /// The larger of the two end radii.
    #[must_use]
    pub fn max_radius(&self) -> f64 {
        self.radius[0].max(self.radius[1])
    }
}
