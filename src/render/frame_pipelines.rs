//! The render pipelines of the frame itself (background, ground, surfaces, lines, the legend's
//! overlay) for one number of samples per pixel: anti-aliased for the frame shown at rest, one
//! sample for the draft drawn while the view changes fast.

use super::formats::{pipeline_layout, DEPTH_FORMAT, SURFACE_STRIDE};

const COMMON: &str = include_str!("../../shaders/common.wgsl");

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

/// The frame's pipelines at one number of samples per pixel.
pub struct FramePipelines {
    /// Samples per pixel of the targets they draw into.
    pub samples: u32,
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
}

impl FramePipelines {
    /// The pipelines for colour targets of `format` with `samples` per pixel, on the bind group
    /// layouts of the frame's uniforms, of an object and of the overlay.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        samples: u32,
        (globals_layout, object_layout, overlay_layout): (
            &wgpu::BindGroupLayout,
            &wgpu::BindGroupLayout,
            &wgpu::BindGroupLayout,
        ),
    ) -> Self {
        let layout = |groups: &[&wgpu::BindGroupLayout]| pipeline_layout(device, groups);
        let scene_layout = layout(&[globals_layout, object_layout]);
        let globals_only = layout(&[globals_layout]);
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
                    count: samples,
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
        let overlay_pipeline_layout = layout(&[overlay_layout]);
        let overlay = color_pipeline(
            "overlay",
            &overlay_pipeline_layout,
            &overlay,
            &[],
            flat(false, always, alpha),
        );

        FramePipelines {
            samples,
            background,
            ground,
            opaque,
            translucent,
            lines,
            overlay,
        }
    }
}
