//! A robot's link meshes in the drawing: each mesh kept in the frame of the
//! DH row that carries it, placed by that frame every frame, and drawn as
//! flat, lit, opaque triangles under the translucent volumes.
//!
//! A link mesh of more than [`LINK_TRIANGLES`] triangles is drawn
//! simplified to that budget.
//!
//! A mesh whose surface is closed (every edge shared by exactly two
//! triangles, walking it in opposite directions, once coincident vertices
//! are merged) is turned to face outwards and drawn one-sided: only its
//! triangles facing the camera reach the rasteriser, about half of them.
//! Any other mesh is drawn two-sided, as it is.

use std::collections::HashMap;

use glam::{DAffine3, DVec3};

use super::scene::{Scene, Triangle};
use crate::fitting::Body;

/// Largest number of mesh triangles drawn (all links together): past it the
/// rest are not drawn, so a heavy mesh cannot stall the page.
pub const MAX_DRAWN_TRIANGLES: usize = 200_000;

/// Triangles a link's mesh is drawn with at most: a heavier one is
/// simplified for drawing ([`crate::mesh::simplify`], quadric error edge
/// collapse; the fitting reads the full mesh). The iiwa 14's collision
/// meshes (46 070 triangles) are drawn with 16 000, within about a
/// millimetre of their surface; the Panda's and the UR5's are drawn whole.
pub const LINK_TRIANGLES: usize = 2_000;

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
                vertices,
                triangles,
                closed,
            })
        })
        .collect()
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

/// Adds the meshes, placed by `frames` (the row frames at the drawn
/// configuration), to `scene` (closed ones to [`Scene::closed`]), up to
/// [`MAX_DRAWN_TRIANGLES`].
pub fn draw_meshes(scene: &mut Scene, meshes: &[LinkMesh], frames: &[DAffine3]) {
    let mut budget = MAX_DRAWN_TRIANGLES;
    let mut placed: Vec<[f32; 3]> = Vec::new();
    for m in meshes {
        let Some(f) = frames.get(m.link) else {
            continue;
        };
        placed.clear();
        placed.extend(
            m.vertices
                .iter()
                .map(|v| f.transform_point3(*v).as_vec3().to_array()),
        );
        let out = if m.closed {
            &mut scene.closed
        } else {
            &mut scene.triangles
        };
        for t in m.triangles.iter().take(budget) {
            let p = t.map(|k| placed.get(k as usize).copied().unwrap_or([0.0; 3]));
            out.push(Triangle {
                p,
                color: MESH_COLOR,
            });
        }
        budget = budget.saturating_sub(m.triangles.len());
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
        let mut scene = Scene::new();
        draw_meshes(&mut scene, &meshes, &moved);
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
            let mut scene = Scene::new();
            draw_meshes(&mut scene, &meshes, &[DAffine3::IDENTITY]);
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
            let mut scene = Scene::new();
            draw_meshes(&mut scene, &meshes, &[DAffine3::IDENTITY]);
            assert!(scene.closed.is_empty());
            assert!(!scene.triangles.is_empty());
        }
    }
}
