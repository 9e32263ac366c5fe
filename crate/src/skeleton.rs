//! The skeleton: nodes and tapered segments built from the DH table (paper §II,
//! fig. 1).
//!
//! Nodes are the Cartesian points reached along the DH chain: per row, the
//! point after its first translation and the point after its second (`d` then
//! `a` in the standard convention, `a` then `d` in the modified one). A
//! translation of zero length adds no node, so nodes never coincide by
//! construction. Segments join consecutive nodes and carry a volume of
//! revolution whose radius varies linearly along them (a tapered capsule).

use glam::DVec3;

use crate::kinematics::{Convention, Frames, JointType, LinkRadii, Robot};

/// Which translation of its DH row a segment spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum SpinePart {
    /// The `d` translation, along the row's z axis.
    D,
    /// The `a` translation, along the row's x axis.
    A,
    /// An extra spine piece behind the joint (counterbalance, motor): `a' < 0`.
    Extension,
}

/// One segment of the skeleton, between two nodes, with the radius of the
/// volume of revolution around it varying linearly from `radius[0]` at `from`
/// to `radius[1]` at `to` (a tapered capsule).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Index of the start node.
    pub from: usize,
    /// Index of the end node.
    pub to: usize,
    /// The DH row (1-based link index) whose translation this segment spans.
    pub link: usize,
    /// Which translation of the row.
    pub part: SpinePart,
    /// Radius at `from` and at `to` (m).
    pub radius: [f64; 2],
}

/// Nodes (Cartesian points, m, world frame) and the segments between them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Skeleton {
    /// Node positions.
    pub nodes: Vec<DVec3>,
    /// Segments between nodes.
    pub segments: Vec<Segment>,
    /// Node at (or, for a zero-length row, standing for) each frame origin,
    /// index 0 (base) ..= n.
    pub frame_nodes: Vec<usize>,
}

impl Skeleton {
    /// End points of segment `s`.
    #[must_use]
    pub fn endpoints(&self, s: &Segment) -> (DVec3, DVec3) {
        (self.nodes[s.from], self.nodes[s.to])
    }
}

/// Translations shorter than this (m) add no node: the node would coincide
/// with the one before it (defined with the robot model, which uses it to
/// find a row's skeleton parent; dependencies point skeleton → kinematics).
pub use crate::kinematics::NODE_TOLERANCE;

impl Skeleton {
    /// Builds the skeleton of `robot` at the configuration of `frames`.
    ///
    /// Per DH row, in the order of its two translations, a node is added after
    /// each translation that is not shorter than [`NODE_TOLERANCE`] (prismatic
    /// `d` always counts), with a segment from the previous node; a row with
    /// an `extension` adds a dead-end segment behind the start of its `a`
    /// translation. Which nodes exist depends only on the DH table, never on
    /// `q`, so segment indices are stable while the robot moves. Branches start
    /// from the node of their parent frame.
    #[must_use]
    pub fn build(robot: &Robot, frames: &Frames) -> Self {
        let mut s = Self::default();
        s.build_into(robot, frames);
        s
    }

    /// [`Skeleton::build`] into existing storage.
    pub fn build_into(&mut self, robot: &Robot, frames: &Frames) {
        self.nodes.clear();
        self.segments.clear();
        self.frame_nodes.clear();
        self.frame_nodes.resize(robot.dof() + 1, 0);
        self.nodes.push(frames.transforms[0].translation);
        for (i, joint) in robot.joints.iter().enumerate() {
            let link = i + 1;
            let start_node = self.frame_nodes[joint.parent];
            let (first_len, second_len, first_part, second_part) = match robot.convention {
                Convention::Standard => (
                    if joint.kind == JointType::Prismatic {
                        f64::INFINITY
                    } else {
                        joint.d.abs()
                    },
                    joint.a.abs(),
                    SpinePart::D,
                    SpinePart::A,
                ),
                Convention::Modified => (
                    joint.a.abs(),
                    if joint.kind == JointType::Prismatic {
                        f64::INFINITY
                    } else {
                        joint.d.abs()
                    },
                    SpinePart::A,
                    SpinePart::D,
                ),
            };
            let mut current = start_node;
            if first_len >= NODE_TOLERANCE {
                current = self.push(
                    current,
                    frames.mids[i],
                    link,
                    first_part,
                    part_radius(&joint.radius, first_part),
                );
            }
            // The a spine starts at the mid node (standard) or at the row's start (modified).
            if joint.extension >= NODE_TOLERANCE {
                let (from, x) = match robot.convention {
                    Convention::Standard => (current, frames.transforms[link].matrix3.x_axis),
                    Convention::Modified => (start_node, frames.starts[i].matrix3.x_axis),
                };
                let sign = if joint.a < 0.0 { -1.0 } else { 1.0 };
                let tip = self.nodes[from] - sign * joint.extension * x;
                self.push(
                    from,
                    tip,
                    link,
                    SpinePart::Extension,
                    joint.radius.extension,
                );
            }
            if second_len >= NODE_TOLERANCE {
                current = self.push(
                    current,
                    frames.transforms[link].translation,
                    link,
                    second_part,
                    part_radius(&joint.radius, second_part),
                );
            }
            self.frame_nodes[link] = current;
        }
    }

    fn push(
        &mut self,
        from: usize,
        p: DVec3,
        link: usize,
        part: SpinePart,
        radius: [f64; 2],
    ) -> usize {
        self.nodes.push(p);
        let to = self.nodes.len() - 1;
        self.segments.push(Segment {
            from,
            to,
            link,
            part,
            radius,
        });
        to
    }

    /// Closest point of the skeleton's spine to `p`: `(segment, t, point)`, or
    /// `None` when the skeleton has no segment.
    #[must_use]
    pub fn closest_point(&self, p: DVec3) -> Option<(usize, f64, DVec3)> {
        let mut best: Option<(usize, f64, DVec3, f64)> = None;
        for (k, s) in self.segments.iter().enumerate() {
            let (a, b) = self.endpoints(s);
            let ab = b - a;
            let l2 = ab.length_squared();
            let t = if l2 > 0.0 {
                ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let c = a + t * ab;
            let d2 = (p - c).length_squared();
            if best.is_none_or(|b| d2 < b.3) {
                best = Some((k, t, c, d2));
            }
        }
        best.map(|(k, t, c, _)| (k, t, c))
    }

    /// The segment of the skeleton a ray points at, and the point of its
    /// spine closest to the ray; `None` when the ray passes every volume by
    /// more than `tolerance` (m) or the skeleton has no segment.
    ///
    /// The ray starts at `origin` and runs along `direction` (any length;
    /// `None` when it is zero or not finite). A segment is hit when the ray
    /// passes within its radius there plus `tolerance`. The volume entered
    /// first is found (its entry estimated as the closest approach minus the
    /// half chord of a sphere of that radius); it and every hit segment
    /// whose closest approach lies no deeper than its closest approach plus
    /// its radius (at the same depth, as all spines of a planar arm seen
    /// from above) compete, and the spine nearest the ray wins. A volume in
    /// front hides what is behind it; volumes that overlap at a joint do not
    /// hide each other's spines.
    #[must_use]
    pub fn ray_hit(&self, origin: DVec3, direction: DVec3, tolerance: f64) -> Option<RayHit> {
        let u = direction.try_normalize()?;
        if !origin.is_finite() || !tolerance.is_finite() {
            return None;
        }
        let tolerance = tolerance.max(0.0);
        let mut hits = Vec::new();
        for (k, s) in self.segments.iter().enumerate() {
            let (a, b) = self.endpoints(s);
            let (t, along) = ray_segment_closest(origin, u, a, b);
            let point = a + (b - a) * t;
            let offset = (origin + u * along - point).length();
            let radius = Self::radius_at(s, t);
            let reach = radius.max(0.0) + tolerance;
            if offset <= reach {
                let entry = along - (reach * reach - offset * offset).max(0.0).sqrt();
                let hit = RayHit {
                    segment: k,
                    t,
                    point,
                    distance: along,
                    offset,
                    radius,
                };
                hits.push((entry, reach, hit));
            }
        }
        let (_, reach, front) = hits.iter().copied().min_by(|x, y| x.0.total_cmp(&y.0))?;
        let depth = front.distance + reach;
        hits.into_iter()
            .map(|(_, _, h)| h)
            .filter(|h| h.distance <= depth)
            .min_by(|x, y| {
                x.offset
                    .total_cmp(&y.offset)
                    .then(x.distance.total_cmp(&y.distance))
            })
    }

    /// Radius of segment `s` at fraction `t` along it.
    #[must_use]
    pub fn radius_at(s: &Segment, t: f64) -> f64 {
        s.radius[0] + (s.radius[1] - s.radius[0]) * t
    }
}

/// The radii `[r0, r1]` a row gives its segment spanning `part`.
#[must_use]
pub fn part_radius(radii: &LinkRadii, part: SpinePart) -> [f64; 2] {
    match part {
        SpinePart::D => radii.d,
        SpinePart::A => radii.a,
        SpinePart::Extension => radii.extension,
    }
}

/// Where a ray passes closest to a skeleton segment: see [`Skeleton::ray_hit`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Index of the segment.
    pub segment: usize,
    /// Fraction along the segment, in `[0, 1]`.
    pub t: f64,
    /// The point of the spine closest to the ray (m, world frame).
    pub point: DVec3,
    /// Distance along the ray from its origin to its closest approach (m).
    pub distance: f64,
    /// Distance between the ray and `point` (m).
    pub offset: f64,
    /// Radius of the segment's volume at `point` (m).
    pub radius: f64,
}

/// Closest points of the ray `origin + s u` (`s ≥ 0`, `u` unit) and the
/// segment `a b`: the fraction `t ∈ [0, 1]` along the segment and `s`.
/// The segment's parameter is solved first and clamped, then the ray's; if
/// the ray's is clamped to its origin the segment's is solved again (the
/// clamping order of Ericson's segment–segment routine).
fn ray_segment_closest(origin: DVec3, u: DVec3, a: DVec3, b: DVec3) -> (f64, f64) {
    let v = b - a;
    let w = a - origin;
    let vv = v.length_squared();
    let uv = u.dot(v);
    let uw = u.dot(w);
    let vw = v.dot(w);
    let denom = vv - uv * uv;
    let t = if vv <= f64::MIN_POSITIVE {
        0.0
    } else if denom > 1e-12 * vv {
        // Lines' closest points, solved for the segment's parameter.
        ((uv * uw - vw) / denom).clamp(0.0, 1.0)
    } else {
        // Parallel: any point does; take the segment's start.
        0.0
    };
    let s = uw + uv * t;
    if s >= 0.0 {
        return (t, s);
    }
    let t = if vv <= f64::MIN_POSITIVE {
        0.0
    } else {
        (-vw / vv).clamp(0.0, 1.0)
    };
    (t, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_segment_closest_points_match_a_dense_search() {
        let cases = [
            (
                DVec3::new(0.0, 0.0, 2.0),
                DVec3::new(0.1, 0.2, -1.0),
                DVec3::new(-1.0, 0.0, 0.0),
                DVec3::new(1.0, 0.5, 0.2),
            ),
            (
                DVec3::new(3.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::ZERO,
                DVec3::new(0.0, 1.0, 0.0),
            ),
            (
                DVec3::new(0.0, 1.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
            ),
            (
                DVec3::new(0.5, 0.5, 0.5),
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::ZERO,
                DVec3::ZERO,
            ),
        ];
        for (o, d, a, b) in cases {
            let u = d.normalize();
            let (t, s) = ray_segment_closest(o, u, a, b);
            let got = (o + u * s - (a + (b - a) * t)).length();
            let mut best = f64::INFINITY;
            for i in 0..=400 {
                let tt = f64::from(i) / 400.0;
                let p = a + (b - a) * tt;
                let ss = (p - o).dot(u).max(0.0);
                best = best.min((o + u * ss - p).length());
            }
            assert!((0.0..=1.0).contains(&t) && s >= 0.0);
            assert!(got <= best + 1e-12, "{got} > {best}");
        }
    }
}
