//! Forward kinematics in one pass: every frame, the start frame of every row,
//! the node between a row's two translations, and (optionally) every frame's
//! velocity.

use glam::{DAffine3, DMat3, DVec3};

use super::{Convention, JointType, Robot};

/// The result of one forward-kinematics pass over a robot at `q` (and
/// optionally `q̇`). Everything the skeleton and the control-point Jacobians
/// need is here; they never multiply the chain again.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frames {
    /// Frame poses in the world, index 0 (base) ..= n.
    pub transforms: Vec<DAffine3>,
    /// Per row (index `j − 1`): the frame the row starts from (its parent frame,
    /// turned by a branch mount when there is one).
    pub starts: Vec<DAffine3>,
    /// Per row: the point between the row's two translations (after `d` in the
    /// standard convention, after `a` in the modified one).
    pub mids: Vec<DVec3>,
    /// Per row: the effective `d` (with the joint value of a prismatic joint).
    pub d: Vec<f64>,
    /// Per row: the joint axis, which is also the direction of the row's `d`
    /// translation (`∂p/∂d`): `z_{i-1}` (standard) or `z_i` (modified).
    pub axis: Vec<DVec3>,
    /// Per row: a point on the joint axis: the row's start (standard) or the
    /// point after its `a` translation (modified).
    pub axis_point: Vec<DVec3>,
    /// Per row: the direction of the row's `a` translation (`∂p/∂a`): `x_i`
    /// (standard) or `x_{i-1}` (modified).
    pub a_direction: Vec<DVec3>,
    /// Per chain: last frame times the tool transform.
    pub end_effectors: Vec<DAffine3>,
    /// Angular velocity of each frame (rad/s), index 0..=n; empty without `q̇`.
    pub omega: Vec<DVec3>,
    /// Linear velocity of each frame origin (m/s), index 0..=n; empty without `q̇`.
    pub velocity: Vec<DVec3>,
    /// The joint speeds the velocities were computed for; empty without `q̇`.
    pub qdot: Vec<f64>,
    /// The convention of the robot the frames belong to.
    pub convention: Option<Convention>,
    /// Memo of `(α, sin α, cos α)` per row: the twists are constant, and
    /// trigonometry is costly in wasm (software libm).
    alpha_memo: Vec<(f64, f64, f64)>,
}

impl Frames {
    /// Origin of frame `k` (0 = base).
    #[must_use]
    pub fn origin(&self, k: usize) -> DVec3 {
        self.transforms[k].translation
    }

    /// The end effector of the main chain.
    #[must_use]
    pub fn end_effector(&self) -> DAffine3 {
        self.end_effectors
            .first()
            .copied()
            .unwrap_or(DAffine3::IDENTITY)
    }

    /// Whether velocities were computed.
    #[must_use]
    pub fn has_velocity(&self) -> bool {
        !self.omega.is_empty()
    }

    pub(super) fn compute(&mut self, robot: &Robot, q: &[f64], qdot: Option<&[f64]>) {
        let n = robot.dof();
        self.resize(n, robot.chains.len(), qdot.is_some());
        self.convention = Some(robot.convention);
        if let Some(qd) = qdot {
            self.omega.push(DVec3::ZERO);
            self.velocity.push(DVec3::ZERO);
            self.qdot.extend_from_slice(qd);
        }
        // Every per-row list has exactly `n` entries (the frames `n + 1`),
        // each written once below: slices of that length let the compiler
        // drop the bounds checks and the pushes' capacity checks.
        let q = &q[..n];
        let transforms = &mut self.transforms[..=n];
        let (starts, mids, ds) = (&mut self.starts[..n], &mut self.mids[..n], &mut self.d[..n]);
        let axes = &mut self.axis[..n];
        let (axis_points, a_directions) = (&mut self.axis_point[..n], &mut self.a_direction[..n]);
        let alpha_memo = &mut self.alpha_memo[..n];
        transforms[0] = robot.base;
        for (i, joint) in robot.joints.iter().enumerate() {
            let parent = transforms[joint.parent];
            let start = match joint.mount {
                Some(m) => DAffine3 {
                    matrix3: parent.matrix3 * DMat3::from_quat(m),
                    translation: parent.translation,
                },
                None => parent,
            };
            let (theta, d) = match joint.kind {
                JointType::Revolute => (joint.theta + q[i], joint.d),
                JointType::Prismatic => (joint.theta, joint.d + q[i]),
            };
            let alpha = alpha_sin_cos(&mut alpha_memo[i], joint.alpha);
            let row = Row::new(robot.convention, &start, joint.a, d, theta, alpha);
            if let Some(qd) = qdot {
                let (w, v) = row.velocity(
                    (robot.convention, joint.kind),
                    (self.omega[joint.parent], self.velocity[joint.parent]),
                    qd[i],
                );
                self.omega.push(w);
                self.velocity.push(v);
            }
            starts[i] = start;
            mids[i] = row.mid;
            ds[i] = d;
            (axes[i], axis_points[i], a_directions[i]) = match robot.convention {
                Convention::Standard => (row.zs, row.o0, row.x),
                Convention::Modified => (row.z, row.mid, row.xs),
            };
            transforms[i + 1] = DAffine3 {
                matrix3: DMat3::from_cols(row.x, row.y, row.z),
                translation: row.origin,
            };
        }
        for chain in &robot.chains {
            self.end_effectors
                .push(self.transforms[chain.last] * chain.tool);
        }
    }

    /// Sizes every list for `n` rows and `chains` end effectors (and the
    /// velocities): the per-row lists and the frames to their final length
    /// (a no-op once they have it; [`Frames::compute`] overwrites every
    /// entry), the others empty with room to grow once. The `α` memo only
    /// grows: its entries are checked against the row's `α` on use.
    fn resize(&mut self, n: usize, chains: usize, velocity: bool) {
        self.transforms.resize(n + 1, DAffine3::IDENTITY);
        self.starts.resize(n, DAffine3::IDENTITY);
        self.mids.resize(n, DVec3::ZERO);
        self.d.resize(n, 0.0);
        self.axis.resize(n, DVec3::ZERO);
        self.axis_point.resize(n, DVec3::ZERO);
        self.a_direction.resize(n, DVec3::ZERO);
        if self.alpha_memo.len() < n {
            self.alpha_memo.resize(n, (f64::NAN, 0.0, 0.0));
        }
        self.end_effectors.clear();
        self.end_effectors.reserve(chains);
        self.omega.clear();
        self.velocity.clear();
        self.qdot.clear();
        if velocity {
            self.omega.reserve(n + 1);
            self.velocity.reserve(n + 1);
            self.qdot.reserve(n);
        }
    }
}

/// `(sin α, cos α)` of a row from its memo `(α, sin α, cos α)`, computed
/// again only when `α` changed.
fn alpha_sin_cos(memo: &mut (f64, f64, f64), alpha: f64) -> (f64, f64) {
    if memo.0.to_bits() != alpha.to_bits() {
        let (s, c) = crate::math::sin_cos(alpha);
        *memo = (alpha, s, c);
    }
    (memo.1, memo.2)
}

/// One DH row applied to its start frame (axes `xs`, `zs`, origin `o0`):
/// the point between its two translations, the new axes and origin.
struct Row {
    xs: DVec3,
    zs: DVec3,
    o0: DVec3,
    mid: DVec3,
    x: DVec3,
    y: DVec3,
    z: DVec3,
    origin: DVec3,
}

impl Row {
    fn new(
        convention: Convention,
        start: &DAffine3,
        a: f64,
        d: f64,
        theta: f64,
        (sa, ca): (f64, f64),
    ) -> Self {
        let (st, ct) = crate::math::sin_cos(theta);
        let xs = start.matrix3.x_axis;
        let ys = start.matrix3.y_axis;
        let zs = start.matrix3.z_axis;
        let o0 = start.translation;
        let (mid, x, y, z, origin) = match convention {
            Convention::Standard => {
                // Rz(θ) Tz(d) Tx(a) Rx(α)
                let x = ct * xs + st * ys;
                let yp = -st * xs + ct * ys;
                let mid = o0 + d * zs;
                let origin = mid + a * x;
                (mid, x, ca * yp + sa * zs, -sa * yp + ca * zs, origin)
            }
            Convention::Modified => {
                // Rx(α) Tx(a) Rz(θ) Tz(d)
                let yp = ca * ys + sa * zs;
                let z = -sa * ys + ca * zs;
                let mid = o0 + a * xs;
                let x = ct * xs + st * yp;
                let y = -st * xs + ct * yp;
                (mid, x, y, z, mid + d * z)
            }
        };
        Self {
            xs,
            zs,
            o0,
            mid,
            x,
            y,
            z,
            origin,
        }
    }

    /// Angular and linear velocity of the row's frame from its start
    /// frame's `(w_s, v_s)` and the joint rate.
    fn velocity(
        &self,
        kind: (Convention, JointType),
        (w_s, v_s): (DVec3, DVec3),
        rate: f64,
    ) -> (DVec3, DVec3) {
        let (o0, mid, origin) = (self.o0, self.mid, self.origin);
        match kind {
            (Convention::Standard, JointType::Revolute) => {
                let w = w_s + rate * self.zs;
                (w, v_s + w_s.cross(mid - o0) + w.cross(origin - mid))
            }
            (Convention::Standard, JointType::Prismatic) => {
                (w_s, v_s + w_s.cross(origin - o0) + rate * self.zs)
            }
            (Convention::Modified, JointType::Revolute) => {
                (w_s + rate * self.z, v_s + w_s.cross(origin - o0))
            }
            (Convention::Modified, JointType::Prismatic) => {
                (w_s, v_s + w_s.cross(origin - o0) + rate * self.z)
            }
        }
    }
}
