//! The linear tier's row of `prehensile bench hand`: the index PIP through keyframes every 15°
//! up to 90° with the linear tier (rest geometry, one factorization, one solve per keyframe)
//! and with the corotated increments: time per keyframe, the distance between the two, and how
//! far the linear tier gets before a crease cell turns inside out.

use super::{distances, FLESH};
use crate::fem::solve::FillOrdering;
use crate::hand::{HandModel, Pose};
use crate::model::{FlexionScheme, FlexionSettings};
use crate::solve::Flexion;
use crate::state::{HandState, KeyframeStats};
use std::fmt::Write;

/// Keyframe angles of the index PIP, degrees.
const ANGLES: [f64; 6] = [15.0, 30.0, 45.0, 60.0, 75.0, 90.0];

/// The two tiers compared at one angle.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// PIP angle, degrees.
    pub angle: f64,
    /// Flesh nodes: largest distance between the two, m.
    pub node_gap: f64,
    /// Display skin: (max, RMS) distance, m.
    pub skin_gap: (f64, f64),
    /// Relative flesh volume change: linear, corotational.
    pub volume_change: [f64; 2],
}

/// The linear tier against the corotated increments at one resolution.
#[derive(Clone, Debug)]
pub struct LinearRow {
    /// Resolution.
    pub resolution: f64,
    /// Free dofs of the linear tier's factor (the whole FEM flesh).
    pub free_dofs: usize,
    /// First keyframe: assembly, ordering, factorization, solve, ms.
    pub first_ms: f64,
    /// Mean of the later keyframes (substitutions with the kept factor), ms.
    pub keyframe_ms: f64,
    /// The corotated increments' mean keyframe (15°, two increments), ms.
    pub corotational_ms: f64,
    /// At 30° and at the largest angle the linear tier reaches.
    pub at: Vec<Comparison>,
    /// Why the linear tier stopped before 90° (None when it reached it).
    pub stopped: Option<String>,
}

/// Steps through [`ANGLES`] until an error: the states and stats reached, and the error.
fn keyframes(
    hand: &HandModel,
    scheme: FlexionScheme,
) -> (Vec<(HandState, KeyframeStats)>, Option<String>) {
    let mut stepper = Flexion::new(
        hand,
        "hand",
        vec![FLESH; hand.flesh.mesh.cells.len()],
        FlexionSettings {
            scheme,
            ..Default::default()
        },
        FillOrdering::Auto,
    );
    let mut state = HandState::rest(hand);
    let mut out = Vec::new();
    for a in ANGLES {
        let pose: Pose = [("index.pip".to_string(), a)].into_iter().collect();
        let target = hand
            .skeleton
            .apply_pose(&state.angles, &pose)
            .expect("pose");
        match stepper.move_to(&mut state, &target) {
            Ok(stats) => out.push((state.clone(), stats)),
            Err(e) => return (out, Some(e.to_string())),
        }
    }
    (out, None)
}

/// Measures the linear tier on `hand` (built at `resolution`).
pub fn linear_row(hand: &HandModel, resolution: f64) -> LinearRow {
    let (linear, stopped) = keyframes(hand, FlexionScheme::Linear);
    let (corot, _) = keyframes(hand, FlexionScheme::Corotational);
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let skin = |s: &HandState| hand.skin.positions(&s.positions);
    let compare = |k: usize| {
        let (l, c) = (&linear[k].0, &corot[k].0);
        Comparison {
            angle: ANGLES[k],
            node_gap: distances(&l.positions, &c.positions).0,
            skin_gap: distances(&skin(l), &skin(c)),
            volume_change: [
                l.flesh_volume(hand) / v0 - 1.0,
                c.flesh_volume(hand) / v0 - 1.0,
            ],
        }
    };
    let mut at: Vec<Comparison> = [1, linear.len().saturating_sub(1)]
        .into_iter()
        .filter(|&k| k < linear.len())
        .map(compare)
        .collect();
    at.dedup_by(|a, b| a.angle == b.angle);
    let later = &linear[1.min(linear.len())..];
    LinearRow {
        resolution,
        free_dofs: linear.first().map_or(0, |l| l.1.free_dofs),
        first_ms: linear.first().map_or(0.0, |l| l.1.total_ms),
        keyframe_ms: later.iter().map(|l| l.1.total_ms).sum::<f64>() / later.len().max(1) as f64,
        corotational_ms: corot.iter().map(|c| c.1.total_ms).sum::<f64>() / corot.len() as f64,
        at,
        stopped,
    }
}

/// The Markdown table of the linear tier's rows.
pub fn linear_table(rows: &[LinearRow]) -> String {
    let mut s = String::from(
        "\n| resolution | linear: free dofs | linear: first keyframe ms (factorization) | linear: \
         ms / keyframe | corotational: ms / 15° keyframe | PIP | node gap mm | skin gap max / \
         RMS mm | volume change linear / corotational | linear tier reaches |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let reach = match &r.stopped {
            None => "90°".to_string(),
            Some(_) => format!(
                "{}° (then a crease cell turns inside out)",
                r.at.last().map_or(0.0, |c| c.angle)
            ),
        };
        for c in &r.at {
            let _ = writeln!(
                s,
                "| {} | {} | {:.0} | {:.1} | {:.1} | {}° | {:.2} | {:.2} / {:.3} | {:+.3} % / \
                 {:+.3} % | {} |",
                r.resolution,
                r.free_dofs,
                r.first_ms,
                r.keyframe_ms,
                r.corotational_ms,
                c.angle,
                c.node_gap * 1e3,
                c.skin_gap.0 * 1e3,
                c.skin_gap.1 * 1e3,
                c.volume_change[0] * 100.0,
                c.volume_change[1] * 100.0,
                reach
            );
        }
    }
    s
}
