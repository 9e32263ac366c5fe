//! URDF reader: a robot spec in standard DH, with its skeleton, from a URDF
//! description (and, optionally, the SRDF beside it: [`super::srdf`]).
//!
//! [`robot_from_urdf`] parses the XML (with `urdf-rs`), takes the chain of
//! joints from a base link to a tip link, and turns the joint axes at the
//! zero configuration into a standard DH table (the DH construction is
//! kinematics, not reading: [`dh_from_axes`]): the pose of DH frame 0 in
//! the base link becomes the spec's `base`, the pose of the tip link in the
//! last DH frame its `tool`. The forward kinematics of the spec then
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
//!   handled (see [`dh_from_axes`] for the choices,
//!   [`PARALLEL_TOLERANCE`](crate::kinematics::dh_from_axes::PARALLEL_TOLERANCE)
//!   for axes nearly parallel).
//! - Limits: `lower`/`upper` become `min`/`max` (none for `continuous`, and
//!   none when `lower == upper`, which is how a missing `<limit>` reads);
//!   `velocity` → `maxVelocity`, `effort` → `maxTorque`, and URDF 1.2's
//!   `acceleration`, `jerk` → `maxAcceleration`, `maxJerk` (zero or infinite
//!   values are left to the documented defaults).
//! - Radii: the largest radius over the primitive collision geometry of the
//!   links a row moves until the next joint (cylinder and capsule: their
//!   radius; sphere: its radius; box: half the diagonal of its two smaller
//!   sides); rows with only meshes (or nothing) keep the default radius
//!   ([`crate::kinematics::DEFAULT_RADIUS`], 0.05 m). With the mesh files at
//!   hand, [`crate::fitting::fit_urdf`] replaces these radii by ones fitted to the
//!   collision meshes (JS: `robotFromUrdf(xml, { meshes })`, `fitUrdf`);
//!   [`robot_with_links`] lists the links with their meshes and poses.
//!   [`UrdfOptions::radii`] replaces a link's geometry by a radius.
//! - Inertial data: every `<inertial>` of the links a row moves, carried
//!   into the row's DH frame and lumped into one body per row (the fixed
//!   links with the moving link they ride on): the row's `inertial` (the
//!   private `inertials.rs` says how; a row whose links carry no mass gets
//!   none). Bad data (negative mass, a tensor that is not positive
//!   semi-definite or breaks the triangle inequality) is refused, naming
//!   the link.
//! - The spec carries every value used (radius and motion limits, the
//!   defaults written in); DH values are cleaned of rounding dust
//!   ([`report::clean`]); [`import_urdf`] also returns a
//!   [`report::UrdfReport`] of what was defaulted and left out.
//!
//! Not imported: mimic joints, `floating`, `planar` and `spherical` joints in
//! the chain (an error names the joint: choose a tip before it), closed loops
//! (a link with two parent joints is an error), joints outside the chain
//! (other arms, fingers, sensors) and the geometry of links outside it.
//!
//! Limits of the reader: the text is parsed whole by `urdf-rs` (its size is
//! limited by the caller: the JavaScript binding reads at most what a file
//! input gives); mesh files are not read here (see [`super::mesh`]), only
//! named ([`MeshRef`]).
//!
//! [`dh_from_axes`]: crate::kinematics::dh_from_axes

mod chain;
mod inertials;
mod links;
pub mod report;
mod tree;

use chain::Chain;
pub use inertials::link_inertial;
use links::chain_links;
use tree::Tree;

use std::collections::BTreeMap;

use glam::{DAffine3, DMat3, DVec3};
use serde::Deserialize;

use crate::error::FieldError;
use crate::kinematics::RobotSpec;
use crate::math;

/// Which part of the URDF to import.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
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
    /// Radius (m) per link name, instead of its collision geometry: a row's
    /// radius is the largest over the links it moves.
    #[serde(default)]
    pub radii: Option<BTreeMap<String, f64>>,
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
/// use skeleton_avoidance::kinematics::Robot;
/// use skeleton_avoidance::parsers::urdf::{robot_from_urdf, UrdfOptions};
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
/// See also [`dh_chain`](crate::kinematics::dh_from_axes::dh_chain),
/// [`Robot::from_spec`](crate::kinematics::Robot::from_spec).
pub fn robot_from_urdf(xml: &str, options: &UrdfOptions) -> Result<RobotSpec, FieldError> {
    Ok(import_urdf(xml, options)?.robot)
}

/// [`robot_from_urdf`] with what it did: the spec (every motion limit and
/// radius filled in) and a [`report::UrdfReport`] of the radii's sources,
/// the defaulted limits, the links without primitive collision shapes and
/// the joints outside the chain (`world::import_urdf` adds the links
/// overlapping at q = 0).
///
/// # Errors
/// As [`robot_from_urdf`], and `radii.<link>: …` for a bad override.
pub fn import_urdf(xml: &str, options: &UrdfOptions) -> Result<report::UrdfImport, FieldError> {
    import_with_links(xml, options).map(|(import, _)| import)
}

/// A link of the imported chain and its geometry at `q = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainLink {
    /// The URDF link's name.
    pub name: String,
    /// 1-based DH row whose frame carries it (0: the base link and the links
    /// fixed to it).
    pub row: usize,
    /// Pose of the link frame in the spec's world frame at `q = 0`.
    pub pose: DAffine3,
    /// Its `<collision>` meshes.
    pub collision: Vec<MeshRef>,
    /// Its `<visual>` meshes.
    pub visual: Vec<MeshRef>,
}

/// A `<mesh>` named by a link's `<visual>` or `<collision>`.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshRef {
    /// The `filename` as written (`package://…`, relative or absolute).
    pub filename: String,
    /// `<mesh scale>` (1 per axis when absent).
    pub scale: DVec3,
    /// The element's `<origin>` in the link frame.
    pub origin: DAffine3,
}

/// [`robot_from_urdf`], and the links of the chain with their meshes and
/// poses at `q = 0` in the spec's world frame (the base link first, then
/// each link after a joint of the chain, fixed ones included).
///
/// # Errors
/// As [`robot_from_urdf`]; also a mesh `<origin>` or `scale` that is not
/// finite (`link "l": collision[0] …`).
pub fn robot_with_links(
    xml: &str,
    options: &UrdfOptions,
) -> Result<(RobotSpec, Vec<ChainLink>), FieldError> {
    import_with_links(xml, options).map(|(import, links)| (import.robot, links))
}

/// The import, its report and the chain's links.
fn import_with_links(
    xml: &str,
    options: &UrdfOptions,
) -> Result<(report::UrdfImport, Vec<ChainLink>), FieldError> {
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
    let links = chain_links(&urdf, &base, &path, &chain)?;
    let mut robot = chain.into_spec(&urdf.name, options.srdf.as_deref())?;
    inertials::fill_inertials(&urdf, &mut robot, &links)?;
    let report = report::complete(&urdf, &path, &mut robot, options)?;
    Ok((report::UrdfImport { robot, report }, links))
}

fn joint_error(name: &str, reason: impl Into<String>) -> FieldError {
    FieldError::new(format!("joint \"{name}\""), reason)
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
