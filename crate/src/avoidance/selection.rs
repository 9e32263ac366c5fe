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
//!
//! **Switch hysteresis.** With `switchHysteresis` = h > 0, a `perObstacle`
//! point stays on the segment it follows while that segment's closest pair
//! is within h of the obstacle's closest pair: sensing noise of bound b
//! moves the gap between two segments' clearances by at most 2b, so with
//! h ≥ 2b noise alone cannot flip the point between two segments at the
//! same distance (which otherwise switches it every step and makes the
//! chattering monitor stop the arm). The price is that the point may
//! answer a pair up to h farther than the closest one; the protective
//! layer (`protect.rs`) still guards every pair. h = 0 (the default) is
//! the paper's selection: always the closest.

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
/// of scene part `id`, `margins[o]` the sensing margin of obstacle `o`,
/// `following[o]` the segment obstacle `o`'s `perObstacle` point follows
/// (read only with a switch hysteresis).
#[must_use]
pub fn select(
    pairs: &[PairDistance],
    owners: &[usize],
    margins: &[f64],
    following: &BTreeMap<usize, usize>,
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
                if config.beyond_influence(p.distance - margins[owner]) {
                    continue;
                }
                if config.selection == Selection::Pairs || config.switch_hysteresis > 0.0 {
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
                if config.beyond_influence(p.distance) {
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
    if config.selection == Selection::PerObstacle {
        for (&owner, &k) in &out.closest {
            // Without a hysteresis `pair_best` is empty here: the closest.
            let k = following
                .get(&owner)
                .and_then(|s| pair_best.get(&(owner, *s)).copied())
                .filter(|&j| pairs[j].distance <= pairs[k].distance + config.switch_hysteresis)
                .unwrap_or(k);
            out.points
                .insert(Key::Obstacle(owner), (at(k), Some(owner)));
        }
    } else if config.selection == Selection::Pairs {
        for ((owner, segment), k) in pair_best {
            out.points
                .insert(Key::Pair(owner, segment), (at(k), Some(owner)));
        }
    }
    out
}

// Compiled only for tests: its unwraps (a preset that exists, its forward
// kinematics at zero) cannot reach a JavaScript caller.
#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;
    use crate::kinematics::{Robot, presets};
    use glam::DVec3;

    /// A pair of segment `segment` and scene part 0 at `distance`.
    fn pair(segment: usize, distance: f64) -> PairDistance {
        PairDistance {
            segment,
            target: Target::Obstacle { id: 0, index: 0 },
            distance,
            point_segment: DVec3::ZERO,
            point_other: DVec3::X,
            fraction: 0.5,
            normal: DVec3::X,
            unique: true,
        }
    }

    fn segment_of(selected: &Selected) -> usize {
        selected.points[&Key::Obstacle(0)].0.segment
    }

    #[test]
    fn a_point_keeps_its_segment_while_it_is_within_the_hysteresis_of_the_closest() {
        let robot = Robot::from_spec(&presets::preset("lwr4").unwrap()).unwrap();
        let skeleton = Skeleton::build(&robot, &robot.forward(&[0.0; 7]).unwrap());
        let pairs = [pair(1, 0.100), pair(2, 0.095)];
        let following = BTreeMap::from([(0, 1)]);
        let with = |h: f64| ControllerConfig {
            switch_hysteresis: h,
            ..ControllerConfig::default()
        };
        let pick = |config: &ControllerConfig, following: &BTreeMap<usize, usize>| {
            select(&pairs, &[0], &[0.0], following, &skeleton, config)
        };
        // The paper's rule: the closest, whatever the point follows.
        assert_eq!(segment_of(&pick(&with(0.0), &following)), 2);
        // 5 mm closer is within a 1 cm hysteresis, not within 4 mm.
        assert_eq!(segment_of(&pick(&with(0.01), &following)), 1);
        assert_eq!(segment_of(&pick(&with(0.004), &following)), 2);
        // A new point, or one whose segment has no pair, takes the closest.
        assert_eq!(segment_of(&pick(&with(0.01), &BTreeMap::new())), 2);
        assert_eq!(segment_of(&pick(&with(0.01), &BTreeMap::from([(0, 4)]))), 2);
        // The obstacle's closest pair is reported as it is.
        assert_eq!(pick(&with(0.01), &following).closest[&0], 1);
        // Other modes are unchanged: one point per pair, or none.
        let pairs_mode = ControllerConfig {
            selection: Selection::Pairs,
            ..with(0.01)
        };
        assert_eq!(pick(&pairs_mode, &following).points.len(), 2);
        let pinned = ControllerConfig {
            selection: Selection::Pinned,
            ..with(0.01)
        };
        assert!(pick(&pinned, &following).points.is_empty());
    }
}
