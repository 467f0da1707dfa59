//! `prehensile bench self-contact`: the skin kept out of itself (issue 16) against the skin left
//! to pass through itself, on the motions that fold it — the index PIP to 110°, the middle finger
//! adducted onto the ring finger, a full fist — per hand resolution: time, increments,
//! factorizations, the pairs held and their force, or why it stopped.

use crate::contact::ContactSettings;
use crate::fem::solve::FillOrdering;
use crate::fem::Material;
use crate::hand::{four_finger_fist, full_fist, HandModel, Pose, Side};
use crate::model::{FlexionScheme, FlexionSettings};
use crate::solve::Flexion;
use crate::state::HandState;
use std::time::Instant;

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
    /// Increments taken and factorizations, pairs held and their force (N) at the end; or the
    /// error.
    pub outcome: Result<(usize, usize, usize, f64), String>,
}

/// The benchmark's motions: a name, the joints and angles (degrees), the increment; for the
/// nonlinear tier, the creases' folding only (its fists stop where the flesh buckles).
fn motions(nonlinear: bool) -> Vec<(&'static str, Pose, f64)> {
    let pose = |pairs: &[(&str, f64)]| -> Pose {
        pairs.iter().map(|(j, a)| (j.to_string(), *a)).collect()
    };
    if nonlinear {
        return vec![
            ("index PIP 110°", pose(&[("index.pip", 110.0)]), 10.0),
            (
                "index and middle PIP 110°",
                pose(&[("index.pip", 110.0), ("middle.pip", 110.0)]),
                10.0,
            ),
        ];
    }
    vec![
        ("index PIP 110°", pose(&[("index.pip", 110.0)]), 10.0),
        (
            "middle MCP abduction −8° (onto the ring)",
            pose(&[("middle.mcp.abd", -8.0)]),
            1.0,
        ),
        ("full fist", full_fist(), 10.0),
        ("four fingers' fist", four_finger_fist(), 10.0),
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
        for (name, pose, step) in motions(nonlinear) {
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
                let mut state = HandState::rest(&hand);
                let target = hand.skeleton.apply_pose(&state.angles, &pose)?;
                let t = Instant::now();
                let outcome = stepper
                    .move_to(&mut state, &target)
                    .map(|s| {
                        (
                            s.increments_taken,
                            s.factorizations,
                            s.self_contacts,
                            s.self_contact_force,
                        )
                    })
                    .map_err(|e| e.to_string());
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

/// The rows as a markdown table.
pub fn self_contact_table(rows: &[SelfContactRow]) -> String {
    let mut out = String::from(
        "| motion | resolution | self-contact | time (s) | increments | factorizations | pairs held | force (N) |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let on = if r.self_contact { "on" } else { "off" };
        match &r.outcome {
            Ok((increments, factorizations, points, force)) => out.push_str(&format!(
                "| {} | {} | {on} | {:.2} | {increments} | {factorizations} | {points} | {force:.3} |\n",
                r.motion, r.resolution, r.seconds
            )),
            Err(e) => {
                // The error's gist: up to its first parenthesis or semicolon.
                let gist = e.split([';', '(']).next().unwrap_or(e).trim();
                out.push_str(&format!(
                    "| {} | {} | {on} | {:.2} | stopped: {gist} | | | |\n",
                    r.motion, r.resolution, r.seconds
                ));
            }
        }
    }
    out
}
