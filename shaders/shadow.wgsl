// Depth-only views of the scene for the key light's shadow map and the ground's under-map.

@group(0) @binding(0) var<uniform> light_view_proj: mat4x4<f32>;

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light_view_proj * vec4<f32>(position, 1.0);
}

// The under-map keeps depth in a colour texture (R16Float): GL cannot load texels of depth
// textures, every backend can load float colour texels.
@fragment
fn fs_under(@builtin(position) clip: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(clip.z, 0.0, 0.0, 1.0);
}
