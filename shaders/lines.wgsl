// Wireframes: unlit lines, pulled slightly towards the eye so that they win over the surface
// they lie on.

struct Object {
    color: vec4<f32>,
    flags: vec4<f32>,
};
@group(1) @binding(0) var<uniform> object: Object;

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    // 0.3% of the way to the eye: far less than any element, enough to beat depth rounding.
    let pulled = mix(position, g.eye.xyz, 0.003);
    return g.view_proj * vec4<f32>(pulled, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return object.color;
}
