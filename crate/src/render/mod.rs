//! The wgpu renderer of the playground (wasm32 only, feature `render`).
//!
//! It knows nothing of robots: each frame the caller describes a [`Scene`]
//! (instanced tapered capsules and spheres with simple shading, lines of a
//! given width on screen, a ground grid) and a [`Camera`], and the renderer
//! draws them into an HTML canvas through WebGPU, or WebGL2 where WebGPU is
//! missing. The shape follows the wgpu examples: [`Renderer::new`] (async),
//! [`Renderer::resize`], [`Renderer::update`], [`Renderer::render`].
//!
//! Colours are sRGB-encoded in the scene; the renderer picks a non-sRGB
//! surface format when one is offered and encodes in the shader, or lets the
//! hardware encode into an sRGB format, so a colour reads the same on both
//! backends.
//!
//! Draw order: opaque solids and opaque triangles (depth written), lines
//! (depth tested, not written), then translucent triangles and translucent
//! solids, each sorted back to front (blended, depth tested, not written),
//! so distance lines stay visible inside volumes and behind a glassy plane.

mod geometry;

use std::borrow::Cow;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use crate::view::{Camera, Grid, Scene, Triangle};

use geometry::{LineInstance, LineVertex, MeshVertex, SolidInstance, SolidVertex};

/// Which graphics API draws the canvas.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// The browser's WebGPU (`navigator.gpu`).
    WebGpu,
    /// WebGL2, through wgpu's GL backend.
    WebGl2,
}

impl Backend {
    /// `"webgpu"` or `"webgl2"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::WebGpu => "webgpu",
            Self::WebGl2 => "webgl2",
        }
    }
}

/// Which backend to ask for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BackendRequest {
    /// WebGPU when the browser really has an adapter, WebGL2 otherwise.
    #[default]
    Auto,
    /// Only WebGPU (fails where it is missing).
    WebGpu,
    /// Only WebGL2 (fails where it is missing).
    WebGl2,
}

impl BackendRequest {
    /// Parses `"auto"`, `"webgpu"`, `"webgl2"`.
    #[must_use]
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "auto" => Some(Self::Auto),
            "webgpu" => Some(Self::WebGpu),
            "webgl2" | "webgl" => Some(Self::WebGl2),
            _ => None,
        }
    }
}

/// Why the renderer could not start or draw.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No adapter for the requested backends (neither WebGPU nor WebGL2).
    #[error(
        "no graphics adapter: this browser offers {requested} (try a recent Chrome, Edge or Firefox with hardware acceleration enabled)"
    )]
    NoAdapter {
        /// What was asked for, in words.
        requested: &'static str,
    },
    /// The canvas could not become a drawing surface.
    #[error("the canvas cannot be drawn on: {0}")]
    Surface(String),
    /// The adapter refused to create a device.
    #[error("the graphics device could not be created: {0}")]
    Device(String),
    /// The surface offers no format the renderer can draw into.
    #[error("the canvas offers no usable colour format")]
    NoFormat,
    /// The surface was lost and could not be recovered.
    #[error("the drawing surface was lost: {0}")]
    Lost(&'static str),
}

/// Uniforms shared by every pipeline (layout mirrors `Globals` in the shader).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    to_camera: [f32; 4],
    key_light: [f32; 4],
    viewport: [f32; 4],
}

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// A GPU buffer of instances that grows (by doubling) when a frame needs more.
#[derive(Debug)]
struct InstanceBuffer {
    buffer: wgpu::Buffer,
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

/// Draws [`Scene`]s into an HTML canvas with wgpu.
///
/// # Example (in an async wasm function)
/// ```ignore
/// let mut renderer = Renderer::new(canvas, BackendRequest::Auto, None).await?;
/// renderer.resize(800, 600);
/// renderer.update(&scene, &camera);
/// renderer.render()?;
/// ```
#[derive(Debug)]
pub struct Renderer {
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    backend: Backend,
    adapter_name: String,
    sample_count: u32,
    depth_view: wgpu::TextureView,
    msaa_view: Option<wgpu::TextureView>,
    globals_buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    solid_opaque: wgpu::RenderPipeline,
    solid_blend: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    line_opaque: wgpu::RenderPipeline,
    hair_pipeline: wgpu::RenderPipeline,
    mesh_opaque: wgpu::RenderPipeline,
    mesh_blend: wgpu::RenderPipeline,
    solid_template: wgpu::Buffer,
    solid_indices: wgpu::Buffer,
    solid_index_count: u32,
    line_template: wgpu::Buffer,
    solids: InstanceBuffer,
    lines: InstanceBuffer,
    mesh: InstanceBuffer,
    hair: InstanceBuffer,
    hair_count: u32,
    mesh_opaque_count: u32,
    mesh_blend_count: u32,
    opaque_count: u32,
    blend_count: u32,
    line_count: u32,
    line_opaque_count: u32,
    background: wgpu::Color,
    encode_srgb: bool,
    globals: Globals,
}

impl Renderer {
    /// Starts a renderer drawing into `canvas` with the backend `request`
    /// asks for, multisampled (4×) when `antialias` says so (`None`: unless
    /// the adapter is a software rasteriser such as SwiftShader, where
    /// multisampling halves the frame rate) and the adapter supports it.
    /// The canvas keeps its size until [`Renderer::resize`].
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] when the browser has neither WebGPU nor
    /// WebGL2 (or not the one requested), [`RenderError::Surface`] when the
    /// canvas cannot get a context (for example it already has another one),
    /// [`RenderError::Device`], [`RenderError::NoFormat`].
    pub async fn new(
        canvas: web_sys::HtmlCanvasElement,
        request: BackendRequest,
        antialias: Option<bool>,
    ) -> Result<Self, RenderError> {
        let (backends, requested) = match request {
            BackendRequest::Auto => (
                wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL,
                "neither WebGPU nor WebGL2",
            ),
            BackendRequest::WebGpu => (wgpu::Backends::BROWSER_WEBGPU, "no WebGPU adapter"),
            BackendRequest::WebGl2 => (wgpu::Backends::GL, "no WebGL2"),
        };
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = backends;
        let instance = wgpu::util::new_instance_with_webgpu_detection(desc).await;
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
            .map_err(|e| {
                let message = e.to_string();
                // With WebGPU requested, a failure means no WebGPU. Otherwise
                // wgpu reports `canvas.getContext() returned null; webgl2 not
                // available …`: the browser has no WebGL2 (or it is disabled).
                let no_webgl2 = message.to_lowercase().contains("webgl2 not available");
                if request == BackendRequest::WebGpu || no_webgl2 {
                    RenderError::NoAdapter { requested }
                } else {
                    RenderError::Surface(message)
                }
            })?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::default(),
                force_fallback_adapter: false,
                compatible_surface: Some(&surface),
                apply_limit_buckets: false,
            })
            .await
            .map_err(|_| RenderError::NoAdapter { requested })?;
        let info = adapter.get_info();
        let adapter_name = [
            info.name.as_str(),
            info.driver.as_str(),
            info.driver_info.as_str(),
        ]
        .into_iter()
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" / ");
        let software = info.device_type == wgpu::DeviceType::Cpu
            || ["swiftshader", "llvmpipe", "software", "lavapipe"]
                .iter()
                .any(|k| adapter_name.to_lowercase().contains(k));
        let antialias = antialias.unwrap_or(!software);
        let backend = match info.backend {
            wgpu::Backend::BrowserWebGpu => Backend::WebGpu,
            _ => Backend::WebGl2,
        };
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("skeleton-avoidance"),
                required_features: wgpu::Features::empty(),
                required_limits: wgpu::Limits::downlevel_webgl2_defaults()
                    .using_resolution(adapter.limits()),
                experimental_features: wgpu::ExperimentalFeatures::default(),
                memory_hints: wgpu::MemoryHints::default(),
                trace: wgpu::Trace::default(),
            })
            .await
            .map_err(|e| RenderError::Device(e.to_string()))?;
        device.on_uncaptured_error(std::sync::Arc::new(|error: wgpu::Error| {
            web_sys::console::error_1(&format!("wgpu: {error}").into());
        }));

        let caps = surface.get_capabilities(&adapter);
        // Prefer a plain 8-bit format and encode sRGB in the shader; accept an
        // sRGB one (the hardware encodes) when nothing else is offered.
        let format = [
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureFormat::Bgra8Unorm,
        ]
        .into_iter()
        .find(|f| caps.formats.contains(f))
        .or_else(|| caps.formats.iter().copied().find(|f| !f.is_srgb()))
        .or_else(|| caps.formats.first().copied())
        .ok_or(RenderError::NoFormat)?;
        let encode_srgb = !format.is_srgb();
        let alpha_mode = if caps.alpha_modes.contains(&wgpu::CompositeAlphaMode::Opaque) {
            wgpu::CompositeAlphaMode::Opaque
        } else {
            caps.alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto)
        };
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width,
            height,
            present_mode: wgpu::PresentMode::Fifo,
            desired_maximum_frame_latency: 2,
            alpha_mode,
            view_formats: Vec::new(),
        };
        surface.configure(&device, &config);

        let format_flags = adapter.get_texture_format_features(format).flags;
        let sample_count = if antialias
            && format_flags.sample_count_supported(4)
            && adapter
                .get_texture_format_features(DEPTH_FORMAT)
                .flags
                .sample_count_supported(4)
        {
            4
        } else {
            1
        };

        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("playground shader"),
            source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(include_str!("shader.wgsl"))),
        });
        let globals = Globals {
            view_proj: glam::Mat4::IDENTITY.to_cols_array_2d(),
            to_camera: [0.0, 0.0, 1.0, 0.0],
            key_light: [0.0, 0.0, 1.0, 0.0],
            viewport: [
                width as f32,
                height as f32,
                if encode_srgb { 1.0 } else { 0.0 },
                0.0,
            ],
        };
        let globals_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("globals"),
            contents: bytemuck::bytes_of(&globals),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<Globals>() as u64),
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &bind_group_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals_buffer.as_entire_binding(),
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("playground"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });

        let pipelines = Pipelines {
            device: &device,
            layout: &layout,
            shader: &shader,
            format,
            sample_count,
        };
        let solid_opaque = pipelines.solid(false);
        let solid_blend = pipelines.solid(true);
        let line_pipeline = pipelines.lines(true);
        let line_opaque = pipelines.lines(false);
        let hair_pipeline = pipelines.hairlines();
        let mesh_opaque = pipelines.mesh(false);
        let mesh_blend = pipelines.mesh(true);

        let (template, template_indices) = geometry::capsule_template();
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
        let solids = InstanceBuffer::new(
            &device,
            "solid instances",
            std::mem::size_of::<SolidInstance>(),
        );
        let lines = InstanceBuffer::new(
            &device,
            "line instances",
            std::mem::size_of::<LineInstance>(),
        );
        let mesh = InstanceBuffer::new(&device, "mesh vertices", std::mem::size_of::<MeshVertex>());
        let hair = InstanceBuffer::new(
            &device,
            "hairline vertices",
            std::mem::size_of::<MeshVertex>(),
        );
        let (depth_view, msaa_view) = attachments(&device, &config, sample_count);

        Ok(Self {
            surface,
            device,
            queue,
            config,
            backend,
            adapter_name,
            sample_count,
            depth_view,
            msaa_view,
            globals_buffer,
            bind_group,
            solid_opaque,
            solid_blend,
            line_pipeline,
            line_opaque,
            hair_pipeline,
            mesh_opaque,
            mesh_blend,
            solid_template,
            solid_indices,
            solid_index_count: template_indices.len() as u32,
            line_template,
            solids,
            lines,
            mesh,
            hair,
            hair_count: 0,
            mesh_opaque_count: 0,
            mesh_blend_count: 0,
            opaque_count: 0,
            blend_count: 0,
            line_count: 0,
            line_opaque_count: 0,
            background: wgpu::Color::WHITE,
            encode_srgb,
            globals,
        })
    }

    /// The backend actually drawing.
    #[must_use]
    pub fn backend(&self) -> Backend {
        self.backend
    }

    /// What the browser says the adapter is (may be empty or masked).
    #[must_use]
    pub fn adapter_name(&self) -> &str {
        &self.adapter_name
    }

    /// The colour format of the canvas, e.g. `Rgba8Unorm`.
    #[must_use]
    pub fn surface_format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// Samples per pixel (4 with multisampling, else 1).
    #[must_use]
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Drawing-buffer size in pixels.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Sets the drawing-buffer size (pixels; the canvas's `width` and
    /// `height` attributes follow). Sizes are clamped to 1 ..= the device's
    /// maximum texture size; an unchanged size costs nothing.
    pub fn resize(&mut self, width: u32, height: u32) {
        let max = self.device.limits().max_texture_dimension_2d.max(1);
        let (width, height) = (width.clamp(1, max), height.clamp(1, max));
        if (width, height) == (self.config.width, self.config.height) {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
        (self.depth_view, self.msaa_view) =
            attachments(&self.device, &self.config, self.sample_count);
    }

    /// Uploads `scene` as seen by `camera`; drawn by the next [`Renderer::render`].
    ///
    /// Translucent solids are sorted back to front from the camera's eye.
    pub fn update(&mut self, scene: &Scene, camera: &Camera) {
        let (width, height) = (self.config.width as f32, self.config.height as f32);
        let view_proj = camera.view_proj(width / height);
        let back = camera.backward();
        let key =
            (glam::Vec3::new(0.4, -0.3, 1.0).normalize() + 0.3 * back).normalize_or(glam::Vec3::Z);
        self.globals = Globals {
            view_proj: view_proj.to_cols_array_2d(),
            to_camera: [back.x, back.y, back.z, 0.0],
            key_light: [key.x, key.y, key.z, 0.0],
            viewport: [width, height, if self.encode_srgb { 1.0 } else { 0.0 }, 0.0],
        };
        let [r, g, b, _] = scene.background.map(|c| f64::from(c.clamp(0.0, 1.0)));
        // The clear colour is written as is: encode it like the shader does.
        self.background = if self.encode_srgb {
            wgpu::Color { r, g, b, a: 1.0 }
        } else {
            wgpu::Color {
                r: srgb_to_linear(r),
                g: srgb_to_linear(g),
                b: srgb_to_linear(b),
                a: 1.0,
            }
        };

        let solid = |a: [f32; 3], b: [f32; 3], radius: [f32; 2], color: [f32; 4]| SolidInstance {
            p0_r0: [a[0], a[1], a[2], radius[0].max(0.0)],
            p1_r1: [b[0], b[1], b[2], radius[1].max(0.0)],
            color,
        };
        let all = scene
            .capsules
            .iter()
            .map(|c| solid(c.a, c.b, c.radius, c.color))
            .chain(
                scene
                    .spheres
                    .iter()
                    .map(|s| solid(s.center, s.center, [s.radius; 2], s.color)),
            )
            .filter(|s| {
                s.p0_r0
                    .iter()
                    .chain(&s.p1_r1)
                    .chain(&s.color)
                    .all(|x| x.is_finite())
            });
        let (opaque, mut blend): (Vec<_>, Vec<_>) = all.partition(|s| s.color[3] >= 1.0);
        let eye = camera.eye();
        let depth = |s: &SolidInstance| {
            let mid = 0.5
                * (glam::Vec3::from_slice(&s.p0_r0[..3]) + glam::Vec3::from_slice(&s.p1_r1[..3]));
            mid.distance_squared(eye)
        };
        blend.sort_by(|x, y| depth(y).total_cmp(&depth(x)));
        self.opaque_count = opaque.len() as u32;
        self.blend_count = blend.len() as u32;
        let mut instances = opaque;
        instances.extend(blend);
        self.solids
            .upload(&self.device, &self.queue, bytemuck::cast_slice(&instances));

        let mut lines: Vec<LineInstance> = Vec::with_capacity(scene.lines.len() + 64);
        // The grid is drawn as one-pixel hairlines: rasterised far faster
        // than long thin quads, notably by software rasterisers.
        let mut hair: Vec<MeshVertex> = Vec::new();
        if let Some(grid) = scene.grid {
            push_grid(&mut hair, &grid);
        }
        self.hair_count = hair.len() as u32;
        self.hair
            .upload(&self.device, &self.queue, bytemuck::cast_slice(&hair));
        lines.extend(scene.lines.iter().map(|l| LineInstance {
            p0_width: [l.a[0], l.a[1], l.a[2], l.width.max(0.0)],
            p1: [l.b[0], l.b[1], l.b[2], 0.0],
            color: l.color,
        }));
        lines.retain(|l| {
            l.p0_width
                .iter()
                .chain(&l.p1)
                .chain(&l.color)
                .all(|x| x.is_finite())
        });
        // Opaque lines first: they are drawn without blending (cheaper).
        let (mut lines, blended): (Vec<_>, Vec<_>) =
            lines.into_iter().partition(|l| l.color[3] >= 1.0);
        self.line_opaque_count = lines.len() as u32;
        lines.extend(blended);
        self.line_count = lines.len() as u32;
        self.lines
            .upload(&self.device, &self.queue, bytemuck::cast_slice(&lines));

        let finite = |t: &&Triangle| t.p.iter().flatten().chain(&t.color).all(|x| x.is_finite());
        let (opaque, mut blend): (Vec<&Triangle>, Vec<&Triangle>) = scene
            .triangles
            .iter()
            .filter(finite)
            .partition(|t| t.color[3] >= 1.0);
        let centroid = |t: &Triangle| {
            (glam::Vec3::from(t.p[0]) + glam::Vec3::from(t.p[1]) + glam::Vec3::from(t.p[2])) / 3.0
        };
        blend.sort_by(|x, y| {
            centroid(y)
                .distance_squared(eye)
                .total_cmp(&centroid(x).distance_squared(eye))
        });
        self.mesh_opaque_count = 3 * opaque.len() as u32;
        self.mesh_blend_count = 3 * blend.len() as u32;
        let mut vertices: Vec<MeshVertex> = Vec::with_capacity(3 * scene.triangles.len());
        for t in opaque.into_iter().chain(blend) {
            let [a, b, c] = t.p.map(glam::Vec3::from);
            let normal = (b - a).cross(c - a).normalize_or(glam::Vec3::Z).to_array();
            vertices.extend(t.p.iter().map(|&position| MeshVertex {
                position,
                normal,
                color: t.color,
            }));
        }
        self.mesh
            .upload(&self.device, &self.queue, bytemuck::cast_slice(&vertices));
    }

    /// Draws the last uploaded scene and presents it; `Ok(false)` when the
    /// frame was skipped.
    ///
    /// A frame the browser is not ready for (timeout, occluded) is skipped
    /// silently; an outdated surface is reconfigured and the frame skipped.
    ///
    /// # Errors
    /// [`RenderError::Lost`] when the surface is lost for good.
    pub fn render(&mut self) -> Result<bool, RenderError> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame)
            | wgpu::CurrentSurfaceTexture::Suboptimal(frame) => frame,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Outdated => {
                self.surface.configure(&self.device, &self.config);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Lost => return Err(RenderError::Lost("lost")),
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(RenderError::Lost("validation error"));
            }
        };
        self.queue
            .write_buffer(&self.globals_buffer, 0, bytemuck::bytes_of(&self.globals));
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        {
            let (target, resolve) = match &self.msaa_view {
                Some(msaa) => (msaa, Some(&view)),
                None => (&view, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: resolve,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(self.background),
                        store: if resolve.is_some() {
                            wgpu::StoreOp::Discard
                        } else {
                            wgpu::StoreOp::Store
                        },
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.bind_group, &[]);
            if self.opaque_count > 0 {
                pass.set_pipeline(&self.solid_opaque);
                pass.set_vertex_buffer(0, self.solid_template.slice(..));
                pass.set_vertex_buffer(1, self.solids.buffer.slice(..));
                pass.set_index_buffer(self.solid_indices.slice(..), wgpu::IndexFormat::Uint16);
                pass.draw_indexed(0..self.solid_index_count, 0, 0..self.opaque_count);
            }
            if self.mesh_opaque_count > 0 {
                pass.set_pipeline(&self.mesh_opaque);
                pass.set_vertex_buffer(0, self.mesh.buffer.slice(..));
                pass.draw(0..self.mesh_opaque_count, 0..1);
            }
            if self.hair_count > 0 {
                pass.set_pipeline(&self.hair_pipeline);
                pass.set_vertex_buffer(0, self.hair.buffer.slice(..));
                pass.draw(0..self.hair_count, 0..1);
            }
            if self.line_opaque_count > 0 {
                pass.set_pipeline(&self.line_opaque);
                pass.set_vertex_buffer(0, self.line_template.slice(..));
                pass.set_vertex_buffer(1, self.lines.buffer.slice(..));
                pass.draw(0..6, 0..self.line_opaque_count);
            }
            if self.line_count > self.line_opaque_count {
                pass.set_pipeline(&self.line_pipeline);
                pass.set_vertex_buffer(0, self.line_template.slice(..));
                pass.set_vertex_buffer(1, self.lines.buffer.slice(..));
                pass.draw(0..6, self.line_opaque_count..self.line_count);
            }
            if self.mesh_blend_count > 0 {
                pass.set_pipeline(&self.mesh_blend);
                pass.set_vertex_buffer(0, self.mesh.buffer.slice(..));
                let start = self.mesh_opaque_count;
                pass.draw(start..start + self.mesh_blend_count, 0..1);
            }
            if self.blend_count > 0 {
                pass.set_pipeline(&self.solid_blend);
                pass.set_vertex_buffer(0, self.solid_template.slice(..));
                pass.set_vertex_buffer(1, self.solids.buffer.slice(..));
                pass.set_index_buffer(self.solid_indices.slice(..), wgpu::IndexFormat::Uint16);
                let start = self.opaque_count;
                pass.draw_indexed(
                    0..self.solid_index_count,
                    0,
                    start..start + self.blend_count,
                );
            }
        }
        self.queue.submit([encoder.finish()]);
        self.queue.present(frame);
        Ok(true)
    }
}

/// Builds the pipelines, which share everything but their state.
struct Pipelines<'a> {
    device: &'a wgpu::Device,
    layout: &'a wgpu::PipelineLayout,
    shader: &'a wgpu::ShaderModule,
    format: wgpu::TextureFormat,
    sample_count: u32,
}

impl Pipelines<'_> {
    fn solid(&self, blend: bool) -> wgpu::RenderPipeline {
        let template = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SolidVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32],
        };
        let instance = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SolidInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![2 => Float32x4, 3 => Float32x4, 4 => Float32x4],
        };
        self.build(
            if blend {
                "translucent solids"
            } else {
                "opaque solids"
            },
            ("vs_solid", "fs_solid"),
            &[Some(template), Some(instance)],
            Some(wgpu::Face::Back),
            !blend,
            blend,
        )
    }

    fn mesh(&self, blend: bool) -> wgpu::RenderPipeline {
        let vertex = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
        };
        self.build(
            if blend {
                "translucent triangles"
            } else {
                "opaque triangles"
            },
            ("vs_mesh", "fs_mesh"),
            &[Some(vertex)],
            None,
            !blend,
            blend,
        )
    }

    fn lines(&self, blend: bool) -> wgpu::RenderPipeline {
        let template = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x2],
        };
        let instance = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![1 => Float32x4, 2 => Float32x4, 3 => Float32x4],
        };
        self.build(
            if blend { "lines" } else { "opaque lines" },
            ("vs_line", "fs_line"),
            &[Some(template), Some(instance)],
            None,
            false,
            blend,
        )
    }

    fn build(
        &self,
        label: &str,
        (vs, fs): (&str, &str),
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        cull_mode: Option<wgpu::Face>,
        depth_write: bool,
        blend: bool,
    ) -> wgpu::RenderPipeline {
        self.build_with(
            label,
            (vs, fs),
            buffers,
            (wgpu::PrimitiveTopology::TriangleList, cull_mode),
            depth_write,
            blend,
        )
    }

    fn hairlines(&self) -> wgpu::RenderPipeline {
        let vertex = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
        };
        self.build_with(
            "hairlines",
            ("vs_mesh", "fs_hair"),
            &[Some(vertex)],
            (wgpu::PrimitiveTopology::LineList, None),
            false,
            false,
        )
    }

    fn build_with(
        &self,
        label: &str,
        (vs, fs): (&str, &str),
        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
        (topology, cull_mode): (wgpu::PrimitiveTopology, Option<wgpu::Face>),
        depth_write: bool,
        blend: bool,
    ) -> wgpu::RenderPipeline {
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(self.layout),
                vertex: wgpu::VertexState {
                    module: self.shader,
                    entry_point: Some(vs),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode,
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: self.sample_count,
                    ..wgpu::MultisampleState::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: self.shader,
                    entry_point: Some(fs),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: self.format,
                        blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
    }
}

/// The depth buffer and, with multisampling, the colour buffer to resolve.
fn attachments(
    device: &wgpu::Device,
    config: &wgpu::SurfaceConfiguration,
    sample_count: u32,
) -> (wgpu::TextureView, Option<wgpu::TextureView>) {
    let texture = |label, format| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: config.width,
                    height: config.height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&wgpu::TextureViewDescriptor::default())
    };
    let depth = texture("depth", DEPTH_FORMAT);
    let msaa = (sample_count > 1).then(|| texture("multisampled colour", config.format));
    (depth, msaa)
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

fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
