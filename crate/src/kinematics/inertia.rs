//! The inertial parameters of one link: mass, centre of mass and inertia
//! tensor about the centre of mass, in a frame carried by the link; their
//! validation, change of frame and lumping.

use glam::{DAffine3, DMat3, DVec3};
use serde::{Deserialize, Serialize};

use super::MAX_MAGNITUDE;
use crate::error::{FieldError, bounded, finite, non_negative};
use crate::linalg::{Mat, symmetric_eigen};

/// Relative slack (of the trace) on the positive semi-definiteness and the
/// triangle inequality of the principal moments: published tensors are
/// rounded to a few digits, and a thin rod sits exactly on the bound.
pub const INERTIA_TOLERANCE: f64 = 1e-9;

/// Largest asymmetry `|I_ij − I_ji|` accepted, relative to the largest
/// entry.
pub const SYMMETRY_TOLERANCE: f64 = 1e-12;

/// A link's inertial parameters as a robot spec would carry them (URDF's
/// layout): all in the link's (DH) frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct InertialSpec {
    /// Mass (kg), ≥ 0.
    pub mass: f64,
    /// Centre of mass in the link frame (m).
    #[serde(default)]
    pub com: [f64; 3],
    /// Inertia tensor about the centre of mass, axes of the link frame
    /// (kg·m²): `[ixx, ixy, ixz, iyy, iyz, izz]`.
    #[serde(default)]
    pub inertia: [f64; 6],
}

/// Validated inertial parameters of a rigid body, in a frame it carries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertial {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass (m).
    pub com: DVec3,
    /// Inertia tensor about the centre of mass (kg·m²), symmetric.
    pub inertia: DMat3,
}

impl Default for Inertial {
    fn default() -> Self {
        Self::ZERO
    }
}

impl Inertial {
    /// A massless body.
    pub const ZERO: Self = Self {
        mass: 0.0,
        com: DVec3::ZERO,
        inertia: DMat3::ZERO,
    };

    /// Validated parameters: a finite, non-negative `mass`, a finite `com`
    /// (each at most [`MAX_MAGNITUDE`] in size, as every length of a
    /// spec), and a finite, symmetric, positive semi-definite `inertia` whose
    /// principal moments satisfy the triangle inequality.
    ///
    /// # Errors
    /// A [`FieldError`] naming the field: `mass: must be >= 0`,
    /// `com[1]: not a finite number`, `inertia[0][2]: not a finite number`,
    /// `inertia: not symmetric …`, `inertia: not positive semi-definite …`,
    /// `inertia: principal moments … violate the triangle inequality …`.
    pub fn new(mass: f64, com: DVec3, inertia: DMat3) -> Result<Self, FieldError> {
        bounded("mass", non_negative("mass", mass)?, MAX_MAGNITUDE)?;
        for (k, c) in com.to_array().iter().enumerate() {
            bounded(&format!("com[{k}]"), *c, MAX_MAGNITUDE)?;
        }
        check_tensor(&inertia)?;
        Ok(Self {
            mass,
            com,
            inertia: symmetrised(&inertia),
        })
    }

    /// [`Inertial::new`] from a spec; `inertia[k]` in errors indexes the six
    /// values.
    ///
    /// # Errors
    /// As [`Inertial::new`].
    pub fn from_spec(spec: &InertialSpec) -> Result<Self, FieldError> {
        for (k, v) in spec.inertia.iter().enumerate() {
            finite(&format!("inertia[{k}]"), *v)?;
        }
        let [xx, xy, xz, yy, yz, zz] = spec.inertia;
        let tensor = DMat3::from_cols(
            DVec3::new(xx, xy, xz),
            DVec3::new(xy, yy, yz),
            DVec3::new(xz, yz, zz),
        );
        Self::new(mass_of(spec)?, DVec3::from_array(spec.com), tensor)
    }

    /// The spec of these parameters (exact: [`Inertial::from_spec`] gives
    /// them back bit for bit).
    #[must_use]
    pub fn to_spec(&self) -> InertialSpec {
        let c = self.inertia.to_cols_array_2d();
        InertialSpec {
            mass: self.mass,
            com: self.com.to_array(),
            inertia: [c[0][0], c[1][0], c[2][0], c[1][1], c[2][1], c[2][2]],
        }
    }

    /// The same body seen from a frame in which the current frame has pose
    /// `pose` (a rigid transform).
    #[must_use]
    pub fn transformed(&self, pose: &DAffine3) -> Self {
        let r = pose.matrix3;
        Self {
            mass: self.mass,
            com: pose.transform_point3(self.com),
            inertia: symmetrised(&(r * self.inertia * r.transpose())),
        }
    }

    /// The body made of `self` and `other` rigidly joined (both in the same
    /// frame): masses add, the centre of mass is their weighted mean, and
    /// each tensor moves to it by the parallel-axis theorem.
    #[must_use]
    pub fn lumped(&self, other: &Self) -> Self {
        let mass = self.mass + other.mass;
        if mass <= 0.0 {
            return Self {
                inertia: self.inertia + other.inertia,
                ..Self::ZERO
            };
        }
        let com = (self.mass * self.com + other.mass * other.com) / mass;
        let shifted = |b: &Self| b.inertia + steiner(b.mass, b.com - com);
        Self {
            mass,
            com,
            inertia: symmetrised(&(shifted(self) + shifted(other))),
        }
    }
}

fn mass_of(spec: &InertialSpec) -> Result<f64, FieldError> {
    non_negative("mass", spec.mass)
}

/// `m (|r|² 1 − r rᵀ)`: the inertia of a point mass `m` at `r` about the
/// origin.
#[must_use]
pub fn steiner(m: f64, r: DVec3) -> DMat3 {
    let outer = DMat3::from_cols(r * r.x, r * r.y, r * r.z);
    m * (DMat3::from_diagonal(DVec3::splat(r.length_squared())) - outer)
}

fn symmetrised(a: &DMat3) -> DMat3 {
    (*a + a.transpose()) * 0.5
}

/// Checks an inertia tensor: finite, symmetric, positive semi-definite,
/// principal moments satisfying the triangle inequality.
fn check_tensor(a: &DMat3) -> Result<(), FieldError> {
    let cols = a.to_cols_array_2d();
    let mut largest: f64 = 0.0;
    for (c, col) in cols.iter().enumerate() {
        for (r, v) in col.iter().enumerate() {
            bounded(&format!("inertia[{r}][{c}]"), *v, MAX_MAGNITUDE)?;
            largest = largest.max(v.abs());
        }
    }
    for (r, c) in [(0, 1), (0, 2), (1, 2)] {
        let (upper, lower) = (cols[c][r], cols[r][c]);
        if (upper - lower).abs() > SYMMETRY_TOLERANCE * largest {
            return Err(FieldError::new(
                "inertia",
                format!("not symmetric: [{r}][{c}] = {upper:e} but [{c}][{r}] = {lower:e}"),
            ));
        }
    }
    let moments = principal_moments(a);
    let slack = INERTIA_TOLERANCE * (moments[0] + moments[1] + moments[2]).abs();
    if moments[0] < -slack {
        return Err(FieldError::new(
            "inertia",
            format!(
                "not positive semi-definite: principal moments {:e}, {:e}, {:e}",
                moments[0], moments[1], moments[2]
            ),
        ));
    }
    if moments[2] > moments[0] + moments[1] + slack {
        return Err(FieldError::new(
            "inertia",
            format!(
                "principal moments {:e}, {:e}, {:e} violate the triangle inequality ({:e} > {:e} + {:e})",
                moments[0], moments[1], moments[2], moments[2], moments[0], moments[1]
            ),
        ));
    }
    Ok(())
}

/// The eigenvalues of the symmetric part of `a`, ascending.
#[must_use]
pub fn principal_moments(a: &DMat3) -> [f64; 3] {
    let s = symmetrised(a);
    let mut m = Mat::zeros(3, 3);
    for r in 0..3 {
        for c in 0..3 {
            m.set(r, c, s.col(c)[r]);
        }
    }
    let (values, _) = symmetric_eigen(&m);
    let mut out = [values[0], values[1], values[2]];
    out.sort_by(f64::total_cmp);
    out
}
