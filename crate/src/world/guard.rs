//! Stage 7 of the control step, the protective layer, and the guards the
//! `constraints` avoidance solves with ([`crate::avoidance::protect`],
//! [`crate::avoidance::constraints`]).
//!
//! The guards are prepared before the control stage: every pair within
//! the influence distance with its protective bound, its damper (in the
//! `constraints` avoidance) and, for an obstacle closing in faster than
//! the arm could stop, the escape the joints can still make
//! ([`crate::avoidance::protect::Guard::escape`]). After the controller, [`World::protect`] projects
//! the request onto the protective bounds (a no-op for the `constraints`
//! avoidance, whose request already meets them) and stops the arm when no
//! admissible motion keeps a pair safe.

use std::collections::BTreeSet;

use super::{StopReason, World};
use crate::avoidance::constraints::INFEASIBLE_TOLERANCE;
use crate::avoidance::limits::{braking_time, cap_for_stop_time, velocity_box};
use crate::avoidance::protect::{self, Damper, GuardPair};
use crate::avoidance::selection::fraction_on;
use crate::avoidance::{Avoidance, ControllerConfig, Mode};
use crate::dependability::EventKind;
use crate::distance::{PairDistance, Primitive, Target, distance};
use crate::error::FieldError;
use crate::skeleton::Skeleton;

impl World {
    /// Whether this controller solves the `constraints` avoidance.
    pub(super) fn uses_constraints(cfg: &ControllerConfig) -> bool {
        cfg.mode == Mode::Velocity && cfg.avoidance == Avoidance::Constraints
    }

    /// The pairs the protective layer guards: every pair within the
    /// influence distance, obstacles as sensed (margin subtracted). A
    /// segment–obstacle pair is guarded at its witness and, unless the
    /// obstacle is a point or a sphere, at both ends of the segment: where
    /// a segment runs nearly parallel to a face or an edge, its
    /// witness can jump from one end to the other between two steps, onto
    /// a point that moves differently; guarding the ends bounds that point
    /// before the jump (measured on the PR2 reach problems).
    ///
    /// An obstacle's approach speed is that of its part's material point at
    /// the witness (a human's hand moving with its arm, not the body).
    fn guard_pairs(&mut self, cfg: &ControllerConfig, pairs: &[PairDistance]) {
        let mut out = std::mem::take(&mut self.guard_pairs);
        out.clear();
        for p in pairs {
            let (distance, obstacle, other, speed, part) = match p.target {
                Target::Obstacle { id, .. } => {
                    let o = self.owners[id as usize];
                    let motion = self
                        .part_motion
                        .get(id as usize)
                        .copied()
                        .unwrap_or_default();
                    self.end_pairs(cfg, p, id as usize, o, &motion, &mut out);
                    // The part's own margin (its own σ with `partSigma`).
                    let margin = self.obstacles[o].part_margin(self.part_index[id as usize]);
                    (
                        p.distance - margin,
                        Some(o),
                        None,
                        -p.normal.dot(motion.velocity_at(p.point_other)),
                        Some(id as usize),
                    )
                }
                Target::Segment(other) => {
                    let u = fraction_on(&self.skeleton, other, p.point_other);
                    (p.distance, None, Some((other, u)), 0.0, None)
                }
            };
            if distance > cfg.influence_distance {
                continue;
            }
            out.push(GuardPair {
                segment: p.segment,
                fraction: p.fraction,
                other,
                normal: p.normal,
                distance,
                obstacle_speed: speed,
                obstacle,
                part,
            });
        }
        self.guard_pairs = out;
    }

    /// The `startContact` event: the deepest of the pairs that overlap in
    /// the first step, if any.
    pub(super) fn report_start_contact(&mut self, pairs: &[PairDistance]) {
        let overlapping = pairs.iter().filter(|p| p.distance <= 0.0);
        let Some(deepest) = overlapping
            .clone()
            .min_by(|a, b| a.distance.total_cmp(&b.distance))
        else {
            return;
        };
        let link = self.skeleton.segments[deepest.segment].link;
        let obstacle = match deepest.target {
            Target::Obstacle { id, .. } => self.obstacles[self.owners[id as usize]].spec.id.clone(),
            Target::Segment(other) => {
                format!(
                    "self:{}",
                    self.robot.link_label(self.skeleton.segments[other].link)
                )
            }
        };
        self.push(EventKind::StartContact {
            obstacle,
            link: self.robot.link_label(link),
            distance: deepest.distance,
            pairs: overlapping.count(),
        });
    }

    /// Guard pairs at the ends of `p`'s segment against scene part `part`
    /// (obstacle `o`, moving at `v`), where they are within the influence
    /// distance and not at the witness already.
    fn end_pairs(
        &self,
        cfg: &ControllerConfig,
        p: &PairDistance,
        part: usize,
        o: usize,
        motion: &super::obstacles::PartMotion,
        out: &mut Vec<GuardPair>,
    ) {
        let Some(shape) = self.scene.obstacles().get(part).map(|x| &x.shape) else {
            return;
        };
        // Against a point or a sphere the clearance along a segment has one
        // minimum that moves continuously: its witness never jumps.
        if matches!(shape, Primitive::Point(_) | Primitive::Sphere(_)) {
            return;
        }
        let seg = &self.skeleton.segments[p.segment];
        let (a, b) = self.skeleton.endpoints(seg);
        for (t, end) in [(0.0, a), (1.0, b)] {
            if (p.fraction - t).abs() < 0.05 {
                continue;
            }
            let Ok(d) = distance(&Primitive::Point(end), shape) else {
                continue;
            };
            let margin = self.obstacles[o].part_margin(self.part_index[part]);
            let clearance = d.distance - Skeleton::radius_at(seg, t) - margin;
            if clearance > cfg.influence_distance || d.distance <= 0.0 {
                continue;
            }
            out.push(GuardPair {
                segment: p.segment,
                fraction: t,
                other: None,
                normal: d.normal,
                distance: clearance,
                obstacle_speed: -d.normal.dot(motion.velocity_at(d.point_b)),
                obstacle: Some(o),
                part: Some(part),
            });
        }
    }

    /// The guards of this step (before the control stage): protective
    /// bounds, dampers, the time-to-collision slowdown, and the escape from
    /// obstacles that close in faster than the arm could stop. An obstacle
    /// with no admissible escape is remembered in `self.doomed`.
    pub(super) fn prepare_guards(
        &mut self,
        cfg: &ControllerConfig,
        pairs: &[PairDistance],
        dt: f64,
    ) -> Result<(), FieldError> {
        self.doomed = None;
        self.stop_time = f64::INFINITY;
        let p = cfg.protective;
        if !p.enabled {
            self.guards.clear();
            return Ok(());
        }
        self.guard_pairs(cfg, pairs);
        self.stop_time = self.stop_time(cfg, dt);
        let braking = braking_time(&self.robot, &self.motion, dt);
        let floor = if self.stopped { 0.0 } else { f64::NEG_INFINITY };
        let damper = Self::uses_constraints(cfg).then_some(Damper {
            gain: cfg.max_repulsion_speed,
            band: cfg.safety_band,
            influence: cfg.influence_distance,
        });
        let mut guards = std::mem::take(&mut self.guards);
        protect::guards(
            &self.robot,
            &self.frames,
            &self.skeleton,
            &self.guard_pairs,
            &p,
            braking,
            floor,
            damper.as_ref(),
            &mut guards,
        )?;
        let (lo, hi) = self.admissible_box();
        for (k, g) in guards.iter_mut().enumerate() {
            // Time to collision shorter than a transition plus braking: the
            // approach to that obstacle is slowed (retreat is left free).
            if let Some(o) = g.obstacle
                && g.bound > 0.0
            {
                g.bound *= self.slowdown.get(o).copied().unwrap_or(1.0);
            }
            // An obstacle closing in faster than the arm could stop: escape
            // along the row if the joints can outrun it, else stop now.
            if g.obstacle_speed > 0.0 && g.bound < 0.0 && !self.stopped {
                match g.escape(&self.robot, &self.motion.qdot, &lo, &hi, &p) {
                    Some(b) => g.bound = b,
                    None if self.doomed.is_none() => {
                        let excess = g.approach(&self.motion.qdot) - g.bound;
                        self.doomed = Some((k, excess.max(0.0)));
                    }
                    None => {}
                }
            }
        }
        self.guards = guards;
        Ok(())
    }

    /// The time within which the joints must be able to stop: for every
    /// obstacle closing in at `v_h` with room `d − d_s` above the safety
    /// distance, `(d − d_s) / v_h − T_r − dt`, the smallest of them (`∞`
    /// when nothing closes in or during a stop).
    ///
    /// The guards bound the arm's approach; this bounds its speed, so that
    /// whatever the arm is doing — escaping an obstacle that appeared next
    /// to it included — stopping still ends before the obstacle closes the
    /// gap. Without it an escape at full speed that later ran out of room
    /// (a joint limit, the row turning) ended in a stop that was still
    /// braking when the obstacle arrived: contact while moving.
    fn stop_time(&self, cfg: &ControllerConfig, dt: f64) -> f64 {
        if self.stopped {
            return f64::INFINITY;
        }
        let p = cfg.protective;
        self.guard_pairs
            .iter()
            .filter(|g| g.obstacle.is_some() && g.obstacle_speed > 0.0)
            .map(|g| (g.distance - p.safety_distance) / g.obstacle_speed - p.reaction_time - dt)
            .fold(f64::INFINITY, f64::min)
    }

    /// The admissible velocity box now: the joints' speed limits, the
    /// braking caps of their position limits, and the stop time of the
    /// obstacles closing in ([`Self::stop_time`]).
    pub(super) fn admissible_box(&self) -> (Vec<f64>, Vec<f64>) {
        let (mut lo, mut hi) = velocity_box(&self.robot, &self.q);
        cap_for_stop_time(&self.robot, self.stop_time, &mut lo, &mut hi);
        (lo, hi)
    }

    /// Stage 7: the protective layer. Projects the request onto the guards
    /// and the admissible velocity box; when no admissible motion keeps a
    /// pair safe the arm stops (`unavoidable`). Returns whether every guard
    /// of an approaching obstacle holds with the arm at rest (a stop after
    /// an unavoidable approach may then end; static and receding obstacles
    /// are backed out of instead).
    pub(super) fn protect(&mut self, cfg: &ControllerConfig, dt: f64) -> bool {
        let p = cfg.protective;
        if !p.enabled {
            return true;
        }
        let braking = braking_time(&self.robot, &self.motion, dt);
        let guards = std::mem::take(&mut self.guards);
        // Emergency brake: the arm already closes in faster than a guard
        // allows (the limiter lags a sudden change of the guards).
        self.braking = guards.iter().any(|g| g.breached(&self.motion.qdot));
        if self.braking {
            self.request.iter_mut().for_each(|v| *v = 0.0);
        }
        let all_hold = self.guard_pairs.iter().all(|g| {
            g.obstacle_speed <= 0.0 || p.bound(g.distance, g.obstacle_speed, braking) >= 0.0
        });
        let (lo, hi) = self.admissible_box();
        let weights = cfg.joint_weights.as_deref().unwrap_or(&[]);
        let mut out = Vec::with_capacity(self.request.len());
        let result = protect::project(&self.request, weights, &lo, &hi, &guards, &mut out);
        self.request = out;
        // A guard the joints cannot meet right now is no reason to stop
        // while the arm can still outrun its obstacle ([`crate::avoidance::protect::Guard::escape`]):
        // the request is the closest admissible retreat.
        let infeasible = result
            .worst
            .filter(|_| result.violation > INFEASIBLE_TOLERANCE)
            .filter(|&k| {
                let g = &guards[k];
                g.obstacle_speed <= 0.0
                    || g.escape(&self.robot, &self.motion.qdot, &lo, &hi, &p)
                        .is_none()
            })
            .map(|k| (k, result.violation));
        let doomed = infeasible.or(self.doomed);
        let mut now = BTreeSet::new();
        if let Some((k, excess)) = doomed.filter(|_| !self.stopped) {
            let g = &guards[k];
            let key = g.obstacle.unwrap_or(usize::MAX);
            now.insert(key);
            if !self.unavoidable.contains(&key) {
                let obstacle = g.obstacle.map_or_else(
                    || format!("self:{}", self.skeleton.segments[g.segment].link),
                    |o| self.obstacles[o].spec.id.clone(),
                );
                self.push(EventKind::Unavoidable {
                    obstacle: obstacle.clone(),
                    segment: g.segment,
                    distance: g.distance,
                    excess,
                });
                // Held until the joints are at rest and every approaching
                // obstacle's guard holds again (`maybe_resume`).
                self.stop(
                    StopReason::Unavoidable,
                    format!("unavoidable approach ({obstacle})"),
                    braking,
                );
                self.request.iter_mut().for_each(|v| *v = 0.0);
            }
        }
        self.unavoidable = now;
        self.guards = guards;
        all_hold
    }
}
