//! The nonlinear tier's row of `prehensile bench hand`: the same index PIP 0° → 90° keyframe in
//! 10° increments, each solved to equilibrium by Newton on the Neo-Hookean flesh, against the
//! corotated increments: time, factorizations (Newton iterations and regularised retries),
//! volume change, the largest bone reaction and how far apart the two land.

use super::{distances, run};
use crate::hand::HandModel;
use crate::model::{FlexionScheme, FlexionSettings};
use crate::state::{HandState, KeyframeStats};
use std::fmt::Write;

/// The nonlinear tier against the corotated increments at one resolution.
#[derive(Clone, Debug)]
pub struct NonlinearRow {
    /// Resolution.
    pub resolution: f64,
    /// The nonlinear keyframe's costs.
    pub stats: KeyframeStats,
    /// The corotated keyframe's wall time, ms.
    pub corotational_ms: f64,
    /// Relative flesh volume change: nonlinear, corotational.
    pub volume_change: [f64; 2],
    /// Largest bone reaction: nonlinear, corotational, N.
    pub reaction: [f64; 2],
    /// Display skin: (max, RMS) distance between the two, m.
    pub skin_gap: (f64, f64),
    /// Why the nonlinear tier stopped (None when it reached 90°).
    pub stopped: Option<String>,
}

fn largest_reaction(hand: &HandModel, state: &HandState) -> f64 {
    state
        .bone_reactions(hand)
        .iter()
        .map(|r| r.norm())
        .fold(0.0, f64::max)
}

/// Measures the nonlinear tier on `hand` (built at `resolution`) against the corotated
/// keyframe `corot` already solved.
pub fn nonlinear_row(
    hand: &HandModel,
    resolution: f64,
    corot: &(HandState, KeyframeStats),
) -> NonlinearRow {
    let settings = FlexionSettings {
        scheme: FlexionScheme::Nonlinear,
        ..Default::default()
    };
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let volume = |s: &HandState| s.flesh_volume(hand) / v0 - 1.0;
    let skin = |s: &HandState| hand.skin.positions(&s.positions);
    let (state, stats, stopped) = match run(hand, settings) {
        Ok((state, stats)) => (state, stats, None),
        Err(e) => (HandState::rest(hand), KeyframeStats::default(), Some(e)),
    };
    NonlinearRow {
        resolution,
        stats,
        corotational_ms: corot.1.total_ms,
        volume_change: [volume(&state), volume(&corot.0)],
        reaction: [
            largest_reaction(hand, &state),
            largest_reaction(hand, &corot.0),
        ],
        skin_gap: distances(&skin(&state), &skin(&corot.0)),
        stopped,
    }
}

/// The Markdown table of the nonlinear tier's rows.
pub fn nonlinear_table(rows: &[NonlinearRow]) -> String {
    let mut s = String::from(
        "\n| resolution | nonlinear: ms / keyframe | factorizations | ms / factorization | \
         corotational: ms / keyframe | time ratio | volume change nonlinear / corotational | \
         largest bone reaction nonlinear / corotational N | skin gap max / RMS mm |\n\
         |---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        if let Some(e) = &r.stopped {
            let _ = writeln!(s, "| {} | stopped: {e} | | | | | | | |", r.resolution);
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | {:.0} | {} | {:.1} | {:.0} | {:.1}× | {:+.4} % / {:+.4} % | {:.3} / {:.3} | \
             {:.2} / {:.3} |",
            r.resolution,
            r.stats.total_ms,
            r.stats.factorizations,
            r.stats.total_ms / r.stats.factorizations.max(1) as f64,
            r.corotational_ms,
            r.stats.total_ms / r.corotational_ms.max(1e-9),
            r.volume_change[0] * 100.0,
            r.volume_change[1] * 100.0,
            r.reaction[0],
            r.reaction[1],
            r.skin_gap.0 * 1e3,
            r.skin_gap.1 * 1e3
        );
    }
    s
}
