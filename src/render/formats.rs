//! What every pipeline of the renderer shares: the depth format, the lit surfaces' vertex
//! stride, how a pipeline layout is made.

/// Depth format of the frame and the shadow maps.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Vertex stride of lit surfaces: position and normal, 6 × f32.
pub const SURFACE_STRIDE: u64 = 24;

/// A pipeline layout of the bind group layouts `groups`, in order.
pub(super) fn pipeline_layout(
    device: &wgpu::Device,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().map(|g| Some(*g)).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &groups,
        immediate_size: 0,
    })
}
