//! The *select* stage: which points of the skeleton become control points
//! (paper §II, fig. 4; DESIGN part 4).
//!
//! From the scene query's pairs (every segment against every obstacle within
//! reach, and non-adjacent segments against each other), [`select`] picks,
//! per [`Selection`] mode, the points the control points should follow:
//! the closest point of each segment–obstacle pair (`pairs`), the closest
//! point over the whole skeleton for each obstacle (`perObstacle`), or
//! nothing (`pinned`: the points are the user's). Self-collision pairs
//! always give a point on each side.
//!
//! The pairs are measured against the obstacles *as sensed*; an obstacle
//! takes part when its clearance minus its sensing margin is within the
//! influence distance.

use std::collections::BTreeMap;

use super::{ControllerConfig, Selection};
use crate::distance::{PairDistance, Target};
use crate::skeleton::Skeleton;
use crate::transition::SkeletonPoint;

/// Which control point: one per obstacle, per segment–obstacle pair, per
/// pinned point, or per side of a self-collision pair.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Key {
    /// The closest point of obstacle `o` over the whole skeleton.
    Obstacle(usize),
    /// The closest point of segment `s` to obstacle `o`: `Pair(o, s)`.
    Pair(usize, usize),
    /// Pinned point `k` of the controller.
    Pinned(usize),
    /// The point of segment `a` closest to segment `b`: `SelfPair(a, b)`.
    SelfPair(usize, usize),
}

/// What [`select`] found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Selected {
    /// Each control point's selected point and the obstacle it answers.
    pub points: BTreeMap<Key, (SkeletonPoint, Option<usize>)>,
    /// Per obstacle, the index (into the pairs) of its closest pair.
    pub closest: BTreeMap<usize, usize>,
}

/// Fraction along segment `seg` of the point closest to `p`.
#[must_use]
pub fn fraction_on(skeleton: &Skeleton, seg: usize, p: glam::DVec3) -> f64 {
    let (a, b) = skeleton.endpoints(&skeleton.segments[seg]);
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The selected points (see the module docs). `owners[id]` is the obstacle
/// of scene part `id`, `margins[o]` the sensing margin of obstacle `o`.
#[must_use]
pub fn select(
    pairs: &[PairDistance],
    owners: &[usize],
    margins: &[f64],
    skeleton: &Skeleton,
    config: &ControllerConfig,
) -> Selected {
    let mut out = Selected::default();
    let mut pair_best: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    let closer = |a: usize, b: usize| pairs[a].distance < pairs[b].distance;
    for (k, p) in pairs.iter().enumerate() {
        match p.target {
            Target::Obstacle { id, .. } => {
                let owner = owners[id as usize];
                if p.distance - margins[owner] > config.influence_distance {
                    continue;
                }
                if config.selection == Selection::Pairs {
                    let e = pair_best.entry((owner, p.segment)).or_insert(k);
                    if closer(k, *e) {
                        *e = k;
                    }
                }
                let e = out.closest.entry(owner).or_insert(k);
                if closer(k, *e) {
                    *e = k;
                }
            }
            Target::Segment(other) => {
                if p.distance > config.influence_distance {
                    continue;
                }
                let here = SkeletonPoint {
                    segment: p.segment,
                    t: p.fraction,
                };
                let there = SkeletonPoint {
                    segment: other,
                    t: fraction_on(skeleton, other, p.point_other),
                };
                out.points
                    .insert(Key::SelfPair(p.segment, other), (here, None));
                out.points
                    .insert(Key::SelfPair(other, p.segment), (there, None));
            }
        }
    }
    let at = |k: usize| SkeletonPoint {
        segment: pairs[k].segment,
        t: pairs[k].fraction,
    };
    for ((owner, segment), k) in pair_best {
        out.points
            .insert(Key::Pair(owner, segment), (at(k), Some(owner)));
    }
    if config.selection == Selection::PerObstacle {
        for (&owner, &k) in &out.closest {
            out.points
                .insert(Key::Obstacle(owner), (at(k), Some(owner)));
        }
    }
    out
}
