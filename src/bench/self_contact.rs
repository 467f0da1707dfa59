//! `prehensile bench self-contact`: the skin kept out of itself (issue 16) against the skin left
//! to pass through itself, on the motions that fold it — the index PIP to 110°, the middle finger
//! adducted onto the ring finger, the shipped full fist (the four fingers closed, then the thumb
//! folded over them) — per hand resolution: time, increments, factorizations, the pairs held and
//! their force, the largest bone reaction, the flesh's change of volume and the flesh crushed
//! below half its volume, or why it stopped. Each motion is a scene of the built-in hand (the
//! anatomical form, as the shipped scenes') solved by the keyframe driver
//! ([`solve_scene`]), its stages its keyframes: what the CLI and the viewer solve.

use crate::hand::{four_finger_fist, thumb_over_fist, Pose};
use crate::headless::solve_scene;
use crate::scene::Scene;
use std::time::Instant;

/// One motion with or without self-contact.
pub struct SelfContactRow {
    /// The motion's name.
    pub motion: String,
    /// Hand resolution.
    pub resolution: f64,
    /// Whether the skin was kept out of itself.
    pub self_contact: bool,
    /// Wall time, s: the model's build (the hand meshed), the keyframes' solve and the report.
    pub seconds: f64,
    /// What the motion came to, or the error.
    pub outcome: Result<MotionOutcome, String>,
}

/// Where a motion that closed ended.
#[derive(Clone, Copy, Debug)]
pub struct MotionOutcome {
    /// Increments taken over its keyframes.
    pub increments: usize,
    /// Factorizations over its keyframes.
    pub factorizations: usize,
    /// Self-contact pairs held at the end (the last keyframe's).
    pub pairs: usize,
    /// Their force, N.
    pub force: f64,
    /// The largest bone reaction at the end, N.
    pub largest_bone: f64,
    /// The flesh's change of volume from rest (a fraction).
    pub volume_change: f64,
    /// The flesh crushed below half its volume at the end, its rest volume, m³.
    pub crushed: f64,
}

/// The benchmark's motions: a name, its stages (joints and angles in degrees, each a keyframe
/// over where the one before ended), the increment; for the nonlinear tier, the creases' folding
/// only (its fists stop where the flesh buckles).
fn motions(nonlinear: bool) -> Vec<(&'static str, Vec<Pose>, f64)> {
    let pose = |pairs: &[(&str, f64)]| -> Pose {
        pairs.iter().map(|(j, a)| (j.to_string(), *a)).collect()
    };
    if nonlinear {
        return vec![
            ("index PIP 110°", vec![pose(&[("index.pip", 110.0)])], 10.0),
            (
                "index and middle PIP 110°",
                vec![pose(&[("index.pip", 110.0), ("middle.pip", 110.0)])],
                10.0,
            ),
        ];
    }
    vec![
        ("index PIP 110°", vec![pose(&[("index.pip", 110.0)])], 10.0),
        (
            "middle MCP abduction −8° (onto the ring)",
            vec![pose(&[("middle.mcp.abd", -8.0)])],
            1.0,
        ),
        // assets/scenes/hand-full-fist.toml's two keyframes.
        (
            "full fist (fingers, then thumb over)",
            vec![four_finger_fist(), thumb_over_fist()],
            10.0,
        ),
    ]
}

/// The name the motions' scenes go by in errors.
const SCENE_FILE: &str = "self-contact-bench.toml";

/// The scene of one motion: the built-in right hand at `resolution`, the shipped scenes' flesh,
/// the corotational increments (or the nonlinear tier's) of at most `step` degrees, `stages` its
/// keyframes one second apart.
fn motion_scene(
    resolution: f64,
    stages: &[Pose],
    step: f64,
    self_contact: bool,
    nonlinear: bool,
) -> String {
    let tier = if nonlinear {
        "nonlinear"
    } else {
        "corotational"
    };
    let mut text = format!(
        "[solver]\ntier = \"{tier}\"\nmax_step_deg = {step}\nself_contact = {self_contact}\n\n\
         [[material]]\nname = \"flesh\"\nyoung = 5.0e4\npoisson = 0.45\ndensity = 1050.0\n\n\
         [[body]]\nname = \"hand\"\nmaterial = \"flesh\"\n\
         shape = {{ hand = {{ side = \"right\", resolution = {resolution} }} }}\n"
    );
    for (k, stage) in stages.iter().enumerate() {
        let joints: Vec<String> = stage
            .iter()
            .map(|(j, a)| format!("\"{j}\" = {a}"))
            .collect();
        text.push_str(&format!(
            "\n[[keyframe]]\ntime = {}\npose = {{ {} }}\n",
            k + 1,
            joints.join(", ")
        ));
    }
    text
}

/// Runs every motion at every resolution, without and with self-contact (by the corotational
/// increments, or the `nonlinear` tier's).
pub fn self_contact_rows(
    resolutions: &[f64],
    nonlinear: bool,
) -> anyhow::Result<Vec<SelfContactRow>> {
    let mut rows = Vec::new();
    for &resolution in resolutions {
        for (name, stages, step) in motions(nonlinear) {
            for self_contact in [false, true] {
                let text = motion_scene(resolution, &stages, step, self_contact, nonlinear);
                // (The file's name, not the motion's, in errors: the table keeps an error's
                // text up to its first parenthesis.)
                let scene = Scene::parse(&text, SCENE_FILE)?;
                let t = Instant::now();
                let outcome = run_motion(&scene);
                rows.push(SelfContactRow {
                    motion: name.to_string(),
                    resolution,
                    self_contact,
                    seconds: t.elapsed().as_secs_f64(),
                    outcome,
                });
            }
        }
    }
    Ok(rows)
}

/// `scene` solved by the keyframe driver: what its last frame came to, or why it stopped (an
/// error, or a keyframe that stopped short of its pose).
fn run_motion(scene: &Scene) -> Result<MotionOutcome, String> {
    let solved = solve_scene(scene, SCENE_FILE).map_err(|e| e.to_string())?;
    let hands: Vec<_> = solved
        .report
        .frames
        .iter()
        .skip(1)
        .map(|f| &f.hands["hand"])
        .collect();
    if let Some(s) = hands.iter().find_map(|h| h.motion.stopped_short.as_ref()) {
        return Err(format!(
            "at {:.1} % of a keyframe: {}",
            100.0 * s.reached,
            s.reason
        ));
    }
    let last = hands.last().ok_or("no keyframe")?;
    Ok(MotionOutcome {
        increments: hands.iter().map(|h| h.motion.increments_taken).sum(),
        factorizations: hands.iter().map(|h| h.motion.factorizations).sum(),
        pairs: last.motion.self_contacts,
        force: last.motion.self_contact_force,
        largest_bone: last.bones.values().map(|b| b.magnitude).fold(0.0, f64::max),
        volume_change: last.volume_change,
        crushed: last.crushed_flesh.rest_volume,
    })
}

/// The rows as a markdown table.
pub fn self_contact_table(rows: &[SelfContactRow]) -> String {
    let mut out = String::from(
        "| motion | resolution | self-contact | time (s) | increments | factorizations | pairs held | force (N) | largest bone reaction (N) | volume (%) | crushed (mm³) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let on = if r.self_contact { "on" } else { "off" };
        match &r.outcome {
            Ok(o) => out.push_str(&format!(
                "| {} | {} | {on} | {:.2} | {} | {} | {} | {:.3} | {:.3} | {:+.2} | {:.0} |\n",
                r.motion,
                r.resolution,
                r.seconds,
                o.increments,
                o.factorizations,
                o.pairs,
                o.force,
                o.largest_bone,
                100.0 * o.volume_change,
                o.crushed * 1e9
            )),
            Err(e) => {
                // The error's gist: up to its first parenthesis or semicolon.
                let gist = e.split([';', '(']).next().unwrap_or(e).trim();
                out.push_str(&format!(
                    "| {} | {} | {on} | {:.2} | stopped: {gist} | | | | | | |\n",
                    r.motion, r.resolution, r.seconds
                ));
            }
        }
    }
    out
}
