//! The planner's collision checker: the clearance of the arm's volumes at a
//! configuration (the same skeleton, volumes, obstacles and self pairs a
//! [`crate::world::World`] queries), and straight joint-space segments
//! certified free with a Lipschitz bound instead of sampled.
//!
//! **The bound.** When joint `j` turns by `Δq_j`, no point of the volumes
//! moves by more than `ρ_j |Δq_j|`, where `ρ_j` bounds the distance of
//! any point carried by joint `j` from its axis: the sum of every later
//! row's lengths (`|a|`, `|d|`, a prismatic joint's travel, the extension)
//! plus the largest radius ([`Checker::reach`]); a prismatic joint moves
//! its points by `|Δq_j|`. So between `q` and `q + Δq` an obstacle
//! clearance changes by at most `Σ ρ_j |Δq_j|`, and a self clearance (two
//! moving volumes) by at most twice that. A segment is walked from one end
//! in steps as long as the margin over the threshold at the current point
//! allows: every configuration in between is then provably at least at
//! the threshold, however thin the obstacle. Each step leaves
//! [`MIN_MARGIN`] of the margin unused, and a point with less than twice
//! that counts as a collision: every step then advances by at least
//! `MIN_MARGIN` of sweep (steps sized by the margin alone would shrink
//! towards a boundary and never reach it), and every configuration of a
//! free segment keeps a margin of `MIN_MARGIN` at least.

use crate::distance::{Obstacle, PairDistance, QueryOptions, Scene, Target};
use crate::error::FieldError;
use crate::kinematics::{Frames, JointType, Robot};
use crate::scenario::Scenario;
use crate::skeleton::Skeleton;
use crate::world::{World, self_pairs_left_out};

/// The smallest margin over the thresholds a configuration on a certified
/// segment may have (m).
pub const MIN_MARGIN: f64 = 5e-4;

/// Clearances beyond this are not measured (m): a configuration this clear
/// certifies long steps anyway.
const HORIZON: f64 = 0.5;

/// Clearances the planner keeps (m).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Thresholds {
    /// Between the arm's volumes and the obstacles.
    pub obstacles: f64,
    /// Between two of the arm's non-adjacent links.
    pub self_pairs: f64,
}

/// The arm's geometry against a scene frozen at one instant.
#[derive(Clone, Debug)]
pub struct Checker {
    robot: Robot,
    scene: Scene,
    adjacency: Vec<Vec<bool>>,
    self_collision: bool,
    frames: Frames,
    skeleton: Skeleton,
    reach: Vec<f64>,
    /// Pairs kept at a threshold of their own (see [`Checker::relax`]).
    relaxed: Vec<(usize, Target, f64)>,
    /// Clearance evaluations so far.
    pub evaluations: usize,
}

impl Checker {
    /// A checker for `robot` among `scene`, leaving out the self pairs
    /// `adjacency` marks (as a world does), self pairs measured only with
    /// `self_collision`.
    ///
    /// # Errors
    /// A robot whose forward kinematics fails at its limits' midpoints.
    pub fn new(
        robot: Robot,
        scene: Scene,
        adjacency: Vec<Vec<bool>>,
        self_collision: bool,
    ) -> Result<Self, FieldError> {
        let mut q = vec![0.0; robot.dof()];
        robot.clamp_to_limits(&mut q);
        let frames = robot.forward(&q)?;
        let skeleton = Skeleton::build(&robot, &frames);
        let reach = reach(&robot);
        Ok(Self {
            robot,
            scene,
            adjacency,
            self_collision,
            frames,
            skeleton,
            reach,
            relaxed: Vec::new(),
            evaluations: 0,
        })
    }

    /// A checker for `scenario`'s robot among its obstacles as they stand
    /// at `t = 0`, with the self pairs its controller measures, and the
    /// scenario's start configuration.
    ///
    /// # Errors
    /// A scenario a world refuses.
    pub fn for_scenario(scenario: &Scenario) -> Result<(Self, Vec<f64>), FieldError> {
        let world =
            World::new(scenario.clone()).map_err(|e| FieldError::new("scenario", e.to_string()))?;
        let robot = world.robot().clone();
        let obstacles = world
            .obstacle_primitives()
            .into_iter()
            .zip(0..)
            .map(|((_, shape), id)| Obstacle { id, shape })
            .collect();
        let controller = &scenario.controller;
        let adjacency = self_pairs_left_out(&robot, controller)?;
        let checker = Self::new(
            robot,
            Scene::new(obstacles),
            adjacency,
            controller.self_collision,
        )?;
        Ok((checker, world.q().to_vec()))
    }

    /// The robot.
    #[must_use]
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Per joint, the bound `ρ_j` of the module docs (m per rad, or 1 for
    /// a prismatic joint).
    #[must_use]
    pub fn reach(&self) -> &[f64] {
        &self.reach
    }

    /// Every pair within half a metre at `q`.
    fn pairs(&mut self, q: &[f64]) -> Result<Vec<PairDistance>, FieldError> {
        self.evaluations += 1;
        self.robot.forward_into(q, &mut self.frames)?;
        self.skeleton.build_into(&self.robot, &self.frames);
        let options = QueryOptions {
            influence_distance: HORIZON,
            self_collision: self.self_collision,
            ..QueryOptions::default()
        };
        let adjacency = &self.adjacency;
        self.scene
            .query(&self.skeleton, &options, |i, j| adjacency[i][j])
            .map_err(|e| FieldError::new("q", e.to_string()))
    }

    /// The smallest obstacle clearance and the smallest self clearance at
    /// `q` (m, each capped at half a metre).
    ///
    /// # Errors
    /// A configuration of the wrong length or not finite.
    pub fn clearances(&mut self, q: &[f64]) -> Result<(f64, f64), FieldError> {
        let (mut obstacles, mut selfs) = (HORIZON, HORIZON);
        for p in self.pairs(q)? {
            match p.target {
                Target::Obstacle { .. } => obstacles = obstacles.min(p.distance),
                Target::Segment(_) => selfs = selfs.min(p.distance),
            }
        }
        Ok((obstacles, selfs))
    }

    /// The margin of `q` over `thresholds`, in metres of obstacle
    /// clearance: the smallest over the pairs of the obstacle margin and
    /// half the self margin (a self clearance closes twice as fast, module
    /// docs), a relaxed pair against its own threshold.
    ///
    /// # Errors
    /// As [`Checker::clearances`].
    pub fn margin(&mut self, q: &[f64], thresholds: &Thresholds) -> Result<f64, FieldError> {
        let m = (HORIZON - thresholds.obstacles).min(0.5 * (HORIZON - thresholds.self_pairs));
        Ok(self
            .pairs(q)?
            .iter()
            .map(|p| self.pair_margin(p, thresholds))
            .fold(m, f64::min))
    }

    /// The margin of one pair (see [`Checker::margin`]).
    fn pair_margin(&self, p: &PairDistance, thresholds: &Thresholds) -> f64 {
        let own = self
            .relaxed
            .iter()
            .find(|r| r.0 == p.segment && r.1 == p.target)
            .map(|r| r.2);
        match p.target {
            Target::Obstacle { .. } => p.distance - own.unwrap_or(thresholds.obstacles),
            Target::Segment(_) => 0.5 * (p.distance - own.unwrap_or(thresholds.self_pairs)),
        }
    }

    /// The gradients (per joint) of the margins of the pairs whose margin
    /// at `q` is below `band`, by forward differences: the directions in
    /// which those pairs close are those with a negative product.
    ///
    /// # Errors
    /// As [`Checker::clearances`].
    pub fn tight_gradients(
        &mut self,
        q: &[f64],
        thresholds: &Thresholds,
        band: f64,
    ) -> Result<Vec<Vec<f64>>, FieldError> {
        const H: f64 = 1e-6;
        let tight: Vec<(PairDistance, f64)> = self
            .pairs(q)?
            .into_iter()
            .map(|p| {
                let m = self.pair_margin(&p, thresholds);
                (p, m)
            })
            .filter(|(_, m)| *m < band)
            .collect();
        let mut gradients = vec![vec![0.0; q.len()]; tight.len()];
        let mut p = q.to_vec();
        for j in 0..q.len() {
            p[j] = q[j] + H;
            let moved = self.pairs(&p)?;
            p[j] = q[j];
            for ((pair, m), g) in tight.iter().zip(&mut gradients) {
                if let Some(x) = moved
                    .iter()
                    .find(|x| x.segment == pair.segment && x.target == pair.target)
                {
                    g[j] = (self.pair_margin(x, thresholds) - m) / H;
                }
            }
        }
        Ok(gradients)
    }

    /// Keeps every pair closer than `thresholds` at `q` at a threshold of
    /// its own, its clearance there less `3 MIN_MARGIN` (`6 MIN_MARGIN` for
    /// a self pair): the planner keeps such a pair (an arm the escape
    /// cannot free further, or two of its volumes that overlap, e.g. one
    /// that turns about its own axis) from closing further, and every
    /// other pair at `thresholds`. An obstacle pair is relaxed only down to
    /// `floor`; returns by how much the closest one falls short of it (m,
    /// 0 when none does: module docs of `escape.rs`).
    ///
    /// # Errors
    /// As [`Checker::clearances`].
    pub fn relax(
        &mut self,
        q: &[f64],
        thresholds: &Thresholds,
        floor: f64,
    ) -> Result<f64, FieldError> {
        let mut short: f64 = 0.0;
        for p in self.pairs(q)? {
            match p.target {
                Target::Obstacle { .. } if p.distance < thresholds.obstacles + 3.0 * MIN_MARGIN => {
                    let own = p.distance - 3.0 * MIN_MARGIN;
                    short = short.max(floor - own);
                    self.relaxed.push((p.segment, p.target, own));
                }
                Target::Segment(_) if p.distance < thresholds.self_pairs + 6.0 * MIN_MARGIN => {
                    self.relaxed
                        .push((p.segment, p.target, p.distance - 6.0 * MIN_MARGIN));
                }
                Target::Obstacle { .. } | Target::Segment(_) => {}
            }
        }
        Ok(short)
    }

    /// How far points of the volumes can move between `a` and `b`, at most
    /// (m): `Σ ρ_j |b_j − a_j|`.
    #[must_use]
    pub fn sweep(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .zip(&self.reach)
            .map(|((x, y), r)| r * (y - x).abs())
            .sum()
    }

    /// Whether every configuration on the straight segment from `a` to `b`
    /// keeps a margin of at least [`MIN_MARGIN`] over `thresholds`, every
    /// point checked keeping twice that (module docs).
    ///
    /// # Errors
    /// As [`Checker::clearances`].
    pub fn segment_free(
        &mut self,
        a: &[f64],
        b: &[f64],
        thresholds: &Thresholds,
    ) -> Result<bool, FieldError> {
        Ok(self.segment_reach(a, b, thresholds)? >= 1.0)
    }

    /// How much of the straight segment from `a` to `b` is certified free:
    /// `1` when all of it is ([`Checker::segment_free`]), else the fraction
    /// of the last point the walk checked with a margin of
    /// `3 MIN_MARGIN` at least (`0` for none), so that the walk from a
    /// node put there can go on (a point with less than `2 MIN_MARGIN`
    /// ends every walk from it).
    ///
    /// # Errors
    /// As [`Checker::clearances`].
    pub fn segment_reach(
        &mut self,
        a: &[f64],
        b: &[f64],
        thresholds: &Thresholds,
    ) -> Result<f64, FieldError> {
        let length = self.sweep(a, b);
        let mut q = a.to_vec();
        let (mut s, mut kept) = (0.0, 0.0);
        loop {
            for ((v, x), y) in q.iter_mut().zip(a).zip(b) {
                *v = x + (y - x) * s;
            }
            let m = self.margin(&q, thresholds)?;
            if m < 2.0 * MIN_MARGIN {
                return Ok(kept);
            }
            if s >= 1.0 || length <= 0.0 {
                return Ok(1.0);
            }
            if m >= 3.0 * MIN_MARGIN {
                kept = s;
            }
            // Any configuration within (m − MIN_MARGIN) of sweep keeps the
            // margin; the next point is checked itself.
            s = (s + (m - MIN_MARGIN) / length).min(1.0);
        }
    }
}

/// `ρ_j` for every joint (module docs).
fn reach(robot: &Robot) -> Vec<f64> {
    let radius = robot
        .joints
        .iter()
        .map(|j| {
            let r = &j.radius;
            [r.d, r.a, r.extension]
                .iter()
                .flatten()
                .copied()
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    let length = |j: &crate::kinematics::Joint| {
        let travel = match j.kind {
            JointType::Prismatic => j.min.abs().max(j.max.abs()),
            JointType::Revolute => 0.0,
        };
        j.a.abs() + j.d.abs() + travel + j.extension
    };
    (0..robot.dof())
        .map(|k| match robot.joints[k].kind {
            JointType::Prismatic => 1.0,
            JointType::Revolute => robot.joints[k..].iter().map(length).sum::<f64>() + radius,
        })
        .collect()
}
