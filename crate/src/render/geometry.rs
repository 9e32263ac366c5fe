//! Vertex layouts and the capsule template at three levels of detail
//! (placed on the CPU for every capsule and sphere).

use bytemuck::{Pod, Zeroable};

/// A vertex of the capsule template: a unit direction in the capsule's frame
/// (z along the axis) and the end it hangs from (0: `a`, 1: `b`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct SolidVertex {
    pub dir: [f32; 3],
    pub side: f32,
}

/// A vertex already in clip space, lit and encoded (the lines' quads).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct ClipVertex {
    pub clip: [f32; 4],
    pub color: [f32; 4],
}

/// A capsule or sphere: end points, radii and colour.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SolidInstance {
    pub p0_r0: [f32; 4],
    pub p1_r1: [f32; 4],
    pub color: [f32; 4],
}

/// A vertex lit and encoded on the CPU (the capsules and spheres).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct ShadedVertex {
    pub position: [f32; 3],
    pub color: [f32; 4],
}

/// One level of detail of the capsule template.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Level {
    /// Rings per hemisphere (from the pole to the equator, inclusive).
    rings: u32,
    /// Vertices around the axis.
    sectors: u32,
    /// The largest on-screen radius (px) drawn at this level.
    up_to_px: f32,
}

/// The levels, coarsest first. A software rasteriser (the only one some
/// browsers have, e.g. SwiftShader in headless Chromium) spends its time per
/// triangle rather than per pixel, so a solid a few pixels across gets few
/// triangles: each level keeps the silhouette within about 0.75 px of the
/// true circle (sagitta `r (1 − cos(π/sectors))`) up to its radius, and
/// within about 1.5 px on a software rasteriser, where each level serves
/// up to twice the radius (`buffers::SOFTWARE_TOLERANCE`).
pub(crate) const LEVELS: [Level; 3] = [
    Level {
        rings: 3,
        sectors: 10,
        up_to_px: 12.0,
    },
    Level {
        rings: 5,
        sectors: 14,
        up_to_px: 30.0,
    },
    Level {
        rings: 7,
        sectors: 18,
        up_to_px: f32::INFINITY,
    },
];

/// The level for a solid whose larger radius spans `pixels` on screen.
pub(crate) fn level_for(pixels: f32) -> usize {
    LEVELS
        .iter()
        .position(|l| pixels <= l.up_to_px)
        .unwrap_or(LEVELS.len() - 1)
}

/// One level of the capsule template: unit directions with the end they
/// hang from, and triangles (indices into them), counter-clockwise seen
/// from outside.
#[derive(Clone, Debug, Default)]
pub(crate) struct Template {
    pub vertices: Vec<SolidVertex>,
    pub triangles: Vec<[u16; 3]>,
}

/// The template of every level, coarsest first.
pub(crate) fn capsule_templates() -> [Template; 3] {
    LEVELS.map(|level| capsule_template(level.rings, level.sectors))
}

/// The capsule template as indexed triangles (a vertex grid shared by its
/// neighbours, so each is lit once), with `rings` per hemisphere and
/// `sectors` around the axis.
///
/// Two hemispheres, the one at `a` (pointing along −z) and the one at `b`
/// (along +z), each with its own equator ring, joined by a band: with equal
/// end points and radii it is a sphere. The rows at the poles are single
/// points repeated around the axis, so the triangles of the bands next to
/// them are fans: the quads' other halves would have no area.
fn capsule_template(rings: u32, sectors: u32) -> Template {
    // Rows of unit directions, from the −z pole to the +z pole; each row
    // carries the side it belongs to. The two equator rows are the band.
    let mut rows: Vec<(f32, f32)> = Vec::new(); // (polar angle from +z, side)
    for i in 0..=rings {
        let t = i as f32 / rings as f32;
        rows.push((std::f32::consts::PI - t * std::f32::consts::FRAC_PI_2, 0.0));
    }
    for i in 0..=rings {
        let t = i as f32 / rings as f32;
        rows.push((std::f32::consts::FRAC_PI_2 * (1.0 - t), 1.0));
    }
    let columns = sectors + 1; // the seam is duplicated
    let mut vertices = Vec::with_capacity(rows.len() * columns as usize);
    for &(polar, side) in &rows {
        let (s, c) = polar.sin_cos();
        for j in 0..columns {
            let phi = j as f32 / sectors as f32 * std::f32::consts::TAU;
            vertices.push(SolidVertex {
                dir: [s * phi.cos(), s * phi.sin(), c],
                side,
            });
        }
    }
    let last_band = rows.len() as u32 - 2;
    let mut triangles = Vec::with_capacity((rows.len() - 1) * sectors as usize * 2);
    for r in 0..=last_band {
        for j in 0..sectors {
            let a = (r * columns + j) as u16;
            let b = a + 1;
            let c = a + columns as u16;
            let d = c + 1;
            // Counter-clockwise seen from outside; a and b are one point on
            // the first row, c and d on the last.
            if r != 0 {
                triangles.push([a, b, d]);
            }
            if r != last_band {
                triangles.push([a, d, c]);
            }
        }
    }
    Template {
        vertices,
        triangles,
    }
}
