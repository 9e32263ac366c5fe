//! The vertex, index and instance buffers: the line template built once, and
//! a scene's capsules and spheres (as lit triangles, `solids.rs`), lines,
//! triangles and grid uploaded each frame, opaque ones first, translucent
//! ones sorted back to front.

use glam::Vec3;

use super::flat;
use super::geometry::{ClipVertex, ShadedVertex, SolidInstance};
use super::solids::{Shading, Solids, Viewpoint};
use crate::view::occlusion::{Ends, Occluder, Occluders};
use crate::view::tessellation::{self, Templates};
use crate::view::{Camera, Drawing, View};

/// A GPU buffer of vertices, instances or indices that grows (by doubling)
/// when a frame needs more.
#[derive(Debug)]
pub(super) struct InstanceBuffer {
    pub buffer: wgpu::Buffer,
    capacity: usize,
    label: &'static str,
    stride: usize,
    usage: wgpu::BufferUsages,
}

impl InstanceBuffer {
    fn new(device: &wgpu::Device, label: &'static str, stride: usize) -> Self {
        Self::with_usage(device, label, stride, wgpu::BufferUsages::VERTEX)
    }

    fn with_usage(
        device: &wgpu::Device,
        label: &'static str,
        stride: usize,
        usage: wgpu::BufferUsages,
    ) -> Self {
        let capacity = 64;
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        Self {
            buffer: Self::create(device, label, stride * capacity, usage),
            capacity,
            label,
            stride,
            usage,
        }
    }

    fn create(
        device: &wgpu::Device,
        label: &str,
        size: usize,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size as u64,
            usage,
            mapped_at_creation: false,
        })
    }

    fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        let needed = bytes.len() / self.stride;
        if needed > self.capacity {
            self.capacity = needed.next_power_of_two();
            self.buffer = Self::create(device, self.label, self.stride * self.capacity, self.usage);
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// How many of each were uploaded; each buffer holds its opaque items first.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Counts {
    /// Indices of the opaque solids' triangles.
    pub solid_opaque: u32,
    /// Indices of every solid's triangles, opaque and translucent.
    pub solids: u32,
    /// Vertices of the opaque lines' quads (six a line).
    pub line_opaque: u32,
    /// Vertices of every line's quad, opaque and translucent.
    pub lines: u32,
    /// Vertices of the grid's hairlines (two a line).
    pub hair: u32,
    /// Vertices of opaque triangles.
    pub mesh_opaque: u32,
    /// Vertices of translucent triangles.
    pub mesh_blend: u32,
}

/// How the camera sees the scene: the eye (for sorting back to front), the
/// size of things on screen (for the solids' level of detail) and where
/// they are seen from (for culling their back faces).
#[derive(Clone, Copy, Debug)]
pub(super) struct Lens {
    pub eye: Vec3,
    viewpoint: Viewpoint,
    /// Pixels a metre spans at unit distance (perspective) or anywhere
    /// (orthographic).
    pixels_per_metre: f32,
    /// How far (px) a solid's outline may stray from the true circle.
    tolerance: f32,
    perspective: bool,
    /// The near clipping plane's distance in front of the eye (perspective).
    near: Option<f32>,
}

impl Lens {
    /// The lens of `camera` on a drawing buffer `height` pixels high;
    /// `software`: the adapter is a software rasteriser, where every
    /// triangle costs, and the solids' outlines are kept within
    /// [`tessellation::SOFTWARE_TOLERANCE`] px instead of
    /// [`tessellation::TOLERANCE`].
    pub fn new(camera: &Camera, height: f32, software: bool) -> Self {
        let perspective = camera.view == View::Orbit;
        let viewpoint = if perspective {
            Viewpoint::Eye(camera.eye())
        } else {
            Viewpoint::Along(-camera.backward())
        };
        Self {
            eye: camera.eye(),
            viewpoint,
            // At a metre from the eye in perspective.
            pixels_per_metre: camera.pixels_per_metre(height, 1.0),
            tolerance: tessellation::tolerance(software),
            perspective,
            near: camera.near_plane(),
        }
    }

    /// A solid's larger radius in pixels, seen from its nearer end.
    fn pixels(&self, s: &SolidInstance) -> f32 {
        let radius = s.p0_r0[3].max(s.p1_r1[3]);
        let mut pixels = radius * self.pixels_per_metre;
        if self.perspective {
            let near = Vec3::from_slice(&s.p0_r0[..3])
                .distance(self.eye)
                .min(Vec3::from_slice(&s.p1_r1[..3]).distance(self.eye));
            pixels /= (near - radius).max(1e-3);
        }
        pixels
    }
}

/// Every buffer the pipelines draw from.
#[derive(Debug)]
pub(super) struct Buffers {
    /// The capsule template at each level of detail.
    templates: Templates,
    /// This frame's solids, reused from frame to frame.
    tessellated: Solids,
    /// The opaque solids that may hide others' triangles.
    occluders: Occluders,
    /// This frame's other vertices, reused from frame to frame.
    clip_vertices: Vec<ClipVertex>,
    shaded_vertices: Vec<ShadedVertex>,
    /// The solids' lit vertices and their triangles.
    pub solid_vertices: InstanceBuffer,
    pub solid_indices: InstanceBuffer,
    pub lines: InstanceBuffer,
    pub mesh: InstanceBuffer,
    pub hair: InstanceBuffer,
    pub counts: Counts,
}

impl Buffers {
    /// Triangles of the last upload's solids at their level of detail,
    /// back faces included.
    pub fn solid_triangles(&self) -> u64 {
        self.tessellated.detail
    }

    /// The templates, and empty buffers.
    pub fn new(device: &wgpu::Device) -> Self {
        let instances = |label, stride| InstanceBuffer::new(device, label, stride);
        Self {
            templates: Templates::default(),
            tessellated: Solids::default(),
            occluders: Occluders::default(),
            clip_vertices: Vec::new(),
            shaded_vertices: Vec::new(),
            solid_vertices: instances("solid vertices", std::mem::size_of::<ShadedVertex>()),
            solid_indices: InstanceBuffer::with_usage(
                device,
                "solid indices",
                4,
                wgpu::BufferUsages::INDEX,
            ),
            lines: instances("line vertices", std::mem::size_of::<ClipVertex>()),
            mesh: instances("mesh vertices", std::mem::size_of::<ShadedVertex>()),
            hair: instances("hairline vertices", std::mem::size_of::<ShadedVertex>()),
            counts: Counts::default(),
        }
    }

    /// Uploads `scene`, its solids lit by `shading`; translucent items are
    /// sorted back to front from the lens's eye.
    pub fn upload(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        scene: &Drawing,
        lens: &Lens,
        shading: &Shading<'_>,
    ) {
        let solids = &mut self.tessellated;
        tessellate(
            (solids, &mut self.occluders),
            &self.templates,
            scene,
            lens,
            shading,
        );
        self.counts.solid_opaque = solids.opaque_indices;
        self.counts.solids = solids.indices.len() as u32;
        self.solid_vertices
            .upload(device, queue, bytemuck::cast_slice(&solids.vertices));
        self.solid_indices
            .upload(device, queue, bytemuck::cast_slice(&solids.indices));
        // The grid is drawn as one-pixel hairlines: rasterised far faster
        // than long thin quads, notably by software rasterisers.
        let vertices = &mut self.shaded_vertices;
        vertices.clear();
        if let Some(grid) = scene.grid {
            flat::push_grid(vertices, &grid, shading);
        }
        self.counts.hair = vertices.len() as u32;
        self.hair
            .upload(device, queue, bytemuck::cast_slice(vertices));
        let quads = &mut self.clip_vertices;
        self.counts.line_opaque = 6 * flat::line_quads(&scene.lines, shading, quads);
        self.counts.lines = quads.len() as u32;
        self.lines
            .upload(device, queue, bytemuck::cast_slice(quads));
        let opaque = flat::triangle_vertices(
            (&scene.triangles, &scene.closed),
            (lens.eye, lens.viewpoint),
            shading,
            vertices,
        );
        self.counts.mesh_opaque = opaque;
        self.counts.mesh_blend = vertices.len() as u32 - opaque;
        self.mesh
            .upload(device, queue, bytemuck::cast_slice(vertices));
    }
}

fn finite(values: &[[f32; 4]]) -> bool {
    values.iter().flatten().all(|x| x.is_finite())
}

/// Capsules and spheres as lit front faces into `out`, opaque first, then
/// translucent ones back to front; items with a non-finite value are
/// dropped, and triangles inside an opaque solid left out
/// (`view::occlusion`).
fn tessellate(
    (out, occluders): (&mut Solids, &mut Occluders),
    templates: &Templates,
    scene: &Drawing,
    lens: &Lens,
    shading: &Shading<'_>,
) {
    let solid = |a: [f32; 3], b: [f32; 3], radius: [f32; 2], color: [f32; 4]| SolidInstance {
        p0_r0: [a[0], a[1], a[2], radius[0].max(0.0)],
        p1_r1: [b[0], b[1], b[2], radius[1].max(0.0)],
        color,
    };
    let capsules = scene
        .capsules
        .iter()
        .map(|c| solid(c.a, c.b, c.radius, c.color));
    let spheres = scene
        .spheres
        .iter()
        .map(|s| solid(s.center, s.center, [s.radius; 2], s.color));
    let all = capsules
        .chain(spheres)
        .filter(|s| finite(&[s.p0_r0, s.p1_r1, s.color]));
    let (opaque, mut blend): (Vec<_>, Vec<_>) = all.partition(|s| s.color[3] >= 1.0);
    let depth = |s: &SolidInstance| {
        let mid = 0.5 * (Vec3::from_slice(&s.p0_r0[..3]) + Vec3::from_slice(&s.p1_r1[..3]));
        mid.distance_squared(lens.eye)
    };
    blend.sort_by(|x, y| depth(y).total_cmp(&depth(x)));
    let template = |s: &SolidInstance| templates.for_radius(lens.pixels(s), lens.tolerance);
    let eye = lens.near.map(|near| (lens.eye, near));
    occluders.clear();
    for s in &opaque {
        occluders.push(Occluder::new(ends(s), template(s), eye));
    }
    let add = |out: &mut Solids, occluders: &mut Occluders, s: &SolidInstance| {
        occluders.select_near(&ends(s));
        out.push(s, template(s), shading, (lens.viewpoint, occluders));
    };
    out.clear();
    for s in &opaque {
        add(out, occluders, s);
    }
    out.opaque_indices = out.indices.len() as u32;
    for s in &blend {
        add(out, occluders, s);
    }
}

fn ends(s: &SolidInstance) -> Ends {
    Ends {
        a: Vec3::from_slice(&s.p0_r0[..3]),
        b: Vec3::from_slice(&s.p1_r1[..3]),
        radii: [s.p0_r0[3], s.p1_r1[3]],
    }
}
