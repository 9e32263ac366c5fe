//! The *propagate* stage of a [`World`] step: first-order standard
//! deviations, caused by the sensing errors, of each control point's
//! clearance, of its witness's DH values, of its repulsion and of the joint
//! command ([`crate::dependability::propagate`]). The step keeps what it
//! needs ([`SigmaInput`]) for the control points that answer an obstacle
//! sensed with a random error; the figures are computed when the state or a
//! trace sample is read ([`World::propagation`]), from the step's own data,
//! so they cost nothing to steps nobody reads and change nothing in the
//! motion.

use glam::DVec3;

use serde::Serialize;

use super::World;
use super::control::request_for;
use super::obstacles::SwitchOdds;
use crate::avoidance::{ControllerConfig, repulsion_speed};
use crate::control_point::DhPoint;
use crate::dependability::propagate::{Covariance, FD_STEP};
use crate::dependability::{PointSigma, SensingSpec, SensorModel, switch_probability};
use crate::distance::{BroadPhase, Obstacle, PairDistance, QueryOptions, Scene};
use crate::error::FieldError;
use crate::scenario::{ScenarioError, ShapeSpec, primitives};
use crate::transition::SkeletonPoint;

/// What an obstacle would face at a place, with the arm where it is
/// ([`World::risk_at`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Risk {
    /// Clearance between the arm and the figure (m; infinite for a robot
    /// without segments).
    pub clearance: f64,
    /// Probability that the closest segment, as sensed, differs from the
    /// ideal one.
    pub switch_probability: f64,
    /// The closest segment.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub segment: Option<usize>,
    /// The likeliest other segment.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alternative: Option<usize>,
}

/// The switch odds of the closest pair `best` of one obstacle against its
/// other pairs `pairs`: each other segment's own closest pair counts when
/// its witness is farther than `jump` from `best`'s. Also returns that
/// likeliest alternative pair.
pub(super) fn segment_odds<'a, I>(
    pairs: I,
    best: &PairDistance,
    jump: f64,
    covariance: &Covariance,
) -> (SwitchOdds, Option<&'a PairDistance>)
where
    I: IntoIterator<Item = &'a PairDistance>,
    I::IntoIter: Clone,
{
    // Each other segment's closest pair (the first of equal ones), in the
    // order of the segments, read off the pairs without collecting them
    // (this runs for every obstacle at every step).
    let pairs = pairs.into_iter();
    let counts = |p: &PairDistance| {
        p.segment != best.segment && (p.point_segment - best.point_segment).length() > jump
    };
    let closest_on = |segment: usize| {
        pairs
            .clone()
            .filter(|p| p.segment == segment && counts(p))
            .fold(None, |e: Option<&'a PairDistance>, p| match e {
                Some(e) if p.distance < e.distance => Some(p),
                Some(e) => Some(e),
                None => Some(p),
            })
    };
    let next_segment = |after: Option<usize>| {
        pairs
            .clone()
            .filter(|p| counts(p) && after.is_none_or(|a| p.segment > a))
            .map(|p| p.segment)
            .min()
    };
    let others = std::iter::successors(next_segment(None), |&s| next_segment(Some(s)))
        .filter_map(closest_on);
    let probability = if covariance.is_zero() {
        0.0
    } else {
        switch_probability(
            (best.distance, best.normal),
            others.clone().map(|p| (p.distance, p.normal)),
            covariance,
        )
    };
    let alt = others.min_by(|x, y| x.distance.total_cmp(&y.distance));
    let odds = SwitchOdds {
        probability,
        segment: Some(best.segment),
        alternative: alt.map(|p| p.segment),
    };
    (odds, alt)
}

/// What the propagation needs of one control point of the last step.
#[derive(Clone, Copy, Debug)]
pub(super) struct SigmaInput {
    /// Index among the step's control points.
    pub(super) point: usize,
    /// Index among the step's active points (those the controller used).
    pub(super) active: Option<usize>,
    /// The obstacle it answers.
    pub(super) owner: usize,
    pub(super) position: DVec3,
    pub(super) radius: f64,
    /// The selected witness it follows (`None`: a pinned point).
    pub(super) witness: Option<SkeletonPoint>,
    /// Factor from repulsion velocity to what the state shows (force in
    /// torque mode).
    pub(super) gain: f64,
}

/// What the command's propagation needs of one active control point: the
/// obstacle it answers and what the controller sees of the point with that
/// obstacle moved by `±h` along x, y and z (in that order).
#[derive(Clone, Copy, Debug)]
pub(super) struct Probes {
    pub(super) owner: usize,
    pub(super) values: [Probe; 6],
}

/// A control point as the controller sees it, for one probe.
#[derive(Clone, Copy, Debug)]
pub(super) struct Probe {
    /// Clearance minus the margin (m).
    distance: f64,
    normal: DVec3,
    /// Where the point is (`None`: where it was, a pinned point).
    dh: Option<DhPoint>,
}

fn axis_offsets() -> [DVec3; 6] {
    let h = FD_STEP;
    [
        DVec3::X * h,
        -DVec3::X * h,
        DVec3::Y * h,
        -DVec3::Y * h,
        DVec3::Z * h,
        -DVec3::Z * h,
    ]
}

/// The body of [`World::propagation`].
pub(super) fn propagation(w: &World) -> (Vec<Option<PointSigma>>, Option<Vec<f64>>) {
    let cfg = &w.model.scenario.controller;
    let mut points = vec![None; w.data.readout.points.len()];
    let mut probes = vec![None; w.data.propagation.active.len()];
    for input in &w.data.propagation.sigma_inputs {
        let Some((sigma, p)) = point_sigma(w, input, cfg) else {
            continue;
        };
        if let Some(slot) = points.get_mut(input.point) {
            *slot = Some(sigma);
        }
        if let Some(slot) = input.active.and_then(|k| probes.get_mut(k)) {
            *slot = Some(p);
        }
    }
    let command = command_sigma(w, cfg, &probes).ok().flatten();
    (points, command)
}

/// The pairs between the arm now and the figure `shape` (not added),
/// whatever their distance.
pub(super) fn pairs_with(w: &World, shape: &ShapeSpec) -> Result<Vec<PairDistance>, ScenarioError> {
    let parts = primitives(shape).map_err(|e| e.within("shape"))?;
    let scene = Scene::new(
        parts
            .into_iter()
            .enumerate()
            .map(|(k, p)| Obstacle {
                id: k as u32,
                shape: p,
            })
            .collect(),
    );
    let options = QueryOptions {
        influence_distance: f64::MAX,
        self_collision: false,
        broad_phase: BroadPhase::BruteForce,
    };
    Ok(scene
        .query(&w.data.skeleton, &options, |_, _| true)
        .map_err(|e| FieldError::new("shape", e.to_string()))?)
}

/// The body of [`World::risk_at`].
pub(super) fn risk_at(
    w: &World,
    shape: &ShapeSpec,
    sensing: &SensingSpec,
) -> Result<Risk, ScenarioError> {
    sensing
        .validate()
        .map_err(|e| ScenarioError::Field(e.within("sensing")))?;
    let pairs = pairs_with(w, shape)?;
    let Some(best) = pairs
        .iter()
        .min_by(|x, y| x.distance.total_cmp(&y.distance))
    else {
        return Ok(Risk {
            clearance: f64::INFINITY,
            switch_probability: 0.0,
            segment: None,
            alternative: None,
        });
    };
    // A human's `partSigma`: its largest part's, as in a world.
    let largest = super::obstacles::human_of(shape)
        .map_err(ScenarioError::Field)?
        .map_or(0.0, |h| h.part_sigma().iter().copied().fold(0.0, f64::max));
    let covariance = SensorModel::from_spec(sensing, 0).covariance_with(largest);
    let jump = w.model.scenario.controller.jump_threshold;
    let (odds, _) = segment_odds(&pairs, best, jump, &covariance);
    Ok(Risk {
        clearance: best.distance,
        switch_probability: odds.probability,
        segment: odds.segment,
        alternative: odds.alternative,
    })
}

/// The standard deviations of a control point answering obstacle
/// `input.owner`, with the probes the command's propagation needs; `None`
/// when the obstacle is sensed exactly. A point that follows its
/// selected witness moves with it, so its clearance, normal and DH
/// values are the witness pair's; a pinned point (no witness) stays
/// where it is.
fn point_sigma(
    w: &World,
    input: &SigmaInput,
    cfg: &ControllerConfig,
) -> Option<(PointSigma, Probes)> {
    let SigmaInput {
        owner,
        position,
        radius,
        witness,
        gain,
        ..
    } = *input;
    let o = w.state.sensed.obstacles.get(owner)?;
    if o.covariance.is_zero() {
        return None;
    }
    let margin = o.margin;
    let mut values = [Probe {
        distance: 0.0,
        normal: DVec3::Z,
        dh: None,
    }; 6];
    for (v, off) in values.iter_mut().zip(axis_offsets()) {
        *v = match witness {
            Some(at) => witness_probe(w, owner, at.segment, off)?,
            None => {
                let (d, normal, _) = w.state.sensed.point_distance(owner, position - off).ok()?;
                Probe {
                    distance: d - radius,
                    normal,
                    dh: None,
                }
            }
        };
        v.distance -= margin;
    }
    let column = |f: &dyn Fn(&Probe) -> Vec<f64>| -> [Vec<f64>; 3] {
        let col = |k: usize| -> Vec<f64> {
            f(&values[2 * k])
                .iter()
                .zip(f(&values[2 * k + 1]))
                .map(|(p, m)| (p - m) / (2.0 * FD_STEP))
                .collect()
        };
        [col(0), col(1), col(2)]
    };
    let cov = o.covariance;
    let distance = cov.std_of(&column(&|p| vec![p.distance]))[0];
    let rep = cov.std_of(&column(&|p| {
        (-p.normal * repulsion_speed(p.distance, cfg) * gain)
            .to_array()
            .to_vec()
    }));
    let dh = cov.std_of(&column(&|p| {
        p.dh.map_or(vec![0.0, 0.0], |x| vec![x.d, x.a])
    }));
    let sigma = PointSigma {
        distance,
        d: dh[0],
        a: dh[1],
        repulsion: [rep[0], rep[1], rep[2]],
    };
    Some((sigma, Probes { owner, values }))
}

/// The closest pair of segment `segment` and obstacle `owner` (its
/// closest part) moved by `offset`, as the controller would see it.
fn witness_probe(w: &World, owner: usize, segment: usize, offset: DVec3) -> Option<Probe> {
    let mut best: Option<PairDistance> = None;
    for index in w.state.sensed.parts_of(owner) {
        let p = w
            .state
            .sensed
            .scene
            .pair_moved(&w.data.skeleton, segment, index, offset)
            .ok()?;
        if best.is_none_or(|b| p.distance < b.distance) {
            best = Some(p);
        }
    }
    let p = best?;
    let dh = DhPoint::from_skeleton(
        &w.model.robot,
        &w.data.frames,
        &w.data.skeleton,
        segment,
        p.fraction,
    )
    .ok()?;
    Some(Probe {
        distance: p.distance,
        normal: p.normal,
        dh: Some(dh),
    })
}

/// Standard deviation of each joint's command: the controller run again
/// with each noisy obstacle moved by `±h` along each axis (its control
/// points' clearances and normals from their probes), the obstacles'
/// errors independent of each other. Only for the paper's repulsion,
/// whose command is a smooth function of the control points; the
/// `constraints` avoidance's command is piecewise (a row binds or it
/// does not) and is not propagated (`None`).
fn command_sigma(
    w: &World,
    cfg: &ControllerConfig,
    probes: &[Option<Probes>],
) -> Result<Option<Vec<f64>>, FieldError> {
    if cfg.uses_constraints() {
        return Ok(None);
    }
    let active = &w.data.propagation.active;
    let mut owners: Vec<usize> = probes.iter().flatten().map(|p| p.owner).collect();
    owners.sort_unstable();
    owners.dedup();
    if owners.is_empty() {
        return Ok(None);
    }
    let mut variance = vec![0.0; w.model.robot.dof()];
    let mut moved = active.to_vec();
    for o in owners {
        let mut columns: [Vec<f64>; 3] = Default::default();
        for (k, column) in columns.iter_mut().enumerate() {
            let mut run = |i: usize| -> Result<Vec<f64>, FieldError> {
                for ((m, a), p) in moved.iter_mut().zip(active).zip(probes) {
                    *m = *a;
                    if let Some(p) = p.filter(|p| p.owner == o) {
                        let v = p.values[i];
                        (m.distance, m.normal) = (v.distance, v.normal);
                        m.dh = v.dh.unwrap_or(m.dh);
                    }
                }
                let prop = &w.data.propagation;
                request_for(&w.model, &w.data, &moved, (&prop.q, &prop.qdot), prop.dt)
            };
            let (plus, minus) = (run(2 * k)?, run(2 * k + 1)?);
            *column = plus
                .iter()
                .zip(&minus)
                .map(|(p, m)| (p - m) / (2.0 * FD_STEP))
                .collect();
        }
        let s = w.state.sensed.obstacles[o].covariance.std_of(&columns);
        for (v, s) in variance.iter_mut().zip(s) {
            *v += s * s;
        }
    }
    Ok(Some(variance.into_iter().map(f64::sqrt).collect()))
}
