//! `prehensile bench self-contact`: the skin kept out of itself (issue 16) against the skin left
//! to pass through itself, on the motions that fold it — the index PIP to 110°, the middle finger
//! adducted onto the ring finger, the shipped full fist (the four fingers closed, then the thumb
//! folded over them) — per hand resolution: time, increments, factorizations, the pairs held and
//! their force, the largest bone reaction and the flesh's change of volume, or why it stopped.
//! The hand is the simple form's ([`HandModel::new`]; the shipped scene's is the anatomical).

use crate::contact::ContactSettings;
use crate::fem::solve::FillOrdering;
use crate::fem::Material;
use crate::hand::{four_finger_fist, thumb_over_fist, HandModel, Pose, Side};
use crate::model::{FlexionScheme, FlexionSettings};
use crate::solve::Flexion;
use crate::state::HandState;
use std::time::{Duration, Instant};

/// One motion with or without self-contact.
pub struct SelfContactRow {
    /// The motion's name.
    pub motion: String,
    /// Hand resolution.
    pub resolution: f64,
    /// Whether the skin was kept out of itself.
    pub self_contact: bool,
    /// Wall time, s.
    pub seconds: f64,
    /// What the motion came to, or the error.
    pub outcome: Result<MotionOutcome, String>,
}

/// Where a motion that closed ended.
#[derive(Clone, Copy, Debug)]
pub struct MotionOutcome {
    /// Increments taken over its stages.
    pub increments: usize,
    /// Factorizations over its stages.
    pub factorizations: usize,
    /// Self-contact pairs held at the end.
    pub pairs: usize,
    /// Their force, N.
    pub force: f64,
    /// The largest bone reaction at the end, N.
    pub largest_bone: f64,
    /// The flesh's change of volume from rest (a fraction).
    pub volume_change: f64,
}

/// The benchmark's motions: a name, its stages (joints and angles in degrees, each over where
/// the one before ended), the increment; for the nonlinear tier, the creases' folding only (its
/// fists stop where the flesh buckles).
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

/// Runs every motion at every resolution, without and with self-contact (by the corotational
/// increments, or the `nonlinear` tier's).
pub fn self_contact_rows(
    resolutions: &[f64],
    nonlinear: bool,
) -> anyhow::Result<Vec<SelfContactRow>> {
    let flesh = Material {
        young: 5.0e4,
        poisson: 0.45,
        density: 1050.0,
    };
    let mut rows = Vec::new();
    for &resolution in resolutions {
        let hand = HandModel::new(Side::Right, resolution)?;
        for (name, stages, step) in motions(nonlinear) {
            for self_contact in [false, true] {
                let mut stepper = Flexion::new(
                    &hand,
                    "hand",
                    vec![flesh; hand.flesh.mesh.cells.len()],
                    FlexionSettings {
                        max_step_deg: step,
                        self_contact: self_contact.then(ContactSettings::default),
                        scheme: if nonlinear {
                            FlexionScheme::Nonlinear
                        } else {
                            FlexionScheme::Corotational
                        },
                        ..Default::default()
                    },
                    FillOrdering::Auto,
                );
                let t = Instant::now();
                let outcome = run_motion(&hand, &mut stepper, &stages, t);
                let seconds = match &outcome {
                    Ok((_, elapsed)) => elapsed.as_secs_f64(),
                    Err(_) => t.elapsed().as_secs_f64(),
                };
                rows.push(SelfContactRow {
                    motion: name.to_string(),
                    resolution,
                    self_contact,
                    seconds,
                    outcome: outcome.map(|(o, _)| o),
                });
            }
        }
    }
    Ok(rows)
}

/// `stages` one after another from rest by one `stepper`, each over where the one before ended
/// (as the keyframe driver asks a scene's keyframes): what they came to and the time since
/// `start` when the last closed (before the bone reactions and volume are read), or the first
/// stage's error.
fn run_motion(
    hand: &HandModel,
    stepper: &mut Flexion,
    stages: &[Pose],
    start: Instant,
) -> Result<(MotionOutcome, Duration), String> {
    let mut state = HandState::rest(hand);
    let rest_volume = state.flesh_volume(hand);
    let (mut increments, mut factorizations, mut pairs, mut force) = (0, 0, 0, 0.0);
    for pose in stages {
        let target = hand
            .skeleton
            .apply_pose(&state.angles, pose)
            .map_err(|e| e.to_string())?;
        let s = stepper
            .move_to(&mut state, &target)
            .map_err(|e| e.to_string())?;
        increments += s.increments_taken;
        factorizations += s.factorizations;
        (pairs, force) = (s.self_contacts, s.self_contact_force);
    }
    let elapsed = start.elapsed();
    let largest_bone = state
        .bone_reactions(hand)
        .iter()
        .map(|r| r.norm())
        .fold(0.0, f64::max);
    let outcome = MotionOutcome {
        increments,
        factorizations,
        pairs,
        force,
        largest_bone,
        volume_change: state.flesh_volume(hand) / rest_volume - 1.0,
    };
    Ok((outcome, elapsed))
}

/// The rows as a markdown table.
pub fn self_contact_table(rows: &[SelfContactRow]) -> String {
    let mut out = String::from(
        "| motion | resolution | self-contact | time (s) | increments | factorizations | pairs held | force (N) | largest bone reaction (N) | volume (%) |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let on = if r.self_contact { "on" } else { "off" };
        match &r.outcome {
            Ok(o) => out.push_str(&format!(
                "| {} | {} | {on} | {:.2} | {} | {} | {} | {:.3} | {:.3} | {:+.2} |\n",
                r.motion,
                r.resolution,
                r.seconds,
                o.increments,
                o.factorizations,
                o.pairs,
                o.force,
                o.largest_bone,
                100.0 * o.volume_change
            )),
            Err(e) => {
                // The error's gist: up to its first parenthesis or semicolon.
                let gist = e.split([';', '(']).next().unwrap_or(e).trim();
                out.push_str(&format!(
                    "| {} | {} | {on} | {:.2} | stopped: {gist} | | | | | |\n",
                    r.motion, r.resolution, r.seconds
                ));
            }
        }
    }
    out
}
