//! The vertex and instance buffers: the template meshes built once, and a
//! scene's capsules, spheres, lines, triangles and grid uploaded each frame,
//! opaque ones first, translucent ones sorted back to front.

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::geometry::{self, LineInstance, MeshVertex, SolidInstance, TemplateRange};
use crate::view::{Camera, Grid, Scene, Triangle, View};

/// A GPU buffer of instances that grows (by doubling) when a frame needs more.
#[derive(Debug)]
pub(super) struct InstanceBuffer {
    pub buffer: wgpu::Buffer,
    capacity: usize,
    label: &'static str,
    stride: usize,
}

impl InstanceBuffer {
    fn new(device: &wgpu::Device, label: &'static str, stride: usize) -> Self {
        let capacity = 64;
        Self {
            buffer: Self::create(device, label, stride * capacity),
            capacity,
            label,
            stride,
        }
    }

    fn create(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: size as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        let needed = bytes.len() / self.stride;
        if needed > self.capacity {
            self.capacity = needed.next_power_of_two();
            self.buffer = Self::create(device, self.label, self.stride * self.capacity);
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// How many of each were uploaded; each buffer holds its opaque items first.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Counts {
    pub solid_opaque: u32,
    pub solid_blend: u32,
    pub line_opaque: u32,
    /// Every line, opaque and translucent.
    pub lines: u32,
    pub hair: u32,
    /// Vertices of opaque triangles.
    pub mesh_opaque: u32,
    /// Vertices of translucent triangles.
    pub mesh_blend: u32,
}

/// How the camera sees the scene: the eye (for sorting back to front) and
/// the size of things on screen (for the solids' level of detail).
#[derive(Clone, Copy, Debug)]
pub(super) struct Lens {
    pub eye: Vec3,
    /// Pixels a metre spans at unit distance (perspective) or anywhere
    /// (orthographic).
    pixels_per_metre: f32,
    perspective: bool,
}

impl Lens {
    /// The lens of `camera` on a drawing buffer `height` pixels high.
    pub fn new(camera: &Camera, height: f32) -> Self {
        let perspective = camera.view == View::Orbit;
        let half = if perspective {
            (0.5 * camera.fov_y).tan()
        } else {
            camera.half_height()
        };
        Self {
            eye: camera.eye(),
            pixels_per_metre: 0.5 * height / half.max(1e-6),
            perspective,
        }
    }

    /// The level of detail of a solid: its larger radius in pixels, seen
    /// from its nearer end.
    fn level(&self, s: &SolidInstance) -> usize {
        let radius = s.p0_r0[3].max(s.p1_r1[3]);
        let mut pixels = radius * self.pixels_per_metre;
        if self.perspective {
            let near = Vec3::from_slice(&s.p0_r0[..3])
                .distance(self.eye)
                .min(Vec3::from_slice(&s.p1_r1[..3]).distance(self.eye));
            pixels /= (near - radius).max(1e-3);
        }
        geometry::level_for(pixels)
    }
}

/// Consecutive solid instances drawn with one level of the template.
#[derive(Clone, Debug)]
pub(super) struct Run {
    pub level: usize,
    pub instances: std::ops::Range<u32>,
}

/// Every buffer the pipelines draw from.
#[derive(Debug)]
pub(super) struct Buffers {
    pub solid_template: wgpu::Buffer,
    pub solid_indices: wgpu::Buffer,
    /// Where each level of detail lies in the template buffers.
    pub levels: [TemplateRange; 3],
    /// Opaque solids by level, then translucent ones back to front.
    pub opaque_runs: Vec<Run>,
    pub blend_runs: Vec<Run>,
    pub line_template: wgpu::Buffer,
    pub solids: InstanceBuffer,
    pub lines: InstanceBuffer,
    pub mesh: InstanceBuffer,
    pub hair: InstanceBuffer,
    pub counts: Counts,
}

impl Buffers {
    /// The templates, and empty instance buffers.
    pub fn new(device: &wgpu::Device) -> Self {
        let (template, template_indices, levels) = geometry::capsule_templates();
        let solid_template = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("capsule template"),
            contents: bytemuck::cast_slice(&template),
            usage: wgpu::BufferUsages::VERTEX,
        });
        // Padded to a multiple of 4 bytes, as buffer writes require.
        let mut index_bytes: Vec<u8> = bytemuck::cast_slice(&template_indices).to_vec();
        index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
        let solid_indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("capsule template indices"),
            contents: &index_bytes,
            usage: wgpu::BufferUsages::INDEX,
        });
        let line_template = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("line template"),
            contents: bytemuck::cast_slice(&geometry::line_template()),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let instances = |label, stride| InstanceBuffer::new(device, label, stride);
        Self {
            solid_template,
            solid_indices,
            levels,
            opaque_runs: Vec::new(),
            blend_runs: Vec::new(),
            line_template,
            solids: instances("solid instances", std::mem::size_of::<SolidInstance>()),
            lines: instances("line instances", std::mem::size_of::<LineInstance>()),
            mesh: instances("mesh vertices", std::mem::size_of::<MeshVertex>()),
            hair: instances("hairline vertices", std::mem::size_of::<MeshVertex>()),
            counts: Counts::default(),
        }
    }

    /// Uploads `scene`; translucent items are sorted back to front from the
    /// lens's eye.
    pub fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        lens: &Lens,
    ) {
        let (solids, opaque, blend) = solid_instances(scene, lens, &mut self.counts);
        (self.opaque_runs, self.blend_runs) = (opaque, blend);
        self.solids
            .upload(device, queue, bytemuck::cast_slice(&solids));
        // The grid is drawn as one-pixel hairlines: rasterised far faster
        // than long thin quads, notably by software rasterisers.
        let mut hair: Vec<MeshVertex> = Vec::new();
        if let Some(grid) = scene.grid {
            push_grid(&mut hair, &grid);
        }
        self.counts.hair = hair.len() as u32;
        self.hair.upload(device, queue, bytemuck::cast_slice(&hair));
        let lines = line_instances(scene, &mut self.counts);
        self.lines
            .upload(device, queue, bytemuck::cast_slice(&lines));
        let vertices = mesh_vertices(scene, lens.eye, &mut self.counts);
        self.mesh
            .upload(device, queue, bytemuck::cast_slice(&vertices));
    }
}

fn finite(values: &[[f32; 4]]) -> bool {
    values.iter().flatten().all(|x| x.is_finite())
}

/// Capsules and spheres as instances, opaque first (grouped by level of
/// detail), then translucent ones back to front; items with a non-finite
/// value are dropped. Returns the instances and the runs of each group.
fn solid_instances(
    scene: &Scene,
    lens: &Lens,
    counts: &mut Counts,
) -> (Vec<SolidInstance>, Vec<Run>, Vec<Run>) {
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
        .filter(|s| finite(&[s.p0_r0, s.p1_r1, s.color]))
        .map(|s| (lens.level(&s), s));
    let (mut opaque, mut blend): (Vec<_>, Vec<_>) = all.partition(|(_, s)| s.color[3] >= 1.0);
    opaque.sort_by_key(|(level, _)| *level);
    let depth = |s: &SolidInstance| {
        let mid = 0.5 * (Vec3::from_slice(&s.p0_r0[..3]) + Vec3::from_slice(&s.p1_r1[..3]));
        mid.distance_squared(lens.eye)
    };
    blend.sort_by(|(_, x), (_, y)| depth(y).total_cmp(&depth(x)));
    counts.solid_opaque = opaque.len() as u32;
    counts.solid_blend = blend.len() as u32;
    let opaque_runs = runs(&opaque, 0);
    let blend_runs = runs(&blend, opaque.len() as u32);
    let instances = opaque.into_iter().chain(blend).map(|(_, s)| s).collect();
    (instances, opaque_runs, blend_runs)
}

/// Consecutive items of one level, as runs of instance indices from `first`.
fn runs(items: &[(usize, SolidInstance)], first: u32) -> Vec<Run> {
    let mut out: Vec<Run> = Vec::new();
    for (k, &(level, _)) in items.iter().enumerate() {
        let index = first + k as u32;
        match out.last_mut() {
            Some(run) if run.level == level => run.instances.end = index + 1,
            _ => out.push(Run {
                level,
                instances: index..index + 1,
            }),
        }
    }
    out
}

/// Lines as instances, opaque ones first (drawn without blending).
fn line_instances(scene: &Scene, counts: &mut Counts) -> Vec<LineInstance> {
    let all = scene
        .lines
        .iter()
        .map(|l| LineInstance {
            p0_width: [l.a[0], l.a[1], l.a[2], l.width.max(0.0)],
            p1: [l.b[0], l.b[1], l.b[2], 0.0],
            color: l.color,
        })
        .filter(|l| finite(&[l.p0_width, l.p1, l.color]));
    let (mut lines, blended): (Vec<_>, Vec<_>) = all.partition(|l| l.color[3] >= 1.0);
    counts.line_opaque = lines.len() as u32;
    lines.extend(blended);
    counts.lines = lines.len() as u32;
    lines
}

/// Triangles as vertices with their face normal, opaque first, then
/// translucent ones back to front by centroid.
fn mesh_vertices(scene: &Scene, eye: Vec3, counts: &mut Counts) -> Vec<MeshVertex> {
    let finite_triangle =
        |t: &&Triangle| t.p.iter().flatten().chain(&t.color).all(|x| x.is_finite());
    let (opaque, mut blend): (Vec<&Triangle>, Vec<&Triangle>) = scene
        .triangles
        .iter()
        .filter(finite_triangle)
        .partition(|t| t.color[3] >= 1.0);
    let centroid =
        |t: &Triangle| (Vec3::from(t.p[0]) + Vec3::from(t.p[1]) + Vec3::from(t.p[2])) / 3.0;
    blend.sort_by(|x, y| {
        centroid(y)
            .distance_squared(eye)
            .total_cmp(&centroid(x).distance_squared(eye))
    });
    counts.mesh_opaque = 3 * opaque.len() as u32;
    counts.mesh_blend = 3 * blend.len() as u32;
    let mut vertices: Vec<MeshVertex> = Vec::with_capacity(3 * scene.triangles.len());
    for t in opaque.into_iter().chain(blend) {
        let [a, b, c] = t.p.map(Vec3::from);
        let normal = (b - a).cross(c - a).normalize_or(Vec3::Z).to_array();
        vertices.extend(t.p.iter().map(|&position| MeshVertex {
            position,
            normal,
            color: t.color,
        }));
    }
    vertices
}

/// Adds the lines of `grid` (the two through the origin in the axis colour).
fn push_grid(lines: &mut Vec<MeshVertex>, grid: &Grid) {
    if !(grid.spacing.is_finite() && grid.half_extent.is_finite())
        || grid.spacing <= 0.0
        || grid.half_extent <= 0.0
    {
        return;
    }
    let h = grid.half_extent;
    let n = ((h / grid.spacing).floor() as i32).min(500);
    for i in -n..=n {
        let t = i as f32 * grid.spacing;
        let color = if i == 0 { grid.axis_color } else { grid.color };
        for (a, b) in [([t, -h, 0.0], [t, h, 0.0]), ([-h, t, 0.0], [h, t, 0.0])] {
            for position in [a, b] {
                lines.push(MeshVertex {
                    position,
                    normal: [0.0, 0.0, 1.0],
                    color,
                });
            }
        }
    }
}
