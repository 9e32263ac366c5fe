//! A robot's link meshes in the drawing: each mesh kept in the frame of the
//! DH row that carries it, placed by that frame every frame, and drawn as
//! flat, lit, opaque triangles under the translucent volumes.
//!
//! A link mesh of more than [`LINK_TRIANGLES`] triangles is drawn
//! simplified to that budget.
//!
//! Levels of detail: each link mesh also keeps coarser versions of itself,
//! each with half the triangles of the one before (down to
//! [`MIN_LEVEL_TRIANGLES`]), with how far each strays from the full mesh
//! (measured at load: the larger of the two one-sided distances between
//! the vertices of one and the surface of the other). A link is drawn with
//! the coarsest version whose error spans no more than the tolerance on
//! screen ([`Detail`]: 1 px on a software rasteriser, 0.5 px on a GPU, as
//! the solids' outlines, `view::tessellation`), seen from the nearest point
//! of its bounding sphere. The iiwa 14 seen whole in a 1280×800 window is
//! drawn with a quarter of its triangles, its outline unchanged (screenshots
//! compared: a few thousand pixels of its shading differ, most by a few
//! levels).
//!
//! A mesh whose surface is closed (every edge shared by exactly two
//! triangles, walking it in opposite directions, once coincident vertices
//! are merged) is turned to face outwards and drawn one-sided: only its
//! triangles facing the camera reach the rasteriser, about half of them.
//! Any other mesh is drawn two-sided, as it is.

use std::collections::HashMap;

use glam::{DAffine3, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::TriMesh as ParryMesh;

use super::camera::Camera;
use super::drawing::{Drawing, Triangle};
use crate::fitting::Body;

/// Largest number of mesh triangles drawn (all links together): past it the
/// rest are not drawn, so a heavy mesh cannot stall the page.
pub const MAX_DRAWN_TRIANGLES: usize = 200_000;

/// Triangles a link's mesh is drawn with at most: a heavier one is
/// simplified for drawing ([`crate::mesh::simplify`], quadric error edge
/// collapse; the fitting reads the full mesh). The iiwa 14's collision
/// meshes (46 070 triangles) are drawn with 16 000 at most, within about a
/// millimetre of their surface (and seen whole in a 1280×800 playground,
/// with about 1 900: the levels of detail); the Panda's and the UR5's keep
/// all their triangles at their finest level.
///
/// Building the levels at load (simplifying and measuring each) takes
/// about 80 ms natively for the iiwa 14, about 0.35 s more in the browser
/// here; the fitting reads the full meshes.
pub const LINK_TRIANGLES: usize = 2_000;

/// The coarsest level of detail keeps at least this many triangles.
pub const MIN_LEVEL_TRIANGLES: usize = 64;

/// sRGB colour of the link meshes.
pub const MESH_COLOR: [f32; 4] = [0.80, 0.81, 0.84, 1.0];

/// Vertices closer than this (m) are one point of the drawn surface.
const WELD: f64 = 1e-6;

/// One link's mesh in the frame of its row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkMesh {
    /// The row whose frame carries it (0: the base).
    pub link: usize,
    /// Vertices in that frame (m).
    pub vertices: Vec<DVec3>,
    /// Triangles (indices into `vertices`).
    pub triangles: Vec<[u32; 3]>,
    /// Whether the surface is closed, its triangles counter-clockwise seen
    /// from outside (then only those facing the camera are drawn).
    pub closed: bool,
    /// Coarser versions, each with half the triangles of the one before.
    pub coarser: Vec<MeshLevel>,
    /// A sphere holding the mesh, in the row's frame: centre and radius (m).
    pub bound: (DVec3, f64),
}

/// A coarser version of a link mesh, drawn when the link is small on screen.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshLevel {
    /// Vertices in the row's frame (m).
    pub vertices: Vec<DVec3>,
    /// Triangles (indices into `vertices`).
    pub triangles: Vec<[u32; 3]>,
    /// Whether it is still a closed surface facing outwards.
    pub closed: bool,
    /// How far it strays from the full mesh (m): the largest distance of a
    /// vertex of either from the surface of the other.
    pub error: f64,
}

/// How finely link meshes are drawn: as seen by `camera` on a view
/// `height` pixels high, each with the coarsest level whose error spans at
/// most `tolerance` pixels.
#[derive(Clone, Copy, Debug)]
pub struct Detail<'a> {
    /// The camera the meshes are seen by.
    pub camera: &'a Camera,
    /// The drawing buffer's height (pixels).
    pub height: f32,
    /// How far (pixels) a drawn level may stray from the full mesh.
    pub tolerance: f32,
}

/// The bodies (world frame at the configuration of `frames`) in the frames
/// of their rows, coincident vertices merged and closed surfaces turned to
/// face outwards; bodies on a row `frames` does not have are dropped.
#[must_use]
pub fn link_meshes(bodies: &[Body], frames: &[DAffine3]) -> Vec<LinkMesh> {
    bodies
        .iter()
        .filter_map(|b| {
            let to_local = frames.get(b.link)?.inverse();
            let local: Vec<DVec3> = b
                .mesh
                .vertices
                .iter()
                .map(|v| to_local.transform_point3(*v))
                .collect();
            let (vertices, triangles) = weld(&local, &b.mesh.triangles);
            let (vertices, mut triangles) =
                crate::mesh::simplify(&vertices, &triangles, LINK_TRIANGLES);
            let closed = match orientation(&vertices, &triangles) {
                Some(outwards) => {
                    if !outwards {
                        for t in &mut triangles {
                            t.swap(1, 2);
                        }
                    }
                    true
                }
                None => false,
            };
            Some(LinkMesh {
                link: b.link,
                coarser: coarser_levels(&vertices, &triangles),
                bound: bounding_sphere(&vertices),
                vertices,
                triangles,
                closed,
            })
        })
        .collect()
}

/// The coarser levels of a mesh: each simplified to half the triangles of
/// the one before, while that keeps at least [`MIN_LEVEL_TRIANGLES`] and
/// the simplification makes progress, with its error measured against the
/// mesh.
fn coarser_levels(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Vec<MeshLevel> {
    let Ok(full) = ParryMesh::new(vertices.to_vec(), triangles.to_vec()) else {
        return Vec::new();
    };
    let mut levels: Vec<MeshLevel> = Vec::new();
    let mut from = (vertices.to_vec(), triangles.to_vec());
    while from.1.len() / 2 >= MIN_LEVEL_TRIANGLES {
        let (v, t) = crate::mesh::simplify(&from.0, &from.1, from.1.len() / 2);
        if t.is_empty() || t.len() >= from.1.len() {
            break;
        }
        let error = deviation((&full, vertices), (&v, &t));
        levels.push(MeshLevel {
            closed: orientation(&v, &t) == Some(true),
            vertices: v.clone(),
            triangles: t.clone(),
            error,
        });
        from = (v, t);
    }
    levels
}

/// The largest distance of a vertex of either mesh from the other's
/// surface; infinite when the second is no surface parry accepts.
fn deviation(
    (full, full_vertices): (&ParryMesh, &[DVec3]),
    (vertices, triangles): (&[DVec3], &[[u32; 3]]),
) -> f64 {
    let Ok(level) = ParryMesh::new(vertices.to_vec(), triangles.to_vec()) else {
        return f64::INFINITY;
    };
    let far = |mesh: &ParryMesh, points: &[DVec3]| {
        points
            .iter()
            .map(|&p| mesh.distance_to_point(&Pose::IDENTITY, p, false))
            .fold(0.0, f64::max)
    };
    far(&level, full_vertices).max(far(full, vertices))
}

/// A sphere holding the points: their box's centre and the farthest point
/// from it.
fn bounding_sphere(vertices: &[DVec3]) -> (DVec3, f64) {
    let lo = vertices.iter().copied().fold(DVec3::INFINITY, DVec3::min);
    let hi = vertices
        .iter()
        .copied()
        .fold(DVec3::NEG_INFINITY, DVec3::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return (DVec3::ZERO, 0.0);
    }
    let centre = 0.5 * (lo + hi);
    let radius = vertices
        .iter()
        .map(|v| v.distance(centre))
        .fold(0.0, f64::max);
    (centre, radius)
}

/// The mesh with vertices closer than [`WELD`] merged, triangles that lost
/// a corner to the merge (or name a missing vertex) dropped.
fn weld(vertices: &[DVec3], triangles: &[[u32; 3]]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut index: HashMap<[i64; 3], u32> = HashMap::new();
    let mut merged: Vec<DVec3> = Vec::new();
    let remap: Vec<u32> = vertices
        .iter()
        .map(|v| {
            let key = (*v / WELD).round().as_i64vec3().to_array();
            *index.entry(key).or_insert_with(|| {
                merged.push(*v);
                merged.len() as u32 - 1
            })
        })
        .collect();
    let kept = triangles
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|k| remap.get(k as usize).copied());
            let (a, b, c) = (a?, b?, c?);
            (a != b && b != c && c != a).then_some([a, b, c])
        })
        .collect();
    (merged, kept)
}

/// For a closed surface (each directed edge once, its reverse once):
/// whether its triangles face outwards (positive enclosed volume); `None`
/// for any other surface.
fn orientation(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Option<bool> {
    if triangles.is_empty() {
        return None;
    }
    let mut edges: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * triangles.len());
    for &[a, b, c] in triangles {
        for edge in [(a, b), (b, c), (c, a)] {
            *edges.entry(edge).or_insert(0) += 1;
        }
    }
    let closed = edges
        .iter()
        .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1));
    if !closed {
        return None;
    }
    let volume: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| vertices[k as usize]);
            a.dot(b.cross(c))
        })
        .sum();
    Some(volume > 0.0)
}

impl LinkMesh {
    /// The vertices, triangles and closedness to draw the mesh with, placed
    /// by `frame`: the full mesh, or the coarsest level `detail` allows.
    fn level(&self, frame: &DAffine3, detail: Option<Detail<'_>>) -> (&[DVec3], &[[u32; 3]], bool) {
        let full = (&self.vertices[..], &self.triangles[..], self.closed);
        let Some(d) = detail else {
            return full;
        };
        let (centre, radius) = self.bound;
        let eye = d.camera.eye().as_dvec3();
        let distance = (frame.transform_point3(centre).distance(eye) - radius) as f32;
        let pixels = d.camera.pixels_per_metre(d.height, distance);
        self.coarser
            .iter()
            .rev()
            .find(|l| l.error as f32 * pixels <= d.tolerance)
            .map_or(full, |l| (&l.vertices[..], &l.triangles[..], l.closed))
    }
}

/// Adds the meshes, placed by `frames` (the row frames at the drawn
/// configuration), to `scene` (closed ones to [`Drawing::closed`]), up to
/// [`MAX_DRAWN_TRIANGLES`]; each at the level of detail `detail` asks for
/// (`None`: the full meshes).
pub fn draw_meshes(
    scene: &mut Drawing,
    meshes: &[LinkMesh],
    frames: &[DAffine3],
    detail: Option<Detail<'_>>,
) {
    let mut budget = MAX_DRAWN_TRIANGLES;
    let mut placed: Vec<[f32; 3]> = Vec::new();
    for m in meshes {
        let Some(f) = frames.get(m.link) else {
            continue;
        };
        let (vertices, triangles, closed) = m.level(f, detail);
        placed.clear();
        placed.extend(
            vertices
                .iter()
                .map(|v| f.transform_point3(*v).as_vec3().to_array()),
        );
        let out = if closed {
            &mut scene.closed
        } else {
            &mut scene.triangles
        };
        for t in triangles.iter().take(budget) {
            let p = t.map(|k| placed.get(k as usize).copied().unwrap_or([0.0; 3]));
            out.push(Triangle {
                p,
                color: MESH_COLOR,
            });
        }
        budget = budget.saturating_sub(triangles.len());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TriMesh;

    #[test]
    fn a_mesh_follows_its_frame() {
        let body = Body {
            name: "l1".into(),
            link: 1,
            mesh: TriMesh {
                vertices: vec![
                    DVec3::new(1.0, 0.0, 0.0),
                    DVec3::new(1.0, 1.0, 0.0),
                    DVec3::new(1.0, 0.0, 1.0),
                ],
                triangles: vec![[0, 1, 2]],
            },
        };
        let at_zero = [DAffine3::IDENTITY, DAffine3::from_translation(DVec3::X)];
        let meshes = link_meshes(&[body], &at_zero);
        assert_eq!(meshes[0].vertices[0], DVec3::ZERO);
        let moved = [
            DAffine3::IDENTITY,
            DAffine3::from_rotation_translation(
                glam::DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
                DVec3::new(0.0, 2.0, 0.0),
            ),
        ];
        assert!(!meshes[0].closed);
        let mut scene = Drawing::new();
        draw_meshes(&mut scene, &meshes, &moved, None);
        assert_eq!(scene.triangles.len(), 1);
        let p = scene.triangles[0].p;
        assert!((glam::Vec3::from_array(p[0]) - glam::Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6);
        assert!((glam::Vec3::from_array(p[1]) - glam::Vec3::new(-1.0, 2.0, 0.0)).length() < 1e-6);
    }

    /// A tetrahedron as an STL gives it: every triangle with its own
    /// corners, and here wound inwards.
    fn tetrahedron(inwards: bool) -> TriMesh {
        let corners = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let mut faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        if inwards {
            for f in &mut faces {
                f.swap(1, 2);
            }
        }
        let vertices = faces.iter().flatten().map(|&k| corners[k]).collect();
        let triangles = (0..4u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        TriMesh {
            vertices,
            triangles,
        }
    }

    #[test]
    fn a_closed_mesh_is_welded_turned_outwards_and_drawn_one_sided() {
        for inwards in [false, true] {
            let body = Body {
                name: "l1".into(),
                link: 0,
                mesh: tetrahedron(inwards),
            };
            let meshes = link_meshes(&[body], &[DAffine3::IDENTITY]);
            let m = &meshes[0];
            assert!(m.closed, "inwards {inwards}");
            assert_eq!((m.vertices.len(), m.triangles.len()), (4, 4));
            assert_eq!(orientation(&m.vertices, &m.triangles), Some(true));
            let mut scene = Drawing::new();
            draw_meshes(&mut scene, &meshes, &[DAffine3::IDENTITY], None);
            assert_eq!((scene.closed.len(), scene.triangles.len()), (4, 0));
        }
    }

    #[test]
    fn an_open_or_inconsistent_mesh_is_drawn_two_sided() {
        let mut open = tetrahedron(false);
        open.triangles.pop();
        let mut mixed = tetrahedron(false);
        mixed.triangles[0].swap(1, 2);
        for mesh in [open, mixed] {
            let body = Body {
                name: "l1".into(),
                link: 0,
                mesh,
            };
            let meshes = link_meshes(&[body], &[DAffine3::IDENTITY]);
            assert!(!meshes[0].closed);
            let mut scene = Drawing::new();
            draw_meshes(&mut scene, &meshes, &[DAffine3::IDENTITY], None);
            assert!(scene.closed.is_empty());
            assert!(!scene.triangles.is_empty());
        }
    }

    /// A UV sphere of radius `r`: `rings` bands of `sectors` quads, each
    /// corner its own vertex (welded at load), wound outwards.
    fn sphere(r: f64, sectors: u32, rings: u32) -> TriMesh {
        use std::f64::consts::{PI, TAU};
        let at = |i: u32, j: u32| {
            let (polar, azimuth) = (
                PI * f64::from(i) / f64::from(rings),
                TAU * f64::from(j) / f64::from(sectors),
            );
            r * DVec3::new(
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            )
        };
        let mut vertices = Vec::new();
        for i in 0..rings {
            for j in 0..sectors {
                let quad = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                for tri in [[0, 1, 2], [0, 2, 3]] {
                    let [a, b, c] = tri.map(|k| quad[k]);
                    if (b - a).cross(c - a).length() > 1e-12 {
                        vertices.extend([a, b, c]);
                    }
                }
            }
        }
        let triangles = (0..vertices.len() as u32 / 3)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        TriMesh {
            vertices,
            triangles,
        }
    }

    /// Each coarser level has at most half the triangles of the one before
    /// and at least the floor; its recorded error bounds how far points
    /// spread over its faces lie from the true sphere, up to the full
    /// mesh's own distance from it (checked without parry: the sphere is
    /// known), and the error grows as the triangles go.
    #[test]
    fn coarser_levels_halve_the_triangles_within_their_recorded_error() {
        let r = 0.1;
        let (sectors, rings) = (48, 24);
        let body = Body {
            name: "ball".into(),
            link: 0,
            mesh: sphere(r, sectors, rings),
        };
        let m = &link_meshes(&[body], &[DAffine3::IDENTITY])[0];
        assert!(m.closed);
        assert!(m.coarser.len() >= 3, "{} levels", m.coarser.len());
        // The full mesh's faces lie within the sagitta of its coarser step.
        let full_gap = r * (1.0 - (std::f64::consts::PI / f64::from(rings)).cos());
        let mut before = m.triangles.len();
        let mut error = 0.0;
        for level in &m.coarser {
            assert!(
                level.triangles.len() <= before / 2 && level.triangles.len() >= MIN_LEVEL_TRIANGLES
            );
            assert!(
                level.closed,
                "{} triangles: not closed",
                level.triangles.len()
            );
            assert!(
                level.error >= error,
                "errors grow: {} after {error}",
                level.error
            );
            let mut worst: f64 = 0.0;
            for t in &level.triangles {
                let [a, b, c] = t.map(|k| level.vertices[k as usize]);
                for (u, v) in [
                    (1.0 / 3.0, 1.0 / 3.0),
                    (0.5, 0.5),
                    (0.5, 0.0),
                    (0.0, 0.5),
                    (0.0, 0.0),
                ] {
                    let p = a + u * (b - a) + v * (c - a);
                    worst = worst.max((p.length() - r).abs());
                }
            }
            assert!(
                worst <= level.error + full_gap + 1e-9,
                "{} triangles: a face strays {worst} m, error {} m",
                level.triangles.len(),
                level.error
            );
            before = level.triangles.len();
            error = level.error;
        }
    }

    /// Near the camera the full mesh is drawn; farther away coarser levels,
    /// each the coarsest whose error spans at most the tolerance.
    #[test]
    fn the_level_drawn_follows_the_size_on_screen() {
        let body = Body {
            name: "ball".into(),
            link: 0,
            mesh: sphere(0.1, 48, 24),
        };
        let meshes = link_meshes(&[body], &[DAffine3::IDENTITY]);
        let m = &meshes[0];
        let mut drawn = Vec::new();
        for distance in [0.3_f32, 1.0, 3.0, 10.0, 100.0] {
            let mut camera =
                Camera::framing(glam::Vec3::ZERO, 0.1, super::super::camera::View::Orbit);
            camera.distance = distance;
            let detail = Detail {
                camera: &camera,
                height: 800.0,
                tolerance: 1.0,
            };
            let mut scene = Drawing::new();
            draw_meshes(&mut scene, &meshes, &[DAffine3::IDENTITY], Some(detail));
            let n = scene.closed.len() + scene.triangles.len();
            let pixels = camera.pixels_per_metre(800.0, distance - 0.1);
            let allowed: Vec<_> = m
                .coarser
                .iter()
                .filter(|l| l.error as f32 * pixels <= 1.0)
                .collect();
            let expected = allowed
                .last()
                .map_or(m.triangles.len(), |l| l.triangles.len());
            assert_eq!(n, expected, "at {distance} m");
            drawn.push(n);
        }
        assert_eq!(drawn[0], m.triangles.len(), "full up close");
        assert!(
            drawn.windows(2).all(|w| w[1] <= w[0]) && drawn[4] < drawn[0] / 4,
            "{drawn:?}"
        );
    }
}
