//! `prehensile bench viewer`'s grasp part (issue 20): what posing a grasp by feel costs in the
//! viewer. The real [`ViewerState`] and solver thread on the built-in default scene, corotational
//! tier: the Power grasp preset from the scene's first frame (slider → converged grasp shown),
//! pressed at once and again (another viewer) once the solver thread went idle (the presets
//! flexed ahead meanwhile),
//! then a finger in contact — the thumb's IP, which carries most of the grip — dragged by 2° at a
//! time (twice one way, twice back), each change solved before the next. For every change: the
//! time to its preview and to its solved frame shown, and where the solver thread spent it (the
//! flexion, each contact step, the last contact step's phases, the draw list).

use super::viewer::{frames_until, stats};
use crate::app::physics::Physics;
use crate::app::pose::Preset;
use crate::app::settings::{SolverParams, Tier};
use crate::app::worker::ThreadSolver;
use crate::app::ViewerState;
use crate::present::{draw_list_with, SkinDetail};
use crate::scene::{Scene, DEFAULT_SCENE};
use crate::util::timing::ms;
use anyhow::{anyhow, Result};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The joint dragged and by how much per change, degrees.
const DRAGGED: &str = "thumb.ip";
const DRAG_DEG: f64 = 2.0;

/// One change measured.
struct Change {
    what: String,
    /// Slider → preview shown, ms (None: no preview came first).
    preview_ms: Option<f64>,
    /// Slider → the frame solved at the pose shown while its contact settles, ms (None: none
    /// came before the settled one).
    settling_ms: Option<f64>,
    /// Slider → solved frame shown, ms.
    shown_ms: f64,
    /// The solver thread's wall time for the job (preview, solve, draw list), ms.
    job_ms: f64,
    /// Building the solved frame's draw list again, ms.
    draw_list_ms: f64,
    flexion_ms: f64,
    contact_steps: usize,
    corrections: usize,
    retries: usize,
    /// The last contact step: its whole time and its phases, ms.
    last_step_ms: f64,
    phases: String,
    grip: f64,
    /// Knots of the flexion flexed ahead while the solver was idle.
    knots_ahead: usize,
}

/// The change to the shown frame after `edit`, measured.
fn measure(
    ctx: &egui::Context,
    state: &mut ViewerState,
    what: String,
    edit: impl FnOnce(&mut ViewerState),
) -> Result<Change> {
    edit(state);
    state.pose_edited();
    let t = Instant::now();
    let before = state.latest_version();
    let preview = std::cell::Cell::new(None);
    let settling = std::cell::Cell::new(None);
    frames_until(ctx, state, Duration::from_secs(600), |s| {
        if preview.get().is_none() && s.showing_preview() {
            preview.set(Some(ms(t)));
        }
        if settling.get().is_none() && s.showing_settling() {
            settling.set(Some(ms(t)));
        }
        s.shown
            .as_ref()
            .is_some_and(|f| f.version > before && !f.solution.preview && !f.solution.settling)
            && !s.computing()
    })?;
    let shown_ms = ms(t);
    if let Some(e) = &state.status.error {
        return Err(anyhow!("{what}: the viewer reports: {e}"));
    }
    let solution = &state.shown.as_ref().expect("shown").solution;
    let frame = &solution.frame;
    let t = Instant::now();
    let _ = draw_list_with(&solution.model, frame, &solution.visual, SkinDetail::Full)?;
    let draw_list_ms = ms(t);
    let hand = frame.hands.first().ok_or_else(|| anyhow!("no hand"))?;
    let (last_step_ms, phases) = frame.contact.as_ref().map_or((0.0, String::new()), |c| {
        let p = &c.times;
        (
            c.contact_ms,
            format!(
                "{:.0} / {:.0} / {:.0} / {:.0} / {:.0} / {:.0} / {:.0} / {:.0} ({:.0})",
                p.detection,
                p.assembly,
                p.symbolic,
                p.factorization,
                p.substitution,
                p.search,
                p.settle,
                p.stress,
                p.beside
            ),
        )
    });
    Ok(Change {
        what,
        preview_ms: preview.get(),
        settling_ms: settling.get(),
        shown_ms,
        job_ms: solution.solve_ms,
        draw_list_ms,
        flexion_ms: hand.stats.total_ms,
        contact_steps: hand.stats.contact_steps,
        corrections: hand.stats.pose_corrections,
        retries: hand.stats.contact_retries,
        last_step_ms,
        phases,
        grip: frame.contact.as_ref().map_or(0.0, |c| c.normal_force()),
        knots_ahead: hand.stats.knots_flexed_ahead,
    })
}

/// The preset and `drags` changes of the dragged joint; the Markdown table and a summary line.
pub fn run(drags: usize) -> Result<String> {
    let ctx = egui::Context::default();
    // The preset pressed as soon as the scene is shown: nothing done ahead.
    let mut state = opened(&ctx)?;
    let skeleton = state.hands[0].skeleton.clone();
    let cold = measure(
        &ctx,
        &mut state,
        "Power grasp preset, pressed at once".into(),
        |s| s.pose[0].1 = Preset::PowerGrasp.angles(&skeleton),
    )?;
    drop(state);
    let mut state = opened(&ctx)?;
    // The scene looked at before a preset is pressed: meanwhile the solver thread acquires
    // what the first keyframe would (`Workspace::prepare`) and, after a pause, flexes the
    // presets ahead (`Workspace::anticipate`).
    let t = Instant::now();
    frames_until(&ctx, &mut state, Duration::from_secs(300), |s| {
        s.solver_idle()
    })?;
    let prepared_ms = ms(t);
    let joint = skeleton
        .dofs
        .iter()
        .position(|d| d.name == DRAGGED)
        .ok_or_else(|| anyhow!("no {DRAGGED}"))?;
    let mut changes = vec![measure(
        &ctx,
        &mut state,
        "Power grasp preset, after the solver went idle".into(),
        |s| s.pose[0].1 = Preset::PowerGrasp.angles(&skeleton),
    )?];
    for i in 0..drags {
        let sign = if i % 4 < 2 { 1.0 } else { -1.0 };
        let to = state.pose[0].1[joint] + sign * DRAG_DEG;
        changes.push(measure(
            &ctx,
            &mut state,
            format!("{DRAGGED} → {to:.0}°"),
            |s| s.pose[0].1[joint] = to,
        )?);
    }
    let mut out = String::from(
        "| change | slider → preview shown ms | slider → frame solved at the pose shown (settling) ms | slider → settled frame shown ms | solver thread ms | of it: flexion ms (knots flexed ahead) | contact steps (corrections, redone) | last contact step ms | its detection / assembly / symbolic / factorization / substitution / search / settle / stress ms (the objects' assembly and factorization beside the detection) | draw list ms | grip N |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for c in std::iter::once(&cold).chain(&changes) {
        out.push_str(&format!(
            "| {} | {} | {} | {:.0} | {:.0} | {:.0} ({}) | {} ({}, {}) | {:.0} | {} | {:.0} | {:.3} |\n",
            c.what,
            c.preview_ms.map_or("—".into(), |p| format!("{p:.0}")),
            c.settling_ms.map_or("—".into(), |p| format!("{p:.0}")),
            c.shown_ms,
            c.job_ms,
            c.flexion_ms,
            c.knots_ahead,
            c.contact_steps,
            c.corrections,
            c.retries,
            c.last_step_ms,
            c.phases,
            c.draw_list_ms,
            c.grip
        ));
    }
    out.push_str(&format!(
        "\nThe solver thread idle after the scene was shown (the first keyframe's memory \
         acquired ahead, the presets flexed ahead): {prepared_ms:.0} ms later.\n"
    ));
    let drag: Vec<f64> = changes[1..].iter().map(|c| c.shown_ms).collect();
    if !drag.is_empty() {
        let (median, p95) = median_p95(&drag);
        // The first solved frame at the pose on screen: the settling one where it came first.
        let first: Vec<f64> = changes[1..]
            .iter()
            .map(|c| c.settling_ms.unwrap_or(c.shown_ms))
            .collect();
        let (first_median, first_p95) = median_p95(&first);
        out.push_str(&format!(
            "\nPower grasp preset → settled frame shown: {:.0} ms pressed at once, {:.0} ms \
             after the solver went idle. A finger in contact dragged by \
             {DRAG_DEG}°: the frame solved at the pose shown after {first_median:.0} ms median, \
             {first_p95:.0} ms at the 95th percentile; the settled frame after {median:.0} ms \
             median, {p95:.0} ms at the 95th percentile ({} changes).\n",
            cold.shown_ms,
            changes[0].shown_ms,
            drag.len()
        ));
    }
    Ok(out)
}

/// The viewer on the default scene (corotational tier, its solver thread) with its first frame
/// shown.
fn opened(ctx: &egui::Context) -> Result<ViewerState> {
    let mut scene = Scene::parse(DEFAULT_SCENE, "default")?;
    let mut params = SolverParams::from_scene(&scene);
    params.tier = Tier::Corotational;
    params.apply(&mut scene);
    let port = ThreadSolver::spawn(Physics::new(), Arc::new(|| {}));
    let mut state = ViewerState::new(scene, "default", Box::new(port)).map_err(|e| anyhow!(e))?;
    state.timeline_solving = false;
    frames_until(ctx, &mut state, Duration::from_secs(300), |s| {
        s.shown.is_some() && !s.computing()
    })?;
    Ok(state)
}

/// The median and the 95th percentile of `values` (not empty).
fn median_p95(values: &[f64]) -> (f64, f64) {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let (_, p95, _) = stats(values);
    (sorted[sorted.len() / 2], p95)
}
