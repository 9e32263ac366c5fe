//! Solids with flat faces: the [`OrientedBox`] and the [`ConvexHull`].

use glam::{DMat3, DQuat, DVec3};
use parry3d_f64::shape::ConvexPolyhedron;

use crate::error::{FieldError, finite, finite3, positive};

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
    pub(super) points: Vec<DVec3>,
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
