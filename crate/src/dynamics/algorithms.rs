//! The recursions: Newton–Euler inverse dynamics and the composite
//! rigid-body mass matrix, over the frames of one forward-kinematics pass.

use crate::error::FieldError;
use crate::kinematics::{Frames, JointType, check_vector};

use super::Dynamics;
use super::spatial::{BodyInertia, Spatial};

/// Storage for the dynamics of one robot, reused by every call: the
/// kinematic frames, each row's motion subspace and body inertia, and the
/// velocity, acceleration and force of each body.
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    pub(super) frames: Frames,
    /// Per row: the joint's motion subspace (unit twist).
    pub(super) axis: Vec<Spatial>,
    /// Per row: the body's inertia (composite in the mass matrix).
    pub(super) inertia: Vec<BodyInertia>,
    /// Per frame 0..=n: velocity.
    pub(super) velocity: Vec<Spatial>,
    /// Per frame 0..=n: acceleration (gravity as a base acceleration).
    pub(super) acceleration: Vec<Spatial>,
    /// Per row: the force the row's joint transmits.
    pub(super) force: Vec<Spatial>,
    /// `n × n`: the mass matrix and its Cholesky factor (forward dynamics).
    pub(super) mass: Vec<f64>,
}

/// Which terms of the equation of motion a Newton–Euler pass includes:
/// velocity terms (with `qdot`), acceleration terms (with `qddot`),
/// gravity.
#[derive(Clone, Copy)]
struct Terms<'a> {
    qdot: Option<&'a [f64]>,
    qddot: Option<&'a [f64]>,
    gravity: bool,
}

impl<'a> Terms<'a> {
    fn all(qdot: &'a [f64], qddot: &'a [f64]) -> Self {
        Self {
            qdot: Some(qdot),
            qddot: Some(qddot),
            gravity: true,
        }
    }
}

/// Checks that an output slice has `n` entries.
fn check_out(field: &str, out: &[f64], n: usize) -> Result<(), FieldError> {
    if out.len() == n {
        Ok(())
    } else {
        Err(FieldError::new(
            field,
            format!("expected room for {n} values, got {}", out.len()),
        ))
    }
}

impl Dynamics {
    /// A workspace sized for this robot (the only allocation).
    #[must_use]
    pub fn workspace(&self) -> Workspace {
        let n = self.dof();
        let mut ws = Workspace {
            frames: Frames::default(),
            axis: vec![Spatial::ZERO; n],
            inertia: vec![BodyInertia::ZERO; n],
            velocity: vec![Spatial::ZERO; n + 1],
            acceleration: vec![Spatial::ZERO; n + 1],
            force: vec![Spatial::ZERO; n],
            mass: vec![0.0; n * n],
        };
        // One pass sizes the frames' lists; later passes reuse them.
        let _ = self.robot.forward_into(&vec![0.0; n], &mut ws.frames);
        ws
    }

    /// Inverse dynamics: the joint torques (N·m) and forces (N)
    /// `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)` into `tau`.
    ///
    /// # Errors
    /// `q`, `qdot`, `qddot` of the wrong length or not finite
    /// (`qdot[2]: not a finite number`); `tau` of the wrong length.
    pub fn inverse_dynamics(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        (qdot, qddot): (&[f64], &[f64]),
        tau: &mut [f64],
    ) -> Result<(), FieldError> {
        check_vector("qdot", qdot, self.dof())?;
        check_vector("qddot", qddot, self.dof())?;
        self.torques(ws, q, Terms::all(qdot, qddot), ("tau", tau))
    }

    /// The gravity torques `g(q)` into `out`.
    ///
    /// # Errors
    /// An invalid `q`; `out` of the wrong length.
    pub fn gravity_torques(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        out: &mut [f64],
    ) -> Result<(), FieldError> {
        let terms = Terms {
            qdot: None,
            qddot: None,
            gravity: true,
        };
        self.torques(ws, q, terms, ("out", out))
    }

    /// The Coriolis and centrifugal torques `C(q, q̇) q̇` into `out`.
    ///
    /// # Errors
    /// An invalid `q` or `qdot`; `out` of the wrong length.
    pub fn coriolis(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        qdot: &[f64],
        out: &mut [f64],
    ) -> Result<(), FieldError> {
        self.velocity_terms(ws, (q, qdot), false, out)
    }

    /// `C(q, q̇) q̇ + g(q)` (what the joints need at `q̈ = 0`) into `out`.
    ///
    /// # Errors
    /// An invalid `q` or `qdot`; `out` of the wrong length.
    pub fn nonlinear_effects(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        qdot: &[f64],
        out: &mut [f64],
    ) -> Result<(), FieldError> {
        self.velocity_terms(ws, (q, qdot), true, out)
    }

    /// `C(q, q̇) q̇`, with `g(q)` added when `gravity`.
    fn velocity_terms(
        &self,
        ws: &mut Workspace,
        (q, qdot): (&[f64], &[f64]),
        gravity: bool,
        out: &mut [f64],
    ) -> Result<(), FieldError> {
        check_vector("qdot", qdot, self.dof())?;
        let terms = Terms {
            qdot: Some(qdot),
            qddot: None,
            gravity,
        };
        self.torques(ws, q, terms, ("out", out))
    }

    /// Checks `out`, runs the kinematics and Newton–Euler for `terms`.
    fn torques(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        terms: Terms<'_>,
        (field, out): (&str, &mut [f64]),
    ) -> Result<(), FieldError> {
        check_out(field, out, self.dof())?;
        self.prepare(ws, q)?;
        self.newton_euler(ws, &terms, out);
        Ok(())
    }

    /// The joint-space mass matrix `M(q)` into `m`, row-major `n × n`
    /// (symmetric positive definite when every joint moves some mass).
    ///
    /// # Errors
    /// An invalid `q`; `m` not of length `n²`.
    pub fn mass_matrix(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        m: &mut [f64],
    ) -> Result<(), FieldError> {
        check_out("m", m, self.dof() * self.dof())?;
        self.prepare(ws, q)?;
        self.composite(ws, m);
        Ok(())
    }

    /// Forward dynamics: the joint accelerations
    /// `q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q))` into `qddot` (Newton–Euler for
    /// the bias, the composite-rigid-body mass matrix and its Cholesky
    /// factor, all in the workspace).
    ///
    /// # Errors
    /// An invalid `q`, `qdot` or `tau` (`tau[3]: not a finite number`);
    /// `qddot` of the wrong length; `inertials: the mass matrix is singular
    /// at this q (joint 7 moves no mass or inertia about its axis)`.
    pub fn forward_dynamics(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        (qdot, tau): (&[f64], &[f64]),
        qddot: &mut [f64],
    ) -> Result<(), FieldError> {
        let n = self.dof();
        check_vector("qdot", qdot, n)?;
        check_vector("tau", tau, n)?;
        check_out("qddot", qddot, n)?;
        self.prepare(ws, q)?;
        let terms = Terms {
            qdot: Some(qdot),
            qddot: None,
            gravity: true,
        };
        self.newton_euler(ws, &terms, qddot);
        for (a, t) in qddot.iter_mut().zip(tau) {
            *a = t - *a;
        }
        let mut m = std::mem::take(&mut ws.mass);
        self.composite(ws, &mut m);
        let solved = cholesky_solve(&mut m, qddot);
        ws.mass = m;
        solved.map_err(|row| {
            FieldError::new(
                "inertials",
                format!(
                    "the mass matrix is singular at this q (joint {} moves no mass or inertia about its axis)",
                    row + 1
                ),
            )
        })
    }

    /// The potential energy of gravity, `−Σ m_k gᵀ c_k` (J; zero with
    /// every centre of mass at the world origin).
    ///
    /// # Errors
    /// An invalid `q`.
    pub fn potential_energy(&self, ws: &mut Workspace, q: &[f64]) -> Result<f64, FieldError> {
        self.robot.forward_into(q, &mut ws.frames)?;
        Ok(self
            .bodies
            .iter()
            .zip(&ws.frames.transforms[1..])
            .map(|(b, t)| -b.mass * self.gravity.dot(t.transform_point3(b.com)))
            .sum())
    }

    /// The composite-rigid-body algorithm over the prepared workspace
    /// (turns each row's inertia into its subtree's) into `m`.
    fn composite(&self, ws: &mut Workspace, m: &mut [f64]) {
        let n = self.dof();
        // Rows on different branches do not couple: their entries stay 0.
        m.fill(0.0);
        for k in (0..n).rev() {
            let parent = self.robot.joints[k].parent;
            if parent >= 1 {
                ws.inertia[parent - 1] = ws.inertia[parent - 1].add(&ws.inertia[k]);
            }
        }
        for i in 0..n {
            let f = ws.inertia[i].apply(&ws.axis[i]);
            m[i * n + i] = ws.axis[i].dot(&f);
            let mut j = self.robot.joints[i].parent;
            while j >= 1 {
                let v = ws.axis[j - 1].dot(&f);
                m[i * n + j - 1] = v;
                m[(j - 1) * n + i] = v;
                j = self.robot.joints[j - 1].parent;
            }
        }
    }

    /// The kinetic energy `½ q̇ᵀ M(q) q̇` (J), from the bodies' velocities.
    ///
    /// # Errors
    /// An invalid `q` or `qdot`.
    pub fn kinetic_energy(
        &self,
        ws: &mut Workspace,
        q: &[f64],
        qdot: &[f64],
    ) -> Result<f64, FieldError> {
        check_vector("qdot", qdot, self.dof())?;
        self.prepare(ws, q)?;
        let mut energy = 0.0;
        for (k, rate) in qdot.iter().enumerate() {
            let parent = self.robot.joints[k].parent;
            let v = ws.velocity[parent].add_scaled(&ws.axis[k], *rate);
            ws.velocity[k + 1] = v;
            energy += 0.5 * v.dot(&ws.inertia[k].apply(&v));
        }
        Ok(energy)
    }

    /// Forward kinematics at `q`, then each row's motion subspace and body
    /// inertia in the world's axes about the base origin.
    fn prepare(&self, ws: &mut Workspace, q: &[f64]) -> Result<(), FieldError> {
        self.robot.forward_into(q, &mut ws.frames)?;
        let f = &ws.frames;
        let origin = self.robot.base.translation;
        for (k, joint) in self.robot.joints.iter().enumerate() {
            let a = f.axis[k];
            ws.axis[k] = match joint.kind {
                JointType::Revolute => Spatial {
                    w: a,
                    v: (f.axis_point[k] - origin).cross(a),
                },
                JointType::Prismatic => Spatial {
                    w: glam::DVec3::ZERO,
                    v: a,
                },
            };
            let t = &f.transforms[k + 1];
            ws.inertia[k] =
                BodyInertia::placed(&self.bodies[k], &t.matrix3, t.translation - origin);
        }
        ws.velocity[0] = Spatial::ZERO;
        Ok(())
    }

    /// Newton–Euler over the prepared workspace: velocities and
    /// accelerations outwards (gravity as an upward acceleration of the
    /// base when `gravity`), forces inwards; `τ_k = s_kᵀ f_k` into `out`.
    fn newton_euler(&self, ws: &mut Workspace, terms: &Terms<'_>, out: &mut [f64]) {
        let Terms {
            qdot,
            qddot,
            gravity,
        } = *terms;
        let n = self.dof();
        ws.acceleration[0] = Spatial {
            w: glam::DVec3::ZERO,
            v: if gravity {
                -self.gravity
            } else {
                glam::DVec3::ZERO
            },
        };
        for k in 0..n {
            let parent = self.robot.joints[k].parent;
            let s = ws.axis[k];
            let rate = qdot.map_or(0.0, |v| v[k]);
            let v = ws.velocity[parent].add_scaled(&s, rate);
            let a = ws.acceleration[parent]
                .add_scaled(&v.cross_motion(&s), rate)
                .add_scaled(&s, qddot.map_or(0.0, |x| x[k]));
            ws.velocity[k + 1] = v;
            ws.acceleration[k + 1] = a;
            let inertia = &ws.inertia[k];
            ws.force[k] = inertia.apply(&a).add(&v.cross_force(&inertia.apply(&v)));
        }
        for k in (0..n).rev() {
            out[k] = ws.axis[k].dot(&ws.force[k]);
            let parent = self.robot.joints[k].parent;
            if parent >= 1 {
                ws.force[parent - 1] = ws.force[parent - 1].add(&ws.force[k]);
            }
        }
    }
}

/// Solves `m x = b` in place (`b` becomes `x`) for a symmetric positive
/// definite `m` (row-major, `b.len()²` entries), which is overwritten by
/// its Cholesky factor (lower triangle).
///
/// # Errors
/// The first row whose pivot is not positive (relative to the largest
/// diagonal entry): `m` is singular there.
fn cholesky_solve(m: &mut [f64], b: &mut [f64]) -> Result<(), usize> {
    let n = b.len();
    let scale = (0..n).map(|i| m[i * n + i].abs()).fold(0.0, f64::max);
    for j in 0..n {
        let pivot = m[j * n + j] - (0..j).map(|k| m[j * n + k] * m[j * n + k]).sum::<f64>();
        if pivot.is_nan() || pivot <= PIVOT_TOLERANCE * scale {
            return Err(j);
        }
        let d = pivot.sqrt();
        m[j * n + j] = d;
        for i in j + 1..n {
            let s = m[i * n + j] - (0..j).map(|k| m[i * n + k] * m[j * n + k]).sum::<f64>();
            m[i * n + j] = s / d;
        }
    }
    for i in 0..n {
        let s = b[i] - (0..i).map(|k| m[i * n + k] * b[k]).sum::<f64>();
        b[i] = s / m[i * n + i];
    }
    for i in (0..n).rev() {
        let s = b[i] - (i + 1..n).map(|k| m[k * n + i] * b[k]).sum::<f64>();
        b[i] = s / m[i * n + i];
    }
    Ok(())
}

/// Smallest Cholesky pivot accepted, relative to the largest diagonal
/// entry of the mass matrix.
const PIVOT_TOLERANCE: f64 = 1e-14;
