//! Triangle meshes: the [`TriMesh`] type and its geometry (bounds, scale
//! and origin, enclosed volume, area).
//!
//! Mesh files (STL, OBJ, COLLADA, glTF) are read by
//! [`crate::parsers::mesh`] ([`load_mesh`](crate::parsers::mesh::load_mesh)).
//! [`TriMesh::transformed`] applies a URDF `<mesh scale>` and the `<origin>`
//! of its `<visual>` or `<collision>`.
//!
//! [`simplify`] reduces a mesh to a triangle budget for drawing (quadric
//! error edge collapse); the fitting never sees it.
//!
//! See also [`crate::parsers::urdf`] (which meshes a URDF names) and
//! [`crate::fitting`] (volumes fitted to them).

mod simplify;

pub use simplify::simplify;

use glam::{DAffine3, DVec3};

/// A triangle mesh: vertex positions and triangles as indices into them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions (the file's units, or m once transformed).
    pub vertices: Vec<DVec3>,
    /// Triangles, counter-clockwise seen from outside where the file says so.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Axis-aligned bounds `(min, max)`; `None` for a mesh without vertices.
    #[must_use]
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let first = *self.vertices.first()?;
        Some(
            self.vertices
                .iter()
                .fold((first, first), |(lo, hi), v| (lo.min(*v), hi.max(*v))),
        )
    }

    /// The mesh scaled per axis by `scale` (a URDF `<mesh scale>`), then moved
    /// by `pose` (the `<origin>` of its `<visual>` or `<collision>`, then the
    /// link's pose): `p ↦ pose(scale ∘ p)`. A negative scale mirrors the mesh
    /// and its triangles are turned over to keep their outside.
    #[must_use]
    pub fn transformed(&self, pose: &DAffine3, scale: DVec3) -> Self {
        let flip = scale.x * scale.y * scale.z < 0.0;
        Self {
            vertices: self
                .vertices
                .iter()
                .map(|v| pose.transform_point3(*v * scale))
                .collect(),
            triangles: self
                .triangles
                .iter()
                .map(|&[a, b, c]| if flip { [a, c, b] } else { [a, b, c] })
                .collect(),
        }
    }

    /// The three corners of triangle `k`.
    #[must_use]
    pub fn corners(&self, k: usize) -> [DVec3; 3] {
        self.triangles[k].map(|i| self.vertices[i as usize])
    }

    /// Enclosed volume (m³): the absolute value of the signed volume
    /// (divergence theorem), exact for a closed, consistently oriented
    /// surface; for an open one it depends on the origin.
    #[must_use]
    pub fn volume(&self) -> f64 {
        let signed: f64 = (0..self.triangles.len())
            .map(|k| {
                let [a, b, c] = self.corners(k);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        signed.abs()
    }

    /// Surface area (m²).
    #[must_use]
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|k| {
                let [a, b, c] = self.corners(k);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    /// Appends `other` (its indices shifted past this mesh's vertices).
    pub fn append(&mut self, other: &Self) {
        let base = u32::try_from(self.vertices.len()).unwrap_or(u32::MAX);
        self.vertices.extend_from_slice(&other.vertices);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| t.map(|k| k.saturating_add(base))),
        );
    }
}
