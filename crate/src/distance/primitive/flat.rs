//! Flat figures with a closed form: the infinite [`Plane`], the
//! [`Rectangle`] and the [`Disk`].

use glam::{DMat3, DVec3};

use super::unit;
use crate::error::{FieldError, finite, finite3, positive};

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
