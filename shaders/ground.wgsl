// The ground plane: a soft grid fading out at its edges, the key light's soft shadow, and
// contact occlusion from the under-map (dark where a surface comes close to the ground).

struct GroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> GroundOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[i];
    var out: GroundOut;
    out.world = vec3<f32>(g.ground.zw + c * g.ground.y, g.ground.x);
    out.clip = g.view_proj * vec4<f32>(out.world, 1.0);
    return out;
}

// Share of the sky hidden near `world` by surfaces just above the ground: the under-map holds,
// per texel, the height above the ground of the lowest surface over it.
fn contact_occlusion(world: vec3<f32>) -> f32 {
    let p = g.under_view_proj * vec4<f32>(world, 1.0);
    let uv = vec2<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5);
    let size = g.params.y;
    let reach = g.extra.y;
    let n = i32(g.extra.w);
    var occ = 0.0;
    var weight = 0.0;
    for (var k = 0; k < n; k++) {
        // Vogel disk: radius √((k + ½)/n), golden-angle turns.
        let r = sqrt((f32(k) + 0.5) / f32(n));
        let a = f32(k) * 2.39996;
        let o = vec2<f32>(cos(a), sin(a)) * r * 0.11;
        let tc = clamp(vec2<i32>((uv + o) * size), vec2<i32>(0), vec2<i32>(i32(size) - 1));
        let h = textureLoad(under_map, tc, 0).r * g.params.w;
        let w = 1.0 - 0.5 * r;
        occ += w * (1.0 - smoothstep(0.0, reach, h));
        weight += w;
    }
    return occ / weight;
}

@fragment
fn fs_main(in: GroundOut) -> @location(0) vec4<f32> {
    let d = length(in.world.xy - g.ground.zw) / g.ground.y;
    let coord = in.world.xy / g.extra.x;
    let cell = abs(fract(coord - 0.5) - 0.5) / max(fwidth(coord), vec2<f32>(1e-6));
    let line = 1.0 - min(min(cell.x, cell.y), 1.0);
    let base = vec3<f32>(0.56, 0.555, 0.54) * (1.0 - 0.16 * line);
    let n = vec3<f32>(0.0, 0.0, 1.0);
    let visibility = key_light_visibility(in.world, n);
    let occlusion = contact_occlusion(in.world);
    let key = max(g.key_dir.z, 0.0) * visibility;
    let lit = base * (ambient(n) * 0.5 * (1.0 - 0.85 * occlusion)
        + key * vec3<f32>(1.0, 0.96, 0.9) * 0.8 * (1.0 - 0.5 * occlusion));
    let alpha = 1.0 - smoothstep(0.5, 1.0, d);
    return vec4<f32>(lit, alpha);
}
