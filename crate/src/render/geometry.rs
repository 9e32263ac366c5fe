//! Template meshes, built once and instanced for every primitive.

use bytemuck::{Pod, Zeroable};

/// A vertex of the capsule template: a unit direction in the capsule's frame
/// (z along the axis) and the end it hangs from (0: `a`, 1: `b`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct SolidVertex {
    pub dir: [f32; 3],
    pub side: f32,
}

/// A corner of the line quad: which end (0, 1) and which side (-1, 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct LineVertex {
    pub corner: [f32; 2],
}

/// Per-instance data of a capsule or sphere.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct SolidInstance {
    pub p0_r0: [f32; 4],
    pub p1_r1: [f32; 4],
    pub color: [f32; 4],
}

/// Per-instance data of a line.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct LineInstance {
    pub p0_width: [f32; 4],
    pub p1: [f32; 4],
    pub color: [f32; 4],
}

/// A vertex of a flat-shaded triangle.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct MeshVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub color: [f32; 4],
}

/// Rings per hemisphere (from the pole to the equator, inclusive).
const RINGS: u32 = 7;
/// Vertices around the axis.
const SECTORS: u32 = 18;

/// The capsule template as indexed triangles (a vertex grid shared by its
/// neighbours, so each is shaded once; WebGL2 and WebGPU alike).
///
/// Two hemispheres, the one at `a` (pointing along −z) and the one at `b`
/// (along +z), each with its own equator ring, joined by a band: with equal
/// end points and radii it is a sphere.
pub(crate) fn capsule_template() -> (Vec<SolidVertex>, Vec<u16>) {
    // Rows of unit directions, from the −z pole to the +z pole; each row
    // carries the side it belongs to. The two equator rows are the band.
    let mut rows: Vec<(f32, f32)> = Vec::new(); // (polar angle from +z, side)
    for i in 0..=RINGS {
        let t = i as f32 / RINGS as f32;
        rows.push((std::f32::consts::PI - t * std::f32::consts::FRAC_PI_2, 0.0));
    }
    for i in 0..=RINGS {
        let t = i as f32 / RINGS as f32;
        rows.push((std::f32::consts::FRAC_PI_2 * (1.0 - t), 1.0));
    }
    let columns = SECTORS + 1; // the seam is duplicated
    let mut vertices = Vec::with_capacity(rows.len() * columns as usize);
    for &(polar, side) in &rows {
        let (s, c) = polar.sin_cos();
        for j in 0..columns {
            let phi = j as f32 / SECTORS as f32 * std::f32::consts::TAU;
            vertices.push(SolidVertex {
                dir: [s * phi.cos(), s * phi.sin(), c],
                side,
            });
        }
    }
    let mut indices = Vec::with_capacity((rows.len() - 1) * SECTORS as usize * 6);
    for r in 0..rows.len() as u32 - 1 {
        for j in 0..SECTORS {
            let a = (r * columns + j) as u16;
            let b = a + 1;
            let c = a + columns as u16;
            let d = c + 1;
            // Counter-clockwise seen from outside.
            indices.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    (vertices, indices)
}

/// The line quad as two triangles.
pub(crate) fn line_template() -> [LineVertex; 6] {
    let v = |t: f32, s: f32| LineVertex { corner: [t, s] };
    [
        v(0.0, -1.0),
        v(1.0, -1.0),
        v(1.0, 1.0),
        v(0.0, -1.0),
        v(1.0, 1.0),
        v(0.0, 1.0),
    ]
}
