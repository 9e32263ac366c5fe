//! Robots described by DH tables: the validated model, presets, forward
//! kinematics in one pass over the chain, and inverse kinematics.
//!
//! A [`Robot`] is built from a [`RobotSpec`] (the JS robot spec) by
//! [`Robot::from_spec`], which validates every field. [`Robot::forward`]
//! computes every frame in one pass ([`Frames`]); the skeleton
//! ([`crate::skeleton`]) and every control-point Jacobian
//! ([`crate::control_point`]) are then read from that pass without multiplying
//! the chain again.
//!
//! Rows are numbered from 1 (row `j` is the transform from its start frame to
//! frame `j`); frame 0 is the base. Several chains may share the base: the
//! rows of [`RobotSpec::joints`] come first, then those of every branch, and
//! each row records the frame it starts from ([`Joint::parent`]).
//!
//! Each row may carry the inertial parameters of the body it moves
//! ([`JointSpec::inertial`], validated by [`inertia`]; the presets' values
//! and their sources in [`preset_inertials`]): what
//! [`crate::dynamics::Dynamics::from_robot`] needs. This module only holds
//! them; the recursions are in [`crate::dynamics`].
//!
//! A robot's DH table from its joint axes ([`dh_from_axes`]) is the
//! kinematics of the URDF reader ([`crate::parsers::urdf`]); reading files
//! is not done here.

pub mod dh_from_axes;
mod frames;
pub mod ik;
pub mod inertia;
pub mod preset_inertials;
pub mod presets;
mod spec;

use glam::{DAffine3, DQuat};

pub use frames::Frames;
pub use spec::{
    BranchSpec, Convention, DEFAULT_LIMITS, DEFAULT_RADIUS, Joint, JointSpec, JointType, Limits,
    LinkRadii, LinkRef, MAX_MAGNITUDE, MAX_RADIUS, PoseSpec, RadiusSpec, RobotSpec, SegmentRadius,
    SegmentRadiusSpec, UNIT_QUAT_TOLERANCE,
};

use crate::error::FieldError;

/// One serial chain of a robot: a contiguous range of rows and a tool.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// Display name.
    pub name: String,
    /// First row of the chain (1-based).
    pub first: usize,
    /// Last row of the chain (1-based, inclusive).
    pub last: usize,
    /// Tool transform after the last row.
    pub tool: DAffine3,
}

/// Translations shorter than this (m) add no skeleton node: the node would
/// coincide with the one before it.
pub const NODE_TOLERANCE: f64 = 1e-6;

/// A validated robot: DH rows, base pose, chains.
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// Display name.
    pub name: String,
    /// DH convention of every row.
    pub convention: Convention,
    /// Pose of frame 0 in the world.
    pub base: DAffine3,
    /// Rows 1..=n, stored from index 0.
    pub joints: Vec<Joint>,
    /// The main chain first, then the branches.
    pub chains: Vec<Chain>,
    /// Link names, one per row (empty when the spec gives none).
    pub link_names: Vec<String>,
    /// Pairs of rows kept out of the self-collision query (the spec's
    /// `selfCollisionExclude`, resolved).
    pub exclude: Vec<(usize, usize)>,
}

/// Validates branch `b` of a spec, appends its joints to `joints` (after
/// those of the earlier chains) and returns its chain.
fn add_branch(
    joints: &mut Vec<Joint>,
    b: usize,
    branch: &spec::BranchSpec,
) -> Result<Chain, FieldError> {
    let field = format!("branches[{b}]");
    if branch.joints.is_empty() {
        return Err(FieldError::new(
            format!("{field}.joints"),
            "the DH table is empty",
        ));
    }
    if branch.parent > joints.len() {
        return Err(FieldError::new(
            format!("{field}.parent"),
            format!(
                "{} is not a frame of an earlier chain (0..={})",
                branch.parent,
                joints.len()
            ),
        ));
    }
    let mount = spec::rotation(&format!("{field}.mount"), branch.mount)?;
    let tool = match &branch.tool {
        Some(p) => spec::pose(&format!("{field}.tool"), p)?,
        None => DAffine3::IDENTITY,
    };
    let first = joints.len() + 1;
    for (i, j) in branch.joints.iter().enumerate() {
        let parent = if i == 0 { branch.parent } else { joints.len() };
        let mut joint = spec::joint(&format!("{field}.joints[{i}]"), j, parent)?;
        if i == 0 && mount != DQuat::IDENTITY {
            joint.mount = Some(mount);
        }
        joints.push(joint);
    }
    Ok(Chain {
        name: branch
            .name
            .clone()
            .unwrap_or_else(|| format!("branch {}", b + 1)),
        first,
        last: joints.len(),
        tool,
    })
}

impl Robot {
    /// Validates `spec` into a robot.
    ///
    /// # Errors
    /// A [`FieldError`] naming the first bad field: an empty DH table
    /// (`joints: the DH table is empty`), a non-finite value
    /// (`joints[3].alpha: not a finite number`), a degenerate or non-unit base
    /// rotation, a negative radius, a branch whose parent frame does not exist,
    /// `jointNames` of the wrong length or with an empty or repeated name.
    pub fn from_spec(spec: &RobotSpec) -> Result<Self, FieldError> {
        if spec.joints.is_empty() {
            return Err(FieldError::new("joints", "the DH table is empty"));
        }
        let base = match &spec.base {
            Some(p) => spec::pose("base", p)?,
            None => DAffine3::IDENTITY,
        };
        let tool = match &spec.tool {
            Some(p) => spec::pose("tool", p)?,
            None => DAffine3::IDENTITY,
        };
        let mut joints = Vec::with_capacity(spec.joints.len());
        for (i, j) in spec.joints.iter().enumerate() {
            joints.push(spec::joint(&format!("joints[{i}]"), j, i)?);
        }
        let mut chains = vec![Chain {
            name: spec.name.clone().unwrap_or_else(|| "main".to_owned()),
            first: 1,
            last: joints.len(),
            tool,
        }];
        for (b, branch) in spec.branches.iter().enumerate() {
            chains.push(add_branch(&mut joints, b, branch)?);
        }
        if let Some(names) = &spec.joint_names {
            check_joint_names(names, joints.len())?;
        }
        if let Some(names) = &spec.link_names {
            check_names("linkNames", names, joints.len())?;
        }
        let mut robot = Self {
            name: spec.name.clone().unwrap_or_default(),
            convention: spec.convention,
            base,
            joints,
            chains,
            link_names: spec.link_names.clone().unwrap_or_default(),
            exclude: Vec::new(),
        };
        robot.exclude = robot.link_pairs("selfCollisionExclude", &spec.self_collision_exclude)?;
        Ok(robot)
    }

    /// The row of `link` (0 the base).
    ///
    /// # Errors
    /// An index past the last row or a name not in `linkNames`, as
    /// `field: …`.
    pub fn link_index(&self, field: &str, link: &LinkRef) -> Result<usize, FieldError> {
        match link {
            LinkRef::Index(k) if *k <= self.dof() => Ok(*k),
            LinkRef::Index(k) => Err(FieldError::new(
                field,
                format!("{k} is not a link of this robot (0 to {})", self.dof()),
            )),
            LinkRef::Name(name) => self
                .link_names
                .iter()
                .position(|n| n == name)
                .map(|k| k + 1)
                .ok_or_else(|| {
                    FieldError::new(
                        field,
                        if self.link_names.is_empty() {
                            format!("no link named \"{name}\": this robot has no linkNames (use row indices)")
                        } else {
                            format!("no link named \"{name}\" (linkNames: {})", self.link_names.join(", "))
                        },
                    )
                }),
        }
    }

    /// Pairs of links resolved to rows; a pair listed twice or a link paired
    /// with itself is refused.
    ///
    /// # Errors
    /// `field[k][side]: …` for an unknown link, `field[k]: …` for a repeat.
    pub fn link_pairs(
        &self,
        field: &str,
        pairs: &[[LinkRef; 2]],
    ) -> Result<Vec<(usize, usize)>, FieldError> {
        let mut out: Vec<(usize, usize)> = Vec::with_capacity(pairs.len());
        for (k, [a, b]) in pairs.iter().enumerate() {
            let a = self.link_index(&format!("{field}[{k}][0]"), a)?;
            let b = self.link_index(&format!("{field}[{k}][1]"), b)?;
            if a == b {
                return Err(FieldError::new(
                    format!("{field}[{k}]"),
                    "a link cannot be paired with itself",
                ));
            }
            let pair = (a.min(b), a.max(b));
            if let Some(first) = out.iter().position(|p| *p == pair) {
                return Err(FieldError::new(
                    format!("{field}[{k}]"),
                    format!("the pair is listed twice (also {field}[{first}])"),
                ));
            }
            out.push(pair);
        }
        Ok(out)
    }

    /// A link's name for messages: its `linkNames` entry, else `link k`.
    #[must_use]
    pub fn link_label(&self, link: usize) -> String {
        match link {
            0 => "base".to_owned(),
            k => self
                .link_names
                .get(k - 1)
                .cloned()
                .unwrap_or_else(|| format!("link {k}")),
        }
    }

    /// Number of joints (= rows = length of `q`).
    #[must_use]
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// Frame the 1-based row `link` starts from (0 = base).
    ///
    /// # Panics
    /// Never for `1 <= link <= dof()`; out-of-range indices are a caller bug.
    #[must_use]
    pub fn parent_link(&self, link: usize) -> usize {
        self.joints[link - 1].parent
    }

    /// Whether row `k` moves the frames of row `link` (`k` is `link` or one of
    /// its ancestors). Both 1-based.
    #[must_use]
    pub fn is_ancestor(&self, k: usize, link: usize) -> bool {
        let mut j = link;
        while j >= 1 {
            if j == k {
                return true;
            }
            j = self.joints[j - 1].parent;
        }
        false
    }

    /// Whether row `link` (1-based) adds a segment to the skeleton: a
    /// translation of at least [`NODE_TOLERANCE`], a
    /// prismatic joint, or an extension.
    #[must_use]
    pub fn has_segment(&self, link: usize) -> bool {
        let j = &self.joints[link - 1];
        let tol = NODE_TOLERANCE;
        j.kind == JointType::Prismatic || j.d.abs() >= tol || j.a.abs() >= tol || j.extension >= tol
    }

    /// The nearest ancestor of row `link` that has a segment (0 = the base):
    /// the row whose last node the segments of `link` start from.
    #[must_use]
    pub fn skeleton_parent(&self, link: usize) -> usize {
        let mut k = self.joints[link - 1].parent;
        while k >= 1 && !self.has_segment(k) {
            k = self.joints[k - 1].parent;
        }
        k
    }

    /// Whether the segments of two rows touch by construction: the same row,
    /// one starting where the other ends (rows without segments in between
    /// are skipped), or siblings starting from the same node (two arms on
    /// one torso); the base is row 0. This is the crate's one definition of
    /// adjacent links: a `World`'s self-collision query skips every pair
    /// within two hops of it.
    #[must_use]
    pub fn adjacent(&self, i: usize, j: usize) -> bool {
        let n = self.dof();
        if i == j {
            return true;
        }
        let sp = |k: usize| {
            if k >= 1 && k <= n {
                Some(self.skeleton_parent(k))
            } else {
                None
            }
        };
        match (sp(i), sp(j)) {
            (Some(pi), Some(pj)) => pi == j || pj == i || pi == pj,
            (Some(pi), None) => pi == j,
            (None, Some(pj)) => pj == i,
            (None, None) => false,
        }
    }

    /// Checks a joint vector: its length and that every value is finite.
    ///
    /// # Errors
    /// `q: expected 7 joint values, got 6` or `q[2]: not a finite number`.
    pub fn check_q(&self, q: &[f64]) -> Result<(), FieldError> {
        check_vector("q", q, self.dof())
    }

    /// Forward kinematics: every frame, in one pass.
    ///
    /// # Errors
    /// An invalid `q` (see [`Robot::check_q`]).
    pub fn forward(&self, q: &[f64]) -> Result<Frames, FieldError> {
        let mut f = Frames::default();
        self.forward_into(q, &mut f)?;
        Ok(f)
    }

    /// [`Robot::forward`] into an existing [`Frames`], reusing its storage.
    ///
    /// # Errors
    /// An invalid `q` (see [`Robot::check_q`]).
    pub fn forward_into(&self, q: &[f64], frames: &mut Frames) -> Result<(), FieldError> {
        self.check_q(q)?;
        frames.compute(self, q, None);
        Ok(())
    }

    /// Forward kinematics with velocities: also every frame's angular velocity
    /// and origin velocity for joint speeds `qdot`, needed by the Jacobian
    /// time derivatives.
    ///
    /// # Errors
    /// An invalid `q` or `qdot` (length, non-finite values).
    pub fn forward_with_velocity(&self, q: &[f64], qdot: &[f64]) -> Result<Frames, FieldError> {
        self.check_q(q)?;
        check_vector("qdot", qdot, self.dof())?;
        let mut f = Frames::default();
        f.compute(self, q, Some(qdot));
        Ok(f)
    }

    /// Clamps `q` into the joint limits.
    pub fn clamp_to_limits(&self, q: &mut [f64]) {
        for (v, j) in q.iter_mut().zip(&self.joints) {
            *v = v.clamp(j.min, j.max);
        }
    }
}

/// Checks the optional `jointNames` of a spec: one non-empty, unique name per
/// row.
fn check_joint_names(names: &[String], dof: usize) -> Result<(), FieldError> {
    check_names("jointNames", names, dof)
}

fn check_names(field: &str, names: &[String], dof: usize) -> Result<(), FieldError> {
    if names.len() != dof {
        return Err(FieldError::new(
            field,
            format!("expected {dof} names (one per joint), got {}", names.len()),
        ));
    }
    for (k, name) in names.iter().enumerate() {
        if name.is_empty() {
            return Err(FieldError::new(format!("{field}[{k}]"), "empty name"));
        }
        if names[..k].contains(name) {
            return Err(FieldError::new(
                format!("{field}[{k}]"),
                format!("\"{name}\" appears twice"),
            ));
        }
    }
    Ok(())
}

/// Checks that `v` has `n` finite values.
///
/// # Errors
/// `field: expected n joint values, got m` or `field[k]: not a finite number`.
pub fn check_vector(field: &str, v: &[f64], n: usize) -> Result<(), FieldError> {
    if v.len() != n {
        return Err(FieldError::new(
            field,
            format!("expected {n} joint values, got {}", v.len()),
        ));
    }
    for (k, x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(FieldError::new(
                format!("{field}[{k}]"),
                "not a finite number",
            ));
        }
    }
    Ok(())
}
