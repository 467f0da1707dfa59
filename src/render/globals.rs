//! Per-frame uniforms: camera, lights and their shadow views, colormap range, ground.

use super::camera::{Bounds, Camera};
use super::colormap::{guard_range, srgb_to_linear};
use super::draw_list::{Ground, Legend};
use super::pipelines::{SHADOW_MAP_SIZE, UNDER_MAP_SIZE};
use super::quality::Quality;
use glam::camera::rh::proj::directx::orthographic;
use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Vec3};

/// Unit vector towards the key light: high, from the front left of the default view, fixed in
/// the world so that orbiting the camera keeps the shadows in place.
pub fn key_direction() -> Vec3 {
    Vec3::new(-0.3, -0.9, 1.6).normalize()
}

/// The uniforms of one frame, laid out as `Globals` in `shaders/common.wgsl`.
pub struct FrameGlobals {
    /// The `Globals` block.
    pub globals: Vec<f32>,
    /// The key light's view-projection (shadow map).
    pub light_view_proj: Mat4,
    /// The view-projection from the ground up (under-map).
    pub under_view_proj: Mat4,
}

fn srgb(c: [f32; 3]) -> [f32; 4] {
    [
        srgb_to_linear(c[0]),
        srgb_to_linear(c[1]),
        srgb_to_linear(c[2]),
        1.0,
    ]
}

/// A view from `eye` towards `target` with a sensible up vector.
fn look(eye: Vec3, target: Vec3) -> Mat4 {
    let dir = (target - eye).normalize_or(Vec3::NEG_Z);
    let up = if dir.cross(Vec3::Z).length() < 1e-3 {
        Vec3::Y
    } else {
        Vec3::Z
    };
    look_at_mat4(eye, target, up)
}

/// How the lights' maps are sized and sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightSampling {
    /// Side of the key light's shadow map, texels.
    pub shadow_size: u32,
    /// Side of the ground's under-map, texels.
    pub under_size: u32,
    /// Half width of the shadow's filter, taps: 2 for 5×5.
    pub shadow_half_width: u32,
    /// Samples of the ground's contact occlusion.
    pub occlusion_samples: u32,
}

impl LightSampling {
    /// The sampling of a frame at `quality`: a draft takes one shadow tap (bilinear) instead of
    /// 25 and 8 occlusion samples instead of 24 — most of what each pixel costs on a software
    /// renderer (the shading is the same).
    pub fn of(quality: Quality) -> Self {
        let full = quality == Quality::Full;
        LightSampling {
            shadow_size: SHADOW_MAP_SIZE,
            under_size: UNDER_MAP_SIZE,
            shadow_half_width: if full { 2 } else { 0 },
            occlusion_samples: if full { 24 } else { 8 },
        }
    }
}

/// Computes the frame's uniforms. `objects` bounds what casts shadows; the ground (if any)
/// widens the depth range of the camera.
pub fn frame_globals(
    camera: &Camera,
    aspect: f32,
    objects: &Bounds,
    ground: Option<&Ground>,
    legend: Option<&Legend>,
    sampling: LightSampling,
) -> FrameGlobals {
    let objects = if objects.is_valid() {
        *objects
    } else {
        Bounds::of([Vec3::splat(-0.5), Vec3::splat(0.5)])
    };
    let c = objects.center();
    let r = objects.radius();
    let mut everything = objects;
    if let Some(g) = ground {
        for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            everything.include(Vec3::new(
                g.center[0] + sx * g.extent,
                g.center[1] + sy * g.extent,
                g.height,
            ));
        }
    }
    let (near, far) = camera.depth_range(&objects, &everything);
    let view_proj = camera.projection(aspect, near, far) * camera.view();

    let key = key_direction();
    let light_view_proj = orthographic(-2.0 * r, 2.0 * r, -2.0 * r, 2.0 * r, 0.0, 6.0 * r)
        * look(c + key * 3.0 * r, c);
    let ground_height = ground.map_or(objects.min.z, |g| g.height);
    let under_eye = Vec3::new(c.x, c.y, ground_height);
    let under_range = (objects.max.z - ground_height).max(r * 0.1);
    let under_view_proj = orthographic(-1.6 * r, 1.6 * r, -1.6 * r, 1.6 * r, 0.0, under_range)
        * look_at_mat4(under_eye, under_eye + Vec3::Z, Vec3::Y);

    let range = legend.map_or([0.0, 1.0], |l| guard_range(l.range));
    let ground_v = ground.map_or([0.0, 0.0, 0.0, 0.0], |g| {
        [g.height, g.extent, g.center[0], g.center[1]]
    });
    let grid = 10f32.powf((r * 0.5).log10().floor());
    let v4 = |v: Vec3| [v.x, v.y, v.z, 0.0];
    let mut globals = Vec::with_capacity(100);
    for m in [view_proj, light_view_proj, under_view_proj] {
        globals.extend_from_slice(&m.to_cols_array());
    }
    for v in [
        [camera.eye.x, camera.eye.y, camera.eye.z, 1.0],
        v4(key),
        v4(Vec3::new(0.9, -0.3, 0.35).normalize()),
        v4(Vec3::new(0.3, 1.0, 0.5).normalize()),
        [range[0], range[1], 0.0, 0.0],
        ground_v,
        srgb([0.66, 0.72, 0.80]),
        srgb([0.95, 0.95, 0.94]),
        [
            sampling.shadow_size as f32,
            sampling.under_size as f32,
            r,
            under_range,
        ],
        [
            grid,
            0.35 * r,
            sampling.shadow_half_width as f32,
            sampling.occlusion_samples as f32,
        ],
    ] {
        globals.extend_from_slice(&v);
    }
    FrameGlobals {
        globals,
        light_view_proj,
        under_view_proj,
    }
}
