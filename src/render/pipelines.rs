//! Bind group layouts, samplers and render pipelines, created once per renderer.

use wgpu::util::DeviceExt;

/// Samples per pixel of the frame (anti-aliasing).
pub const MSAA_SAMPLES: u32 = 4;
/// Depth format of the frame and the shadow maps.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Side of the key light's shadow map, texels.
pub const SHADOW_MAP_SIZE: u32 = 2048;
/// Format of the ground's under-map (heights as depth values, in a colour texture).
pub const UNDER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// Side of the ground's under-map, texels.
pub const UNDER_MAP_SIZE: u32 = 512;

const COMMON: &str = include_str!("../../shaders/common.wgsl");

/// Vertex stride of lit surfaces: position and normal, 6 × f32.
pub const SURFACE_STRIDE: u64 = 24;

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
    /// Gradient background.
    pub background: wgpu::RenderPipeline,
    /// Ground plane.
    pub ground: wgpu::RenderPipeline,
    /// Opaque lit surfaces.
    pub opaque: wgpu::RenderPipeline,
    /// Translucent lit surfaces (blended, no depth write, back faces culled).
    pub translucent: wgpu::RenderPipeline,
    /// Wireframes.
    pub lines: wgpu::RenderPipeline,
    /// Screen-space images (the legend).
    pub overlay: wgpu::RenderPipeline,
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

const SURFACE_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
const SCALAR_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![2 => Float32];
const POSITION_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![0 => Float32x3];

fn surface_buffers() -> [Option<wgpu::VertexBufferLayout<'static>>; 2] {
    [
        Some(wgpu::VertexBufferLayout {
            array_stride: SURFACE_STRIDE,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &SURFACE_ATTRIBUTES,
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: 4,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &SCALAR_ATTRIBUTES,
        }),
    ]
}

/// How a pipeline treats depth and colour.
struct Style {
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
    blend: Option<wgpu::BlendState>,
    cull: Option<wgpu::Face>,
    topology: wgpu::PrimitiveTopology,
}

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
        let layout = |groups: &[&wgpu::BindGroupLayout]| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> =
                groups.iter().map(|g| Some(*g)).collect();
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: None,
                bind_group_layouts: &groups,
                immediate_size: 0,
            })
        };
        let scene_layout = layout(&[&globals_layout, &object_layout]);
        let globals_only = layout(&[&globals_layout]);
        let module = |label: &str, source: String| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
        };
        let mesh = module(
            "mesh",
            format!("{COMMON}\n{}", include_str!("../../shaders/mesh.wgsl")),
        );
        let lines = module(
            "lines",
            format!("{COMMON}\n{}", include_str!("../../shaders/lines.wgsl")),
        );
        let ground = module(
            "ground",
            format!("{COMMON}\n{}", include_str!("../../shaders/ground.wgsl")),
        );
        let background = module(
            "background",
            format!(
                "{COMMON}\n{}",
                include_str!("../../shaders/background.wgsl")
            ),
        );
        let overlay = module("overlay", include_str!("../../shaders/overlay.wgsl").into());
        let shadow = module("shadow", include_str!("../../shaders/shadow.wgsl").into());

        let alpha = Some(wgpu::BlendState::ALPHA_BLENDING);
        let color_pipeline = |label: &str,
                              layout: &wgpu::PipelineLayout,
                              module: &wgpu::ShaderModule,
                              buffers: &[Option<wgpu::VertexBufferLayout>],
                              style: Style| {
            let targets = [Some(wgpu::ColorTargetState {
                format,
                blend: style.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: style.topology,
                    cull_mode: style.cull,
                    front_face: wgpu::FrontFace::Ccw,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(style.depth_write),
                    depth_compare: Some(style.depth_compare),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: MSAA_SAMPLES,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let tri = wgpu::PrimitiveTopology::TriangleList;
        let always = wgpu::CompareFunction::Always;
        let less = wgpu::CompareFunction::Less;
        let flat = |depth_write, depth_compare, blend| Style {
            depth_write,
            depth_compare,
            blend,
            cull: None,
            topology: tri,
        };
        let background = color_pipeline(
            "background",
            &globals_only,
            &background,
            &[],
            flat(false, always, None),
        );
        let ground = color_pipeline(
            "ground",
            &globals_only,
            &ground,
            &[],
            flat(false, always, alpha),
        );
        let opaque = color_pipeline(
            "opaque",
            &scene_layout,
            &mesh,
            &surface_buffers(),
            flat(true, less, None),
        );
        let translucent = color_pipeline(
            "translucent",
            &scene_layout,
            &mesh,
            &surface_buffers(),
            Style {
                depth_write: false,
                depth_compare: less,
                blend: alpha,
                cull: Some(wgpu::Face::Back),
                topology: tri,
            },
        );
        let position_only = [Some(wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &POSITION_ATTRIBUTES,
        })];
        let lines = color_pipeline(
            "lines",
            &scene_layout,
            &lines,
            &position_only,
            Style {
                depth_write: false,
                depth_compare: wgpu::CompareFunction::LessEqual,
                blend: alpha,
                cull: None,
                topology: wgpu::PrimitiveTopology::LineList,
            },
        );
        let overlay_pipeline_layout = layout(&[&overlay_layout]);
        let overlay = color_pipeline(
            "overlay",
            &overlay_pipeline_layout,
            &overlay,
            &[],
            flat(false, always, alpha),
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
            background,
            ground,
            opaque,
            translucent,
            lines,
            overlay,
            shadow,
            under,
        }
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
