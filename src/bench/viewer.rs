//! `prehensile bench viewer`: the viewer's responsiveness without a window. The real
//! [`ViewerState`] and its panels run in a headless egui context at 1400×860 points, with the
//! real solver thread on the built-in default scene; the 3D view's part (upload of the new draw
//! list, drawing it at the central panel's size) runs on the headless renderer.
//!
//! - UI frame time: `Context::run_ui` + tessellation of the whole window, per frame, while the
//!   solver thread works on a slider change (the window paces frames at 16 ms).
//! - Latency: from the slider change (a joint angle +10°) to the new frame shown by the state,
//!   plus the upload and the 3D draw of that frame (submit and wait).

use crate::app::physics::Physics;
use crate::app::settings::{SolverParams, Tier};
use crate::app::worker::ThreadSolver;
use crate::app::ViewerState;
use crate::render::{Camera, Renderer};
use crate::scene::{Scene, DEFAULT_SCENE};
use crate::util::timing::ms;
use anyhow::{anyhow, Result};
use std::sync::Arc;
use std::time::{Duration, Instant};

const FRAME: Duration = Duration::from_millis(16);
const VIEW: (u32, u32) = (780, 700);

struct Row {
    tier: Tier,
    first_ms: f64,
    frame_ms: Vec<f64>,
    /// From the slider change to a preview on screen, where one came first.
    preview_ms: Vec<f64>,
    /// Upload and 3D draw of each preview (its coarse skin), at the full view's size and at
    /// the viewer's interactive size.
    preview_draw_ms: Vec<f64>,
    preview_draw_reduced_ms: Vec<f64>,
    solve_ms: Vec<f64>,
    upload_ms: Vec<f64>,
    draw_ms: Vec<f64>,
    /// The solved frame drawn again as the window draws it while the camera orbits (the
    /// interactive size, one sample per pixel), ms.
    orbit_ms: Vec<f64>,
}

fn ui_frame(ctx: &egui::Context, state: &mut ViewerState) -> f64 {
    let t = Instant::now();
    let input = egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(1400.0, 860.0),
        )),
        ..Default::default()
    };
    let out = ctx.run_ui(input, |ui| state.ui(ui));
    let _ = ctx.tessellate(out.shapes, out.pixels_per_point);
    ms(t)
}

/// Runs frames every 16 ms until `done`, returning the frame times; fails after `limit`.
/// `done` is asked at once and after each frame, before the pause to the next: what a frame
/// takes from the solver is on screen when that frame ends (until 2026-12-05 it was asked after
/// the pause, which counted up to one more frame).
pub(super) fn frames_until(
    ctx: &egui::Context,
    state: &mut ViewerState,
    limit: Duration,
    done: impl Fn(&ViewerState) -> bool,
) -> Result<Vec<f64>> {
    let start = Instant::now();
    let mut times = Vec::new();
    while !done(state) {
        if start.elapsed() > limit {
            return Err(anyhow!(
                "no frame after {:?}: {:?}",
                limit,
                state.status.error
            ));
        }
        let t = Instant::now();
        times.push(ui_frame(ctx, state));
        if done(state) {
            break;
        }
        if let Some(rest) = FRAME.checked_sub(t.elapsed()) {
            std::thread::sleep(rest);
        }
    }
    Ok(times)
}

fn tier_row(tier: Tier, changes: usize, renderer: &mut Renderer) -> Result<Row> {
    let mut scene = Scene::parse(DEFAULT_SCENE, "default")?;
    let mut params = SolverParams::from_scene(&scene);
    params.tier = tier;
    params.apply(&mut scene);
    let ctx = egui::Context::default();
    let port = ThreadSolver::spawn(Physics::new(), Arc::new(|| {}));
    let mut state = ViewerState::new(scene, "default", Box::new(port)).map_err(|e| anyhow!(e))?;
    state.timeline_solving = false;
    let t = Instant::now();
    frames_until(&ctx, &mut state, Duration::from_secs(300), |s| {
        s.shown.is_some() && !s.computing()
    })?;
    let first_ms = ms(t);
    let joint = state.hands[0]
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == "index.pip")
        .ok_or_else(|| anyhow!("no index.pip"))?;
    let mut row = Row {
        tier,
        first_ms,
        frame_ms: Vec::new(),
        preview_ms: Vec::new(),
        preview_draw_ms: Vec::new(),
        preview_draw_reduced_ms: Vec::new(),
        solve_ms: Vec::new(),
        upload_ms: Vec::new(),
        draw_ms: Vec::new(),
        orbit_ms: Vec::new(),
    };
    for i in 0..changes {
        let angle = &mut state.pose[0].1[joint];
        *angle = if i % 2 == 0 {
            *angle + 10.0
        } else {
            *angle - 5.0
        };
        state.pose_edited();
        let t = Instant::now();
        let before = state.latest_version();
        let preview = std::cell::RefCell::new(None);
        let times = frames_until(&ctx, &mut state, Duration::from_secs(120), |s| {
            if preview.borrow().is_none() && s.showing_preview() {
                let shown = s.shown.as_ref().expect("a preview is shown");
                *preview.borrow_mut() = Some((ms(t), shown.solution.draw_list.clone()));
            }
            s.shown.as_ref().is_some_and(|f| f.version > before) && !s.computing()
        })?;
        row.solve_ms.push(ms(t));
        if let Some((at, list)) = preview.into_inner() {
            row.preview_ms.push(at);
            row.preview_draw_ms
                .push(upload_and_draw(renderer, &list, VIEW)?);
            // As the window draws a preview: a quarter of the pixels, one sample each.
            let reduced = crate::app::view3d::drawn_size(VIEW, true);
            renderer.set_quality(crate::render::Quality::Draft);
            let drawn = upload_and_draw(renderer, &list, reduced);
            renderer.set_quality(crate::render::Quality::Full);
            row.preview_draw_reduced_ms.push(drawn?);
        }
        row.frame_ms.extend(times);
        let shown = state.shown.as_ref().expect("shown");
        let t = Instant::now();
        let mut gpu = renderer.upload(&shown.solution.draw_list)?;
        row.upload_ms.push(ms(t));
        let t = Instant::now();
        draw(renderer, &mut gpu, &shown.solution.draw_list, VIEW)?;
        row.draw_ms.push(ms(t));
        renderer.set_quality(crate::render::Quality::Draft);
        let t = Instant::now();
        let orbit = draw(
            renderer,
            &mut gpu,
            &shown.solution.draw_list,
            crate::app::view3d::drawn_size(VIEW, true),
        );
        renderer.set_quality(crate::render::Quality::Full);
        orbit?;
        row.orbit_ms.push(ms(t));
    }
    Ok(row)
}

/// One draw of `list`'s uploaded buffers at `size` pixels.
fn draw(
    renderer: &mut Renderer,
    gpu: &mut crate::render::GpuScene,
    list: &crate::render::DrawList,
    size: (u32, u32),
) -> Result<()> {
    let bounds = list.bounds().ok_or_else(|| anyhow!("empty draw list"))?;
    let camera =
        Camera::preset("three-quarter", &bounds, size.0 as f32 / size.1 as f32).expect("a preset");
    renderer.render_scene_to_rgba(gpu, &camera, size.0, size.1)?;
    Ok(())
}

/// Upload and one draw of `list` at `size` pixels, ms.
fn upload_and_draw(
    renderer: &mut Renderer,
    list: &crate::render::DrawList,
    size: (u32, u32),
) -> Result<f64> {
    let t = Instant::now();
    let mut gpu = renderer.upload(list)?;
    draw(renderer, &mut gpu, list, size)?;
    Ok(ms(t))
}

pub(super) fn stats(v: &[f64]) -> (f64, f64, f64) {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    if s.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let mean = s.iter().sum::<f64>() / s.len() as f64;
    let p95 = s[((s.len() as f64 * 0.95).ceil() as usize).clamp(1, s.len()) - 1];
    (mean, p95, *s.last().expect("non-empty"))
}

/// Measures every tier; returns the Markdown table.
pub fn run(changes: usize) -> Result<String> {
    let mut renderer = Renderer::new_headless()?;
    // As the window does when it opens.
    renderer.prepare(crate::render::Quality::Draft);
    eprintln!("adapter: {}", renderer.adapter_summary());
    let mut out = String::from(
        "| tier | first frame ms | UI frames measured | UI frame ms mean / p95 / max | slider → preview shown ms (mean; previews) | + its upload and 3D draw ms (mean), full / interactive (half each side, one sample) | slider → frame shown ms (mean / max) | + upload ms (mean) | + 3D draw ms (mean) | slider → on screen ms (mean) | solved frame redrawn while orbiting ms (mean) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for tier in Tier::ALL {
        let row = tier_row(tier, changes, &mut renderer)?;
        let (fm, fp, fx) = stats(&row.frame_ms);
        let (sm, _, sx) = stats(&row.solve_ms);
        let (pm, _, _) = stats(&row.preview_ms);
        let (pd, _, _) = stats(&row.preview_draw_ms);
        let (pr, _, _) = stats(&row.preview_draw_reduced_ms);
        let (um, _, _) = stats(&row.upload_ms);
        let (dm, _, _) = stats(&row.draw_ms);
        let (om, _, _) = stats(&row.orbit_ms);
        out.push_str(&format!(
            "| {} | {:.0} | {} | {fm:.2} / {fp:.2} / {fx:.2} | {pm:.0} ({}) | {pd:.0} / {pr:.0} | {sm:.0} / {sx:.0} | {um:.0} | {dm:.0} | {:.0} | {om:.0} |\n",
            crate::app::settings::tier_label(row.tier),
            row.first_ms,
            row.frame_ms.len(),
            row.preview_ms.len(),
            sm + um + dm
        ));
    }
    Ok(out)
}
