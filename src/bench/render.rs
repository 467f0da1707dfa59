//! `prehensile bench render`: the cost of a headless 1280×720 frame on the adapter in use, and
//! the per-frame cost of updating a deformed surface on the GPU (positions and normals only:
//! one `write_buffer`, no pipeline or buffer rebuilt).

use crate::headless::solve_scene;
use crate::headless::{camera_for, draw_lists};
use crate::present::{Overlay, VisualOptions};
use crate::render::{Camera, DrawList, RenderError, Renderer, Surface};
use crate::scene::{Scene, BALL_SCENE};
use crate::util::timing::ms;
use std::time::Instant;

/// Frame timings.
#[derive(Clone, Debug)]
pub struct FrameTimes {
    /// The adapter.
    pub adapter: String,
    /// Image size.
    pub size: (u32, u32),
    /// Creating the renderer (instance, device, pipelines), ms.
    pub renderer_ms: f64,
    /// First frame of the default scene (upload, targets, legend, first use of the shaders,
    /// readback), ms.
    pub first_ms: f64,
    /// Later frames of the same uploaded scene, mean, ms (render and readback).
    pub steady_ms: f64,
    /// Frames averaged.
    pub frames: usize,
}

/// Per-frame cost of a deformed surface.
#[derive(Clone, Debug)]
pub struct UpdateRow {
    /// What mesh.
    pub label: String,
    /// Vertices given.
    pub vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// `update_positions`: normals recomputed on the CPU and the vertex buffer written, mean ms.
    pub update_ms: f64,
    /// Submitting and waiting for the upload to reach the GPU, mean ms.
    pub upload_wait_ms: f64,
    /// A whole 1280×720 frame with the update (update, render, readback), mean ms.
    pub frame_ms: f64,
}

/// The default scene's draw list with the stress overlay, and its camera.
fn default_scene_list(aspect: f32) -> (DrawList, Camera) {
    let scene = Scene::parse(BALL_SCENE, "default").expect("the ball scene parses");
    let solved = solve_scene(&scene, "default").expect("the default scene solves");
    let options = VisualOptions {
        overlay: Overlay::Stress,
        ..Default::default()
    };
    let lists = draw_lists(&solved, &options).expect("draw list");
    let camera = camera_for(&lists, "three-quarter", aspect).expect("camera");
    (lists.into_iter().next().expect("one frame"), camera)
}

/// A closed sphere-like grid of `n × 2n` quads (radius 5 cm), as triangles (`n` at least 1:
/// none is empty).
pub fn sphere_surface(n: usize) -> Surface {
    let (rings, segs) = (n, 2 * n);
    let mut positions = Vec::new();
    for j in 0..=rings {
        let th = j as f32 / rings as f32 * std::f32::consts::PI;
        for i in 0..segs {
            let ph = i as f32 / segs as f32 * std::f32::consts::TAU;
            positions.push([
                0.05 * th.sin() * ph.cos(),
                0.05 * th.sin() * ph.sin(),
                0.05 + 0.05 * th.cos(),
            ]);
        }
    }
    let mut indices = Vec::new();
    for j in 0..rings as u32 {
        for i in 0..segs as u32 {
            let a = j * segs as u32 + i;
            let b = j * segs as u32 + (i + 1) % segs as u32;
            let (c, d) = (a + segs as u32, b + segs as u32);
            indices.extend([a, c, d, a, d, b]);
        }
    }
    Surface {
        positions,
        indices,
        scalars: None,
        color: [0.6, 0.2, 0.1, 1.0],
    }
}

/// Times frames of the default scene.
pub fn frame_times(
    renderer_ms: f64,
    renderer: &mut Renderer,
    frames: usize,
) -> Result<FrameTimes, RenderError> {
    let (w, h) = (1280, 720);
    let (list, camera) = default_scene_list(w as f32 / h as f32);
    let t = Instant::now();
    renderer.render_to_rgba(&list, &camera, w, h)?;
    let first_ms = ms(t);
    let mut scene = renderer.upload(&list)?;
    renderer.render_scene_to_rgba(&mut scene, &camera, w, h)?;
    let t = Instant::now();
    for _ in 0..frames {
        renderer.render_scene_to_rgba(&mut scene, &camera, w, h)?;
    }
    Ok(FrameTimes {
        adapter: renderer.adapter_summary(),
        size: (w, h),
        renderer_ms,
        first_ms,
        steady_ms: ms(t) / frames as f64,
        frames,
    })
}

/// Times updates of a deformed surface: the default scene's ball and bigger spheres.
pub fn update_rows(
    renderer: &mut Renderer,
    sphere_sizes: &[usize],
    frames: usize,
) -> Result<Vec<UpdateRow>, RenderError> {
    let (w, h) = (1280, 720);
    let (list, _) = default_scene_list(w as f32 / h as f32);
    let mut cases = vec![("default scene ball".to_string(), list.surfaces[0].clone())];
    for &n in sphere_sizes {
        cases.push((format!("sphere {n}×{}", 2 * n), sphere_surface(n)));
    }
    let mut rows = Vec::new();
    for (label, surface) in cases {
        let list = DrawList {
            surfaces: vec![surface.clone()],
            ..Default::default()
        };
        let Some(bounds) = list.bounds() else {
            return Err(RenderError::InvalidInput(format!(
                "{label}: nothing to draw"
            )));
        };
        let camera = Camera::preset("three-quarter", &bounds, w as f32 / h as f32).expect("preset");
        let mut scene = renderer.upload(&list)?;
        renderer.render_scene_to_rgba(&mut scene, &camera, w, h)?;
        // Each frame: a travelling bulge, so that every position and normal changes.
        let deformed = |k: usize| -> Vec<[f32; 3]> {
            let phase = k as f32 * 0.7;
            surface
                .positions
                .iter()
                .map(|p| {
                    let s = 1.0 + 0.03 * (p[0] * 60.0 + phase).sin();
                    [p[0] * s, p[1] * s, p[2]]
                })
                .collect()
        };
        let queue = renderer.queue().clone();
        let (mut update_ms, mut wait_ms) = (0.0, 0.0);
        for k in 0..frames {
            let pos = deformed(k);
            let t = Instant::now();
            scene.surfaces[0].update_positions(&queue, &pos)?;
            update_ms += ms(t);
            let t = Instant::now();
            queue.submit([]);
            renderer.wait_idle()?;
            wait_ms += ms(t);
        }
        let t = Instant::now();
        for k in 0..frames {
            scene.surfaces[0].update_positions(&queue, &deformed(k))?;
            renderer.render_scene_to_rgba(&mut scene, &camera, w, h)?;
        }
        let frame_ms = ms(t) / frames as f64;
        rows.push(UpdateRow {
            label,
            vertices: surface.positions.len(),
            triangles: surface.indices.len() / 3,
            update_ms: update_ms / frames as f64,
            upload_wait_ms: wait_ms / frames as f64,
            frame_ms,
        });
    }
    Ok(rows)
}

/// The benchmark as Markdown.
pub fn render_table(times: &FrameTimes, rows: &[UpdateRow]) -> String {
    let mut s = format!(
        "adapter: {}\n\n| {}×{} headless frame | ms |\n|---|---|\n| renderer creation (device, pipelines) | {:.0} |\n\
         | first frame (default scene, stress overlay; upload, targets, readback) | {:.0} |\n\
         | steady-state frame (mean of {}; render and readback) | {:.0} |\n\n",
        times.adapter, times.size.0, times.size.1, times.renderer_ms, times.first_ms, times.frames, times.steady_ms
    );
    s += "| deformed mesh | vertices | triangles | update positions + normals ms | upload submit + wait ms | frame with update ms |\n\
          |---|---|---|---|---|---|\n";
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.2} | {:.2} | {:.0} |\n",
            r.label, r.vertices, r.triangles, r.update_ms, r.upload_wait_ms, r.frame_ms
        );
    }
    s
}
