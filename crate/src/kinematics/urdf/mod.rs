//! URDF import: a robot spec in standard DH, with its skeleton, from a URDF
//! description.
//!
//! [`robot_from_urdf`] parses the XML (with `urdf-rs`), takes the chain of
//! joints from a base link to a tip link, and turns the joint axes at the
//! zero configuration into a standard DH table ([`dh`]): the pose of DH frame
//! 0 in the base link becomes the spec's `base`, the pose of the tip link in
//! the last DH frame its `tool`. The forward kinematics of the spec then
//! reproduces the URDF's frame of the tip for every joint vector, expressed in
//! the base link's frame; `jointNames` lists the URDF joints in the order of
//! `q`.
//!
//! What is read, and how:
//! - `revolute` and `continuous` joints become revolute rows, `prismatic`
//!   joints prismatic rows; `fixed` joints inside the chain are folded into
//!   the geometry (and into the tool after the last joint).
//! - Axes may point anywhere (any sign: positive joint values keep the URDF's
//!   sense); parallel, coincident and intersecting consecutive axes are
//!   handled (see [`dh`] for the choices, [`dh::PARALLEL_TOLERANCE`] for axes
//!   nearly parallel).
//! - Limits: `lower`/`upper` become `min`/`max` (none for `continuous`, and
//!   none when `lower == upper`, which is how a missing `<limit>` reads);
//!   `velocity` → `maxVelocity`, `effort` → `maxTorque`, and URDF 1.2's
//!   `acceleration`, `jerk` → `maxAcceleration`, `maxJerk` (zero or infinite
//!   values are left to the documented defaults).
//! - Radii: the largest radius over the primitive collision geometry of the
//!   links a row moves until the next joint (cylinder and capsule: their
//!   radius; sphere: its radius; box: half the diagonal of its two smaller
//!   sides); rows with only meshes (or nothing) keep the default radius
//!   ([`super::DEFAULT_RADIUS`], 0.05 m).
//!
//! Not imported: mimic joints, `floating`, `planar` and `spherical` joints in
//! the chain (an error names the joint: choose a tip before it), closed loops
//! (a link with two parent joints is an error), joints outside the chain
//! (other arms, fingers, sensors) and the geometry of links outside it.

pub mod dh;

use std::collections::{HashMap, HashSet};

use glam::{DAffine3, DMat3, DQuat, DVec3};
use serde::Deserialize;
use urdf_rs::{Geometry, JointType as UrdfJointType};

use super::{Convention, JointSpec, JointType, LinkRef, PoseSpec, RadiusSpec, Robot, RobotSpec};
use crate::error::FieldError;
use crate::math;

/// Which part of the URDF to import.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct UrdfOptions {
    /// The link at the end of the chain; default: the end of the longest
    /// chain of revolute, continuous and prismatic (non-mimic) joints below
    /// `base`, followed through a single fixed joint at a time.
    #[serde(default)]
    pub tip: Option<String>,
    /// The link the chain starts from (the spec's world frame); default: the
    /// root link.
    #[serde(default)]
    pub base: Option<String>,
    /// An SRDF document (MoveIt's semantic description): its
    /// `disable_collisions` pairs between links of the chain become the
    /// spec's `selfCollisionExclude`.
    #[serde(default)]
    pub srdf: Option<String>,
}

/// A robot spec in standard DH from a URDF document.
///
/// Lengths in m, angles in rad; the spec's world frame is the base link's
/// frame. See the [module docs](self) for what is read and how.
///
/// # Errors
/// A [`FieldError`] naming the element: `xml: …` for malformed XML or a
/// document that is not a URDF, `base: no link named "x"`, `tip: link "t" is
/// not below base link "b"`, `joint "j3": axis has zero length`,
/// `joint "j3": origin.xyz[1] is not a finite number`, `joint "j": mimic
/// joints cannot be imported …`, `joint "j": link "c" already has parent
/// joint "k" (closed loops are not supported)`.
///
/// # Example
/// ```
/// use skeleton_avoidance::kinematics::{Robot, urdf::{robot_from_urdf, UrdfOptions}};
/// let xml = r#"<robot name="r">
///   <link name="base"/><link name="l1"/>
///   <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/>
///     <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/></joint>
/// </robot>"#;
/// let spec = robot_from_urdf(xml, &UrdfOptions::default())?;
/// assert_eq!(spec.joint_names.as_deref(), Some(&["j1".to_owned()][..]));
/// let robot = Robot::from_spec(&spec)?;
/// # Ok::<(), skeleton_avoidance::FieldError>(())
/// ```
///
/// See also [`dh::dh_chain`], [`Robot::from_spec`].
pub fn robot_from_urdf(xml: &str, options: &UrdfOptions) -> Result<RobotSpec, FieldError> {
    let urdf = urdf_rs::read_from_string(xml)
        .map_err(|e| FieldError::new("xml", format!("not a readable URDF: {e}")))?;
    let tree = Tree::new(&urdf)?;
    let base = tree.base(options.base.as_deref())?;
    let tip = match options.tip.as_deref() {
        Some(t) => {
            tree.link(t, "tip")?;
            t.to_owned()
        }
        None => tree.default_tip(&base),
    };
    let path = tree.path(&base, &tip)?;
    let chain = Chain::read(&urdf, &path)?;
    if chain.axes.is_empty() {
        return Err(FieldError::new(
            "tip",
            format!(
                "no revolute, continuous or prismatic joint between base \"{base}\" and tip \"{tip}\""
            ),
        ));
    }
    chain.into_spec(&urdf.name, options.srdf.as_deref())
}

/// The `disable_collisions` pairs of an SRDF document between links of the
/// chain, as rows (`rows`: link → row). Pairs naming links outside the
/// chain, or two links moved by the same row, change nothing and are left
/// out; a pair listed twice is kept once.
///
/// # Errors
/// `srdf: …` for a document that is not well-formed XML or an element
/// without `link1` / `link2`.
fn srdf_pairs(
    srdf: Option<&str>,
    rows: &[(String, usize)],
) -> Result<Vec<[LinkRef; 2]>, FieldError> {
    use quick_xml::events::Event;
    let Some(xml) = srdf else {
        return Ok(Vec::new());
    };
    let row = |name: &str| rows.iter().find(|(l, _)| l == name).map(|(_, r)| *r);
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut out: Vec<[LinkRef; 2]> = Vec::new();
    loop {
        let event = reader
            .read_event()
            .map_err(|e| FieldError::new("srdf", format!("not well-formed XML: {e}")))?;
        let element = match &event {
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == b"disable_collisions" => e,
            Event::Eof => break,
            _ => continue,
        };
        let link = |key: &[u8]| -> Result<String, FieldError> {
            element
                .try_get_attribute(key)
                .ok()
                .flatten()
                .and_then(|a| a.unescape_value().ok().map(|v| v.into_owned()))
                .ok_or_else(|| {
                    FieldError::new(
                        "srdf",
                        format!(
                            "a disable_collisions element without {}",
                            String::from_utf8_lossy(key)
                        ),
                    )
                })
        };
        let (a, b) = (link(b"link1")?, link(b"link2")?);
        if let (Some(a), Some(b)) = (row(&a), row(&b)) {
            let pair = [LinkRef::Index(a.min(b)), LinkRef::Index(a.max(b))];
            if a != b && !out.contains(&pair) {
                out.push(pair);
            }
        }
    }
    Ok(out)
}

/// The links and joints of a URDF as a tree.
struct Tree<'a> {
    urdf: &'a urdf_rs::Robot,
    links: HashSet<&'a str>,
    /// Child link → index of its parent joint.
    parent: HashMap<&'a str, usize>,
    /// Parent link → indices of its child joints, in document order.
    children: HashMap<&'a str, Vec<usize>>,
}

fn joint_error(name: &str, reason: impl Into<String>) -> FieldError {
    FieldError::new(format!("joint \"{name}\""), reason)
}

impl<'a> Tree<'a> {
    fn new(urdf: &'a urdf_rs::Robot) -> Result<Self, FieldError> {
        let links: HashSet<&str> = urdf.links.iter().map(|l| l.name.as_str()).collect();
        let mut parent = HashMap::new();
        let mut children: HashMap<&str, Vec<usize>> = HashMap::new();
        for (k, j) in urdf.joints.iter().enumerate() {
            for (what, l) in [("parent", &j.parent.link), ("child", &j.child.link)] {
                if !links.contains(l.as_str()) {
                    return Err(joint_error(
                        &j.name,
                        format!("{what} link \"{l}\" is not defined"),
                    ));
                }
            }
            if let Some(&other) = parent.get(j.child.link.as_str()) {
                let other: &urdf_rs::Joint = &urdf.joints[other];
                return Err(joint_error(
                    &j.name,
                    format!(
                        "link \"{}\" already has parent joint \"{}\" (closed loops are not supported)",
                        j.child.link, other.name
                    ),
                ));
            }
            parent.insert(j.child.link.as_str(), k);
            children.entry(j.parent.link.as_str()).or_default().push(k);
        }
        Ok(Self {
            urdf,
            links,
            parent,
            children,
        })
    }

    fn link(&self, name: &str, field: &str) -> Result<(), FieldError> {
        if self.links.contains(name) {
            Ok(())
        } else {
            Err(FieldError::new(field, format!("no link named \"{name}\"")))
        }
    }

    fn base(&self, requested: Option<&str>) -> Result<String, FieldError> {
        if let Some(b) = requested {
            self.link(b, "base")?;
            return Ok(b.to_owned());
        }
        let roots: Vec<&str> = self
            .urdf
            .links
            .iter()
            .map(|l| l.name.as_str())
            .filter(|l| !self.parent.contains_key(l))
            .collect();
        match roots.as_slice() {
            [root] => Ok((*root).to_owned()),
            [] => Err(FieldError::new(
                "xml",
                "no root link (every link has a parent joint: a closed loop)",
            )),
            many => Err(FieldError::new(
                "base",
                format!(
                    "the URDF has several root links ({}); name one",
                    many.iter()
                        .map(|r| format!("\"{r}\""))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// Whether joint `k` counts towards the default tip's chain.
    fn is_chain_joint(&self, k: usize) -> bool {
        let j = &self.urdf.joints[k];
        j.mimic.is_none()
            && matches!(
                j.joint_type,
                UrdfJointType::Revolute | UrdfJointType::Continuous | UrdfJointType::Prismatic
            )
    }

    /// The end of the longest chain of movable, non-mimic joints below
    /// `base` (the first in document order on ties), then through single
    /// fixed joints.
    fn default_tip(&self, base: &str) -> String {
        let mut best = (0usize, base);
        let mut stack = vec![(base, 0usize)];
        let mut seen = HashSet::new();
        while let Some((link, count)) = stack.pop() {
            if !seen.insert(link) {
                continue;
            }
            if count > best.0 {
                best = (count, link);
            }
            let kids = self.children.get(link).map_or(&[][..], Vec::as_slice);
            for &k in kids.iter().rev() {
                let j = &self.urdf.joints[k];
                let next = match j.joint_type {
                    UrdfJointType::Fixed => count,
                    _ if self.is_chain_joint(k) => count + 1,
                    _ => continue,
                };
                stack.push((j.child.link.as_str(), next));
            }
        }
        let mut tip = best.1;
        let mut steps = 0;
        while let Some([k]) = self.children.get(tip).map(Vec::as_slice) {
            let j = &self.urdf.joints[*k];
            if j.joint_type != UrdfJointType::Fixed || steps > self.urdf.joints.len() {
                break;
            }
            tip = j.child.link.as_str();
            steps += 1;
        }
        tip.to_owned()
    }

    /// Indices of the joints from `base` down to `tip`, in chain order.
    fn path(&self, base: &str, tip: &str) -> Result<Vec<usize>, FieldError> {
        let mut out = Vec::new();
        let mut link = tip;
        while link != base {
            let Some(&k) = self.parent.get(link) else {
                return Err(FieldError::new(
                    "tip",
                    format!("link \"{tip}\" is not below base link \"{base}\""),
                ));
            };
            if out.len() > self.urdf.joints.len() {
                return Err(joint_error(
                    &self.urdf.joints[k].name,
                    "is part of a closed loop (not supported)",
                ));
            }
            out.push(k);
            link = self.urdf.joints[k].parent.link.as_str();
        }
        out.reverse();
        Ok(out)
    }
}

/// The chain read from the URDF at q = 0, in the base link's frame.
struct Chain {
    axes: Vec<dh::AxisLine>,
    joints: Vec<JointSpec>,
    names: Vec<String>,
    /// The child link of each moving joint.
    links: Vec<String>,
    /// Every link of the path and the row that moves it (0: the base).
    rows: Vec<(String, usize)>,
    tip: DAffine3,
}

fn finite_vec(joint: &str, what: &str, v: [f64; 3]) -> Result<DVec3, FieldError> {
    for (k, c) in v.iter().enumerate() {
        if !c.is_finite() {
            return Err(joint_error(
                joint,
                format!("{what}[{k}] is not a finite number"),
            ));
        }
    }
    Ok(DVec3::from_array(v))
}

/// `Rz(yaw) Ry(pitch) Rx(roll)`: URDF's fixed-axis roll, pitch, yaw.
fn rpy_matrix(rpy: DVec3) -> DMat3 {
    let (sr, cr) = math::sin_cos(rpy.x);
    let (sp, cp) = math::sin_cos(rpy.y);
    let (sy, cy) = math::sin_cos(rpy.z);
    DMat3::from_cols(
        DVec3::new(cy * cp, sy * cp, -sp),
        DVec3::new(cy * sp * sr - sy * cr, sy * sp * sr + cy * cr, cp * sr),
        DVec3::new(cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr),
    )
}

fn origin(j: &urdf_rs::Joint) -> Result<DAffine3, FieldError> {
    let xyz = finite_vec(&j.name, "origin.xyz", j.origin.xyz.0)?;
    let rpy = finite_vec(&j.name, "origin.rpy", j.origin.rpy.0)?;
    Ok(DAffine3::from_mat3_translation(rpy_matrix(rpy), xyz))
}

impl Chain {
    fn read(urdf: &urdf_rs::Robot, path: &[usize]) -> Result<Self, FieldError> {
        let links: HashMap<&str, &urdf_rs::Link> =
            urdf.links.iter().map(|l| (l.name.as_str(), l)).collect();
        let mut chain = Self {
            axes: Vec::new(),
            joints: Vec::new(),
            names: Vec::new(),
            links: Vec::new(),
            rows: Vec::new(),
            tip: DAffine3::IDENTITY,
        };
        if let Some(&k) = path.first() {
            chain.rows.push((urdf.joints[k].parent.link.clone(), 0));
        }
        for &k in path {
            let j = &urdf.joints[k];
            chain.tip *= origin(j)?;
            let kind = match j.joint_type {
                UrdfJointType::Fixed => None,
                UrdfJointType::Revolute | UrdfJointType::Continuous => Some(JointType::Revolute),
                UrdfJointType::Prismatic => Some(JointType::Prismatic),
                UrdfJointType::Floating | UrdfJointType::Planar | UrdfJointType::Spherical => {
                    return Err(joint_error(
                        &j.name,
                        format!(
                            "{:?} joints are not supported in the chain (only revolute, continuous, prismatic and fixed); choose a tip before it",
                            j.joint_type
                        )
                        .to_lowercase(),
                    ));
                }
            };
            if let Some(kind) = kind {
                if let Some(m) = &j.mimic {
                    return Err(joint_error(
                        &j.name,
                        format!(
                            "mimic joints cannot be imported (it follows \"{}\"); choose a tip before it",
                            m.joint
                        ),
                    ));
                }
                let axis = finite_vec(&j.name, "axis", j.axis.xyz.0)?;
                let length = axis.length();
                if length < 1e-12 {
                    return Err(joint_error(&j.name, "axis has zero length"));
                }
                chain.axes.push(dh::AxisLine {
                    point: chain.tip.translation,
                    direction: chain.tip.matrix3 * (axis / length),
                });
                chain.joints.push(limits(j, kind)?);
                chain.names.push(j.name.clone());
                chain.links.push(j.child.link.clone());
            }
            chain.rows.push((j.child.link.clone(), chain.joints.len()));
            if let (Some(row), Some(link)) =
                (chain.joints.last_mut(), links.get(j.child.link.as_str()))
            {
                widen(row, link)?;
            }
        }
        Ok(chain)
    }

    fn into_spec(self, name: &str, srdf: Option<&str>) -> Result<RobotSpec, FieldError> {
        let table = dh::dh_chain(&self.axes, &self.tip);
        let mut joints = self.joints;
        for (spec, row) in joints.iter_mut().zip(&table.rows) {
            spec.a = row.a;
            spec.alpha = row.alpha;
            spec.d = row.d;
            spec.theta = row.theta;
        }
        let mut spec = RobotSpec {
            name: (!name.is_empty()).then(|| name.to_owned()),
            convention: Convention::Standard,
            base: Some(pose(&table.base)),
            joints,
            tool: None,
            branches: Vec::new(),
            joint_names: Some(self.names),
            link_names: Some(self.links),
            self_collision_exclude: srdf_pairs(srdf, &self.rows)?,
        };
        // The tool from the frame the library's own forward kinematics puts
        // at the end of the table, so that the two agree at q = 0 to rounding.
        let robot = Robot::from_spec(&spec)?;
        let frames = robot.forward(&vec![0.0; robot.dof()])?;
        let last = frames.transforms[robot.dof()];
        spec.tool = Some(pose(&(last.inverse() * self.tip)));
        Ok(spec)
    }
}

fn pose(t: &DAffine3) -> PoseSpec {
    let q = DQuat::from_mat3(&t.matrix3).normalize();
    PoseSpec {
        position: t.translation.to_array(),
        rotation: q.to_array(),
    }
}

/// A positive, finite limit, or `None` (zero, infinite: not given).
fn given(v: f64) -> Option<f64> {
    (v.is_finite() && v > 0.0).then_some(v)
}

/// The row of joint `j` with its limits (the DH values are filled in later).
fn limits(j: &urdf_rs::Joint, kind: JointType) -> Result<JointSpec, FieldError> {
    let l = &j.limit;
    let mut spec = JointSpec {
        kind,
        max_velocity: given(l.velocity),
        max_torque: given(l.effort),
        max_acceleration: given(l.acceleration),
        max_jerk: given(l.jerk),
        ..JointSpec::default()
    };
    if j.joint_type != UrdfJointType::Continuous {
        if l.lower.is_nan() || l.upper.is_nan() {
            return Err(joint_error(&j.name, "limit is not a finite number"));
        }
        if l.lower > l.upper {
            return Err(joint_error(
                &j.name,
                format!("limit lower ({}) is above upper ({})", l.lower, l.upper),
            ));
        }
        if l.lower < l.upper {
            spec.min = l.lower.is_finite().then_some(l.lower);
            spec.max = l.upper.is_finite().then_some(l.upper);
        }
    }
    Ok(spec)
}

/// Radius of a primitive collision shape around its long axis (m), `None`
/// for meshes.
fn primitive_radius(g: &Geometry) -> Option<f64> {
    match g {
        Geometry::Cylinder { radius, .. }
        | Geometry::Capsule { radius, .. }
        | Geometry::Sphere { radius } => Some(*radius),
        Geometry::Box { size } => {
            let mut s = size.0.map(f64::abs);
            s.sort_by(f64::total_cmp);
            Some(0.5 * s[0].hypot(s[1]))
        }
        Geometry::Mesh { .. } => None,
    }
}

/// Grows the radius of `row` to cover the primitive collision shapes of `link`.
fn widen(row: &mut JointSpec, link: &urdf_rs::Link) -> Result<(), FieldError> {
    for (k, c) in link.collision.iter().enumerate() {
        let Some(r) = primitive_radius(&c.geometry) else {
            continue;
        };
        if !r.is_finite() || r < 0.0 {
            return Err(FieldError::new(
                format!("link \"{}\"", link.name),
                format!(
                    "collision[{k}] has a radius or size that is not a finite, non-negative number"
                ),
            ));
        }
        let current = match row.radius {
            Some(RadiusSpec::Uniform(v)) => v,
            _ => 0.0,
        };
        if r > current {
            row.radius = Some(RadiusSpec::Uniform(r));
        }
    }
    Ok(())
}
