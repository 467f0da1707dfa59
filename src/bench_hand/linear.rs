//! The linear tier's row of `prehensile bench hand`: the index PIP through keyframes at 30° and
//! 60° (then 90°) with the linear tier (rest geometry, one factorization, one solve per
//! keyframe) against the corotated increments: time per keyframe and the distance between them.

use super::{distances, FLESH};
use crate::fem::solve::FillOrdering;
use crate::hand::{HandModel, Pose};
use crate::sim::{Flexion, FlexionScheme, FlexionSettings, HandState, KeyframeStats};
use std::fmt::Write;

/// The linear tier against the corotated increments at one resolution.
#[derive(Clone, Debug)]
pub struct LinearRow {
    /// Resolution.
    pub resolution: f64,
    /// Free dofs of the linear tier's factor (the whole FEM flesh).
    pub free_dofs: usize,
    /// First keyframe (PIP 30°): assembly, ordering, factorization, solve, ms.
    pub first_ms: f64,
    /// Second keyframe (PIP 60°): substitutions with the kept factor, ms.
    pub keyframe_ms: f64,
    /// The corotated increments' mean keyframe (30° in three increments), ms.
    pub corotational_ms: f64,
    /// At PIP 60°, flesh nodes: largest distance to the corotated result, m.
    pub node_gap: f64,
    /// At PIP 60°, display skin: (max, RMS) distance to the corotated result, m.
    pub skin_gap: (f64, f64),
    /// Relative flesh volume change at PIP 60°: linear, corotational.
    pub volume_change: [f64; 2],
    /// What the linear tier does at PIP 90° (`"solved"`, or the error).
    pub at_90: String,
}

fn keyframes(
    hand: &HandModel,
    scheme: FlexionScheme,
) -> (Flexion<'_>, HandState, Vec<KeyframeStats>) {
    let mut stepper = Flexion::new(
        hand,
        "hand",
        vec![FLESH; hand.flesh.mesh.cells.len()],
        FlexionSettings {
            scheme,
            ..Default::default()
        },
        FillOrdering::NestedDissection,
    );
    let mut state = HandState::rest(hand);
    let stats = [30.0, 60.0]
        .iter()
        .map(|&a| {
            let target = pip(hand, &state, a);
            stepper.move_to(&mut state, &target).expect("flexion")
        })
        .collect();
    (stepper, state, stats)
}

fn pip(hand: &HandModel, state: &HandState, angle: f64) -> Vec<f64> {
    let pose: Pose = [("index.pip".to_string(), angle)].into_iter().collect();
    hand.skeleton
        .apply_pose(&state.angles, &pose)
        .expect("pose")
}

/// Measures the linear tier on `hand` (built at `resolution`).
pub fn linear_row(hand: &HandModel, resolution: f64) -> LinearRow {
    let (mut stepper, linear, ls) = keyframes(hand, FlexionScheme::Linear);
    let (_, corot, cs) = keyframes(hand, FlexionScheme::Corotational);
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let skin = |s: &HandState| hand.skin.positions(&s.positions);
    let mut state = linear.clone();
    let target = pip(hand, &state, 90.0);
    let at_90 = match stepper.move_to(&mut state, &target) {
        Ok(_) => "solved".to_string(),
        Err(e) => e.to_string(),
    };
    LinearRow {
        resolution,
        free_dofs: ls[0].free_dofs,
        first_ms: ls[0].total_ms,
        keyframe_ms: ls[1].total_ms,
        corotational_ms: cs.iter().map(|s| s.total_ms).sum::<f64>() / cs.len() as f64,
        node_gap: distances(&linear.positions, &corot.positions).0,
        skin_gap: distances(&skin(&linear), &skin(&corot)),
        volume_change: [
            linear.flesh_volume(hand) / v0 - 1.0,
            corot.flesh_volume(hand) / v0 - 1.0,
        ],
        at_90,
    }
}

/// The Markdown table of the linear tier's rows.
pub fn linear_table(rows: &[LinearRow]) -> String {
    let mut s = String::from(
        "\n| resolution | linear: free dofs | linear: first keyframe ms (factorization) | linear: \
         ms / keyframe | corotational: ms / 30° keyframe | PIP 60°: node gap mm | skin gap max \
         / RMS mm | volume change linear / corotational | PIP 90° (linear) |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let at_90 = if r.at_90 == "solved" {
            "solved".to_string()
        } else if r.at_90.contains("inside out") {
            "a crease cell turns inside out".to_string()
        } else {
            r.at_90.clone()
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.0} | {:.1} | {:.1} | {:.2} | {:.2} / {:.3} | {:+.3} % / {:+.3} % | {} |",
            r.resolution,
            r.free_dofs,
            r.first_ms,
            r.keyframe_ms,
            r.corotational_ms,
            r.node_gap * 1e3,
            r.skin_gap.0 * 1e3,
            r.skin_gap.1 * 1e3,
            r.volume_change[0] * 100.0,
            r.volume_change[1] * 100.0,
            at_90
        );
    }
    s
}
