//! Skeleton volumes fitted to a robot's own geometry (paper §II: the
//! volumes "have to approach the real volume" of each part; segments cover
//! the spine of every mechanical part, counterbalances and motors included).
//!
//! Input: a robot spec, a configuration `q`, and [`Body`]s: triangle meshes
//! in the world frame at `q`, each rigidly attached to the frame of one DH
//! row (a URDF link moved by joint `k` is attached to row `k`).
//!
//! [`fit_volumes`] sets, per skeleton segment, the tapered radii `[r0, r1]`
//! (and, where a part reaches behind the start of the row's `a` spine, an
//! `extension`) so that every vertex of every body lies inside the skeleton
//! volumes that move rigidly with that body, as tight as the model allows:
//! 1. The segments rigid with frame `k` are found numerically: both end
//!    points keep their coordinates in frame `k` when `q` changes (for a
//!    revolute row `k` this is its own `a` spine and the next row's `d`
//!    spine, which lie on joint axes).
//! 2. Each vertex goes to the rigid segment whose spine is nearest; with
//!    `t` its fraction along the spine and `δ` its distance from it, the
//!    volume contains it when `(1 − t) r0 + t r1 ≥ δ` (the ball at the
//!    nearest spine point; the round cone holds that ball).
//! 3. Per segment, `(r0, r1)` minimises the volume of its round cone
//!    (frustum plus end balls, a convex function) over those half-planes:
//!    for each `r0` the least feasible `r1` is explicit, and the convex
//!    one-dimensional remainder is minimised by golden-section search, up
//!    to the `r0` whose end ball alone outweighs the widest distance taken
//!    as both radii (the best `r0` may exceed every vertex's distance when
//!    it lets `r1` shrink: a part wide near its start, narrow at its end). A
//!    row with one segment gets `radius: [r0, r1]`, a row with more the
//!    per-segment form `{ d, a, extension }` (a segment no vertex goes to
//!    keeps its radius).
//! 4. Extensions: per row, a few lengths up to the farthest vertex behind
//!    the `a` spine's start are tried; the one with the least total volume
//!    is kept (zero when none helps).
//!
//! The model's limits, stated: one radius pair per segment (a part whose
//! width changes more than linearly along its spine, wide at both ends and
//! narrow between, keeps the wider ends' cone), volumes are round cones
//! around the DH spine, and a part that is not around its spine (a flange
//! off to one side) makes its cone wide. Rows whose frame carries no body keep
//! their radii. Fitting is done at `q`; for a prismatic row the rigid sets
//! exclude its changing `d` spine.
//!
//! [`bodies_onto`] carries a URDF's bodies onto another description of the
//! same arm (a preset's DH table), checked by its tips.
//!
//! [`coverage`] measures any spec against the bodies (see [`Coverage`]):
//! the share of vertices inside (must be 100 % after fitting), the share of
//! the surface inside within a tolerance, and the excess (volume of the
//! volumes over the meshes' volume).

mod align;
mod coverage;
mod robot_meshes;

pub use align::{SAME_ARM_TOLERANCE, bodies_onto, rigid_fit};
pub use coverage::{BodyCoverage, Coverage, CoverageOptions, coverage};
pub use robot_meshes::{UrdfFit, fit_urdf, urdf_bodies};

use glam::DVec3;

use crate::error::FieldError;
use crate::kinematics::{
    DEFAULT_RADIUS, LinkRadii, RadiusSpec, Robot, RobotSpec, SegmentRadius, SegmentRadiusSpec,
};
use crate::mesh::TriMesh;
use crate::skeleton::{Skeleton, SpinePart, part_radius};

/// A mesh rigidly attached to the frame of one DH row.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Display name (the URDF link's).
    pub name: String,
    /// 1-based index of the row whose frame carries it (0: the base, which
    /// no skeleton segment is fitted to).
    pub link: usize,
    /// The mesh in the world frame at the configuration given with it (m).
    pub mesh: TriMesh,
}

/// Smallest radius a fitted row gets (m): volumes must be solid.
pub const MIN_RADIUS: f64 = 1e-3;

/// The segments rigid with each frame: `rigid[k]` lists the indices of the
/// skeleton segments whose end points keep their coordinates in frame `k`
/// when the configuration changes (`k = 0..=n`).
///
/// # Errors
/// A [`FieldError`] when `q` does not fit the robot.
pub fn rigid_segments(robot: &Robot, q: &[f64]) -> Result<Vec<Vec<usize>>, FieldError> {
    let n = robot.dof();
    let frames = robot.forward(q)?;
    let skeleton = Skeleton::build(robot, &frames);
    let mut moved = Vec::new();
    for s in [0.37, -0.61] {
        let q2: Vec<f64> = q
            .iter()
            .enumerate()
            .map(|(i, v)| v + s * (1.0 + 0.29 * i as f64))
            .collect();
        let f2 = robot.forward(&q2)?;
        moved.push((Skeleton::build(robot, &f2), f2));
    }
    let local =
        |sk: &Skeleton, t: &glam::DAffine3, p: usize| t.inverse().transform_point3(sk.nodes[p]);
    let mut rigid = vec![Vec::new(); n + 1];
    for (k, list) in rigid.iter_mut().enumerate() {
        for (i, seg) in skeleton.segments.iter().enumerate() {
            let same = moved.iter().all(|(sk, f)| {
                [seg.from, seg.to].iter().all(|&p| {
                    let a = local(&skeleton, &frames.transforms[k], p);
                    let b = local(sk, &f.transforms[k], p);
                    (a - b).length() <= 1e-9 * (1.0 + a.length())
                })
            });
            if same {
                list.push(i);
            }
        }
    }
    Ok(rigid)
}

/// Fraction along `a → b` of the point nearest `p`, and the distance to it.
pub(crate) fn spine(p: DVec3, a: DVec3, b: DVec3) -> (f64, f64) {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (t, (p - (a + ab * t)).length())
}

/// Unique vertices of a mesh (exact duplicates dropped: STL repeats each
/// vertex once per triangle).
fn unique_vertices(m: &TriMesh) -> Vec<DVec3> {
    let mut v: Vec<[u64; 3]> = m
        .vertices
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect();
    v.sort_unstable();
    v.dedup();
    v.into_iter()
        .map(|b| DVec3::from_array(b.map(f64::from_bits)))
        .collect()
}

/// Per segment: constraints `(t, δ)` and its length.
struct RowProblem {
    constraints: Vec<(f64, f64)>,
    lengths: Vec<f64>,
}

/// Volume of a row's round cones, up to the overlap of the end balls: the
/// frustums plus one ball of each end radius, halved (shared with the
/// neighbours).
fn row_volume(lengths: &[f64], r0: f64, r1: f64) -> f64 {
    use std::f64::consts::PI;
    let frustum: f64 = lengths.iter().sum::<f64>() * PI / 3.0 * (r0 * r0 + r0 * r1 + r1 * r1);
    frustum + 2.0 * PI / 3.0 * (r0.powi(3) + r1.powi(3))
}

impl RowProblem {
    /// The least `r1` with `(r0, r1)` feasible.
    fn r1_for(&self, r0: f64) -> f64 {
        self.constraints
            .iter()
            .filter(|(t, _)| *t > 1e-12)
            .map(|&(t, d)| (d - (1.0 - t) * r0) / t)
            .fold(MIN_RADIUS, f64::max)
    }

    /// The optimal `(r0, r1)` and its volume, `None` without constraints.
    fn solve(&self) -> Option<([f64; 2], f64)> {
        if self.constraints.is_empty() {
            return None;
        }
        let lo = self
            .constraints
            .iter()
            .filter(|(t, _)| *t <= 1e-12)
            .map(|c| c.1)
            .fold(MIN_RADIUS, f64::max);
        // The widest distance, as both radii, is feasible; no optimum has an
        // `r0` whose end ball alone holds more volume than that pair's (the
        // optimal `r0` may exceed the widest distance when it lets `r1`
        // shrink, so the widest distance is no bound on its own).
        let widest = self.constraints.iter().map(|c| c.1).fold(lo, f64::max);
        let bound = row_volume(&self.lengths, widest, widest);
        let hi = (1.5 * bound / std::f64::consts::PI).cbrt().max(widest);
        let f = |r0: f64| row_volume(&self.lengths, r0, self.r1_for(r0));
        let (mut a, mut b) = (lo, hi);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let (x1, x2) = (b - g * (b - a), a + g * (b - a));
            if f(x1) <= f(x2) {
                b = x2;
            } else {
                a = x1;
            }
        }
        // Round the radii up by a hair so that every constraint holds after
        // rounding.
        let r0 = 0.5 * (a + b);
        let r1 = self.r1_for(r0);
        let pad = 1e-9;
        Some(([r0 + pad, r1 + pad], f(r0)))
    }
}

/// The radii (and their total volume) fitted to `bodies` for the spec's
/// current extensions; rows without vertices keep their radius.
fn fit_once(
    spec: &RobotSpec,
    q: &[f64],
    bodies: &[(usize, Vec<DVec3>)],
) -> Result<(RobotSpec, f64), FieldError> {
    let robot = Robot::from_spec(spec)?;
    let frames = robot.forward(q)?;
    let skeleton = Skeleton::build(&robot, &frames);
    let rigid = rigid_segments(&robot, q)?;
    // One problem per segment: each gets its own pair.
    let mut problems: Vec<RowProblem> = skeleton
        .segments
        .iter()
        .map(|s| {
            let (a, b) = skeleton.endpoints(s);
            RowProblem {
                constraints: Vec::new(),
                lengths: vec![(b - a).length()],
            }
        })
        .collect();
    for (link, points) in bodies {
        let candidates = rigid.get(*link).map_or(&[][..], Vec::as_slice);
        for p in points {
            let best = candidates
                .iter()
                .map(|&i| {
                    let (a, b) = skeleton.endpoints(&skeleton.segments[i]);
                    let (t, d) = spine(*p, a, b);
                    (i, t, d)
                })
                .min_by(|x, y| x.2.total_cmp(&y.2));
            if let Some((i, t, d)) = best {
                problems[i].constraints.push((t, d));
            }
        }
    }
    let mut out = spec.clone();
    let mut total = 0.0;
    for (row, joint) in robot.joints.iter().enumerate().take(spec.joints.len()) {
        let mut fitted = LinkRadii::same([DEFAULT_RADIUS; 2]);
        let mut parts = Vec::new();
        let mut any = false;
        for (i, s) in skeleton.segments.iter().enumerate() {
            if s.link != row + 1 {
                continue;
            }
            let pair = match problems[i].solve() {
                Some((r, v)) => {
                    total += v;
                    any = true;
                    r
                }
                None => part_radius(&joint.radius, s.part),
            };
            set_part(&mut fitted, s.part, pair);
            parts.push(s.part);
        }
        if any {
            out.joints[row].radius = Some(radius_spec(&fitted, &parts));
        }
    }
    Ok((out, total))
}

/// Sets the pair of `part` in `radii`.
fn set_part(radii: &mut LinkRadii, part: SpinePart, pair: [f64; 2]) {
    match part {
        SpinePart::D => radii.d = pair,
        SpinePart::A => radii.a = pair,
        SpinePart::Extension => radii.extension = pair,
    }
}

/// The spec form of a row's fitted radii: `[r0, r1]` when the row has one
/// segment, one pair per segment (`parts`) otherwise.
fn radius_spec(radii: &LinkRadii, parts: &[SpinePart]) -> RadiusSpec {
    if let [part] = parts {
        return RadiusSpec::Tapered(part_radius(radii, *part));
    }
    let pick = |p: SpinePart| {
        parts
            .contains(&p)
            .then(|| SegmentRadius::Tapered(part_radius(radii, p)))
    };
    RadiusSpec::PerSegment(SegmentRadiusSpec {
        d: pick(SpinePart::D),
        a: pick(SpinePart::A),
        extension: pick(SpinePart::Extension),
    })
}

/// Radii (and extensions) fitted so that every vertex of `bodies` lies
/// inside the volumes rigid with its frame; see the [module docs](self).
///
/// `q` is the configuration the bodies are given in (world frame). Only the
/// main chain's rows are fitted (branches keep their radii).
///
/// # Errors
/// A [`FieldError`] for an invalid spec or `q`, or `bodies[i].link: …` for
/// a body on a row that does not exist.
///
/// # Example
/// ```
/// use skeleton_avoidance::fitting::{Body, fit_volumes};
/// use skeleton_avoidance::kinematics::presets::preset;
/// use skeleton_avoidance::mesh::TriMesh;
/// use glam::DVec3;
/// let spec = preset("planar3")?;
/// // A point 0.1 m off the middle of link 1 (which lies along x at q = 0).
/// let mesh = TriMesh { vertices: vec![DVec3::new(0.2, 0.1, 0.0)], triangles: vec![] };
/// let fitted = fit_volumes(&spec, &[0.0; 3], &[Body { name: "l1".into(), link: 1, mesh }])?;
/// # Ok::<(), skeleton_avoidance::FieldError>(())
/// ```
pub fn fit_volumes(spec: &RobotSpec, q: &[f64], bodies: &[Body]) -> Result<RobotSpec, FieldError> {
    let n = spec.joints.len();
    let mut points = Vec::new();
    for (i, b) in bodies.iter().enumerate() {
        if b.link > n {
            return Err(FieldError::new(
                format!("bodies[{i}].link"),
                format!("{} is past the {n} rows of the main chain", b.link),
            ));
        }
        points.push((b.link, unique_vertices(&b.mesh)));
    }
    let mut spec = spec.clone();
    let (mut best, mut best_volume) = fit_once(&spec, q, &points)?;
    for row in 0..n {
        let reach = behind_reach(&spec, q, row, &points)?;
        if reach < 0.01 {
            continue;
        }
        for f in [0.25, 0.5, 0.75, 1.0] {
            let mut trial = best.clone();
            trial.joints[row].extension = Some(f * reach);
            let (fitted, volume) = fit_once(&trial, q, &points)?;
            if volume < 0.98 * best_volume {
                (best, best_volume) = (fitted, volume);
            }
        }
        spec = best.clone();
    }
    Ok(best)
}

/// How far the bodies of row `row`'s frame reach behind the start of its
/// `a` spine, along the direction an extension would take (m, ≤ 0 when
/// nothing does).
fn behind_reach(
    spec: &RobotSpec,
    q: &[f64],
    row: usize,
    points: &[(usize, Vec<DVec3>)],
) -> Result<f64, FieldError> {
    let mut probe = spec.clone();
    probe.joints[row].extension = Some(1.0);
    let robot = Robot::from_spec(&probe)?;
    let skeleton = Skeleton::build(&robot, &robot.forward(q)?);
    let Some(s) = skeleton
        .segments
        .iter()
        .find(|s| s.link == row + 1 && s.part == crate::skeleton::SpinePart::Extension)
    else {
        return Ok(0.0);
    };
    let (a, b) = skeleton.endpoints(s);
    let u = b - a;
    Ok(points
        .iter()
        .filter(|(link, _)| *link == row + 1)
        .flat_map(|(_, p)| p.iter().map(|p| (*p - a).dot(u)))
        .fold(0.0, f64::max))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part wide near its start and narrow at its end: the least volume
    /// takes `r0` past the widest distance so that `r1` can shrink (a
    /// search bounded by the widest distance stopped at `r0 = r1 = 0.15`).
    #[test]
    fn the_least_volume_pair_may_start_wider_than_any_vertex() -> Result<(), String> {
        let p = RowProblem {
            constraints: vec![(0.0, 0.15), (0.2, 0.15), (1.0, 0.05)],
            lengths: vec![0.4],
        };
        let ([r0, r1], v) = p.solve().ok_or("no pair")?;
        for &(t, d) in &p.constraints {
            assert!((1.0 - t) * r0 + t * r1 >= d, "({t}, {d}) outside {r0} {r1}");
        }
        assert!(r0 > 0.15 && r1 < 0.15, "{r0} {r1}");
        let scanned = (0..=20_000)
            .map(|i| 0.15 + 0.1 * f64::from(i) / 20_000.0)
            .map(|x| row_volume(&p.lengths, x, p.r1_for(x)))
            .fold(f64::INFINITY, f64::min);
        assert!(v <= scanned + 1e-12, "{v} > {scanned}");
        assert!(v < row_volume(&p.lengths, 0.15, 0.15));
        Ok(())
    }
}
