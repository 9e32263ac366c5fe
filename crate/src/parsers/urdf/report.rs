//! What the URDF import did, so that a caller need not re-read the XML: the
//! radius each row got and where from (the links' primitive collision
//! shapes, an override, or the default), the limits left to the defaults
//! (and written into the spec, so the values used are visible), the links
//! without primitive collision geometry, the joints outside the chain, and
//! the pairs of links that overlap at the zero configuration (by their URDF
//! names: an import that starts in self-collision says where; computed by
//! `world::import_urdf`, since the reader builds no skeleton and measures
//! no distance).
//!
//! Also the cleaning of the DH table: values within [`DUST`] of 0, ±π/2 or
//! ±π are set to them exactly (`-1.11e-16` → `0`, `-0` → `0`).

use std::collections::BTreeMap;

use serde::Serialize;
use urdf_rs::{Geometry, JointType as UrdfJointType};

use super::UrdfOptions;
use crate::error::FieldError;
use crate::kinematics::{DEFAULT_RADIUS, RadiusSpec, RobotSpec};

/// Values closer than this to 0, ±π/2 or ±π are rounding dust (rad or m).
pub const DUST: f64 = 1e-14;

/// Largest radius an override may give (m), as for any spec.
const MAX_RADIUS: f64 = 1000.0;

/// `v` with floating-point dust removed: exactly 0, ±π/2 or ±π when within
/// [`DUST`] of them, and never `-0`.
#[must_use]
pub fn clean(v: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    for target in [0.0, FRAC_PI_2, -FRAC_PI_2, PI, -PI] {
        if (v - target).abs() < DUST {
            return target + 0.0;
        }
    }
    v
}

/// `v` with dust removed around 0 only (lengths, quaternion components).
#[must_use]
pub fn clean_length(v: f64) -> f64 {
    if v.abs() < DUST { 0.0 } else { v }
}

/// Where a row's radius came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub enum RadiusFrom {
    /// The largest primitive collision shape of the links it moves.
    Collision,
    /// `options.radii` for one of its links.
    Override,
    /// None of its links has a primitive collision shape: [`DEFAULT_RADIUS`].
    Default,
}

/// One imported joint (one DH row).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct JointReport {
    /// The URDF joint.
    pub name: String,
    /// The links it moves up to the next joint (its child, then links
    /// attached by fixed joints).
    pub links: Vec<String>,
    /// The radius of its volume (m).
    pub radius: f64,
    /// Where that radius came from.
    pub radius_from: RadiusFrom,
    /// Spec fields the URDF did not give and the defaults filled in
    /// (`maxVelocity`, `maxAcceleration`, `maxJerk`, `maxTorque`).
    pub defaulted: Vec<&'static str>,
    /// Whether it has position limits (`min`, `max`); continuous joints and
    /// `lower == upper` have none.
    pub position_limits: bool,
}

/// Two links whose volumes overlap at the zero configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct StartContact {
    /// The URDF links (the first link of each row).
    pub links: [String; 2],
    /// The URDF joints that move them.
    pub joints: [String; 2],
    /// Their clearance (m, negative: overlap depth).
    pub distance: f64,
}

/// What [`super::import_urdf`] did besides the spec.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct UrdfReport {
    /// One per imported joint, in the order of `q`.
    pub joints: Vec<JointReport>,
    /// Links of the chain with no primitive collision shape (only meshes,
    /// or none): they did not size any volume.
    pub links_without_primitive: Vec<String>,
    /// Joints of the document outside the chain (not imported).
    pub outside_chain: Vec<String>,
    /// Self-collision at the zero configuration (non-adjacent links whose
    /// volumes overlap): a simulation starting there stops at once. Filled
    /// by `world::import_urdf` (the skeleton and the distance queries are
    /// built on this module); empty from [`super::import_urdf`].
    pub start_contacts: Vec<StartContact>,
}

/// The spec and what the import did.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct UrdfImport {
    /// The robot spec (every limit and radius filled in).
    pub robot: RobotSpec,
    /// What was read, defaulted and left out.
    pub report: UrdfReport,
}

/// The links each movable joint of `path` moves, up to the next one.
fn row_links(urdf: &urdf_rs::Robot, path: &[usize]) -> Vec<Vec<String>> {
    let mut rows: Vec<Vec<String>> = Vec::new();
    for &k in path {
        let j = &urdf.joints[k];
        if j.joint_type == UrdfJointType::Fixed {
            if let Some(row) = rows.last_mut() {
                row.push(j.child.link.clone());
            }
        } else {
            rows.push(vec![j.child.link.clone()]);
        }
    }
    rows
}

/// The largest primitive collision radius of `link` (see
/// [`super::chain::primitive_radius`]), `None` when it has none.
fn link_radius(link: &urdf_rs::Link) -> Option<f64> {
    link.collision
        .iter()
        .filter_map(|c| match c.geometry {
            Geometry::Mesh { .. } => None,
            ref g => super::chain::primitive_radius(g),
        })
        .filter(|r| r.is_finite())
        .reduce(f64::max)
}

fn check_overrides(
    urdf: &urdf_rs::Robot,
    rows: &[Vec<String>],
    radii: &BTreeMap<String, f64>,
) -> Result<(), FieldError> {
    for (name, &r) in radii {
        let field = format!("radii.{name}");
        if !urdf.links.iter().any(|l| &l.name == name) {
            return Err(FieldError::new(field, format!("no link named \"{name}\"")));
        }
        if !rows.iter().flatten().any(|l| l == name) {
            return Err(FieldError::new(
                field,
                "this link is not moved by the imported chain",
            ));
        }
        if !(r.is_finite() && r > 0.0 && r <= MAX_RADIUS) {
            return Err(FieldError::new(
                field,
                format!("must be a number in (0, {MAX_RADIUS}] m, got {r}"),
            ));
        }
    }
    Ok(())
}

/// Sets each row's radius (overrides, then collision shapes, then the
/// default), fills the motion limits the URDF left out, and reports it all.
///
/// # Errors
/// `radii.<link>: …` for an override naming no link of the chain or out of
/// range; nothing is changed then.
pub(super) fn complete(
    urdf: &urdf_rs::Robot,
    path: &[usize],
    spec: &mut RobotSpec,
    options: &UrdfOptions,
) -> Result<UrdfReport, FieldError> {
    let rows = row_links(urdf, path);
    let none = BTreeMap::new();
    let radii = options.radii.as_ref().unwrap_or(&none);
    check_overrides(urdf, &rows, radii)?;
    let links: BTreeMap<&str, &urdf_rs::Link> =
        urdf.links.iter().map(|l| (l.name.as_str(), l)).collect();
    let names = spec.joint_names.clone().unwrap_or_default();
    let mut report = UrdfReport::default();
    for (k, (joint, row)) in spec.joints.iter_mut().zip(&rows).enumerate() {
        let mut from = RadiusFrom::Default;
        let mut radius = 0.0_f64;
        for l in row {
            let (r, source) = match radii.get(l) {
                Some(&r) => (Some(r), RadiusFrom::Override),
                None => {
                    let r = links.get(l.as_str()).and_then(|link| link_radius(link));
                    if r.is_none() {
                        report.links_without_primitive.push(l.clone());
                    }
                    (r, RadiusFrom::Collision)
                }
            };
            if let Some(r) = r
                && (from == RadiusFrom::Default || r > radius)
            {
                radius = r;
                from = source;
            }
        }
        if from == RadiusFrom::Default {
            radius = DEFAULT_RADIUS;
        }
        joint.radius = Some(RadiusSpec::Uniform(radius));
        let defaults = joint.kind.default_limits();
        let mut defaulted = Vec::new();
        for (field, slot, value) in [
            ("maxVelocity", &mut joint.max_velocity, defaults.velocity),
            (
                "maxAcceleration",
                &mut joint.max_acceleration,
                defaults.acceleration,
            ),
            ("maxJerk", &mut joint.max_jerk, defaults.jerk),
            ("maxTorque", &mut joint.max_torque, defaults.torque),
        ] {
            if slot.is_none() {
                *slot = Some(value);
                defaulted.push(field);
            }
        }
        report.joints.push(JointReport {
            name: names.get(k).cloned().unwrap_or_default(),
            links: row.clone(),
            radius,
            radius_from: from,
            defaulted,
            position_limits: joint.min.is_some() || joint.max.is_some(),
        });
    }
    report.outside_chain = urdf
        .joints
        .iter()
        .enumerate()
        .filter(|(k, _)| !path.contains(k))
        .map(|(_, j)| j.name.clone())
        .collect();
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::clean;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn dust_goes_and_real_values_stay() {
        assert_eq!(clean(-1.11e-16).to_bits(), 0.0_f64.to_bits());
        assert_eq!(clean(-0.0).to_bits(), 0.0_f64.to_bits());
        assert_eq!(clean(FRAC_PI_2 + 2.2e-16), FRAC_PI_2);
        assert_eq!(clean(-FRAC_PI_2 - 2.2e-16), -FRAC_PI_2);
        assert_eq!(clean(0.333), 0.333);
        assert_eq!(clean(1e-9), 1e-9);
    }
}
