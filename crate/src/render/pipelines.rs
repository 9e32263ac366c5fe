//! The render pipelines (one per kind of primitive and blending), the
//! uniforms they share and their bind group.

use std::borrow::Cow;

use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::geometry::{ClipVertex, ShadedVertex};
use super::gpu::DEPTH_FORMAT;

/// Uniforms shared by every pipeline (layout mirrors `Globals` in the shader).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(super) struct Globals {
    pub view_proj: [[f32; 4]; 4],
    pub to_camera: [f32; 4],
    pub key_light: [f32; 4],
    pub viewport: [f32; 4],
}

/// Every pipeline, and the uniform buffer they read.
#[derive(Debug)]
pub(super) struct Pipelines {
    pub globals_buffer: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
    pub solid_opaque: wgpu::RenderPipeline,
    pub solid_blend: wgpu::RenderPipeline,
    pub line_blend: wgpu::RenderPipeline,
    pub line_opaque: wgpu::RenderPipeline,
    pub hair: wgpu::RenderPipeline,
    pub mesh_opaque: wgpu::RenderPipeline,
    pub mesh_blend: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Compiles the shader and builds every pipeline for a `format` target
    /// with `sample_count` samples; the uniforms start as `globals`.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        sample_count: u32,
        globals: &Globals,
    ) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("playground shader"),
            source: wgpu::ShaderSource::Wgsl(Cow::Borrowed(include_str!("shader.wgsl"))),
        });
        let globals_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("globals"),
            contents: bytemuck::bytes_of(globals),
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
        let builder = Builder {
            device,
            layout: &layout,
            shader: &shader,
            format,
            sample_count,
        };
        Self {
            globals_buffer,
            bind_group,
            solid_opaque: builder.solid(false),
            solid_blend: builder.solid(true),
            line_blend: builder.lines(true),
            line_opaque: builder.lines(false),
            hair: builder.hairlines(),
            mesh_opaque: builder.mesh(false),
            mesh_blend: builder.mesh(true),
        }
    }
}

/// Builds the pipelines, which share everything but their state.
struct Builder<'a> {
    device: &'a wgpu::Device,
    layout: &'a wgpu::PipelineLayout,
    shader: &'a wgpu::ShaderModule,
    format: wgpu::TextureFormat,
    sample_count: u32,
}

impl Builder<'_> {
    fn solid(&self, blend: bool) -> wgpu::RenderPipeline {
        let vertex = shaded_layout();
        self.build(
            if blend {
                "translucent solids"
            } else {
                "opaque solids"
            },
            ("vs_world", "fs_color"),
            &[Some(vertex)],
            Some(wgpu::Face::Back),
            !blend,
            blend,
        )
    }

    fn mesh(&self, blend: bool) -> wgpu::RenderPipeline {
        let vertex = shaded_layout();
        self.build(
            if blend {
                "translucent triangles"
            } else {
                "opaque triangles"
            },
            ("vs_world", "fs_color"),
            &[Some(vertex)],
            None,
            !blend,
            blend,
        )
    }

    fn lines(&self, blend: bool) -> wgpu::RenderPipeline {
        let vertex = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<ClipVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4],
        };
        self.build(
            if blend { "lines" } else { "opaque lines" },
            ("vs_clip", "fs_color"),
            &[Some(vertex)],
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
        let vertex = shaded_layout();
        self.build_with(
            "hairlines",
            ("vs_world", "fs_color"),
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

/// The layout of a lit vertex in world space (position, colour).
fn shaded_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRIBUTES: [wgpu::VertexAttribute; 2] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4];
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<ShadedVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &ATTRIBUTES,
    }
}
