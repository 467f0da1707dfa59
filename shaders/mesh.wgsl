// Lit surfaces (bodies, skin, bones, arrows): smooth normals, optional scalar colormap.

struct Object {
    color: vec4<f32>,
    // x > 0.5: colour from the scalar through the colormap.
    flags: vec4<f32>,
};
@group(1) @binding(0) var<uniform> object: Object;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) scalar: f32,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) t: f32,
};

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var out: VsOut;
    out.clip = g.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    let span = g.scalar_range.y - g.scalar_range.x;
    out.t = clamp((v.scalar - g.scalar_range.x) / span, 0.0, 1.0);
    return out;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Two-sided: a face seen from behind is lit as seen from its other side.
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    var base = object.color.rgb;
    if (object.flags.x > 0.5) {
        let u = in.t * (255.0 / 256.0) + 0.5 / 256.0;
        base = textureSampleLevel(colormap_tex, linear_sampler, vec2<f32>(u, 0.5), 0.0).rgb;
    }
    let visibility = key_light_visibility(in.world, n);
    return vec4<f32>(shade(base, n, in.world, visibility), object.color.a);
}
