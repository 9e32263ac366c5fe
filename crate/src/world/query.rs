//! Stage 2 of the control step, *scene query*: forward kinematics, the
//! skeleton, every segment against every obstacle within reach (and
//! non-adjacent links against each other), and the true smallest clearance
//! (paper §II).

use super::obstacles::ObstacleState;
use super::parts::{Model, State, StepData};
use crate::avoidance::Mode;
use crate::distance::{PairDistance, QueryOptions, Target};
use crate::error::FieldError;

/// Stage 2, *scene query*: forward kinematics, skeleton, and the scene query against
/// the obstacles as sensed; also the true smallest clearance.
pub(super) fn scene_query(
    model: &Model,
    state: &State,
    data: &mut StepData,
) -> Result<Vec<PairDistance>, FieldError> {
    let cfg = &model.scenario.controller;
    if cfg.mode == Mode::Clik2 {
        data.frames = model
            .robot
            .forward_with_velocity(&state.q, &state.motion.qdot)?;
    } else {
        model.robot.forward_into(&state.q, &mut data.frames)?;
    }
    data.skeleton.build_into(&model.robot, &data.frames);
    let max_margin = state
        .sensed
        .obstacles
        .iter()
        .map(|o| o.margin)
        .fold(0.0, f64::max);
    let options = QueryOptions {
        influence_distance: cfg.influence() + max_margin,
        self_collision: cfg.self_collision,
        ..QueryOptions::default()
    };
    let adjacency = &model.adjacency;
    let query = |scene: &crate::distance::Scene| {
        scene
            .query(&data.skeleton, &options, |i, j| adjacency[i][j])
            .map_err(|e| FieldError::new("scene", e.to_string()))
    };
    let pairs = query(&state.sensed.scene)?;
    let part = |p: &PairDistance| match p.target {
        Target::Obstacle { id, .. } => state.sensed.scene_part_name(id as usize),
        Target::Segment(_) => None,
    };
    let smallest = |pairs: &mut dyn Iterator<Item = &PairDistance>| {
        pairs
            .min_by(|a, b| a.distance.total_cmp(&b.distance))
            .copied()
    };
    // The clearance reported is the true one: with noisy sensing the
    // scene as it is, where only its nearest pairs are wanted
    // (`Scene::nearest`); self-collision pairs are the same in both.
    let (closest, human) = if state.sensed.obstacles.iter().any(ObstacleState::noisy) {
        let truth = state
            .sensed
            .clone_scene_at(state.t)
            .nearest(&data.skeleton, options.influence_distance, |j| {
                state.sensed.is_named_part(j)
            })
            .map_err(|e| FieldError::new("scene", e.to_string()))?;
        let own = smallest(
            &mut pairs
                .iter()
                .filter(|p| matches!(p.target, Target::Segment(_))),
        );
        let closest = match (truth.all, own) {
            (Some(a), Some(b)) if b.distance < a.distance => Some(b),
            (None, b) => b,
            (a, _) => a,
        };
        (closest, truth.kept)
    } else {
        let named = |p: &&PairDistance| matches!(p.target, Target::Obstacle { id, .. } if state.sensed.is_named_part(id as usize));
        let human = smallest(&mut pairs.iter().filter(named));
        (smallest(&mut pairs.iter()), human)
    };
    let closest_part = closest.as_ref().and_then(part);
    let closest_human = human.as_ref().and_then(|p| Some((part(p)?, p.distance)));
    data.readout.min_clearance = closest.map(|p| p.distance);
    data.readout.closest_part = closest_part;
    data.readout.closest_human = closest_human;
    Ok(pairs)
}
