//! The wgpu renderer of the playground (wasm32 only, feature `render`).
//!
//! It knows nothing of robots: each frame the caller describes a [`Drawing`]
//! (tapered capsules and spheres with simple shading, lines of a given
//! width on screen, flat triangles, a ground grid) and a [`Camera`], and the renderer
//! draws them into an HTML canvas through WebGPU, or WebGL2 where WebGPU is
//! missing. The shape follows the wgpu examples: [`Renderer::new`] (async),
//! [`Renderer::resize`], [`Renderer::update`], [`Renderer::render`].
//!
//! | file | what it holds |
//! |---|---|
//! | `mod.rs` | [`Renderer`]: update (uniforms, upload) and the render pass |
//! | `gpu.rs` | surface and device setup: the canvas or its `OffscreenCanvas`, backends, adapter, device, surface format, multisampling, attachments |
//! | `pipelines.rs` | the uniforms, their bind group, one pipeline per primitive and blending |
//! | `buffers.rs` | the per-frame vertex, index and instance buffers (opaque first, translucent back to front), the solids' level of detail |
//! | `solids.rs` | capsules and spheres placed, lit and back-face culled on the CPU (and their triangles inside opaque ones left out, `view::occlusion`), drawn as one list of triangles |
//! | `flat.rs` | lines (as quads in clip space), flat triangles and the grid, lit on the CPU |
//! | `geometry.rs` | the vertex layouts |
//! | `shader.wgsl` | the shaders |
//!
//! Colours are sRGB-encoded in the scene; the renderer picks a non-sRGB
//! surface format when one is offered and encodes on the CPU as it lights
//! each vertex, or lets the hardware encode into an sRGB format, so a colour
//! reads the same on both backends. The shaders only place the vertices.
//!
//! Draw order: opaque solids and opaque triangles (depth written), lines
//! (depth tested, not written), then translucent triangles and translucent
//! solids, each sorted back to front (blended, depth tested, not written),
//! so distance lines stay visible inside volumes and behind a glassy plane.
//!
//! Level of detail: each capsule or sphere is drawn with the fewest sectors
//! around its axis that keep its outline within 0.5 px of the true circle,
//! from its radius on screen (1 px on a software rasteriser), from 48
//! triangles for a node a few pixels across up (`view::tessellation`),
//! about half of them facing the eye. A software rasteriser spends its time
//! per triangle (about 2 µs on SwiftShader) and per pixel rather than per
//! draw: the solids are placed, lit and culled on the CPU (`solids.rs`) and
//! reach it as two indexed draws of front faces, not one instance each.
//!
//! Cost on headless Chromium's SwiftShader (WebGPU, 1280×800, `npm run
//! bench -- --frames`):
//! - placing, lighting and culling on the CPU took the GPU process's time
//!   per frame in `human-panda` from 38.1 to about 27 ms on the machine of
//!   2026-11-25 (31 242 to 14 713 triangles), the iiwa 14 with its
//!   simplified meshes from 53.9 to 27–29 ms; the coarser solids of a
//!   software rasteriser took planar-transition from 50.4 to 56.9 fps;
//! - on a machine about half as fast (2026-11-27) a cleared canvas of the
//!   view's size alone costs about 25 ms; a drawing buffer smaller than the
//!   view saves little, the browser then scaling it (a quarter of the
//!   pixels saved about 9 ms, three quarters nothing measurable);
//! - there, a level of detail per sector count instead of three fixed
//!   levels took `human-panda`'s triangles from 7 141 to 4 114 and won
//!   every round of an interleaved A/B in the 3D examples (human-panda 35.1
//!   against 31.6 fps, lwr4-elbow 46.5 against 41.9); the 2D examples,
//!   whose large circles keep their sectors, were unchanged.
//!
//! - triangles inside an opaque solid left out (`view::occlusion`):
//!   human-panda 4 310 → 3 512 triangles, human-reach 4 116 → 3 432; link
//!   meshes drawn at the level of detail their size on screen allows
//!   (`view::meshes`): the iiwa 14 in the human-panda scene 7 729 → 1 914
//!   triangles, 32.5 → 40.8 fps (A/B, three rounds, all won); its outline
//!   unchanged, some of its shading a few levels different;
//! - most of the cleared canvas's cost is the browser compositing the
//!   canvas (it grows with the canvas's area on the page, not with its
//!   drawing buffer). Drawn through its `OffscreenCanvas` (`gpu.rs`,
//!   `CanvasOptions::offscreen`) the canvas costs the GPU process 5–13 ms
//!   less a frame: lwr4-elbow 37.5 → 51.4 fps, chattering 30.8 → 37.1,
//!   the iiwa 14 31.2 → 41.2 (A/B, three rounds, all won, in a slow hour);
//!   on WebGL2 chattering 30.0 → 41.4.
//! - where a frame's time goes, from a Chromium trace of `human-panda`
//!   (2 660 triangles): the GPU process's main thread runs the frame's
//!   WebGPU commands and then waits for SwiftShader to finish the render
//!   pass, reads the picture back and uploads it for the compositor (Skia
//!   allocates a fresh staging buffer of the canvas's size each frame,
//!   about 2 ms), then composites the page (4.5–7 ms). The waiting and
//!   copying take 4.2 ms a frame with a cleared canvas and 10–13 ms in
//!   `human-panda`; of the difference, the solids' triangles account for
//!   about 1.3 µs each (1 000 fewer saved 1–1.7 ms), the floor plane's
//!   blended pixels for 0.7–1.7 ms. Ray-cast impostors (a box per solid,
//!   its surface found per pixel) cost far more there: sixteen of them
//!   took a cleared canvas from about 27 to 39 ms of the GPU process.
//! - what a cleared canvas costs is the browser showing each new picture,
//!   not the render pass: a canvas only acquired (`getCurrentTexture`, no
//!   pass) costs as much as a cleared one, a depth attachment nothing
//!   measurable; the cost grows with the pixels shown (about 4 ms a frame
//!   and 38 ns a pixel; a drawing buffer smaller than the view costs more,
//!   the browser then scaling it). In the playground, turning off meshes,
//!   volumes, nodes or grid changed neither frame rate nor GPU time
//!   beyond the noise; the view's area is the lever (`web/style.js`).
//!
//! The README gives the table, with the cleared canvas as its reference row.

mod buffers;
mod flat;
mod geometry;
mod gpu;
mod pipelines;
mod solids;

use crate::view::{Camera, Drawing};

use buffers::{Buffers, Lens};
pub use gpu::CanvasOptions;
use gpu::Gpu;
use pipelines::{Globals, Pipelines};
use solids::{Roots, Shading};

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

/// Draws [`Drawing`]s into an HTML canvas with wgpu.
///
/// # Example (in an async wasm function)
/// ```ignore
/// let mut renderer = Renderer::new(canvas, BackendRequest::Auto, CanvasOptions::default()).await?;
/// renderer.resize(800, 600);
/// renderer.update(&scene, &camera);
/// renderer.render()?;
/// ```
#[derive(Debug)]
pub struct Renderer {
    gpu: Gpu,
    pipelines: Pipelines,
    buffers: Buffers,
    depth_view: wgpu::TextureView,
    msaa_view: Option<wgpu::TextureView>,
    background: wgpu::Color,
    globals: Globals,
    /// The table lit colours are encoded with.
    roots: Roots,
}

impl Renderer {
    /// Starts a renderer drawing into `canvas` with the backend `request`
    /// asks for, multisampled (4×) when `options.antialias` says so (`None`:
    /// unless the adapter is a software rasteriser such as SwiftShader,
    /// where multisampling halves the frame rate) and the adapter supports
    /// it, through the canvas's `OffscreenCanvas` with `options.offscreen`
    /// (where the browser can hand it over). The canvas keeps its size until
    /// [`Renderer::resize`].
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] when the browser has neither WebGPU nor
    /// WebGL2 (or not the one requested), [`RenderError::Surface`] when the
    /// canvas cannot get a context (for example it already has another one),
    /// [`RenderError::Device`], [`RenderError::NoFormat`].
    pub async fn new(
        canvas: web_sys::HtmlCanvasElement,
        request: BackendRequest,
        options: CanvasOptions,
    ) -> Result<Self, RenderError> {
        let gpu = Gpu::connect(canvas, request, options).await?;
        let globals = Globals {
            view_proj: glam::Mat4::IDENTITY.to_cols_array_2d(),
            to_camera: [0.0, 0.0, 1.0, 0.0],
            key_light: [0.0, 0.0, 1.0, 0.0],
            viewport: [
                gpu.config.width as f32,
                gpu.config.height as f32,
                if gpu.encode_srgb { 1.0 } else { 0.0 },
                0.0,
            ],
        };
        let pipelines = Pipelines::new(&gpu.device, gpu.config.format, gpu.sample_count, &globals);
        let buffers = Buffers::new(&gpu.device);
        let (depth_view, msaa_view) = gpu.attachments();
        Ok(Self {
            gpu,
            pipelines,
            buffers,
            depth_view,
            msaa_view,
            background: wgpu::Color::WHITE,
            globals,
            roots: Roots::default(),
        })
    }

    /// The backend actually drawing.
    #[must_use]
    pub fn backend(&self) -> Backend {
        self.gpu.backend
    }

    /// What the browser says the adapter is (may be empty or masked).
    #[must_use]
    pub fn adapter_name(&self) -> &str {
        &self.gpu.adapter_name
    }

    /// The colour format of the canvas, e.g. `Rgba8Unorm`.
    #[must_use]
    pub fn surface_format(&self) -> wgpu::TextureFormat {
        self.gpu.config.format
    }

    /// Samples per pixel (4 with multisampling, else 1).
    #[must_use]
    pub fn sample_count(&self) -> u32 {
        self.gpu.sample_count
    }

    /// Triangles the last uploaded scene draws: solids at their level of
    /// detail (the faces turned away from the eye left out), flat figures
    /// and line quads (grid hairlines not counted).
    #[must_use]
    pub fn triangles(&self) -> u64 {
        let n = self.buffers.counts;
        u64::from(n.solids + n.mesh_opaque + n.mesh_blend + n.lines) / 3
    }

    /// Triangles of the last uploaded scene's capsules and spheres at their
    /// level of detail, back faces included.
    #[must_use]
    pub fn solid_triangles(&self) -> u64 {
        self.buffers.solid_triangles()
    }

    /// Whether the adapter is a software rasteriser (SwiftShader, llvmpipe).
    #[must_use]
    pub fn is_software(&self) -> bool {
        self.gpu.software
    }

    /// Whether the renderer draws through the canvas's `OffscreenCanvas`.
    #[must_use]
    pub fn is_offscreen(&self) -> bool {
        self.gpu.offscreen
    }

    /// Drawing-buffer size in pixels.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (self.gpu.config.width, self.gpu.config.height)
    }

    /// Sets the drawing-buffer size (pixels; the canvas's `width` and
    /// `height` attributes follow, with an `OffscreenCanvas` once the frame
    /// is shown). Sizes are clamped to 1 ..= the device's
    /// maximum texture size; an unchanged size costs nothing.
    pub fn resize(&mut self, width: u32, height: u32) {
        if self.gpu.resize(width, height) {
            (self.depth_view, self.msaa_view) = self.gpu.attachments();
        }
    }

    /// Uploads `scene` as seen by `camera`; drawn by the next [`Renderer::render`].
    ///
    /// Translucent solids are sorted back to front from the camera's eye.
    pub fn update(&mut self, scene: &Drawing, camera: &Camera) {
        let (width, height) = self.size();
        let (width, height) = (width as f32, height as f32);
        let back = camera.backward();
        let key =
            (glam::Vec3::new(0.4, -0.3, 1.0).normalize() + 0.3 * back).normalize_or(glam::Vec3::Z);
        let encode = self.gpu.encode_srgb;
        self.globals = Globals {
            view_proj: camera.view_proj(width / height).to_cols_array_2d(),
            to_camera: [back.x, back.y, back.z, 0.0],
            key_light: [key.x, key.y, key.z, 0.0],
            viewport: [width, height, if encode { 1.0 } else { 0.0 }, 0.0],
        };
        let [r, g, b, _] = scene.background.map(|c| f64::from(c.clamp(0.0, 1.0)));
        // The clear colour is written as is: encode it like the shader does.
        let channel = |c: f64| if encode { c } else { srgb_to_linear(c) };
        self.background = wgpu::Color {
            r: channel(r),
            g: channel(g),
            b: channel(b),
            a: 1.0,
        };
        let shading = Shading {
            to_camera: back,
            key_light: key,
            encode,
            view_proj: camera.view_proj(width / height),
            half_px: 0.5 * glam::Vec2::new(width, height),
            roots: &self.roots,
        };
        self.buffers.upload(
            (&self.gpu.device, &self.gpu.queue),
            scene,
            &Lens::new(camera, height, self.gpu.software),
            &shading,
        );
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
        let gpu = &self.gpu;
        let frame = match gpu.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame)
            | wgpu::CurrentSurfaceTexture::Suboptimal(frame) => frame,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Outdated => {
                gpu.surface.configure(&gpu.device, &gpu.config);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Lost => return Err(RenderError::Lost("lost")),
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(RenderError::Lost("validation error"));
            }
        };
        gpu.queue.write_buffer(
            &self.pipelines.globals_buffer,
            0,
            bytemuck::bytes_of(&self.globals),
        );
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode_pass(&mut encoder, &view);
        gpu.queue.submit([encoder.finish()]);
        gpu.queue.present(frame);
        Ok(true)
    }

    /// The one render pass of a frame into `view` (through the multisampled
    /// buffer when there is one).
    fn encode_pass(&self, encoder: &mut wgpu::CommandEncoder, view: &wgpu::TextureView) {
        let (target, resolve) = match &self.msaa_view {
            Some(msaa) => (msaa, Some(view)),
            None => (view, None),
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
        pass.set_bind_group(0, &self.pipelines.bind_group, &[]);
        self.draw(&mut pass);
    }

    /// The draw calls, in the order the module docs give: opaque solids and
    /// triangles, the grid, lines, then translucent triangles and solids.
    fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        let (p, b, n) = (&self.pipelines, &self.buffers, self.buffers.counts);
        let solids = |pass: &mut wgpu::RenderPass<'_>, pipeline, range: std::ops::Range<u32>| {
            if range.is_empty() {
                return;
            }
            pass.set_pipeline(pipeline);
            pass.set_vertex_buffer(0, b.solid_vertices.buffer.slice(..));
            pass.set_index_buffer(b.solid_indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(range, 0, 0..1);
        };
        let vertices = |pass: &mut wgpu::RenderPass<'_>,
                        pipeline,
                        buffer: &wgpu::Buffer,
                        range: std::ops::Range<u32>| {
            if range.is_empty() {
                return;
            }
            pass.set_pipeline(pipeline);
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(range, 0..1);
        };
        let all_mesh = n.mesh_opaque + n.mesh_blend;
        solids(pass, &p.solid_opaque, 0..n.solid_opaque);
        vertices(pass, &p.mesh_opaque, &b.mesh.buffer, 0..n.mesh_opaque);
        vertices(pass, &p.hair, &b.hair.buffer, 0..n.hair);
        vertices(pass, &p.line_opaque, &b.lines.buffer, 0..n.line_opaque);
        vertices(pass, &p.line_blend, &b.lines.buffer, n.line_opaque..n.lines);
        vertices(pass, &p.mesh_blend, &b.mesh.buffer, n.mesh_opaque..all_mesh);
        solids(pass, &p.solid_blend, n.solid_opaque..n.solids);
    }
}

fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
