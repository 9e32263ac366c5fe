//! Environment primitives with validated constructors, and their serde
//! description ([`PrimitiveSpec`]) as it crosses the JavaScript boundary.
//!
//! Every constructor checks its input (finite coordinates, positive radii,
//! non-zero normals, non-degenerate figures) and reports a [`FieldError`]
//! whose path uses the JavaScript field names (`radius`, `halfExtents[1]`), so
//! the wasm layer only has to put `a.` or `b.` in front.

use glam::{DMat3, DQuat, DVec2, DVec3};
use parry3d_f64::shape::ConvexPolyhedron;
use serde::{Deserialize, Serialize};

use crate::error::{FieldError, finite, finite3, positive};

/// Relative tolerance used to decide that a figure is degenerate (parallel
/// axes, non-planar polygon, …), scaled by the figure's size.
pub(crate) const REL_TOL: f64 = 1e-9;

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

/// An infinite plane `n·x + offset = 0` with a unit normal `n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal.
    pub normal: DVec3,
    /// Offset for the unit normal (m).
    pub offset: f64,
}

impl Plane {
    /// The plane `normal·x + offset = 0`; `normal` need not be unit (the
    /// offset is scaled with it, so `[0,0,2]·x − 2 = 0` is `z = 1`).
    ///
    /// # Errors
    /// Non-finite values, `normal: must not be zero`.
    pub fn new(normal: DVec3, offset: f64) -> Result<Self, FieldError> {
        let n = finite3("normal", normal)?;
        let o = finite("offset", offset)?;
        let len = n.length();
        if !(len > 0.0 && len.is_finite()) {
            return Err(FieldError::new("normal", "must not be zero"));
        }
        Ok(Self {
            normal: n / len,
            offset: o / len,
        })
    }

    /// Signed distance of `p` from the plane (positive on the normal's side).
    #[must_use]
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) + self.offset
    }
}

/// A flat rectangle: `center + x u + y v` with `|x| ≤ hu`, `|y| ≤ hv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    /// Centre (m).
    pub center: DVec3,
    /// Orthonormal in-plane axes `u`, `v`.
    pub axes: [DVec3; 2],
    /// Unit normal `u × v`.
    pub normal: DVec3,
    /// Half extents along `u` and `v` (m, > 0).
    pub half_extents: [f64; 2],
}

impl Rectangle {
    /// A rectangle; the two axes must be non-zero and orthogonal (they are
    /// normalised).
    ///
    /// # Errors
    /// Non-finite values, `axes[k]: must not be zero`,
    /// `axes: must be orthogonal`, `halfExtents[k]: must be > 0`.
    pub fn new(
        center: DVec3,
        axes: [DVec3; 2],
        half_extents: [f64; 2],
    ) -> Result<Self, FieldError> {
        let center = finite3("center", center)?;
        let u = unit("axes[0]", axes[0])?;
        let v = unit("axes[1]", axes[1])?;
        let hu = positive("halfExtents[0]", half_extents[0])?;
        let hv = positive("halfExtents[1]", half_extents[1])?;
        if u.dot(v).abs() > 1e-6 {
            return Err(FieldError::new("axes", "must be orthogonal"));
        }
        let normal = u.cross(v).normalize();
        let v = normal.cross(u);
        Ok(Self {
            center,
            axes: [u, v],
            normal,
            half_extents: [hu, hv],
        })
    }

    /// The rotation whose columns are `u`, `v`, `normal`.
    #[must_use]
    pub fn basis(&self) -> DMat3 {
        DMat3::from_cols(self.axes[0], self.axes[1], self.normal)
    }

    /// The four corners, counter-clockwise around the normal.
    #[must_use]
    pub fn corners(&self) -> [DVec3; 4] {
        let u = self.axes[0] * self.half_extents[0];
        let v = self.axes[1] * self.half_extents[1];
        let c = self.center;
        [c - u - v, c + u - v, c + u + v, c - u + v]
    }
}

/// A flat disk: the points of the plane through `center` with unit `normal`
/// within `radius` of the centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    /// Centre (m).
    pub center: DVec3,
    /// Unit normal.
    pub normal: DVec3,
    /// Radius (m, > 0).
    pub radius: f64,
}

impl Disk {
    /// A disk; `normal` is normalised.
    ///
    /// # Errors
    /// Non-finite values, `normal: must not be zero`, `radius: must be > 0`.
    pub fn new(center: DVec3, normal: DVec3, radius: f64) -> Result<Self, FieldError> {
        Ok(Self {
            center: finite3("center", center)?,
            normal: unit("normal", normal)?,
            radius: positive("radius", radius)?,
        })
    }
}

/// A planar simple polygon (convex or not), given by its vertices in order.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    vertices: Vec<DVec3>,
    origin: DVec3,
    u: DVec3,
    v: DVec3,
    normal: DVec3,
    local: Vec<DVec2>,
    convex: bool,
}

impl Polygon {
    /// A polygon from at least three vertices that lie in one plane and
    /// bound a simple (non-self-intersecting) region of non-zero area.
    ///
    /// # Errors
    /// `vertices: polygon needs at least 3 vertices`, `vertices[k][j]: not a
    /// finite number`, `vertices[k]: repeats the previous vertex`,
    /// `vertices: polygon has zero area`, `vertices: polygon is not planar`,
    /// `vertices: polygon is self-intersecting`.
    ///
    /// # Example
    /// ```
    /// use glam::DVec3;
    /// use skeleton_avoidance::distance::Polygon;
    /// let v = |x, y, z| DVec3::new(x, y, z);
    /// let bent = Polygon::new(vec![v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 1.)]);
    /// assert_eq!(bent.unwrap_err().to_string(), "vertices: polygon is not planar");
    /// ```
    pub fn new(vertices: Vec<DVec3>) -> Result<Self, FieldError> {
        let n = vertices.len();
        if n < 3 {
            return Err(FieldError::new(
                "vertices",
                "polygon needs at least 3 vertices",
            ));
        }
        for (k, p) in vertices.iter().enumerate() {
            finite3(&format!("vertices[{k}]"), *p)?;
        }
        let mut scale: f64 = 0.0;
        for p in &vertices {
            scale = scale.max((*p - vertices[0]).length());
        }
        for k in 0..n {
            let prev = vertices[(k + n - 1) % n];
            if (vertices[k] - prev).length() <= REL_TOL * scale {
                return Err(FieldError::new(
                    format!("vertices[{k}]"),
                    "repeats the previous vertex",
                ));
            }
        }
        // Newell's normal: twice the vector area of the polygon.
        let mut area = DVec3::ZERO;
        for k in 0..n {
            area += vertices[k].cross(vertices[(k + 1) % n]);
        }
        let area_len = area.length();
        if area_len.is_nan() || area_len <= REL_TOL * scale * scale {
            return Err(FieldError::new("vertices", "polygon has zero area"));
        }
        let normal = area / area_len;
        let origin = vertices[0];
        for p in &vertices {
            if normal.dot(*p - origin).abs() > REL_TOL * scale.max(1.0) {
                return Err(FieldError::new("vertices", "polygon is not planar"));
            }
        }
        let u = (vertices[1] - origin).normalize();
        let v = normal.cross(u);
        let local: Vec<DVec2> = vertices
            .iter()
            .map(|p| DVec2::new(u.dot(*p - origin), v.dot(*p - origin)))
            .collect();
        for i in 0..n {
            for j in (i + 1)..n {
                if j == i + 1 || (i == 0 && j == n - 1) {
                    continue;
                }
                if segments_touch_2d(local[i], local[(i + 1) % n], local[j], local[(j + 1) % n]) {
                    return Err(FieldError::new("vertices", "polygon is self-intersecting"));
                }
            }
        }
        let convex = (0..n).all(|k| {
            let a = local[k];
            let b = local[(k + 1) % n];
            let c = local[(k + 2) % n];
            (b - a).perp_dot(c - b) >= -REL_TOL * scale * scale
        });
        Ok(Self {
            vertices,
            origin,
            u,
            v,
            normal,
            local,
            convex,
        })
    }

    /// The vertices as given.
    #[must_use]
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Unit normal (counter-clockwise vertex order around it).
    #[must_use]
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// Whether the polygon is convex.
    #[must_use]
    pub fn is_convex(&self) -> bool {
        self.convex
    }

    /// In-plane coordinates of `p` (projected along the normal) and its
    /// signed height above the plane.
    pub(crate) fn to_local(&self, p: DVec3) -> (DVec2, f64) {
        let d = p - self.origin;
        (DVec2::new(self.u.dot(d), self.v.dot(d)), self.normal.dot(d))
    }

    /// The point of the plane with in-plane coordinates `q`.
    pub(crate) fn point_at(&self, q: DVec2) -> DVec3 {
        self.origin + self.u * q.x + self.v * q.y
    }

    /// Vertices in in-plane coordinates.
    pub(crate) fn local(&self) -> &[DVec2] {
        &self.local
    }

    /// A triangulation by ear clipping: index triples into the vertices,
    /// counter-clockwise around the normal.
    #[must_use]
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        let pts = &self.local;
        let mut idx: Vec<usize> = (0..pts.len()).collect();
        let mut out = Vec::with_capacity(pts.len().saturating_sub(2));
        // A vertex on (or within rounding of) a candidate ear's boundary
        // disqualifies it.
        let scale = pts
            .iter()
            .map(|p| (*p - pts[0]).length())
            .fold(0.0, f64::max);
        let eps = 1e-12 * scale * scale;
        let inside = |p: DVec2, a: DVec2, b: DVec2, c: DVec2| {
            (b - a).perp_dot(p - a) >= -eps
                && (c - b).perp_dot(p - b) >= -eps
                && (a - c).perp_dot(p - c) >= -eps
        };
        while idx.len() > 3 {
            let m = idx.len();
            let ear = (0..m).find(|&k| {
                let (i, j, l) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
                let (a, b, c) = (pts[i], pts[j], pts[l]);
                (b - a).perp_dot(c - b) > 0.0
                    && idx
                        .iter()
                        .all(|&o| o == i || o == j || o == l || !inside(pts[o], a, b, c))
            });
            // A simple polygon always has an ear; rounding may hide it, then
            // the most convex corner is clipped.
            let k = ear.unwrap_or_else(|| {
                (0..m)
                    .max_by(|&x, &y| {
                        let turn = |k: usize| {
                            let (a, b, c) = (
                                pts[idx[(k + m - 1) % m]],
                                pts[idx[k]],
                                pts[idx[(k + 1) % m]],
                            );
                            (b - a).perp_dot(c - b)
                        };
                        turn(x).total_cmp(&turn(y))
                    })
                    .unwrap_or(0)
            });
            out.push([idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]]);
            idx.remove(k);
        }
        if idx.len() == 3 {
            out.push([idx[0], idx[1], idx[2]]);
        }
        out
    }

    /// The sides as segments, `vertices[k]`–`vertices[k + 1]`.
    pub(crate) fn sides(&self) -> impl Iterator<Item = (DVec3, DVec3)> + '_ {
        let v = &self.vertices;
        (0..v.len()).map(move |k| (v[k], v[(k + 1) % v.len()]))
    }

    /// Whether the in-plane point `q` is inside (even–odd rule; points on the
    /// boundary may answer either way).
    pub(crate) fn contains_local(&self, q: DVec2) -> bool {
        let pts = &self.local;
        let n = pts.len();
        let mut inside = false;
        let mut j = n - 1;
        for i in 0..n {
            let (pi, pj) = (pts[i], pts[j]);
            if (pi.y > q.y) != (pj.y > q.y) {
                let x = pj.x + (q.y - pj.y) * (pi.x - pj.x) / (pi.y - pj.y);
                if q.x < x {
                    inside = !inside;
                }
            }
            j = i;
        }
        inside
    }
}

/// Whether two closed 2-D segments share a point.
fn segments_touch_2d(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let orient = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let on = |p: DVec2, q: DVec2, r: DVec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    (o1 == 0.0 && on(a, b, c))
        || (o2 == 0.0 && on(a, b, d))
        || (o3 == 0.0 && on(c, d, a))
        || (o4 == 0.0 && on(c, d, b))
}

/// A solid oriented box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientedBox {
    /// Centre (m).
    pub center: DVec3,
    /// Half extents along the box's own axes (m, > 0).
    pub half_extents: DVec3,
    /// Orientation (unit quaternion).
    pub rotation: DQuat,
    /// The box's axes in the world frame (columns of the rotation).
    pub axes: [DVec3; 3],
}

impl OrientedBox {
    /// A box; `rotation` is `[x, y, z, w]` and is normalised.
    ///
    /// # Errors
    /// Non-finite values, `halfExtents[k]: must be > 0`,
    /// `rotation: must not be zero`.
    pub fn new(center: DVec3, half_extents: DVec3, rotation: [f64; 4]) -> Result<Self, FieldError> {
        let center = finite3("center", center)?;
        let h = DVec3::new(
            positive("halfExtents[0]", half_extents.x)?,
            positive("halfExtents[1]", half_extents.y)?,
            positive("halfExtents[2]", half_extents.z)?,
        );
        for (k, c) in rotation.iter().enumerate() {
            finite(&format!("rotation[{k}]"), *c)?;
        }
        let q = DQuat::from_array(rotation);
        let len = q.length();
        if !(len > 1e-12 && len.is_finite()) {
            return Err(FieldError::new("rotation", "must not be zero"));
        }
        let q = q / len;
        let m = DMat3::from_quat(q);
        Ok(Self {
            center,
            half_extents: h,
            rotation: q,
            axes: [m.x_axis, m.y_axis, m.z_axis],
        })
    }

    /// Coordinates of `p` in the box frame.
    #[must_use]
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        let d = p - self.center;
        DVec3::new(
            self.axes[0].dot(d),
            self.axes[1].dot(d),
            self.axes[2].dot(d),
        )
    }

    /// The world point with box-frame coordinates `q`.
    #[must_use]
    pub fn from_local(&self, q: DVec3) -> DVec3 {
        self.center + self.axes[0] * q.x + self.axes[1] * q.y + self.axes[2] * q.z
    }
}

/// The convex hull of a set of points, computed by parry.
#[derive(Clone, Debug)]
pub struct ConvexHull {
    points: Vec<DVec3>,
    shape: ConvexPolyhedron,
}

impl PartialEq for ConvexHull {
    fn eq(&self, other: &Self) -> bool {
        self.points == other.points
    }
}

impl ConvexHull {
    /// The convex hull of `points` (at least four, not all in one plane).
    ///
    /// # Errors
    /// `points: needs at least 4 points`, `points[k][j]: not a finite number`,
    /// `points: all points lie in one plane`, `points: hull could not be built`.
    pub fn new(points: Vec<DVec3>) -> Result<Self, FieldError> {
        if points.len() < 4 {
            return Err(FieldError::new("points", "needs at least 4 points"));
        }
        for (k, p) in points.iter().enumerate() {
            finite3(&format!("points[{k}]"), *p)?;
        }
        if !has_volume(&points) {
            return Err(FieldError::new("points", "all points lie in one plane"));
        }
        let shape = ConvexPolyhedron::from_convex_hull(&points)
            .ok_or_else(|| FieldError::new("points", "hull could not be built"))?;
        let points = shape.points().to_vec();
        Ok(Self { points, shape })
    }

    /// The hull's vertices.
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The parry shape (world coordinates, identity pose).
    #[must_use]
    pub fn shape(&self) -> &ConvexPolyhedron {
        &self.shape
    }
}

/// Whether the points span a volume (are not all within a plane, relative to
/// their spread).
fn has_volume(points: &[DVec3]) -> bool {
    let p0 = points[0];
    let Some(p1) = points.iter().copied().max_by(|a, b| {
        (*a - p0)
            .length_squared()
            .total_cmp(&(*b - p0).length_squared())
    }) else {
        return false;
    };
    let e1 = p1 - p0;
    let scale = e1.length();
    if scale.is_nan() || scale <= 0.0 {
        return false;
    }
    let Some(p2) = points.iter().copied().max_by(|a, b| {
        e1.cross(*a - p0)
            .length_squared()
            .total_cmp(&e1.cross(*b - p0).length_squared())
    }) else {
        return false;
    };
    let n = e1.cross(p2 - p0);
    let nl = n.length();
    if nl.is_nan() || nl <= 1e-9 * scale * scale {
        return false;
    }
    let n = n / nl;
    points.iter().any(|p| n.dot(*p - p0).abs() > 1e-9 * scale)
}

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

/// The description of a primitive as it crosses the JavaScript boundary
/// (`{ type: "sphere", center: [x, y, z], radius }`, …). Validate it with
/// [`Primitive::from_spec`].
///
/// It serialises as an internally tagged enum. It deserialises through a flat
/// struct holding every key any figure uses, then checks that the keys fit
/// the `type`: unlike serde's buffered tagged enums, this keeps the path of a
/// bad value (`shape.center[1]: not a finite number`) and refuses unknown keys.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "camelCase", try_from = "PrimitiveFields")]
pub enum PrimitiveSpec {
    /// `{ type: "point", p }`.
    Point(PointSpec),
    /// `{ type: "segment", a, b }`.
    Segment(SegmentSpec),
    /// `{ type: "sphere", center, radius }`.
    Sphere(SphereSpec),
    /// `{ type: "capsule", a, b, radius }`.
    Capsule(CapsuleSpec),
    /// `{ type: "taperedCapsule", a, b, radius: [r0, r1] }`.
    TaperedCapsule(TaperedCapsuleSpec),
    /// `{ type: "plane", normal, offset }`: `normal·x + offset = 0`.
    Plane(PlaneSpec),
    /// `{ type: "rectangle", center, axes: [u, v], halfExtents: [hu, hv] }`.
    Rectangle(RectangleSpec),
    /// `{ type: "disk", center, normal, radius }`.
    Disk(DiskSpec),
    /// `{ type: "polygon", vertices }`.
    Polygon(PolygonSpec),
    /// `{ type: "box", center, halfExtents, rotation? }` (`[x, y, z, w]`,
    /// identity when absent).
    Box(BoxSpec),
    /// `{ type: "convexHull", points }`.
    ConvexHull(ConvexHullSpec),
}

/// Fields of `{ type: "point" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpec {
    /// The point.
    pub p: [f64; 3],
}

/// Fields of `{ type: "segment" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// Start.
    pub a: [f64; 3],
    /// End.
    pub b: [f64; 3],
}

/// Fields of `{ type: "sphere" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Radius.
    pub radius: f64,
}

/// Fields of `{ type: "capsule" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CapsuleSpec {
    /// Start.
    pub a: [f64; 3],
    /// End.
    pub b: [f64; 3],
    /// Radius.
    pub radius: f64,
}

/// Fields of `{ type: "taperedCapsule" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaperedCapsuleSpec {
    /// Start.
    pub a: [f64; 3],
    /// End.
    pub b: [f64; 3],
    /// Radius at `a` and at `b`.
    pub radius: [f64; 2],
}

/// Fields of `{ type: "plane" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneSpec {
    /// Normal (any non-zero length).
    pub normal: [f64; 3],
    /// Offset.
    pub offset: f64,
}

/// Fields of `{ type: "rectangle" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct RectangleSpec {
    /// Centre.
    pub center: [f64; 3],
    /// In-plane axes.
    pub axes: [[f64; 3]; 2],
    /// Half extents along the axes.
    pub half_extents: [f64; 2],
}

/// Fields of `{ type: "disk" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Normal.
    pub normal: [f64; 3],
    /// Radius.
    pub radius: f64,
}

/// Fields of `{ type: "polygon" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolygonSpec {
    /// Vertices in order.
    pub vertices: Vec<[f64; 3]>,
}

/// Fields of `{ type: "box" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct BoxSpec {
    /// Centre.
    pub center: [f64; 3],
    /// Half extents.
    pub half_extents: [f64; 3],
    /// Orientation quaternion `[x, y, z, w]` (identity when absent).
    #[serde(default)]
    pub rotation: Option<[f64; 4]>,
}

/// Fields of `{ type: "convexHull" }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConvexHullSpec {
    /// The points whose hull is taken.
    pub points: Vec<[f64; 3]>,
}

/// A radius: one number, or `[r0, r1]` for a tapered capsule.
#[derive(Clone, Copy, Debug, PartialEq)]
enum RadiusField {
    One(f64),
    Two([f64; 2]),
}

impl<'de> Deserialize<'de> for RadiusField {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RadiusField;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number or [r0, r1]")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<RadiusField, E> {
                Ok(RadiusField::One(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<RadiusField, E> {
                Ok(RadiusField::One(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<RadiusField, E> {
                Ok(RadiusField::One(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<RadiusField, A::Error> {
                let r0: f64 = seq
                    .next_element()?
                    .ok_or_else(|| serde::de::Error::invalid_length(0, &self))?;
                let r1: f64 = seq
                    .next_element()?
                    .ok_or_else(|| serde::de::Error::invalid_length(1, &self))?;
                if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    return Err(serde::de::Error::invalid_length(3, &self));
                }
                Ok(RadiusField::Two([r0, r1]))
            }
        }
        d.deserialize_any(V)
    }
}

/// A `type` value, checked while deserialising so that the error names the
/// `type` field.
struct PrimitiveKind(String);

impl<'de> Deserialize<'de> for PrimitiveKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let kind = String::deserialize(d)?;
        if PrimitiveSpec::KINDS.contains(&kind.as_str()) {
            Ok(Self(kind))
        } else {
            Err(serde::de::Error::custom(format!(
                "unknown primitive \"{kind}\" (known: {})",
                PrimitiveSpec::KINDS.join(", ")
            )))
        }
    }
}

/// Every key any primitive uses; see [`PrimitiveSpec`].
#[derive(Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct PrimitiveFields {
    #[serde(rename = "type")]
    kind: PrimitiveKind,
    p: Option<[f64; 3]>,
    a: Option<[f64; 3]>,
    b: Option<[f64; 3]>,
    center: Option<[f64; 3]>,
    radius: Option<RadiusField>,
    normal: Option<[f64; 3]>,
    offset: Option<f64>,
    axes: Option<[[f64; 3]; 2]>,
    half_extents: Option<Vec<f64>>,
    vertices: Option<Vec<[f64; 3]>>,
    rotation: Option<[f64; 4]>,
    points: Option<Vec<[f64; 3]>>,
}

impl TryFrom<PrimitiveFields> for PrimitiveSpec {
    type Error = String;

    fn try_from(f: PrimitiveFields) -> Result<Self, String> {
        let kind = f.kind.0.as_str();
        let present = [
            ("p", f.p.is_some()),
            ("a", f.a.is_some()),
            ("b", f.b.is_some()),
            ("center", f.center.is_some()),
            ("radius", f.radius.is_some()),
            ("normal", f.normal.is_some()),
            ("offset", f.offset.is_some()),
            ("axes", f.axes.is_some()),
            ("halfExtents", f.half_extents.is_some()),
            ("vertices", f.vertices.is_some()),
            ("rotation", f.rotation.is_some()),
            ("points", f.points.is_some()),
        ];
        let (required, optional): (&[&str], &[&str]) = match kind {
            "point" => (&["p"], &[]),
            "segment" => (&["a", "b"], &[]),
            "sphere" => (&["center", "radius"], &[]),
            "capsule" | "taperedCapsule" => (&["a", "b", "radius"], &[]),
            "plane" => (&["normal", "offset"], &[]),
            "rectangle" => (&["center", "axes", "halfExtents"], &[]),
            "disk" => (&["center", "normal", "radius"], &[]),
            "polygon" => (&["vertices"], &[]),
            "box" => (&["center", "halfExtents"], &["rotation"]),
            _ => (&["points"], &[]),
        };
        let fields = || {
            required
                .iter()
                .chain(optional)
                .copied()
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (name, is) in present {
            if is && !required.contains(&name) && !optional.contains(&name) {
                return Err(format!(
                    "`{name}` is not a field of a {kind} (its fields: {})",
                    fields()
                ));
            }
            if !is && required.contains(&name) {
                return Err(format!("missing `{name}` (a {kind} needs {})", fields()));
            }
        }
        let missing = || String::from("internal: a required field went missing");
        let one = |r: Option<RadiusField>| match r {
            Some(RadiusField::One(x)) => Ok(x),
            _ => Err(format!("`radius` of a {kind} is one number")),
        };
        let half = |h: Option<Vec<f64>>, n: usize| -> Result<Vec<f64>, String> {
            let h = h.ok_or_else(missing)?;
            if h.len() == n {
                Ok(h)
            } else {
                Err(format!(
                    "`halfExtents` of a {kind} has {n} numbers, got {}",
                    h.len()
                ))
            }
        };
        Ok(match kind {
            "point" => Self::Point(PointSpec {
                p: f.p.ok_or_else(missing)?,
            }),
            "segment" => Self::Segment(SegmentSpec {
                a: f.a.ok_or_else(missing)?,
                b: f.b.ok_or_else(missing)?,
            }),
            "sphere" => Self::Sphere(SphereSpec {
                center: f.center.ok_or_else(missing)?,
                radius: one(f.radius)?,
            }),
            "capsule" => Self::Capsule(CapsuleSpec {
                a: f.a.ok_or_else(missing)?,
                b: f.b.ok_or_else(missing)?,
                radius: one(f.radius)?,
            }),
            "taperedCapsule" => Self::TaperedCapsule(TaperedCapsuleSpec {
                a: f.a.ok_or_else(missing)?,
                b: f.b.ok_or_else(missing)?,
                radius: match f.radius {
                    Some(RadiusField::Two(r)) => r,
                    _ => return Err("`radius` of a taperedCapsule is [r0, r1]".to_owned()),
                },
            }),
            "plane" => Self::Plane(PlaneSpec {
                normal: f.normal.ok_or_else(missing)?,
                offset: f.offset.ok_or_else(missing)?,
            }),
            "rectangle" => {
                let h = half(f.half_extents, 2)?;
                Self::Rectangle(RectangleSpec {
                    center: f.center.ok_or_else(missing)?,
                    axes: f.axes.ok_or_else(missing)?,
                    half_extents: [h[0], h[1]],
                })
            }
            "disk" => Self::Disk(DiskSpec {
                center: f.center.ok_or_else(missing)?,
                normal: f.normal.ok_or_else(missing)?,
                radius: one(f.radius)?,
            }),
            "polygon" => Self::Polygon(PolygonSpec {
                vertices: f.vertices.ok_or_else(missing)?,
            }),
            "box" => {
                let h = half(f.half_extents, 3)?;
                Self::Box(BoxSpec {
                    center: f.center.ok_or_else(missing)?,
                    half_extents: [h[0], h[1], h[2]],
                    rotation: f.rotation,
                })
            }
            _ => Self::ConvexHull(ConvexHullSpec {
                points: f.points.ok_or_else(missing)?,
            }),
        })
    }
}

impl PrimitiveSpec {
    /// Every accepted `type` value.
    pub const KINDS: [&'static str; 11] = [
        "point",
        "segment",
        "sphere",
        "capsule",
        "taperedCapsule",
        "plane",
        "rectangle",
        "disk",
        "polygon",
        "box",
        "convexHull",
    ];

    /// Checks a `type` value before the rest is read, so an unknown figure is
    /// reported as such.
    ///
    /// # Errors
    /// `type: unknown primitive "cone"`.
    pub fn check_kind(kind: &str) -> Result<(), FieldError> {
        if Self::KINDS.contains(&kind) {
            Ok(())
        } else {
            Err(FieldError::new(
                "type",
                format!("unknown primitive \"{kind}\""),
            ))
        }
    }
}
