//! The serialisable robot description (the JS "robot spec") and its
//! validation into a [`Robot`](super::Robot).

use glam::{DAffine3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::inertia::{Inertial, InertialSpec};
use crate::error::{FieldError, bounded, finite, finite3, non_negative, positive};

/// DH convention of a robot's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum Convention {
    /// Siciliano & Sciavicco: `A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)`.
    Standard,
    /// Craig: `A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)`; row `i` holds
    /// `a_{i-1}, α_{i-1}, d_i, θ_i`.
    Modified,
}

/// Kind of joint of a DH row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum JointType {
    /// The joint value is added to `theta` (rad).
    #[default]
    Revolute,
    /// The joint value is added to `d` (m).
    Prismatic,
}

/// A pose: position (m) and rotation as a quaternion `[x, y, z, w]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct PoseSpec {
    /// Translation (m).
    #[serde(default)]
    pub position: [f64; 3],
    /// Unit quaternion `[x, y, z, w]`.
    #[serde(default = "identity_quat")]
    pub rotation: [f64; 4],
}

fn identity_quat() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

impl Default for PoseSpec {
    fn default() -> Self {
        Self {
            position: [0.0; 3],
            rotation: identity_quat(),
        }
    }
}

/// Radius of the volume around a link's segments: one value, `[r0, r1]`
/// varying linearly along each segment, or one of these per segment,
/// `{ d?, a?, extension? }` (a segment left out gets [`DEFAULT_RADIUS`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum RadiusSpec {
    /// The same radius along the whole link (m).
    Uniform(f64),
    /// Radius at the start and at the end of each segment of the link (m).
    Tapered([f64; 2]),
    /// A radius (one value or `[r0, r1]`) for each of the link's segments.
    PerSegment(SegmentRadiusSpec),
}

/// One segment's radius in [`RadiusSpec::PerSegment`]: one value or
/// `[r0, r1]` from the segment's start to its end (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SegmentRadius {
    /// The same radius along the segment (m).
    Uniform(f64),
    /// Radius at the start and at the end of the segment (m).
    Tapered([f64; 2]),
}

/// The radii of a row's segments, by the translation each spans (see
/// [`crate::skeleton::SpinePart`]); a segment left out gets
/// [`DEFAULT_RADIUS`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentRadiusSpec {
    /// The segment along the row's `d` translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub d: Option<SegmentRadius>,
    /// The segment along the row's `a` translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a: Option<SegmentRadius>,
    /// The segment behind the start of the `a` spine (the row's `extension`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extension: Option<SegmentRadius>,
}

/// A validated row's radii, at the start and end of each of its segments
/// (m); the same pair thrice for a spec's one-value and `[r0, r1]` forms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkRadii {
    /// The `d` segment's.
    pub d: [f64; 2],
    /// The `a` segment's.
    pub a: [f64; 2],
    /// The extension's.
    pub extension: [f64; 2],
}

impl LinkRadii {
    /// The same pair on every segment.
    #[must_use]
    pub const fn same(r: [f64; 2]) -> Self {
        Self {
            d: r,
            a: r,
            extension: r,
        }
    }

    /// The largest radius of any segment (m).
    #[must_use]
    pub fn max(&self) -> f64 {
        [self.d, self.a, self.extension]
            .iter()
            .flatten()
            .fold(0.0, |m, r| f64::max(m, *r))
    }
}

/// One DH row.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct JointSpec {
    /// Link length `a` (m); `a_{i-1}` in the modified convention.
    pub a: f64,
    /// Link twist `α` (rad); `α_{i-1}` in the modified convention.
    pub alpha: f64,
    /// Link offset `d` (m); the offset added to the joint value of a prismatic joint.
    pub d: f64,
    /// Joint angle `θ` (rad); the offset added to the joint value of a revolute joint.
    pub theta: f64,
    /// Revolute (default) or prismatic.
    #[serde(default, rename = "type")]
    pub kind: JointType,
    /// Lower joint limit (rad or m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Upper joint limit (rad or m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// Joint speed limit (rad/s or m/s), > 0; default
    /// [`DEFAULT_LIMITS`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_velocity: Option<f64>,
    /// Joint acceleration limit (rad/s² or m/s²), > 0; default
    /// [`DEFAULT_LIMITS`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_acceleration: Option<f64>,
    /// Joint jerk limit (rad/s³ or m/s³), > 0; default [`DEFAULT_LIMITS`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_jerk: Option<f64>,
    /// Joint torque (N·m) or force (N) limit, > 0; default
    /// [`DEFAULT_LIMITS`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_torque: Option<f64>,
    /// Radius of the volume around the link's segments (m); default 0.05.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<RadiusSpec>,
    /// Length (m) by which the link's `a` spine extends behind its start
    /// (counterbalances, motors); adds a skeleton segment with `a' < 0`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extension: Option<f64>,
    /// The inertial parameters of the body this row moves (the link and
    /// everything rigidly attached to it), in the row's DH frame; what
    /// [`crate::kinematics::inertia`] validates and the dynamics need.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertial: Option<InertialSpec>,
}

/// A further chain carried by a joint frame of an earlier chain (an arm on a
/// torso).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct BranchSpec {
    /// Display name ("left", "right").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// 1-based index (over all earlier rows) of the joint frame carrying the
    /// branch; 0 is the base.
    pub parent: usize,
    /// Fixed rotation `[x, y, z, w]` between the parent frame and the branch's
    /// first row (no translation: offsets belong in the DH rows, so that the
    /// skeleton spans them).
    #[serde(default = "identity_quat")]
    pub mount: [f64; 4],
    /// The branch's DH rows, in the robot's convention.
    pub joints: Vec<JointSpec>,
    /// Tool transform after the branch's last row.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool: Option<PoseSpec>,
}

/// A robot described by its DH table (the JS robot spec of DESIGN.md).
///
/// The joint vector `q` lists the rows of `joints` first, then the rows of each
/// branch in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct RobotSpec {
    /// Display name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// DH convention of every row.
    pub convention: Convention,
    /// Pose of frame 0 in the world.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<PoseSpec>,
    /// DH rows of the main chain.
    pub joints: Vec<JointSpec>,
    /// Tool transform after the main chain's last row.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool: Option<PoseSpec>,
    /// Further chains on the same base (arms of a torso).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub branches: Vec<BranchSpec>,
    /// Names of the joints in the order of `q` (one per row, branches
    /// included), e.g. the URDF joint names of an imported robot.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_names: Option<Vec<String>>,
    /// Names of the links in the order of `q` (the link each row moves,
    /// e.g. the URDF child link of each joint of an imported robot); what
    /// `selfCollisionExclude` and the events name links by.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub link_names: Option<Vec<String>>,
    /// Pairs of links that never repel each other (an SRDF's
    /// `disable_collisions`, or the user's), each side a row index (1-based,
    /// 0 the base) or a name from `linkNames`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub self_collision_exclude: Vec<[LinkRef; 2]>,
}

/// A link named by its row index (1-based, 0 the base) or, for a robot
/// with `linkNames`, by its name.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum LinkRef {
    /// Row index (1-based; 0 is the base).
    Index(usize),
    /// A name from the robot's `linkNames`.
    Name(String),
}

/// The motion limits of one joint (SI: rad or m, per s, s², s³; N·m or N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Speed limit.
    pub velocity: f64,
    /// Acceleration limit.
    pub acceleration: f64,
    /// Jerk limit.
    pub jerk: f64,
    /// Torque (revolute) or force (prismatic) limit.
    pub torque: f64,
}

/// Limits of a joint whose spec names none, per kind of joint. Finite on
/// purpose: a spec without limits must still give motion a real arm could
/// follow. Revolute: 2 rad/s, 10 rad/s², 5000 rad/s³, 100 N·m (between a
/// Franka Panda's wrist and shoulder joints); prismatic: 0.5 m/s, 2 m/s²,
/// 1000 m/s³, 500 N (a mid-size linear axis).
pub const DEFAULT_LIMITS: [Limits; 2] = [
    Limits {
        velocity: 2.0,
        acceleration: 10.0,
        jerk: 5000.0,
        torque: 100.0,
    },
    Limits {
        velocity: 0.5,
        acceleration: 2.0,
        jerk: 1000.0,
        torque: 500.0,
    },
];

impl JointType {
    /// The limits used for the fields a spec leaves out.
    #[must_use]
    pub fn default_limits(self) -> Limits {
        match self {
            Self::Revolute => DEFAULT_LIMITS[0],
            Self::Prismatic => DEFAULT_LIMITS[1],
        }
    }
}

/// Default radius of a link's volume when the spec names none (m).
pub const DEFAULT_RADIUS: f64 = 0.05;

/// Tolerance on `|q| = 1` for quaternions in a spec.
pub const UNIT_QUAT_TOLERANCE: f64 = 1e-6;

pub(crate) fn rotation(field: &str, r: [f64; 4]) -> Result<DQuat, FieldError> {
    for (k, c) in r.iter().enumerate() {
        finite(&format!("{field}[{k}]"), *c)?;
    }
    let q = DQuat::from_array(r);
    let n = q.length();
    if n < 1e-12 {
        return Err(FieldError::new(
            field,
            "degenerate quaternion (zero length)",
        ));
    }
    if (n - 1.0).abs() > UNIT_QUAT_TOLERANCE {
        return Err(FieldError::new(
            field,
            format!("quaternion [x, y, z, w] must have unit length, got |q| = {n}"),
        ));
    }
    Ok(q / n)
}

fn radius(field: &str, r: f64) -> Result<f64, FieldError> {
    bounded(field, non_negative(field, r)?, MAX_RADIUS)
}

/// One segment's pair from its spec form, `field` naming it.
fn segment_radius(field: &str, r: Option<SegmentRadius>) -> Result<[f64; 2], FieldError> {
    Ok(match r {
        None => [DEFAULT_RADIUS; 2],
        Some(SegmentRadius::Uniform(r)) => [radius(field, r)?; 2],
        Some(SegmentRadius::Tapered([r0, r1])) => [
            radius(&format!("{field}[0]"), r0)?,
            radius(&format!("{field}[1]"), r1)?,
        ],
    })
}

/// A row's radii from its `radius` field (named `field`).
fn link_radii(field: &str, r: Option<RadiusSpec>) -> Result<LinkRadii, FieldError> {
    Ok(match r {
        None => LinkRadii::same([DEFAULT_RADIUS; 2]),
        Some(RadiusSpec::Uniform(r)) => {
            LinkRadii::same(segment_radius(field, Some(SegmentRadius::Uniform(r)))?)
        }
        Some(RadiusSpec::Tapered(r)) => {
            LinkRadii::same(segment_radius(field, Some(SegmentRadius::Tapered(r)))?)
        }
        Some(RadiusSpec::PerSegment(s)) => LinkRadii {
            d: segment_radius(&format!("{field}.d"), s.d)?,
            a: segment_radius(&format!("{field}.a"), s.a)?,
            extension: segment_radius(&format!("{field}.extension"), s.extension)?,
        },
    })
}

pub(crate) fn pose(field: &str, p: &PoseSpec) -> Result<DAffine3, FieldError> {
    let t = finite3(&format!("{field}.position"), DVec3::from_array(p.position))?;
    for (k, c) in p.position.iter().enumerate() {
        bounded(&format!("{field}.position[{k}]"), *c, MAX_MAGNITUDE)?;
    }
    let r = rotation(&format!("{field}.rotation"), p.rotation)?;
    Ok(DAffine3::from_rotation_translation(r, t))
}

/// A validated DH row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joint {
    /// Link length `a` (m).
    pub a: f64,
    /// Link twist `α` (rad).
    pub alpha: f64,
    /// Link offset `d` (m) (offset of the joint value when prismatic).
    pub d: f64,
    /// Joint angle `θ` (rad) (offset of the joint value when revolute).
    pub theta: f64,
    /// Revolute or prismatic.
    pub kind: JointType,
    /// Lower limit (−∞ when none).
    pub min: f64,
    /// Upper limit (+∞ when none).
    pub max: f64,
    /// Speed limit (the kind's default when the spec names none).
    pub max_velocity: f64,
    /// Acceleration limit.
    pub max_acceleration: f64,
    /// Jerk limit.
    pub max_jerk: f64,
    /// Torque (N·m) or force (N) limit.
    pub max_torque: f64,
    /// Radius at the start and end of each of the link's segments (m).
    pub radius: LinkRadii,
    /// Extension of the `a` spine behind its start (m, ≥ 0).
    pub extension: f64,
    /// The moved body's inertial parameters in the row's DH frame, when
    /// the spec gives them.
    pub inertial: Option<Inertial>,
    /// Index of the frame this row starts from: 0 is the base, `k` the frame
    /// after row `k`.
    pub parent: usize,
    /// Fixed rotation from the parent frame to this row's start (branches).
    pub mount: Option<DQuat>,
}

/// Largest magnitude of a DH length (`a`, `d`, a base position, an
/// extension, a prismatic limit) in metres, and of an angle or a limit in
/// any unit: inside it every frame, Jacobian and rate stays finite.
pub const MAX_MAGNITUDE: f64 = 1e6;

/// Largest radius of a link's volume (m).
pub const MAX_RADIUS: f64 = 1e3;

pub(crate) fn joint(field: &str, j: &JointSpec, parent: usize) -> Result<Joint, FieldError> {
    let big = |name: &str, v: f64| bounded(&format!("{field}.{name}"), v, MAX_MAGNITUDE);
    let a = big("a", j.a)?;
    let alpha = big("alpha", j.alpha)?;
    let d = big("d", j.d)?;
    let theta = big("theta", j.theta)?;
    let min = match j.min {
        Some(v) => big("min", v)?,
        None => f64::NEG_INFINITY,
    };
    let max = match j.max {
        Some(v) => big("max", v)?,
        None => f64::INFINITY,
    };
    if min > max {
        return Err(FieldError::new(
            format!("{field}.min"),
            format!("{min} is above max {max}"),
        ));
    }
    let defaults = j.kind.default_limits();
    let limit = |name: &str, v: Option<f64>, default: f64| match v {
        Some(v) => positive(&format!("{field}.{name}"), v)
            .and_then(|v| bounded(&format!("{field}.{name}"), v, MAX_MAGNITUDE)),
        None => Ok(default),
    };
    let max_velocity = limit("maxVelocity", j.max_velocity, defaults.velocity)?;
    let max_acceleration = limit("maxAcceleration", j.max_acceleration, defaults.acceleration)?;
    let max_jerk = limit("maxJerk", j.max_jerk, defaults.jerk)?;
    let max_torque = limit("maxTorque", j.max_torque, defaults.torque)?;
    let radius = link_radii(&format!("{field}.radius"), j.radius)?;
    let extension = match j.extension {
        Some(e) => bounded(
            &format!("{field}.extension"),
            non_negative(&format!("{field}.extension"), e)?,
            MAX_MAGNITUDE,
        )?,
        None => 0.0,
    };
    let inertial = match &j.inertial {
        Some(spec) => {
            Some(Inertial::from_spec(spec).map_err(|e| e.within(&format!("{field}.inertial")))?)
        }
        None => None,
    };
    Ok(Joint {
        a,
        alpha,
        d,
        theta,
        kind: j.kind,
        min,
        max,
        max_velocity,
        max_acceleration,
        max_jerk,
        max_torque,
        radius,
        extension,
        inertial,
        parent,
        mount: None,
    })
}
