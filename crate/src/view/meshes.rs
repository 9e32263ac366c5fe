//! A robot's link meshes in the drawing: each mesh kept in the frame of the
//! DH row that carries it, placed by that frame every frame, and drawn as
//! flat, lit, opaque triangles under the translucent volumes.

use glam::{DAffine3, DVec3};

use super::scene::{Scene, Triangle};
use crate::fitting::Body;

/// Largest number of mesh triangles drawn (all links together): past it the
/// rest are not drawn, so a heavy mesh cannot stall the page.
pub const MAX_DRAWN_TRIANGLES: usize = 200_000;

/// sRGB colour of the link meshes.
pub const MESH_COLOR: [f32; 4] = [0.80, 0.81, 0.84, 1.0];

/// One link's mesh in the frame of its row.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkMesh {
    /// The row whose frame carries it (0: the base).
    pub link: usize,
    /// Vertices in that frame (m).
    pub vertices: Vec<DVec3>,
    /// Triangles (indices into `vertices`).
    pub triangles: Vec<[u32; 3]>,
}

/// The bodies (world frame at the configuration of `frames`) in the frames
/// of their rows; bodies on a row `frames` does not have are dropped.
#[must_use]
pub fn link_meshes(bodies: &[Body], frames: &[DAffine3]) -> Vec<LinkMesh> {
    bodies
        .iter()
        .filter_map(|b| {
            let to_local = frames.get(b.link)?.inverse();
            Some(LinkMesh {
                link: b.link,
                vertices: b
                    .mesh
                    .vertices
                    .iter()
                    .map(|v| to_local.transform_point3(*v))
                    .collect(),
                triangles: b.mesh.triangles.clone(),
            })
        })
        .collect()
}

/// Adds the meshes, placed by `frames` (the row frames at the drawn
/// configuration), to `scene`, up to [`MAX_DRAWN_TRIANGLES`].
pub fn draw_meshes(scene: &mut Scene, meshes: &[LinkMesh], frames: &[DAffine3]) {
    let mut budget = MAX_DRAWN_TRIANGLES;
    for m in meshes {
        let Some(f) = frames.get(m.link) else {
            continue;
        };
        for t in m.triangles.iter().take(budget) {
            let p = t.map(|k| {
                m.vertices
                    .get(k as usize)
                    .map_or([0.0; 3], |v| f.transform_point3(*v).as_vec3().to_array())
            });
            scene.triangles.push(Triangle {
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
        let mut scene = Scene::new();
        draw_meshes(&mut scene, &meshes, &moved);
        assert_eq!(scene.triangles.len(), 1);
        let p = scene.triangles[0].p;
        assert!((glam::Vec3::from_array(p[0]) - glam::Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6);
        assert!((glam::Vec3::from_array(p[1]) - glam::Vec3::new(-1.0, 2.0, 0.0)).length() < 1e-6);
    }
}
