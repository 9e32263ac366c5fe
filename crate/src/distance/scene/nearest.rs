//! The smallest clearance alone: [`Scene::nearest`].
//!
//! The world measures the scene twice a step when its sensing is noisy:
//! once as sensed, for the controller, which needs every pair within the
//! influence distance, and once as it truly is, for the clearance it
//! reports, which needs only the nearest pair (and the nearest pair with a
//! person's part). That second query measures its candidates in the order
//! of a lower bound on their clearance and skips every candidate whose
//! bound already exceeds the minima found, so most pairs of a person beside
//! the arm are never measured exactly.
//!
//! The bound: an obstacle lies inside its bounding box, and every point of a
//! segment's volume lies within the volume's largest radius of its axis. So
//! when the axis stays out of the box, by a gap `g`, the axis stays out of
//! the obstacle, and moving the volume by at most `r_max − g` separates the
//! two: the clearance, negative or not, is at least `g − r_max`. An axis
//! that reaches into the box gets no bound (a volume deep inside a large
//! obstacle may be far more negative than `−r_max`), nor do planes
//! (unbounded) and points and balls (cheaper to measure than to bound);
//! those are measured first.

use super::box_tree::bounds_of;
use super::{DistanceError, PairDistance, Scene, Target, axis_of, pair, volumes};
use crate::distance::cuboid::segment_aabb_distance2;
use crate::distance::{Primitive, distance};
use crate::error::non_negative;
use crate::skeleton::Skeleton;

/// The nearest pairs [`Scene::nearest`] finds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Nearest {
    /// The nearest segment–obstacle pair within the influence distance.
    pub all: Option<PairDistance>,
    /// The nearest such pair whose obstacle the caller's filter accepts.
    pub kept: Option<PairDistance>,
}

impl Scene {
    /// The nearest segment–obstacle pair within `influence` of `skeleton`,
    /// and the nearest one among the obstacles (by index) that `keep`
    /// accepts: the smallest of what [`Scene::query`] would report without
    /// self-collision, found without measuring the pairs that cannot be
    /// the smallest (see the module docs). Equal clearances may name a
    /// different pair of the two.
    ///
    /// # Errors
    /// A negative or NaN `influence` (`influenceDistance`), a skeleton with
    /// non-finite nodes or node indices out of range, as [`Scene::query`].
    pub fn nearest(
        &self,
        skeleton: &Skeleton,
        influence: f64,
        keep: impl Fn(usize) -> bool,
    ) -> Result<Nearest, DistanceError> {
        let influence = non_negative("influenceDistance", influence)?;
        let volumes = volumes(skeleton)?;
        // (lower bound, segment, obstacle) of every candidate within reach.
        let mut candidates = Vec::new();
        let mut near = Vec::new();
        for (i, vol) in volumes.iter().enumerate() {
            let (s0, s1, rmax) = axis_of(vol);
            near.clear();
            self.tree.query(&bounds_of(vol).grown(influence), &mut near);
            near.extend_from_slice(&self.unbounded);
            for &j in &near {
                let b = &self.bounds[j];
                let exact_is_cheap = matches!(
                    self.obstacles[j].shape,
                    Primitive::Sphere(_) | Primitive::Point(_)
                );
                let gap = if exact_is_cheap || !b.is_finite() {
                    0.0
                } else {
                    segment_aabb_distance2(s0, s1, b.min, b.max).sqrt()
                };
                // An axis that reaches into the box may be deep inside the
                // obstacle: no bound on how negative the clearance is.
                let bound = if gap > 0.0 {
                    gap - rmax
                } else {
                    f64::NEG_INFINITY
                };
                if bound <= influence {
                    candidates.push((bound, i, j));
                }
            }
        }
        candidates
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut found = Nearest::default();
        let clearance = |p: &Option<PairDistance>| p.map_or(influence, |p| p.distance);
        for (bound, i, j) in candidates {
            let (all, kept) = (clearance(&found.all), clearance(&found.kept));
            let wanted = keep(j);
            if bound > all && (!wanted || bound > kept) {
                if bound > all.max(kept) {
                    break;
                }
                continue;
            }
            let o = &self.obstacles[j];
            let d = distance(&volumes[i], &o.shape)?;
            if d.distance > influence {
                continue;
            }
            let p = pair(i, &volumes[i], Target::Obstacle { index: j, id: o.id }, d);
            if found.all.is_none_or(|b| p.distance < b.distance) {
                found.all = Some(p);
            }
            if wanted && found.kept.is_none_or(|b| p.distance < b.distance) {
                found.kept = Some(p);
            }
        }
        Ok(found)
    }
}
