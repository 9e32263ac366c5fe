//! Capsules and spheres placed, lit and culled on the CPU each frame.
//!
//! Each solid is its template (at the level of detail its size on screen
//! asks for) moved to its end points and radii, lit per vertex as the
//! shaders light everything else, and encoded to the surface's colour
//! space. Triangles facing away from the eye are left out: the solids are
//! closed, so they would be culled anyway; so are those inside an opaque
//! solid of equal radii, which its surface hides (`view::occlusion`).
//! Every solid of a frame then goes to the rasteriser as one indexed draw
//! for the opaque ones and one for the translucent ones (back to front). A software rasteriser (SwiftShader)
//! runs each instance of an instanced draw as a draw of its own, with its
//! own batches and synchronisation between its threads, and shades every
//! vertex of every back face before culling it: drawing the solids as one
//! list of front faces took the CPU time of Chromium's GPU process per frame
//! of the `human-panda` example from about 34 to 25 ms, its triangles from
//! 31 500 to 14 600, with the same pixels.

use glam::{Mat4, Vec2, Vec3};

use super::geometry::{ShadedVertex, SolidInstance};
use crate::view::occlusion::Occluders;
use crate::view::tessellation::Template;

/// The lights and the colour space, as the shaders have them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Shading<'a> {
    /// Unit vector from the scene towards the camera (the headlight).
    pub to_camera: Vec3,
    /// Unit vector towards the key light.
    pub key_light: Vec3,
    /// Whether colours are encoded to sRGB here (the surface format is not
    /// an sRGB one) or left linear (the hardware encodes).
    pub encode: bool,
    /// World to clip space.
    pub view_proj: Mat4,
    /// Half the drawing buffer's size (pixels).
    pub half_px: Vec2,
    /// The roots `lit` encodes with.
    pub roots: &'a Roots,
}

/// Where the triangles are seen from, for culling the back faces.
#[derive(Clone, Copy, Debug)]
pub(super) enum Viewpoint {
    /// Perspective: the eye.
    Eye(Vec3),
    /// Orthographic: the direction the camera looks along.
    Along(Vec3),
}

impl Viewpoint {
    /// Whether the triangle `[p, q, r]` (counter-clockwise seen from its
    /// front) shows its back, with a margin: a triangle seen edge on is
    /// kept, and the pipeline's own culling decides.
    pub fn faces_away(self, [p, q, r]: [Vec3; 3]) -> bool {
        let normal = (q - p).cross(r - p);
        let view = match self {
            Viewpoint::Eye(eye) => p - eye,
            Viewpoint::Along(direction) => direction,
        };
        let d = normal.dot(view);
        d > 0.0 && d * d > 1e-6 * normal.length_squared() * view.length_squared()
    }
}

/// The solids of a frame as lit vertices and triangles (indices into them).
#[derive(Debug, Default)]
pub(super) struct Solids {
    pub vertices: Vec<ShadedVertex>,
    pub indices: Vec<u32>,
    /// Indices of the opaque solids (they come first).
    pub opaque_indices: u32,
    /// Triangles of the templates, back faces included.
    pub detail: u64,
    /// For each vertex of the solid being added, the occluders hiding it.
    masks: Vec<u32>,
}

impl Solids {
    /// Empties the lists, keeping their memory.
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.indices.clear();
        self.opaque_indices = 0;
        self.detail = 0;
    }

    /// Adds `solid` drawn with `template`: its triangles that face the
    /// viewpoint, but not those inside one of the occluders chosen near it.
    pub fn push(
        &mut self,
        solid: &SolidInstance,
        template: &Template,
        shading: &Shading<'_>,
        (viewpoint, occluders): (Viewpoint, &Occluders),
    ) {
        let a = Vec3::from_slice(&solid.p0_r0[..3]);
        let b = Vec3::from_slice(&solid.p1_r1[..3]);
        let radii = [solid.p0_r0[3], solid.p1_r1[3]];
        let axis = (b - a).try_normalize().unwrap_or(Vec3::Z);
        // Any unit vector not parallel to the axis gives an orthonormal frame.
        let helper = if axis.x.abs() > 0.9 { Vec3::Y } else { Vec3::X };
        let u = helper.cross(axis).normalize();
        let v = axis.cross(u);
        let srgb = [solid.color[0], solid.color[1], solid.color[2]];
        let linear = srgb.map(srgb_to_linear);
        self.detail += template.triangles.len() as u64;
        let first = self.vertices.len() as u32;
        for t in &template.vertices {
            let n = u * t.dir[0] + v * t.dir[1] + axis * t.dir[2];
            let (centre, radius) = if t.at_b { (b, radii[1]) } else { (a, radii[0]) };
            let key = n.dot(shading.key_light).max(0.0);
            let head = n.dot(shading.to_camera).max(0.0);
            let light = 0.28 + 0.47 * key + 0.35 * head;
            let [r, g, bl] = shading.lit(srgb, linear, light);
            self.vertices.push(ShadedVertex {
                position: (centre + radius * n).to_array(),
                color: [r, g, bl, solid.color[3]],
            });
        }
        let placed = &self.vertices[first as usize..];
        let position = |k: u16| Vec3::from_array(placed[usize::from(k)].position);
        self.masks.clear();
        if occluders.any_near() {
            let masks = placed
                .iter()
                .map(|v| occluders.mask(Vec3::from(v.position)));
            self.masks.extend(masks);
        }
        let hidden = |tri: &[u16; 3]| {
            !self.masks.is_empty()
                && tri
                    .iter()
                    .fold(u32::MAX, |m, &k| m & self.masks[usize::from(k)])
                    != 0
        };
        for tri in &template.triangles {
            if !viewpoint.faces_away(tri.map(position)) && !hidden(tri) {
                self.indices.extend(tri.map(|k| first + u32::from(k)));
            }
        }
    }
}

/// sRGB decoding of one channel.
pub(super) fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Samples of `light^(1/2.4)` over `0..=ROOT_RANGE`, for encoding lit
/// colours without a power per vertex.
const ROOT_SAMPLES: usize = 64;
const ROOT_RANGE: f32 = 1.25;

/// `light^(1/2.4)` for `light` in `0..=ROOT_RANGE`, interpolated linearly
/// between samples (within about 1e-4 of the power from 0.25 on, far below a
/// step of an 8-bit channel), the power itself elsewhere.
#[derive(Clone, Debug)]
pub(super) struct Roots([f32; ROOT_SAMPLES + 1]);

impl Default for Roots {
    fn default() -> Self {
        Self(std::array::from_fn(|k| {
            (k as f32 * ROOT_RANGE / ROOT_SAMPLES as f32).powf(1.0 / 2.4)
        }))
    }
}

impl Roots {
    fn get(&self, light: f32) -> f32 {
        if !(0.25..ROOT_RANGE).contains(&light) {
            return light.max(0.0).powf(1.0 / 2.4);
        }
        let x = light * (ROOT_SAMPLES as f32 / ROOT_RANGE);
        let k = (x as usize).min(ROOT_SAMPLES - 1);
        let t = x - k as f32;
        self.0[k] + t * (self.0[k + 1] - self.0[k])
    }
}

impl Shading<'_> {
    /// The colour `srgb` (decoded: `linear`) lit by `light`: linear, or
    /// encoded back to sRGB (clamped to 0..=1) when encoding.
    ///
    /// Encoding `linear · light` takes no power per channel: where both
    /// decoding and encoding follow the power law, the result is
    /// `(c + 0.055) · light^(1/2.4) − 0.055` exactly, the root interpolated
    /// from a table.
    pub fn lit(&self, srgb: [f32; 3], linear: [f32; 3], light: f32) -> [f32; 3] {
        if !self.encode {
            return linear.map(|c| c * light);
        }
        let root = self.roots.get(light);
        let mut out = [0.0; 3];
        for ((o, &c), &lin) in out.iter_mut().zip(&srgb).zip(&linear) {
            let x = lin * light;
            *o = if x <= 0.003_130_8 {
                12.92 * x.max(0.0)
            } else if x >= 1.0 {
                1.0
            } else if c > 0.04045 {
                ((c + 0.055) * root - 0.055).min(1.0)
            } else {
                1.055 * x.powf(1.0 / 2.4) - 0.055
            };
        }
        out
    }
}
