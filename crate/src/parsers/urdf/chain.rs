//! The chain of joints read from a URDF at q = 0 (axes, motion limits,
//! radii of primitive collision shapes) and its spec in standard DH.

use std::collections::HashMap;

use glam::{DAffine3, DQuat};
use urdf_rs::{Geometry, JointType as UrdfJointType};

use super::{finite_vec, joint_error, origin, report};
use crate::error::FieldError;
use crate::kinematics::dh_from_axes;
use crate::kinematics::{Convention, JointSpec, JointType, PoseSpec, RadiusSpec, Robot, RobotSpec};
use crate::parsers::srdf;

/// The chain read from the URDF at q = 0, in the base link's frame.
pub(super) struct Chain {
    pub(super) axes: Vec<dh_from_axes::AxisLine>,
    pub(super) joints: Vec<JointSpec>,
    pub(super) names: Vec<String>,
    /// The child link of each moving joint.
    pub(super) links: Vec<String>,
    /// Every link of the path and the row that moves it (0: the base).
    pub(super) rows: Vec<(String, usize)>,
    pub(super) tip: DAffine3,
    /// Per joint of the path: the child link's row and pose at q = 0.
    pub(super) poses: Vec<(usize, DAffine3)>,
}

impl Chain {
    pub(super) fn read(urdf: &urdf_rs::Robot, path: &[usize]) -> Result<Self, FieldError> {
        let links: HashMap<&str, &urdf_rs::Link> =
            urdf.links.iter().map(|l| (l.name.as_str(), l)).collect();
        let mut chain = Self {
            axes: Vec::new(),
            joints: Vec::new(),
            names: Vec::new(),
            links: Vec::new(),
            rows: Vec::new(),
            tip: DAffine3::IDENTITY,
            poses: Vec::new(),
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
                chain.axes.push(dh_from_axes::AxisLine {
                    point: chain.tip.translation,
                    direction: chain.tip.matrix3 * (axis / length),
                });
                chain.joints.push(limits(j, kind)?);
                chain.names.push(j.name.clone());
                chain.links.push(j.child.link.clone());
            }
            chain.rows.push((j.child.link.clone(), chain.joints.len()));
            chain.poses.push((chain.joints.len(), chain.tip));
            if let (Some(row), Some(link)) =
                (chain.joints.last_mut(), links.get(j.child.link.as_str()))
            {
                widen(row, link)?;
            }
        }
        Ok(chain)
    }

    pub(super) fn into_spec(self, name: &str, srdf: Option<&str>) -> Result<RobotSpec, FieldError> {
        let table = dh_from_axes::dh_chain(&self.axes, &self.tip);
        let mut joints = self.joints;
        for (spec, row) in joints.iter_mut().zip(&table.rows) {
            spec.a = report::clean(row.a);
            spec.alpha = report::clean(row.alpha);
            spec.d = report::clean(row.d);
            spec.theta = report::clean(row.theta);
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
            self_collision_exclude: srdf::disabled_pairs(srdf, &self.rows)?,
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
        position: t.translation.to_array().map(report::clean_length),
        rotation: q.to_array().map(report::clean_length),
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
pub(super) fn primitive_radius(g: &Geometry) -> Option<f64> {
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
