//! How well a spec's volumes cover the bodies: vertices, surface, excess.

use glam::DVec3;
use serde::Serialize;

use super::{Body, rigid_segments};
use crate::distance::{Primitive, TaperedCapsule, distance};
use crate::error::FieldError;
use crate::kinematics::{Robot, RobotSpec};
use crate::skeleton::Skeleton;

/// Settings of [`coverage`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoverageOptions {
    /// A surface sample counts as covered when it is at most this far
    /// outside the volumes (m); default 0.001.
    pub surface_tolerance: f64,
    /// Spacing of the surface samples on each triangle (m); default 0.005.
    pub surface_spacing: f64,
    /// Spacing of the grid that estimates the volumes' volume (m); default
    /// 0.005 (about 1 % on a 5 cm radius).
    pub grid: f64,
}

impl Default for CoverageOptions {
    fn default() -> Self {
        Self {
            surface_tolerance: 0.001,
            surface_spacing: 0.005,
            grid: 0.005,
        }
    }
}

/// Coverage of one body by the volumes rigid with it.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BodyCoverage {
    /// The body's name.
    pub name: String,
    /// The row whose frame carries it.
    pub link: usize,
    /// Number of (unique) vertices.
    pub vertices: usize,
    /// Share of them inside the volumes (0..1).
    pub vertex_coverage: f64,
    /// Share of the surface (by area) inside within the tolerance (0..1).
    pub surface_coverage: f64,
    /// Largest distance of a vertex outside the volumes (m; ≤ 0 when all
    /// are inside).
    pub worst_outside: f64,
    /// Volume enclosed by the mesh (m³).
    pub mesh_volume: f64,
    /// Volume of the union of the volumes rigid with the body (m³).
    pub volumes_volume: f64,
    /// `volumes_volume / mesh_volume`.
    pub excess: f64,
}

/// [`coverage`]'s report: per body, and for the robot (all vertices, all
/// surfaces, the union of all volumes over the sum of the meshes' volumes).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Coverage {
    /// Per body.
    pub bodies: Vec<BodyCoverage>,
    /// The robot as a whole (name "robot", link 0).
    pub robot: BodyCoverage,
    /// The surface tolerance used (m).
    pub surface_tolerance: f64,
}

struct Volume {
    capsule: TaperedCapsule,
    lo: DVec3,
    hi: DVec3,
}

impl Volume {
    fn signed(&self, p: DVec3) -> f64 {
        distance(
            &Primitive::Point(p),
            &Primitive::TaperedCapsule(self.capsule),
        )
        .map_or(f64::INFINITY, |d| d.distance)
    }
}

fn volumes(skeleton: &Skeleton) -> Result<Vec<Volume>, FieldError> {
    skeleton
        .segments
        .iter()
        .map(|s| {
            let (a, b) = skeleton.endpoints(s);
            let r = s.radius.map(|r| r.max(1e-9));
            let m = r[0].max(r[1]);
            Ok(Volume {
                capsule: TaperedCapsule::new(a, b, r)?,
                lo: a.min(b) - DVec3::splat(m),
                hi: a.max(b) + DVec3::splat(m),
            })
        })
        .collect()
}

fn signed_union(vols: &[&Volume], p: DVec3) -> f64 {
    vols.iter()
        .map(|v| v.signed(p))
        .fold(f64::INFINITY, f64::min)
}

/// Volume of the union of `vols` by counting grid cell centres (m³).
fn union_volume(vols: &[&Volume], h: f64) -> f64 {
    let Some(first) = vols.first() else {
        return 0.0;
    };
    let (lo, hi) = vols
        .iter()
        .fold((first.lo, first.hi), |(l, u), v| (l.min(v.lo), u.max(v.hi)));
    let n = ((hi - lo) / h).ceil();
    let mut inside = 0usize;
    for i in 0..n.x as usize {
        for j in 0..n.y as usize {
            for k in 0..n.z as usize {
                let p = lo + DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * h;
                let hit = vols
                    .iter()
                    .any(|v| p.cmpge(v.lo).all() && p.cmple(v.hi).all() && v.signed(p) <= 0.0);
                inside += usize::from(hit);
            }
        }
    }
    inside as f64 * h * h * h
}

/// `(covered area, area)` of a mesh's surface, sampled on a triangular grid.
fn surface(body: &Body, vols: &[&Volume], o: &CoverageOptions) -> (f64, f64) {
    let (mut covered, mut total) = (0.0, 0.0);
    for k in 0..body.mesh.triangles.len() {
        let [a, b, c] = body.mesh.corners(k);
        let area = 0.5 * (b - a).cross(c - a).length();
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        let m = ((longest / o.surface_spacing).ceil() as usize).clamp(1, 40);
        let mut hits = 0usize;
        let mut count = 0usize;
        for i in 0..=m {
            for j in 0..=(m - i) {
                let (u, v) = (i as f64 / m as f64, j as f64 / m as f64);
                let p = a + (b - a) * u + (c - a) * v;
                count += 1;
                hits += usize::from(signed_union(vols, p) <= o.surface_tolerance);
            }
        }
        covered += area * hits as f64 / count as f64;
        total += area;
    }
    (covered, total)
}

/// Coverage of `bodies` (world frame at `q`) by the volumes of `spec`: per
/// body by the volumes rigid with it (which keep covering it as the robot
/// moves), and for the robot by all volumes.
///
/// # Errors
/// A [`FieldError`] for an invalid spec or `q`.
pub fn coverage(
    spec: &RobotSpec,
    q: &[f64],
    bodies: &[Body],
    o: &CoverageOptions,
) -> Result<Coverage, FieldError> {
    let robot = Robot::from_spec(spec)?;
    let skeleton = Skeleton::build(&robot, &robot.forward(q)?);
    let all = volumes(&skeleton)?;
    let rigid = rigid_segments(&robot, q)?;
    let mut out = Vec::new();
    let (mut vin, mut vn, mut worst, mut scov, mut sarea, mut mvol) =
        (0usize, 0usize, f64::NEG_INFINITY, 0.0, 0.0, 0.0);
    for b in bodies {
        let vols: Vec<&Volume> = rigid
            .get(b.link)
            .map(|l| l.iter().map(|&i| &all[i]).collect())
            .unwrap_or_default();
        let points = super::unique_vertices(&b.mesh);
        let d: Vec<f64> = points.iter().map(|p| signed_union(&vols, *p)).collect();
        let inside = d.iter().filter(|x| **x <= 1e-9).count();
        let w = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (c, a) = surface(b, &vols, o);
        let mv = b.mesh.volume();
        let vv = union_volume(&vols, o.grid);
        out.push(BodyCoverage {
            name: b.name.clone(),
            link: b.link,
            vertices: points.len(),
            vertex_coverage: inside as f64 / points.len().max(1) as f64,
            surface_coverage: if a > 0.0 { c / a } else { 1.0 },
            worst_outside: w,
            mesh_volume: mv,
            volumes_volume: vv,
            excess: vv / mv,
        });
        (vin, vn, worst, scov, sarea, mvol) = (
            vin + inside,
            vn + points.len(),
            worst.max(w),
            scov + c,
            sarea + a,
            mvol + mv,
        );
    }
    let all_refs: Vec<&Volume> = all.iter().collect();
    let vv = union_volume(&all_refs, o.grid);
    let robot = BodyCoverage {
        name: "robot".into(),
        link: 0,
        vertices: vn,
        vertex_coverage: vin as f64 / vn.max(1) as f64,
        surface_coverage: if sarea > 0.0 { scov / sarea } else { 1.0 },
        worst_outside: worst,
        mesh_volume: mvol,
        volumes_volume: vv,
        excess: vv / mvol,
    };
    Ok(Coverage {
        bodies: out,
        robot,
        surface_tolerance: o.surface_tolerance,
    })
}
