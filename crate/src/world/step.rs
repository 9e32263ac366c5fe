//! One control step of a [`World`]: the stages of the pipeline, called in
//! order by [`World::step`] (the table is in the [`super`] module docs).

use glam::DVec3;

use super::{MAX_EVENTS, StopReason, World};
use crate::avoidance::constraints::{ConstraintsInput, constrained_velocity};
use crate::avoidance::limits::{self, braking_time};
use crate::avoidance::selection::{self, Key, fraction_on};
use crate::avoidance::{self, ActivePoint, ControllerConfig, Mode};
use crate::control_point::DhPoint;
use crate::control_point::PointMotion;
use crate::dependability::EventKind;
use crate::distance::{PairDistance, QueryOptions, Target};
use crate::error::FieldError;
use crate::skeleton::Skeleton;
use crate::transition::dh_motion;

use super::monitor::Approach;
use super::obstacles::ObstacleState;
use super::state::ControlPointState;
use super::uncertainty::SigmaInput;

/// Time constant of the low-pass filter on the closing speed used for the
/// time to collision (s): long against the jitter of the sensed normal,
/// short against the arm's and the obstacles' changes of speed.
pub const CLOSING_FILTER_TIME: f64 = 0.05;

impl World {
    /// Advances the simulation by `dt` seconds (one control step). A
    /// non-finite or non-positive `dt` does nothing.
    pub fn step(&mut self, dt: f64) {
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        if self.step_inner(dt).is_err() {
            // Only reachable through a bug: brake as a stop would.
            let n = self.robot.dof();
            let robot = &self.robot;
            limits::step(robot, &self.q, &vec![0.0; n], &mut self.motion, dt);
        }
        if !self.keep_all_events && self.events.len() > MAX_EVENTS {
            let drop = self.events.len() - MAX_EVENTS / 2;
            self.events.drain(..drop);
            self.events_dropped += drop;
        }
    }

    fn step_inner(&mut self, dt: f64) -> Result<(), FieldError> {
        let cfg = self.scenario.controller.clone();
        // 1. sense
        // A figure moved by edits counts as moving until its edit velocity
        // has expired, so that the scene (which carries each part's
        // velocity) is rebuilt once more with the figure at rest.
        let t = self.t;
        let moving = self.obstacles.iter().any(|o| {
            o.moves()
                || o.dragged
                    .is_some_and(|(at, _)| t - at <= 2.0 * super::obstacles::DRAG_HOLD)
        });
        if moving || self.scene_dirty {
            self.rebuild_scene(self.t, true, dt);
        }
        let t = self.t;
        for o in &mut self.obstacles {
            o.update_margin(t, dt);
        }
        // 2. scene query
        let pairs = self.scene_query(&cfg)?;
        if self.t == 0.0 {
            self.report_start_contact(&pairs);
        }
        // 3. select
        let margins: Vec<f64> = self.obstacles.iter().map(|o| o.margin).collect();
        // The segments the perObstacle points follow, read only with a
        // hysteresis (an empty map allocates nothing on this hot path).
        let following: std::collections::BTreeMap<usize, usize> = if cfg.switch_hysteresis > 0.0 {
            self.trackers
                .iter()
                .filter_map(|(key, t)| match key {
                    Key::Obstacle(o) => Some((*o, t.mover.selected().segment)),
                    _ => None,
                })
                .collect()
        } else {
            std::collections::BTreeMap::new()
        };
        let selected = selection::select(
            &pairs,
            &self.owners,
            &margins,
            &following,
            &self.skeleton,
            &cfg,
        );
        // 4.–5. transition and monitor
        self.monitor_switch_risk(&pairs, &selected, &cfg);
        self.track(&selected, &pairs, dt, &cfg)?;
        let active = self.active_points(&cfg, dt)?;
        // 6. control (what the propagation of the sensing errors needs is
        // kept, and computed when the state is read)
        self.step_qdot.clone_from(&self.motion.qdot);
        self.step_q.clone_from(&self.q);
        self.step_dt = dt;
        self.prepare_guards(&cfg, &pairs, dt)?;
        self.control(&cfg, &active, dt)?;
        self.active = active;
        // 7. protect
        let all_hold = self.protect(&cfg, dt);
        self.maybe_resume(all_hold);
        // 8.–9. limit and integrate, then the command monitor
        self.limit_and_integrate(dt);
        self.monitor_command();
        Ok(())
    }

    /// Stage 2: forward kinematics, skeleton, and the scene query against
    /// the obstacles as sensed; also the true smallest clearance.
    fn scene_query(&mut self, cfg: &ControllerConfig) -> Result<Vec<PairDistance>, FieldError> {
        if cfg.mode == Mode::Clik2 {
            self.frames = self
                .robot
                .forward_with_velocity(&self.q, &self.motion.qdot)?;
        } else {
            self.robot.forward_into(&self.q, &mut self.frames)?;
        }
        self.skeleton.build_into(&self.robot, &self.frames);
        let max_margin = self.obstacles.iter().map(|o| o.margin).fold(0.0, f64::max);
        let options = QueryOptions {
            influence_distance: cfg.influence_distance + max_margin,
            self_collision: cfg.self_collision,
            ..QueryOptions::default()
        };
        let adjacency = &self.adjacency;
        let query = |scene: &crate::distance::Scene| {
            scene
                .query(&self.skeleton, &options, |i, j| adjacency[i][j])
                .map_err(|e| FieldError::new("scene", e.to_string()))
        };
        let pairs = query(&self.scene)?;
        let part = |p: &PairDistance| match p.target {
            Target::Obstacle { id, .. } => self.scene_part_name(id as usize),
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
        let (closest, human) = if self.obstacles.iter().any(ObstacleState::noisy) {
            let truth = self
                .clone_scene_at(self.t)
                .nearest(&self.skeleton, options.influence_distance, |j| {
                    self.is_named_part(j)
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
            let named = |p: &&PairDistance| matches!(p.target, Target::Obstacle { id, .. } if self.is_named_part(id as usize));
            let human = smallest(&mut pairs.iter().filter(named));
            (smallest(&mut pairs.iter()), human)
        };
        let closest_part = closest.as_ref().and_then(part);
        let closest_human = human.as_ref().and_then(|p| Some((part(p)?, p.distance)));
        self.min_clearance = closest.map(|p| p.distance);
        self.closest_part = closest_part;
        self.closest_human = closest_human;
        Ok(pairs)
    }

    /// Where control point `key` is, its clearance, normal and witness.
    pub(super) fn locate(
        &self,
        key: &Key,
        owner: Option<usize>,
        position: DVec3,
        radius: f64,
    ) -> Result<(f64, DVec3, DVec3, Option<usize>), FieldError> {
        if let Key::SelfPair(_, other) = key {
            let seg = &self.skeleton.segments[*other];
            let u = fraction_on(&self.skeleton, *other, position);
            let (a, b) = self.skeleton.endpoints(seg);
            let c = a + (b - a) * u;
            let r2 = Skeleton::radius_at(seg, u);
            let v = c - position;
            let len = v.length();
            let n = if len > 0.0 { v / len } else { DVec3::Z };
            return Ok((len - radius - r2, n, c - n * r2, None));
        }
        Ok(match owner {
            Some(o) => {
                let (d, n, w) = self.point_distance(o, position)?;
                (d - radius, n, w, Some(o))
            }
            None => (f64::INFINITY, DVec3::Z, position, None),
        })
    }

    /// The active control points where they are now, with their repulsion,
    /// time to collision and the `transitionTooSlow` monitor.
    fn active_points(
        &mut self,
        cfg: &ControllerConfig,
        dt: f64,
    ) -> Result<Vec<ActivePoint>, FieldError> {
        let mut active = Vec::new();
        let mut sigma_inputs = Vec::new();
        let mut states = Vec::new();
        let mut min_ttc = f64::INFINITY;
        let braking = braking_time(&self.robot, &self.motion, dt);
        self.slowdown.clear();
        self.slowdown.resize(self.obstacles.len(), 1.0);
        let keys: Vec<Key> = self.trackers.keys().cloned().collect();
        for key in keys {
            let Some((dh, radius)) = self.tracked_point(&key, cfg)? else {
                continue;
            };
            let Some(tr) = self.trackers.get(&key) else {
                continue;
            };
            let (prev, remaining, owner) = (tr.closing, tr.mover.remaining(), tr.owner);
            let target = tr.mover.transition().map(|x| x.target());
            let selected_at = (!matches!(key, Key::Pinned(_))).then(|| tr.mover.selected());
            let was_slow = tr.too_slow;
            let position = dh.position(&self.robot, &self.frames);
            let owner = match key {
                Key::Pinned(k) => self.pinned_owner(&key, k, position),
                _ => owner,
            };
            let (dist, normal, witness, owner) = self.locate(&key, owner, position, radius)?;
            let margin = owner.map_or(0.0, |o| self.margin_near(o, position));
            let effective = dist - margin;
            let ap = ActivePoint {
                dh,
                motion: PointMotion::default(),
                normal,
                distance: effective,
            };
            let gain = if cfg.mode == Mode::Torque {
                cfg.torque.force_gain
            } else {
                1.0
            };
            let name = self.point_name(&key, owner);
            let at = selected_at.filter(|_| remaining > 0.0);
            let (ttc, closing, ttc_normal) =
                self.time_to_collision_at(&key, at, owner, (dh, normal, effective), prev, dt)?;
            min_ttc = min_ttc.min(ttc);
            let approach = Approach {
                owner,
                obstacle_velocity: owner
                    .map_or(DVec3::ZERO, |o| self.approach_velocity(o, position)),
                name: &name,
                ttc,
                normal: ttc_normal,
                remaining,
                braking,
                closing,
                was_slow,
            };
            self.monitor_transition(&key, &approach, cfg);
            let target = target.and_then(|x| {
                DhPoint::from_skeleton(&self.robot, &self.frames, &self.skeleton, x.segment, x.t)
                    .ok()
            });
            if let Some(owner) = owner.filter(|&o| !self.obstacles[o].covariance.is_zero()) {
                sigma_inputs.push(SigmaInput {
                    point: states.len(),
                    active: dist.is_finite().then_some(active.len()),
                    owner,
                    position,
                    radius,
                    witness: selected_at,
                    gain,
                });
            }
            if dist.is_finite() {
                active.push(ap);
            }
            states.push(ControlPointState {
                position: position.to_array(),
                link: dh.link,
                d: dh.d,
                a: dh.a,
                part: owner.and_then(|o| self.witness_part(o, position)),
                obstacle: name,
                distance: dist,
                witness: witness.to_array(),
                repulsion: (ap.repulsion(cfg) * gain).to_array(),
                transitioning: target.is_some(),
                target,
                sigma: None,
                table: Vec::new(),
            });
        }
        self.points = states;
        self.sigma_inputs = sigma_inputs;
        self.time_to_collision = min_ttc.is_finite().then_some(min_ttc);
        Ok(active)
    }

    /// Where the tracked point `key` is (DH values) and the radius of the
    /// arm's volume there; `None` for a pinned point the configuration no
    /// longer has, or a key no longer tracked.
    fn tracked_point(
        &self,
        key: &Key,
        cfg: &ControllerConfig,
    ) -> Result<Option<(DhPoint, f64)>, FieldError> {
        let Some(tr) = self.trackers.get(key) else {
            return Ok(None);
        };
        Ok(Some(if let Key::Pinned(k) = key {
            let Some(p) = cfg.pinned.get(*k) else {
                return Ok(None);
            };
            (
                p.clamped(&self.frames),
                self.robot.joints[p.link - 1].radius[0],
            )
        } else {
            let pt = tr.mover.point();
            let (dh, _) = dh_motion(&self.robot, &self.frames, &self.skeleton, pt, 0.0, 0.0)?;
            let seg = &self.skeleton.segments[pt.segment];
            (dh, Skeleton::radius_at(seg, pt.t))
        }))
    }

    /// The obstacle id a control point reports (`pinned:<k>` for a pinned
    /// point with no obstacle in reach).
    fn point_name(&self, key: &Key, owner: Option<usize>) -> String {
        match (key, owner) {
            (Key::Pinned(k), None) => format!("pinned:{k}"),
            (Key::Pinned(_), Some(o)) => self.obstacles[o].spec.id.clone(),
            _ => self.name(key),
        }
    }

    /// The obstacle pinned point `k` answers: the closest one, unless a
    /// `lock` holds another; a change is a switch for the chattering
    /// monitor.
    fn pinned_owner(&mut self, key: &Key, k: usize, position: DVec3) -> Option<usize> {
        let closest = self.closest_obstacle(position);
        let mut tracker = self.trackers.remove(key)?;
        let owner = match tracker.lock {
            Some((held, until)) if self.t < until && held < self.obstacles.len() => Some(held),
            Some(_) => {
                tracker.lock = None;
                let obstacle = format!("pinned:{k}");
                self.push(EventKind::Unlock { obstacle });
                closest
            }
            None => closest,
        };
        let switched = tracker.owner.is_some() && owner.is_some() && tracker.owner != owner;
        tracker.owner = owner;
        if let Some(o) = owner {
            self.monitor_chattering(&mut tracker, &Key::Pinned(k), switched, o);
        }
        self.trackers.insert(key.clone(), tracker);
        owner
    }

    /// Stage 6: the controller's requested joint velocities (zero while
    /// stopped).
    fn control(
        &mut self,
        cfg: &ControllerConfig,
        active: &[ActivePoint],
        dt: f64,
    ) -> Result<(), FieldError> {
        let mut refs = std::mem::take(&mut self.references);
        self.scenario.task.references(
            &self.robot,
            self.t,
            &self.anchors,
            Self::uses_constraints(cfg),
            &mut refs,
        );
        self.references = refs;
        if Self::uses_constraints(cfg) {
            let input = ConstraintsInput {
                robot: &self.robot,
                frames: &self.frames,
                q: &self.q,
                stop_time: self.stop_time,
                tasks: &self.references,
                guards: &self.guards,
                config: cfg,
            };
            let mut out = std::mem::take(&mut self.request);
            let outcome = constrained_velocity(&input, &mut self.qp, &mut out)?;
            self.relaxed = outcome.relaxed;
            self.request = out;
        } else {
            self.request = self.request_for(cfg, active, &self.q, &self.motion.qdot, dt)?;
        }
        if self.stopped {
            self.request.iter_mut().for_each(|v| *v = 0.0);
        }
        Ok(())
    }

    /// The controller's joint command for the active points `active` and
    /// this step's task references (the paper's repulsion; the
    /// `constraints` avoidance is solved in [`World::control`]).
    pub(super) fn request_for(
        &self,
        cfg: &ControllerConfig,
        active: &[ActivePoint],
        q: &[f64],
        qdot: &[f64],
        dt: f64,
    ) -> Result<Vec<f64>, FieldError> {
        let (robot, frames) = (&self.robot, &self.frames);
        let refs = &self.references;
        Ok(match cfg.mode {
            Mode::Velocity => avoidance::velocity_control(robot, frames, active, refs, cfg)?,
            Mode::Torque => {
                avoidance::torque_control(robot, frames, qdot, active, refs, cfg, dt)?.0
            }
            Mode::Clik2 => {
                let joints = avoidance::JointState { q, qdot };
                avoidance::clik2_control(robot, frames, joints, active, refs, cfg, dt)?
            }
        })
    }

    /// Stages 8 and 9: the joint limits, then `q += q̇ dt`, `t += dt`
    /// (counted as `k·dt`, see `clock`).
    fn limit_and_integrate(&mut self, dt: f64) {
        self.step_t = self.t;
        // A chattering stop decelerates gently (`maxDeceleration`); a stop
        // before an unavoidable contact and the emergency brake use the
        // full deceleration of the slowest joint. Every stop is
        // synchronised: the joint velocities shrink along one line to zero,
        // so every pair's approach speed shrinks with them (joints braked
        // each at its own rate can turn a motion along an obstacle into one
        // towards it: measured on the PR2 reach problems).
        let urgent = self.braking || self.stop_reason == Some(StopReason::Unavoidable);
        let options = limits::StepOptions {
            max_acceleration: if self.stopped && !urgent {
                self.scenario.dependability.max_deceleration
            } else {
                f64::INFINITY
            },
            synchronise: true,
        };
        limits::step_with(
            &self.robot,
            &self.q,
            &self.request,
            &mut self.motion,
            dt,
            &options,
        );
        for (q, v) in self.q.iter_mut().zip(&self.motion.qdot) {
            *q += v * dt;
        }
        self.robot.clamp_to_limits(&mut self.q);
        self.t = self.clock.advance(self.t, dt);
    }
}
