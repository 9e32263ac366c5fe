//! Vertex layouts: the vertices the pipelines read, and a capsule or sphere
//! as the renderer receives it (placed on the CPU from the templates of
//! `view::tessellation`).

use bytemuck::{Pod, Zeroable};

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
