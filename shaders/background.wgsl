// Vertical gradient behind everything, from a fullscreen triangle.

struct BgOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> BgOut {
    let x = f32(i32(i & 1u) * 4 - 1);
    let y = f32(i32(i >> 1u) * 4 - 1);
    var out: BgOut;
    out.clip = vec4<f32>(x, y, 1.0, 1.0);
    out.uv = vec2<f32>(x * 0.5 + 0.5, y * 0.5 + 0.5);
    return out;
}

@fragment
fn fs_main(in: BgOut) -> @location(0) vec4<f32> {
    let t = smoothstep(0.0, 1.0, in.uv.y);
    let vignette = 1.0 - 0.12 * length(in.uv - vec2<f32>(0.5, 0.55));
    return vec4<f32>(mix(g.sky_bottom.rgb, g.sky_top.rgb, t) * vignette, 1.0);
}
