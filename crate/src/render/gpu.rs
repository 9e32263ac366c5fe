//! Surface and device setup, apart from what is drawn: the wgpu instance for
//! the requested backends, the canvas surface, the adapter, the device, the
//! surface format and configuration, multisampling, and the depth and
//! multisampled colour attachments that follow the canvas size.
//!
//! With [`CanvasOptions::offscreen`] the surface is the canvas's
//! `OffscreenCanvas` (`transferControlToOffscreen`): the browser then takes
//! each frame straight to its compositor instead of through the page's
//! canvas layer. On Chromium's software compositor (SwiftShader, 1280×800)
//! that cost the GPU process about 4–7 ms less a frame: `human-panda`
//! 47.1 → 54.7 fps, `chattering` 56.4 → 59.7, `planar-transition` with the
//! view dragged 53.3 → 58.7 (interleaved, three rounds each; a bare
//! cleared canvas 28.4 → 22.8 ms). The canvas element then belongs to the
//! renderer: it can give no other context and its `width` and `height`
//! can no longer be set (they follow the surface, as before).

use wasm_bindgen::JsCast;

use super::{Backend, BackendRequest, RenderError};

/// How the renderer takes over its canvas.
#[derive(Clone, Copy, Debug, Default)]
pub struct CanvasOptions {
    /// 4× multisampling; `None`: on unless the adapter is a software
    /// rasteriser (SwiftShader, llvmpipe), where it halves the frame rate.
    pub antialias: Option<bool>,
    /// Draw through the canvas's `OffscreenCanvas` where the browser offers
    /// one (see the module docs); the element itself otherwise.
    pub offscreen: bool,
}

/// Format of the depth buffer.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// A configured canvas surface and the device drawing into it.
#[derive(Debug)]
pub(super) struct Gpu {
    pub surface: wgpu::Surface<'static>,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub config: wgpu::SurfaceConfiguration,
    pub backend: Backend,
    pub adapter_name: String,
    /// 4 with multisampling, else 1.
    pub sample_count: u32,
    /// Whether the shader encodes sRGB (the surface format is not sRGB).
    pub encode_srgb: bool,
    /// Whether the adapter is a software rasteriser (SwiftShader, llvmpipe).
    pub software: bool,
    /// Whether the surface is the canvas's `OffscreenCanvas`.
    pub offscreen: bool,
}

impl Gpu {
    /// Connects to `canvas` through the backends `request` allows; see
    /// [`super::Renderer::new`] for the options and the errors.
    pub async fn connect(
        canvas: web_sys::HtmlCanvasElement,
        request: BackendRequest,
        options: CanvasOptions,
    ) -> Result<Self, RenderError> {
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let (instance, surface, offscreen) =
            surface_for(canvas, request, options.offscreen).await?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::default(),
                force_fallback_adapter: false,
                compatible_surface: Some(&surface),
                apply_limit_buckets: false,
            })
            .await
            .map_err(|_| RenderError::NoAdapter {
                requested: request.missing(),
            })?;
        let info = adapter.get_info();
        let (adapter_name, software) = describe(&info);
        let backend = match info.backend {
            wgpu::Backend::BrowserWebGpu => Backend::WebGpu,
            _ => Backend::WebGl2,
        };
        let (device, queue) = request_device(&adapter).await?;
        let config = configure(&surface, &adapter, &device, (width, height))?;
        let antialias = options.antialias.unwrap_or(!software);
        let sample_count = sample_count(&adapter, config.format, antialias);
        Ok(Self {
            encode_srgb: !config.format.is_srgb(),
            surface,
            device,
            queue,
            config,
            backend,
            adapter_name,
            sample_count,
            software,
            offscreen,
        })
    }

    /// Sets the drawing-buffer size, clamped to 1 ..= the device's largest
    /// texture; `false` when the size did not change.
    pub fn resize(&mut self, width: u32, height: u32) -> bool {
        let max = self.device.limits().max_texture_dimension_2d.max(1);
        let (width, height) = (width.clamp(1, max), height.clamp(1, max));
        if (width, height) == (self.config.width, self.config.height) {
            return false;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
        true
    }

    /// The depth buffer and, with multisampling, the colour buffer to
    /// resolve, at the surface's size.
    pub fn attachments(&self) -> (wgpu::TextureView, Option<wgpu::TextureView>) {
        let texture = |label, format| {
            self.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: self.config.width,
                        height: self.config.height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: self.sample_count,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let depth = texture("depth", DEPTH_FORMAT);
        let msaa =
            (self.sample_count > 1).then(|| texture("multisampled colour", self.config.format));
        (depth, msaa)
    }
}

impl BackendRequest {
    /// The backends to ask wgpu for.
    fn backends(self) -> wgpu::Backends {
        match self {
            Self::Auto => wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL,
            Self::WebGpu => wgpu::Backends::BROWSER_WEBGPU,
            Self::WebGl2 => wgpu::Backends::GL,
        }
    }

    /// What the browser lacks when no adapter answers, in words.
    fn missing(self) -> &'static str {
        match self {
            Self::Auto => "neither WebGPU nor WebGL2",
            Self::WebGpu => "no WebGPU adapter",
            Self::WebGl2 => "no WebGL2",
        }
    }
}

/// The instance for `request`'s backends and the canvas's surface (its
/// `OffscreenCanvas` when `offscreen` asks for it and the browser can hand
/// it over; the flag returned says which).
async fn surface_for(
    canvas: web_sys::HtmlCanvasElement,
    request: BackendRequest,
    offscreen: bool,
) -> Result<(wgpu::Instance, wgpu::Surface<'static>, bool), RenderError> {
    let instance = instance_for(request.backends()).await;
    match offscreen.then(|| transfer(&canvas)).flatten() {
        Some(Ok(off)) => {
            let target = wgpu::SurfaceTarget::OffscreenCanvas(off.clone());
            match instance.create_surface(target) {
                Ok(surface) => Ok((instance, surface, true)),
                // A browser may offer WebGPU but not on an OffscreenCanvas:
                // with either backend allowed, WebGL2 on it.
                Err(_) if request == BackendRequest::Auto => {
                    let gl = instance_for(wgpu::Backends::GL).await;
                    let surface = gl
                        .create_surface(wgpu::SurfaceTarget::OffscreenCanvas(off))
                        .map_err(|e| surface_error(request, &e.to_string()))?;
                    Ok((gl, surface, true))
                }
                Err(e) => Err(surface_error(request, &e.to_string())),
            }
        }
        // Already handed over (to an earlier renderer) or holding a context:
        // the element itself, which works in the second case.
        Some(Err(reason)) => match instance.create_surface(wgpu::SurfaceTarget::Canvas(canvas)) {
            Ok(surface) => Ok((instance, surface, false)),
            // wgpu's message carries the browser's stack: the reason alone.
            Err(_) => Err(RenderError::Surface(format!(
                "its drawing could not be handed over ({reason}) nor drawn on directly; a canvas whose drawing an earlier viewer took cannot be drawn on again: give each viewer a canvas of its own"
            ))),
        },
        None => match instance.create_surface(wgpu::SurfaceTarget::Canvas(canvas)) {
            Ok(surface) => Ok((instance, surface, false)),
            Err(e) => Err(surface_error(request, &e.to_string())),
        },
    }
}

/// A wgpu instance for `backends` (WebGPU only where the browser has it).
async fn instance_for(backends: wgpu::Backends) -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    wgpu::util::new_instance_with_webgpu_detection(desc).await
}

/// The error for a canvas that gave no context: with WebGPU requested, a
/// failure means no WebGPU. Otherwise wgpu reports `canvas.getContext()
/// returned null; webgl2 not available …`: the browser has no WebGL2 (or
/// it is disabled).
fn surface_error(request: BackendRequest, message: &str) -> RenderError {
    let no_webgl2 = message.to_lowercase().contains("webgl2 not available");
    if request == BackendRequest::WebGpu || no_webgl2 {
        RenderError::NoAdapter {
            requested: request.missing(),
        }
    } else {
        RenderError::Surface(message.to_owned())
    }
}

/// The canvas's `OffscreenCanvas`: `None` where the browser has no
/// `transferControlToOffscreen`, the browser's reason where it refuses (the
/// canvas already has a context, or was handed over before).
fn transfer(
    canvas: &web_sys::HtmlCanvasElement,
) -> Option<Result<web_sys::OffscreenCanvas, String>> {
    let method = js_sys::Reflect::get(canvas, &"transferControlToOffscreen".into()).ok()?;
    if !method.is_function() {
        return None;
    }
    Some(canvas.transfer_control_to_offscreen().map_err(|e| {
        e.dyn_ref::<js_sys::Error>()
            .map_or_else(|| format!("{e:?}"), |e| String::from(e.message()))
    }))
}

/// The adapter's name as the browser gives it, and whether it is a software
/// rasteriser (where multisampling halves the frame rate).
fn describe(info: &wgpu::AdapterInfo) -> (String, bool) {
    let name = [
        info.name.as_str(),
        info.driver.as_str(),
        info.driver_info.as_str(),
    ]
    .into_iter()
    .filter(|s| !s.is_empty())
    .collect::<Vec<_>>()
    .join(" / ");
    let lower = name.to_lowercase();
    let software = info.device_type == wgpu::DeviceType::Cpu
        || ["swiftshader", "llvmpipe", "software", "lavapipe"]
            .iter()
            .any(|k| lower.contains(k));
    (name, software)
}

/// A device within WebGL2's limits; its uncaptured errors go to the console.
async fn request_device(
    adapter: &wgpu::Adapter,
) -> Result<(wgpu::Device, wgpu::Queue), RenderError> {
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
    Ok((device, queue))
}

/// Chooses the surface format and configures the surface at `size`.
///
/// A plain 8-bit format is preferred (the shader encodes sRGB); an sRGB one
/// (the hardware encodes) is accepted when nothing else is offered.
///
/// The canvas is composited as opaque. Premultiplied was measured too: on
/// a bare canvas on a page of its own it cost SwiftShader's GPU process
/// about 3 ms less a frame, but in the playground it cost 7–11 ms more
/// (planar-transition 45.7 against 56.9 fps, human-panda 33.4 against 41.3,
/// interleaved, four rounds), presumably because the compositor then
/// draws what lies beneath the canvas as well.
fn configure(
    surface: &wgpu::Surface<'static>,
    adapter: &wgpu::Adapter,
    device: &wgpu::Device,
    (width, height): (u32, u32),
) -> Result<wgpu::SurfaceConfiguration, RenderError> {
    let caps = surface.get_capabilities(adapter);
    let format = [
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::Bgra8Unorm,
    ]
    .into_iter()
    .find(|f| caps.formats.contains(f))
    .or_else(|| caps.formats.iter().copied().find(|f| !f.is_srgb()))
    .or_else(|| caps.formats.first().copied())
    .ok_or(RenderError::NoFormat)?;
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
    surface.configure(device, &config);
    Ok(config)
}

/// 4 when `antialias` asks for it and both the colour and the depth format
/// support it, else 1.
fn sample_count(adapter: &wgpu::Adapter, format: wgpu::TextureFormat, antialias: bool) -> u32 {
    let supports = |f| {
        adapter
            .get_texture_format_features(f)
            .flags
            .sample_count_supported(4)
    };
    if antialias && supports(format) && supports(DEPTH_FORMAT) {
        4
    } else {
        1
    }
}
