//! Power and force limiting in the world
//! ([`crate::avoidance::protect::pfl`]): the body region of a human's part
//! at a guard pair's witness, the arm's effective mass there and the
//! permissible speed it gives (when the protective mode is `pfl`), and the
//! readout of the bound in force for the human part nearest the arm.

use glam::DVec3;
use serde::Serialize;

use super::parts::{Model, Sensed, State, StepData};
use crate::avoidance::limits::braking_time;
use crate::avoidance::protect::pfl::{OnPart, region_of};
use crate::avoidance::protect::{BodyRegion, ContactLimit, GuardPair, ProtectiveMode};
use crate::control_point::DhPoint;
use crate::distance::Primitive;
use crate::error::FieldError;

/// The bound in force for the human part nearest the arm
/// ([`super::WorldState::protection`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ProtectionReadout {
    /// The part, `id:part` (`person:rightHand`).
    pub part: String,
    /// Its ISO/TS 15066 body region at the witness.
    pub region: BodyRegion,
    /// Which bound holds the arm's approach: `ssm` (separation
    /// monitoring) or `pfl` (the permissible contact speed is the larger).
    pub active: ProtectiveMode,
    /// Clearance (m).
    pub distance: f64,
    /// The separation-monitoring bound on the arm's approach (m/s).
    pub ssm_bound: f64,
    /// In `pfl`, where the region allows transient contact: the arm's
    /// effective mass (kg) and the permissible relative speed (m/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactLimit>,
}

/// The segment's axis and radius-free centre of a capsule or sphere part.
fn axis_of(shape: &Primitive) -> Option<(DVec3, DVec3)> {
    match shape {
        Primitive::Capsule(c) => Some((c.segment.a, c.segment.b)),
        Primitive::Sphere(s) => Some((s.center, s.center)),
        _ => None,
    }
}

/// The body region of scene part `part` (a human's) at `point`.
pub(super) fn region_at(sensed: &Sensed, part: usize, point: DVec3) -> Option<BodyRegion> {
    let o = *sensed.owners.get(part)?;
    let name = sensed.obstacles[o].part_name(*sensed.part_index.get(part)?)?;
    let shapes = sensed.scene.obstacles();
    let (a, b) = axis_of(&shapes.get(part)?.shape)?;
    let start = *sensed.part_start.get(o)?;
    // The body's forward direction: the pelvis (left to right) and the
    // torso (up) of the same figure, parts 0 and 1 of the model.
    let (pl, pr) = axis_of(&shapes.get(start)?.shape)?;
    let (t0, t1) = axis_of(&shapes.get(start + 1)?.shape)?;
    let forward = (pl - pr).cross(t1 - t0).normalize_or_zero();
    let axis = b - a;
    let along = if axis.length_squared() > 0.0 {
        ((point - a).dot(axis) / axis.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let centre = a + axis * along;
    let front = (point - centre).dot(forward) > 0.0;
    let above = point.z > centre.z;
    region_of(
        name,
        OnPart {
            front,
            along,
            above,
        },
    )
}

/// In `pfl`: each guard pair against a human's part whose region allows
/// transient contact gets its [`ContactLimit`] (the arm's effective mass
/// at the witness along the pair's normal, and the permissible speed).
///
/// # Errors
/// A pair whose segment is not in the skeleton (a bug).
pub(super) fn fill_contacts(
    model: &Model,
    state: &State,
    data: &mut StepData,
) -> Result<(), FieldError> {
    let cfg = &model.scenario.controller;
    let Ok(dynamics) = model.dynamics.as_ref() else {
        return Ok(());
    };
    if cfg.protective.mode != ProtectiveMode::Pfl || data.guard.pairs.is_empty() {
        return Ok(());
    }
    let scratch = &mut data.dynamics.scratch;
    scratch
        .factor
        .update(dynamics, &mut scratch.workspace, &state.q)?;
    let mut row = Vec::with_capacity(model.robot.dof());
    for p in &mut data.guard.pairs {
        let Some(part) = p.part.filter(|_| p.other.is_none()) else {
            continue;
        };
        let point = DhPoint::from_skeleton(
            &model.robot,
            &data.frames,
            &data.skeleton,
            p.segment,
            p.fraction.clamp(0.0, 1.0),
        )?;
        let j = point.jacobians(&model.robot, &data.frames);
        let witness = j.position + p.normal * (p.distance.max(0.0) + radius(&data.skeleton, p));
        let Some(region) = region_at(&state.sensed, part, witness) else {
            continue;
        };
        row.clear();
        row.extend(j.j_theta.iter().map(|c| c.dot(p.normal)));
        let arm_mass = scratch.factor.effective_mass(&row);
        p.contact = region
            .permissible_speed(arm_mass)
            .map(|speed| ContactLimit {
                region,
                arm_mass,
                speed,
            });
    }
    Ok(())
}

/// The radius of the arm's volume at a pair's witness.
fn radius(skeleton: &crate::skeleton::Skeleton, p: &GuardPair) -> f64 {
    skeleton
        .segments
        .get(p.segment)
        .map_or(0.0, |s| crate::skeleton::Skeleton::radius_at(s, p.fraction))
}

/// The readout of the guard pair nearest a human's part: its region and
/// which bound holds it.
pub(super) fn protection_readout(
    model: &Model,
    state: &State,
    data: &StepData,
    dt: f64,
) -> Option<ProtectionReadout> {
    let cfg = &model.scenario.controller;
    let p = data
        .guard
        .pairs
        .iter()
        .filter(|p| p.other.is_none() && p.part.is_some())
        .filter(|p| p.part.is_some_and(|k| state.sensed.is_named_part(k)))
        .min_by(|a, b| a.distance.total_cmp(&b.distance))?;
    let part = p.part?;
    let (a, b) = data
        .skeleton
        .endpoints(data.skeleton.segments.get(p.segment)?);
    let witness =
        a.lerp(b, p.fraction) + p.normal * (p.distance.max(0.0) + radius(&data.skeleton, p));
    let region = region_at(&state.sensed, part, witness)?;
    let braking = braking_time(&model.robot, &state.motion, dt);
    let ssm_bound = cfg.protective.bound(p.distance, p.obstacle_speed, braking);
    let active = match p.contact_bound() {
        Some(b) if b > ssm_bound => ProtectiveMode::Pfl,
        _ => ProtectiveMode::Ssm,
    };
    Some(ProtectionReadout {
        part: state.sensed.scene_part_name(part)?,
        region,
        active,
        distance: p.distance,
        ssm_bound,
        contact: p.contact,
    })
}
