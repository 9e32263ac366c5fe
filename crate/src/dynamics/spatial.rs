//! Spatial vectors and rigid-body inertias (Featherstone, *Rigid Body
//! Dynamics Algorithms*, ch. 2) in one fixed frame: the axes of the world,
//! reference point at the robot's base origin. Every body's quantities are
//! expressed there, so the recursions need no frame changes between links.

use glam::{DMat3, DVec3};

use crate::kinematics::inertia::{Inertial, steiner};

/// A motion vector (angular `w`, linear `v` at the reference point) or a
/// force vector (moment `w` about the reference point, force `v`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spatial {
    /// Angular part (rad/s, rad/s²) or moment (N·m).
    pub w: DVec3,
    /// Linear part (m/s, m/s²) or force (N).
    pub v: DVec3,
}

impl Spatial {
    /// Zero.
    pub const ZERO: Self = Self {
        w: DVec3::ZERO,
        v: DVec3::ZERO,
    };

    /// `self × m` for motion vectors (`crm`).
    #[must_use]
    pub fn cross_motion(&self, m: &Self) -> Self {
        Self {
            w: self.w.cross(m.w),
            v: self.w.cross(m.v) + self.v.cross(m.w),
        }
    }

    /// `self ×* f` for a force vector (`crf`).
    #[must_use]
    pub fn cross_force(&self, f: &Self) -> Self {
        Self {
            w: self.w.cross(f.w) + self.v.cross(f.v),
            v: self.w.cross(f.v),
        }
    }

    /// `selfᵀ f`: the power of a force on a motion.
    #[must_use]
    pub fn dot(&self, f: &Self) -> f64 {
        self.w.dot(f.w) + self.v.dot(f.v)
    }

    /// `self + k o`.
    #[must_use]
    pub fn add_scaled(&self, o: &Self, k: f64) -> Self {
        Self {
            w: self.w + k * o.w,
            v: self.v + k * o.v,
        }
    }

    /// `self + o`.
    #[must_use]
    pub fn add(&self, o: &Self) -> Self {
        self.add_scaled(o, 1.0)
    }
}

/// A rigid-body inertia about the reference point: mass `m`, first moment
/// `h = m c` and rotational inertia `i` about the reference point. Linear in
/// its parameters, so composite bodies are sums.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyInertia {
    /// Mass (kg).
    pub m: f64,
    /// First moment of mass `m c` (kg·m).
    pub h: DVec3,
    /// Rotational inertia about the reference point (kg·m²).
    pub i: DMat3,
}

impl BodyInertia {
    /// No body.
    pub const ZERO: Self = Self {
        m: 0.0,
        h: DVec3::ZERO,
        i: DMat3::ZERO,
    };

    /// The inertia of a body whose parameters are given in a frame with
    /// axes `rot` and origin `origin` (relative to the reference point).
    #[must_use]
    pub fn placed(body: &Inertial, rot: &DMat3, origin: DVec3) -> Self {
        let c = origin + *rot * body.com;
        Self {
            m: body.mass,
            h: body.mass * c,
            i: *rot * body.inertia * rot.transpose() + steiner(body.mass, c),
        }
    }

    /// `I v`: the momentum of the body moving with `v`.
    #[must_use]
    pub fn apply(&self, v: &Spatial) -> Spatial {
        Spatial {
            w: self.i * v.w + self.h.cross(v.v),
            v: self.m * v.v - self.h.cross(v.w),
        }
    }

    /// `self + o`.
    #[must_use]
    pub fn add(&self, o: &Self) -> Self {
        Self {
            m: self.m + o.m,
            h: self.h + o.h,
            i: self.i + o.i,
        }
    }
}
