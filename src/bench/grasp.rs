//! `prehensile bench grasp`: the grasps a user meets — the viewer's presets on the built-in
//! default scene (from the scene's pose) and the shipped grasp scenes — per hand resolution and
//! tier: wall time per keyframe, contact steps (and retries), factorizations, the grip on the
//! object and the penetration left, or why it stopped.

use crate::app::pose::Preset;
use crate::headless::solve_scene;
use crate::scene::{ContactMethodName, Scene, Shape, TierName, DEFAULT_SCENE};
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

/// One grasp solved at one resolution with one tier.
pub struct GraspRow {
    /// The grasp: a preset or a scene file.
    pub case: String,
    /// Hand mesh resolution.
    pub resolution: f64,
    /// Tier.
    pub tier: TierName,
    /// Contact method: the exact one (Lagrange) or the paper's iteration.
    pub method: ContactMethodName,
    /// Keyframes solved after the initial pose.
    pub keyframes: usize,
    /// Wall time of the whole scene, s.
    pub total_s: f64,
    /// Contact solves kept, and redone, over the keyframes.
    pub contact_steps: (usize, usize),
    /// Factorizations of the flexion over the keyframes.
    pub factorizations: usize,
    /// The last frame's contact force on the hands (N), penetration left (m) and the least
    /// fraction of a keyframe's motion reached (1: every pose reached), or the error.
    pub outcome: Result<(f64, f64, f64), String>,
    /// The last frame's contact force on each digit's bones (thumb … little), N, over the hands.
    pub digits: [f64; 5],
    /// The last frame's largest contact pressure on the hands' contact skin, Pa.
    pub skin_pressure: f64,
}

/// The built-in default scene with one keyframe at time 1 to `preset` (what pressing the
/// preset's button in the viewer asks for).
pub fn preset_scene(preset: Preset) -> Scene {
    // The default scene's hand (its rest: the anatomical thumb's abduction).
    let default = Scene::parse(DEFAULT_SCENE, "default.toml").expect("the default scene parses");
    let skeleton = crate::app::pose::hands_of(&default)
        .into_iter()
        .next()
        .expect("the default scene has a hand")
        .skeleton;
    let angles = preset.angles(&skeleton);
    let pose: Vec<String> = skeleton
        .dofs
        .iter()
        .zip(&angles)
        .map(|(d, a)| format!("\"{}\" = {a}", d.name))
        .collect();
    let base = &DEFAULT_SCENE[..DEFAULT_SCENE
        .find("[[keyframe]]")
        .unwrap_or(DEFAULT_SCENE.len())];
    let text = format!(
        "{base}[[keyframe]]\ntime = 1.0\npose = {{ {} }}\n",
        pose.join(", ")
    );
    Scene::parse(&text, "default.toml").expect("the default scene with a preset parses")
}

/// `scene` with every hand meshed at `resolution`.
pub fn at_hand_resolution(scene: &Scene, resolution: f64) -> Scene {
    let mut s = scene.clone();
    for body in &mut s.body {
        if let Shape::Hand { resolution: r, .. } = &mut body.shape {
            *r = resolution;
        }
    }
    s
}

/// The cases: `presets` (names as on the viewer's buttons) and scene files.
fn cases(presets: &[String], scenes: &[String]) -> anyhow::Result<Vec<(String, Scene)>> {
    let mut out = Vec::new();
    for name in presets.iter().filter(|n| !n.trim().is_empty()) {
        let preset = Preset::ALL
            .iter()
            .copied()
            .find(|p| p.label().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| {
                anyhow::anyhow!("no preset \"{name}\" (Rest, Fist, Pinch, Power grasp)")
            })?;
        out.push((format!("preset {}", preset.label()), preset_scene(preset)));
    }
    for file in scenes.iter().filter(|f| !f.trim().is_empty()) {
        out.push((file.clone(), Scene::load(Path::new(file))?));
    }
    Ok(out)
}

/// Solves every case at every resolution with every tier and contact method, each row also
/// printed to standard error as it is done (a long table shows its progress).
pub fn grasp_rows(
    presets: &[String],
    scenes: &[String],
    resolutions: &[f64],
    tiers: &[TierName],
    methods: &[ContactMethodName],
) -> anyhow::Result<Vec<GraspRow>> {
    let mut rows = Vec::new();
    for (case, scene) in cases(presets, scenes)? {
        for &resolution in resolutions {
            for (&tier, &method) in tiers
                .iter()
                .flat_map(|t| methods.iter().map(move |m| (t, m)))
            {
                let mut s = at_hand_resolution(&scene, resolution);
                s.solver.tier = Some(tier);
                s.solver.contact = Some(method);
                let t = Instant::now();
                let solved = solve_scene(&s, &case);
                let total_s = t.elapsed().as_secs_f64();
                let mut row = GraspRow {
                    case: case.clone(),
                    resolution,
                    tier,
                    method,
                    keyframes: s.keyframe.len(),
                    total_s,
                    contact_steps: (0, 0),
                    factorizations: 0,
                    outcome: Err(String::new()),
                    digits: [0.0; 5],
                    skin_pressure: 0.0,
                };
                match solved {
                    Ok(solved) => {
                        for f in solved.frames.iter().skip(1) {
                            for h in &f.hands {
                                row.contact_steps.0 += h.stats.contact_steps;
                                row.contact_steps.1 += h.stats.contact_retries;
                                row.factorizations += h.stats.factorizations;
                            }
                        }
                        let last = solved.frames.last().expect("a frame");
                        let force: nalgebra::Vector3<f64> =
                            last.hands.iter().flat_map(|h| &h.contact_force).sum();
                        let left = last.contact.as_ref().map_or(0.0, |c| c.max_penetration);
                        // The least of the keyframes' motion reached (1 when every pose was).
                        let reached = solved
                            .frames
                            .iter()
                            .flat_map(|f| &f.hands)
                            .filter_map(|h| h.stats.stopped_short.as_ref())
                            .map(|s| s.reached)
                            .fold(1.0, f64::min);
                        row.outcome = Ok((force.norm(), left, reached));
                        for h in &last.hands {
                            let hand = solved.model.bodies[h.body]
                                .hand
                                .as_deref()
                                .expect("a hand body");
                            let on = h.contact_force_by_digit(&hand.skeleton);
                            for (d, f) in row.digits.iter_mut().zip(on) {
                                *d += f.norm();
                            }
                            let peak =
                                crate::state::contact_skin_pressure(&solved.model, last, h.body)
                                    .unwrap_or_default()
                                    .into_iter()
                                    .fold(0.0, f64::max);
                            row.skin_pressure = row.skin_pressure.max(peak);
                        }
                    }
                    Err(e) => row.outcome = Err(e.to_string()),
                }
                eprint!("{}", grasp_table_rows(std::slice::from_ref(&row)));
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// The rows as a Markdown table.
pub fn grasp_table(rows: &[GraspRow]) -> String {
    let mut out = String::from(
        "| grasp | resolution | tier | contact | keyframes | s per keyframe | contact steps (redone) | \
         flexion factorizations | force on the hands (N) | thumb / index / middle / ring / \
         little (N) | peak skin pressure (kPa) | penetration left (µm) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    out.push_str(&grasp_table_rows(rows));
    out
}

/// The table's rows, without its header.
fn grasp_table_rows(rows: &[GraspRow]) -> String {
    let mut out = String::new();
    for r in rows {
        let per = r.total_s / r.keyframes.max(1) as f64;
        let (force, left) = match &r.outcome {
            Ok((f, p, reached)) if *reached < 1.0 => (
                format!("{f:.3} (stopped at {:.0} % of its motion)", reached * 100.0),
                format!("{:.1}", p * 1e6),
            ),
            Ok((f, p, _)) => (format!("{f:.3}"), format!("{:.1}", p * 1e6)),
            Err(e) => {
                let short: String = e.chars().take(140).collect();
                (format!("stopped: {short}…"), "—".into())
            }
        };
        let (digits, pressure) = match &r.outcome {
            Ok(_) => (
                r.digits
                    .iter()
                    .map(|f| format!("{f:.3}"))
                    .collect::<Vec<_>>()
                    .join(" / "),
                format!("{:.1}", r.skin_pressure * 1e-3),
            ),
            Err(_) => ("—".into(), "—".into()),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {:?} | {} | {} | {per:.1} | {} ({}) | {} | {force} | {digits} | {pressure} | \
             {left} |",
            r.case,
            r.resolution,
            r.tier,
            r.method.name(),
            r.keyframes,
            r.contact_steps.0,
            r.contact_steps.1,
            r.factorizations
        );
    }
    out
}
