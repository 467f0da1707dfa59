// A screen-space image (the legend) laid over the frame with its alpha.

struct Rect {
    // Left, top, right, bottom in normalised device coordinates.
    ndc: vec4<f32>,
};
@group(0) @binding(0) var<uniform> rect: Rect;
@group(0) @binding(1) var image: texture_2d<f32>;
@group(0) @binding(2) var image_sampler: sampler;

struct OverlayOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> OverlayOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 1.0), vec2<f32>(0.0, 1.0),
    );
    let c = corners[i];
    var out: OverlayOut;
    out.clip = vec4<f32>(mix(rect.ndc.x, rect.ndc.z, c.x), mix(rect.ndc.y, rect.ndc.w, c.y), 0.0, 1.0);
    out.uv = c;
    return out;
}

@fragment
fn fs_main(in: OverlayOut) -> @location(0) vec4<f32> {
    return textureSampleLevel(image, image_sampler, in.uv, 0.0);
}
