// Shared by the scene shaders: per-frame globals, shadow maps, colormap, lighting.
// Included before mesh.wgsl, lines.wgsl, ground.wgsl and background.wgsl. World z is up.

struct Globals {
    view_proj: mat4x4<f32>,
    // Orthographic view of the key light (shadow map).
    light_view_proj: mat4x4<f32>,
    // Orthographic view from the ground up (height above ground of the lowest surface).
    under_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // Unit vectors towards the key, fill and rim lights.
    key_dir: vec4<f32>,
    fill_dir: vec4<f32>,
    rim_dir: vec4<f32>,
    // Scalar range of the colormap: min, max.
    scalar_range: vec4<f32>,
    // Ground: height, half side, centre x, centre y.
    ground: vec4<f32>,
    sky_top: vec4<f32>,
    sky_bottom: vec4<f32>,
    // Key shadow map size (texels), under-map size (texels), scene radius (m), under-map depth range (m).
    params: vec4<f32>,
    // Grid spacing (m), contact-occlusion reach (m), half width of the shadow filter (taps:
    // 2 for 5×5, 0 for one in a draft), contact-occlusion samples (24; 8 in a draft).
    extra: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
@group(0) @binding(3) var under_map: texture_2d<f32>;
@group(0) @binding(4) var colormap_tex: texture_2d<f32>;
@group(0) @binding(5) var linear_sampler: sampler;

// Fraction of the key light reaching `world` (1 = lit): 5×5 percentage-closer filtering of the
// shadow map (one tap in a draft: `g.extra.z`), each tap itself bilinearly filtered, for a soft
// penumbra. The point is pushed along its normal by a small fraction of the scene to avoid
// self-shadowing acne.
fn key_light_visibility(world: vec3<f32>, normal: vec3<f32>) -> f32 {
    let p = g.light_view_proj * vec4<f32>(world + normal * (g.params.z * 0.006), 1.0);
    let uv = vec2<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5);
    let texel = 1.0 / g.params.x;
    let half = i32(g.extra.z);
    var lit = 0.0;
    for (var j = -half; j <= half; j++) {
        for (var i = -half; i <= half; i++) {
            let o = vec2<f32>(f32(i), f32(j)) * (1.6 * texel);
            lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + o, p.z - 0.0015);
        }
    }
    let taps = f32((2 * half + 1) * (2 * half + 1));
    let inside = all(uv > vec2<f32>(0.0)) && all(uv < vec2<f32>(1.0)) && p.z < 1.0;
    return select(1.0, lit / taps, inside);
}

// Hemisphere ambient: sky colour from above, warm bounce from the ground below.
fn ambient(n: vec3<f32>) -> vec3<f32> {
    let sky = vec3<f32>(0.62, 0.68, 0.78);
    let bounce = vec3<f32>(0.36, 0.33, 0.30);
    return mix(bounce, sky, n.z * 0.5 + 0.5);
}

// Three-point lighting of a surface of colour `base` with unit normal `n` facing the viewer.
fn shade(base: vec3<f32>, n: vec3<f32>, world: vec3<f32>, visibility: f32) -> vec3<f32> {
    let v = normalize(g.eye.xyz - world);
    let key = max(dot(n, g.key_dir.xyz), 0.0) * visibility;
    let fill = max(dot(n, g.fill_dir.xyz), 0.0);
    let rim = pow(1.0 - max(dot(n, v), 0.0), 2.5) * max(dot(n, g.rim_dir.xyz) + 0.3, 0.0);
    let h = normalize(g.key_dir.xyz + v);
    let spec = pow(max(dot(n, h), 0.0), 40.0) * 0.22 * visibility;
    let light = ambient(n) * 0.42 + key * vec3<f32>(1.0, 0.96, 0.9) * 0.95
        + fill * vec3<f32>(0.55, 0.62, 0.75) * 0.32;
    return base * light + vec3<f32>(spec) + rim * vec3<f32>(0.35, 0.38, 0.45) * 0.5;
}
