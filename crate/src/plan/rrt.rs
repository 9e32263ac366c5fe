//! RRT-Connect (Kuffner & LaValle, 2000) in joint space, with the
//! certified segments of [`super::checker`], then shortcutting.
//!
//! Two trees grow, one from the start and one from the goal. Each round
//! one tree takes a step of at most [`Search::step`] (in metres of
//! [`Checker::sweep`], so a step moves no point of the arm further than
//! that) towards a random configuration; the other then extends towards
//! the new node step by step until it reaches it or is blocked. The trees
//! swap roles every round. Distances are measured by the same sweep, so
//! the nearest node is the one the arm reaches with the least motion.
//!
//! A search that *creeps* ([`Search::creep`]) also keeps the certified
//! part of a blocked step when that is at least [`MIN_PROGRESS`] long
//! ([`Checker::segment_reach`]), and otherwise slides: the step projected
//! onto the directions that close none of the pairs near their thresholds
//! ([`Problem::slide`]). Without it a tree in a narrow passage, where
//! every straight step soon closes some pair (a gripper between two
//! boxes), hardly grows. It is the second try only: its trees fill with nodes along the
//! obstacles, so its paths have more corners (the arm stops at each) and
//! cost about ten times the evaluations (measured on the PR2 bookshelf).

use super::checker::{Checker, Thresholds};
use super::{MIN_SEGMENT_TIME, segment_time};
use crate::avoidance::protect::{Guard, project};
use crate::error::FieldError;
use crate::rng::Rng;

/// The search's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Search {
    /// Longest step of a tree (m of sweep).
    pub step: f64,
    /// Rounds before giving up.
    pub rounds: usize,
    /// Shortcut attempts on the path found.
    pub shortcuts: usize,
    /// Whether a blocked step keeps its certified part and slides along
    /// the pairs that block it (module docs).
    pub creep: bool,
}

/// One tree: nodes and each node's parent (`usize::MAX` for the root).
struct Tree {
    nodes: Vec<Vec<f64>>,
    parents: Vec<usize>,
}

impl Tree {
    fn new(root: Vec<f64>) -> Self {
        Self {
            nodes: vec![root],
            parents: vec![usize::MAX],
        }
    }

    fn nearest(&self, checker: &Checker, q: &[f64]) -> usize {
        let mut best = (0, f64::INFINITY);
        for (k, n) in self.nodes.iter().enumerate() {
            let d = checker.sweep(n, q);
            if d < best.1 {
                best = (k, d);
            }
        }
        best.0
    }

    /// The path from the root to node `k`.
    fn path_to(&self, mut k: usize) -> Vec<Vec<f64>> {
        let mut out = Vec::new();
        while k != usize::MAX {
            out.push(self.nodes[k].clone());
            k = self.parents[k];
        }
        out.reverse();
        out
    }
}

/// What an extension did.
enum Extend {
    Blocked,
    Advanced(usize),
    Reached(usize),
}

/// Shortest part of a blocked step kept as a node (m of sweep): shorter
/// ones would fill the tree with nodes that gain nothing.
const MIN_PROGRESS: f64 = 0.005;

/// Pairs whose margin is below this are kept from closing by a slide
/// (m; [`Problem::slide`]).
const SLIDE_BAND: f64 = 0.003;

/// The configuration a fraction `f` of the way from `a` to `b`.
fn along(a: &[f64], b: &[f64], f: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x + (y - x) * f).collect()
}

/// The planning problem as the search sees it.
pub(super) struct Problem<'a> {
    pub checker: &'a mut Checker,
    pub thresholds: Thresholds,
    pub bounds: &'a [(f64, f64)],
    pub search: Search,
}

impl Problem<'_> {
    /// One step of `tree` towards `target`.
    fn extend(&mut self, tree: &mut Tree, target: &[f64]) -> Result<Extend, FieldError> {
        let near = tree.nearest(self.checker, target);
        let from = &tree.nodes[near];
        let d = self.checker.sweep(from, target);
        let reached = d <= self.search.step;
        let q: Vec<f64> = if reached {
            target.to_vec()
        } else {
            let f = self.search.step / d;
            from.iter()
                .zip(target)
                .map(|(a, b)| a + (b - a) * f)
                .collect()
        };
        let free = self.checker.segment_reach(from, &q, &self.thresholds)?;
        let (q, reached) = if free >= 1.0 {
            (q, reached)
        } else if !self.search.creep {
            return Ok(Extend::Blocked);
        } else if free * d.min(self.search.step) >= MIN_PROGRESS {
            // Blocked on the way: the certified part is kept.
            (along(from, &q, free), false)
        } else {
            let from = from.clone();
            match self.slide(&from, &q, target)? {
                Some(q) => (q, false),
                None => return Ok(Extend::Blocked),
            }
        };
        tree.nodes.push(q);
        tree.parents.push(near);
        let k = tree.nodes.len() - 1;
        Ok(if reached {
            Extend::Reached(k)
        } else {
            Extend::Advanced(k)
        })
    }

    /// A step from `from` towards `to` that closes no pair near its
    /// threshold: the step projected onto the directions in which none of
    /// their margins falls (to first order), then walked as far as it is
    /// certified (`None` when that is shorter than [`MIN_PROGRESS`], or
    /// brings the tree less than that closer to `target`: a connection
    /// then still ends).
    ///
    /// Between two pairs whose normals oppose (a gripper in a pocket
    /// between boxes) every straight step closes one of them, so almost no
    /// random step is certified; the way out is along the pocket.
    fn slide(
        &mut self,
        from: &[f64],
        to: &[f64],
        target: &[f64],
    ) -> Result<Option<Vec<f64>>, FieldError> {
        let gradients = self
            .checker
            .tight_gradients(from, &self.thresholds, SLIDE_BAND)?;
        if gradients.is_empty() {
            return Ok(None);
        }
        let guards: Vec<Guard> = gradients
            .into_iter()
            .map(|g| Guard {
                row: g.iter().map(|x| -x).collect(),
                ..Guard::default()
            })
            .collect();
        let desired: Vec<f64> = from.iter().zip(to).map(|(a, b)| b - a).collect();
        let weights: Vec<f64> = self.checker.reach().iter().map(|r| r * r).collect();
        let n = desired.len();
        let (lo, hi) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
        let mut step = Vec::with_capacity(n);
        project(&desired, &weights, &lo, &hi, &guards, &mut step);
        let mut end: Vec<f64> = from.iter().zip(&step).map(|(a, s)| a + s).collect();
        // The projection may leave the joints' box; the segment to the
        // clamped end stays within it (a box is convex).
        self.checker.robot().clamp_to_limits(&mut end);
        let length = self.checker.sweep(from, &end);
        if !length.is_finite() || length < MIN_PROGRESS {
            return Ok(None);
        }
        let free = self.checker.segment_reach(from, &end, &self.thresholds)?;
        if free * length < MIN_PROGRESS {
            return Ok(None);
        }
        let q = along(from, &end, free);
        let closer = self.checker.sweep(from, target) - self.checker.sweep(&q, target);
        Ok((closer >= MIN_PROGRESS).then_some(q))
    }

    /// Extends `tree` towards `target` until it reaches it or is blocked.
    fn connect(&mut self, tree: &mut Tree, target: &[f64]) -> Result<Option<usize>, FieldError> {
        loop {
            match self.extend(tree, target)? {
                Extend::Blocked => return Ok(None),
                Extend::Reached(k) => return Ok(Some(k)),
                Extend::Advanced(_) => {}
            }
        }
    }

    fn sample(&self, rng: &mut Rng) -> Vec<f64> {
        self.bounds
            .iter()
            .map(|&(lo, hi)| rng.range(lo, hi))
            .collect()
    }

    /// A free path from `start` to `goal` (both free), or `None` after
    /// [`Search::rounds`] rounds.
    pub fn search(
        &mut self,
        start: &[f64],
        goal: &[f64],
        rng: &mut Rng,
    ) -> Result<Option<Vec<Vec<f64>>>, FieldError> {
        if self.checker.segment_free(start, goal, &self.thresholds)? {
            return Ok(Some(vec![start.to_vec(), goal.to_vec()]));
        }
        let mut a = Tree::new(start.to_vec());
        let mut b = Tree::new(goal.to_vec());
        let mut a_is_start = true;
        for _ in 0..self.search.rounds {
            let target = self.sample(rng);
            if let Extend::Advanced(k) | Extend::Reached(k) = self.extend(&mut a, &target)? {
                let new = a.nodes[k].clone();
                if let Some(j) = self.connect(&mut b, &new)? {
                    let (mut head, mut tail) = (a.path_to(k), b.path_to(j));
                    if !a_is_start {
                        std::mem::swap(&mut head, &mut tail);
                    }
                    tail.reverse();
                    tail.remove(0);
                    head.extend(tail);
                    return Ok(Some(head));
                }
            }
            std::mem::swap(&mut a, &mut b);
            a_is_start = !a_is_start;
        }
        Ok(None)
    }

    /// How long the `joints` task takes over `path` (s): each segment
    /// timed as the plan times it.
    fn duration(&self, path: &[Vec<f64>]) -> f64 {
        path.windows(2)
            .filter(|w| w[0] != w[1])
            .map(|w| segment_time(self.checker.robot(), &w[0], &w[1]).max(MIN_SEGMENT_TIME))
            .sum()
    }

    /// `path` shortened: first greedily (from each kept node, the farthest
    /// node it sees), then [`Search::shortcuts`] random attempts to join
    /// two points on the path, each kept only if the path then takes less
    /// time (a shortcut adds two nodes, and the arm stops at each).
    pub fn shorten(
        &mut self,
        path: Vec<Vec<f64>>,
        rng: &mut Rng,
    ) -> Result<Vec<Vec<f64>>, FieldError> {
        let thresholds = self.thresholds;
        let checker = &mut *self.checker;
        let mut out = super::skip_nodes(path, |a, b| checker.segment_free(a, b, &thresholds))?;
        for _ in 0..self.search.shortcuts {
            if out.len() < 3 {
                break;
            }
            let (a, b) = two_points(out.len(), rng);
            let pa = point_on(&out, a);
            let pb = point_on(&out, b);
            let (ia, ib) = (a.floor() as usize, b.floor() as usize);
            let mut next = out[..=ia].to_vec();
            next.push(pa.clone());
            next.push(pb.clone());
            next.extend_from_slice(&out[ib + 1..]);
            next.dedup();
            // Kept only if it saves time: each node it adds is a stop.
            if self.duration(&next) < self.duration(&out)
                && self.checker.segment_free(&pa, &pb, &self.thresholds)?
            {
                out = next;
            }
        }
        Ok(out)
    }
}

/// Two positions `a < b` on a path of `n` nodes (node `k` at `k`), on
/// different segments.
fn two_points(n: usize, rng: &mut Rng) -> (f64, f64) {
    let span = (n - 1) as f64;
    let (x, y) = (rng.range(0.0, span), rng.range(0.0, span));
    let (a, b) = (x.min(y), x.max(y));
    if b.floor() <= a.floor() {
        (a.floor(), (a.floor() + 1.0).min(span))
    } else {
        (a, b)
    }
}

/// The configuration at position `s` along `path` (node `k` at `s = k`).
fn point_on(path: &[Vec<f64>], s: f64) -> Vec<f64> {
    let k = (s.floor() as usize).min(path.len() - 2);
    let f = s - k as f64;
    if f <= 0.0 || f >= 1.0 {
        // A node itself, to the bit.
        return path[if f <= 0.0 { k } else { k + 1 }].clone();
    }
    path[k]
        .iter()
        .zip(&path[k + 1])
        .map(|(a, b)| a + (b - a) * f)
        .collect()
}
