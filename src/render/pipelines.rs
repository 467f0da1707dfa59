//! Bind group layouts, samplers and render pipelines, created once per renderer.

use super::formats::pipeline_layout;
pub use super::formats::{DEPTH_FORMAT, SURFACE_STRIDE};
use super::frame_pipelines::FramePipelines;
use wgpu::util::DeviceExt;

/// Samples per pixel of the frame (anti-aliasing).
pub const MSAA_SAMPLES: u32 = 4;
/// Side of the key light's shadow map, texels.
pub const SHADOW_MAP_SIZE: u32 = 2048;
/// Format of the ground's under-map (heights as depth values, in a colour texture).
pub const UNDER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// Side of the ground's under-map, texels.
pub const UNDER_MAP_SIZE: u32 = 512;

/// All pipelines and layouts.
pub struct Pipelines {
    /// Group 0 of the scene pipelines: frame uniforms, shadow map, under-map, colormap.
    pub globals_layout: wgpu::BindGroupLayout,
    /// Group 1 of surfaces and lines: colour and flags.
    pub object_layout: wgpu::BindGroupLayout,
    /// Group 0 of the light views: one view-projection matrix.
    pub light_layout: wgpu::BindGroupLayout,
    /// Group 0 of the overlay: screen rectangle, image, sampler.
    pub overlay_layout: wgpu::BindGroupLayout,
    /// The frame's pipelines, anti-aliased ([`MSAA_SAMPLES`] per pixel).
    pub frame: FramePipelines,
    /// The colour format of the frame.
    pub format: wgpu::TextureFormat,
    /// Depth-only key-light shadow map.
    pub shadow: wgpu::RenderPipeline,
    /// Heights above the ground, seen from below.
    pub under: wgpu::RenderPipeline,
    /// Comparison sampler of the shadow map.
    pub shadow_sampler: wgpu::Sampler,
    /// Bilinear sampler (colormap).
    pub linear_sampler: wgpu::Sampler,
    /// Nearest sampler (legend, pixel-exact).
    pub nearest_sampler: wgpu::Sampler,
}

fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn sampler_entry(binding: u32, ty: wgpu::SamplerBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(ty),
        count: None,
    }
}

const POSITION_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![0 => Float32x3];

impl Pipelines {
    /// Creates everything for colour targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[
                uniform_entry(0, vf),
                texture_entry(1, wgpu::TextureSampleType::Depth),
                sampler_entry(2, wgpu::SamplerBindingType::Comparison),
                texture_entry(3, wgpu::TextureSampleType::Float { filterable: false }),
                texture_entry(4, wgpu::TextureSampleType::Float { filterable: true }),
                sampler_entry(5, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("object"),
            entries: &[uniform_entry(0, vf)],
        });
        let light_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("light"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX)],
        });
        let overlay_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("overlay"),
            entries: &[
                uniform_entry(0, wgpu::ShaderStages::VERTEX),
                texture_entry(1, wgpu::TextureSampleType::Float { filterable: true }),
                sampler_entry(2, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let layout = |groups: &[&wgpu::BindGroupLayout]| pipeline_layout(device, groups);
        let shadow = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shadow"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/shadow.wgsl").into()),
        });

        let frame = FramePipelines::new(
            device,
            format,
            MSAA_SAMPLES,
            (&globals_layout, &object_layout, &overlay_layout),
        );
        let shadow_layout = layout(&[&light_layout]);
        let position_at_stride = [Some(wgpu::VertexBufferLayout {
            array_stride: SURFACE_STRIDE,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &POSITION_ATTRIBUTES,
        })];
        let under = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("under"),
            layout: Some(&shadow_layout),
            vertex: wgpu::VertexState {
                module: &shadow,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &position_at_stride,
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shadow,
                entry_point: Some("fs_under"),
                compilation_options: Default::default(),
                targets: &[Some(UNDER_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let shadow = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("shadow"),
            layout: Some(&shadow_layout),
            vertex: wgpu::VertexState {
                module: &shadow,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &position_at_stride,
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: wgpu::DepthBiasState {
                    constant: 2,
                    slope_scale: 1.5,
                    clamp: 0.0,
                },
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let sampler = |label, filter, compare| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                mag_filter: filter,
                min_filter: filter,
                compare,
                ..Default::default()
            })
        };
        let linear = wgpu::FilterMode::Linear;
        Self {
            shadow_sampler: sampler("shadow", linear, Some(wgpu::CompareFunction::LessEqual)),
            linear_sampler: sampler("linear", linear, None),
            nearest_sampler: sampler("nearest", wgpu::FilterMode::Nearest, None),
            globals_layout,
            object_layout,
            light_layout,
            overlay_layout,
            frame,
            format,
            shadow,
            under,
        }
    }

    /// The frame's pipelines for `samples` per pixel, on the layouts of these (1: the draft
    /// frame drawn while the view changes fast, `Quality::Draft`).
    pub fn frame_pipelines(&self, device: &wgpu::Device, samples: u32) -> FramePipelines {
        FramePipelines::new(
            device,
            self.format,
            samples,
            (
                &self.globals_layout,
                &self.object_layout,
                &self.overlay_layout,
            ),
        )
    }

    /// A uniform buffer holding `bytes` and a bind group of `layout` on it (binding 0).
    pub fn uniform(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        bytes: &[u8],
    ) -> (wgpu::Buffer, wgpu::BindGroup) {
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        (buffer, group)
    }
}
