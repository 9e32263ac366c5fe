//! Routes along the skeleton: the legs through the nodes between two points,
//! one per segment (that is, one per DH value), in the order they are met.

use super::SkeletonPoint;
use crate::skeleton::Skeleton;

/// Legs shorter than this (in `t`) are dropped from a route.
const LEG_EPSILON: f64 = 1e-12;

/// One leg of a route: segment `segment`, from `t0` to `t1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RouteLeg {
    /// Segment travelled.
    pub segment: usize,
    /// Fraction at the start of the leg.
    pub t0: f64,
    /// Fraction at the end of the leg.
    pub t1: f64,
}

/// The route along the skeleton from `from` to `to`: the legs through the
/// nodes, in order (empty when the points coincide). `None` when the two
/// segments are not connected (never for a skeleton built from one robot).
///
/// The skeleton is a tree, so the route is unique: it leaves `from`'s
/// segment through the end that leads towards `to`'s segment.
#[must_use]
pub fn route(skeleton: &Skeleton, from: SkeletonPoint, to: SkeletonPoint) -> Option<Vec<RouteLeg>> {
    let segs = &skeleton.segments;
    let (fs, ts) = (segs.get(from.segment)?, segs.get(to.segment)?);
    let mut legs = Vec::new();
    if from.segment == to.segment {
        if (to.t - from.t).abs() > LEG_EPSILON {
            legs.push(RouteLeg {
                segment: from.segment,
                t0: from.t,
                t1: to.t,
            });
        }
        return Some(legs);
    }
    // Breadth-first search over nodes from both ends of `from`'s segment,
    // never crossing the two end segments, until an end of `to`'s segment.
    let n = skeleton.nodes.len();
    let mut prev: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut seen = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    for start in [fs.from, fs.to] {
        if start < n && !seen[start] {
            seen[start] = true;
            queue.push_back(start);
        }
    }
    let mut goal = None;
    while let Some(u) = queue.pop_front() {
        if u == ts.from || u == ts.to {
            goal = Some(u);
            break;
        }
        for (k, s) in segs.iter().enumerate() {
            if k == from.segment || k == to.segment {
                continue;
            }
            let v = if s.from == u {
                s.to
            } else if s.to == u {
                s.from
            } else {
                continue;
            };
            if v < n && !seen[v] {
                seen[v] = true;
                prev[v] = Some((u, k));
                queue.push_back(v);
            }
        }
    }
    let goal = goal?;
    let mut middle = Vec::new();
    let mut node = goal;
    while let Some((u, k)) = prev[node] {
        middle.push((k, u, node));
        node = u;
    }
    middle.reverse();
    let exit = node;
    let end_of = |seg: usize, node: usize| if segs[seg].from == node { 0.0 } else { 1.0 };
    legs.push(RouteLeg {
        segment: from.segment,
        t0: from.t,
        t1: end_of(from.segment, exit),
    });
    for (k, u, v) in middle {
        legs.push(RouteLeg {
            segment: k,
            t0: end_of(k, u),
            t1: end_of(k, v),
        });
    }
    legs.push(RouteLeg {
        segment: to.segment,
        t0: end_of(to.segment, goal),
        t1: to.t,
    });
    legs.retain(|l| (l.t1 - l.t0).abs() > LEG_EPSILON);
    Some(legs)
}

/// Length of the route from `from` to `to` along the skeleton (m);
/// infinite when they are not connected.
#[must_use]
pub fn route_length(skeleton: &Skeleton, from: SkeletonPoint, to: SkeletonPoint) -> f64 {
    // Along one segment: the one leg [`route`] would give, without
    // building it (the tracker asks this of every point at every step).
    if from.segment == to.segment {
        return match skeleton.segments.get(from.segment) {
            Some(s) if (to.t - from.t).abs() > LEG_EPSILON => {
                let (a, b) = skeleton.endpoints(s);
                (to.t - from.t).abs() * (b - a).length()
            }
            Some(_) => 0.0,
            None => f64::INFINITY,
        };
    }
    route(skeleton, from, to).map_or(f64::INFINITY, |legs| {
        legs.iter()
            .map(|l| {
                let (a, b) = skeleton.endpoints(&skeleton.segments[l.segment]);
                (l.t1 - l.t0).abs() * (b - a).length()
            })
            .sum()
    })
}
