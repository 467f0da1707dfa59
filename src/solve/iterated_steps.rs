//! Contact steps iterated along the motion, on the nonlinear tier.
//!
//! A contact step along a keyframe's motion is one Newton iteration of the bodies (and the
//! flesh near the contact) about where the last step left them; only the pose's corrections
//! iterate to equilibrium. Where the Neo-Hookean bodies are squeezed hard the steps drift
//! from it, one after the other: the soft solid ball pressed by the index to MCP 38°
//! (tests/soft_ball_press.rs) reached its pose at a 2× overestimated press, and the first
//! correction from there pushed a skin point through the ball's folded facets — it failed, and
//! the keyframe kept the drifted frame. Such a keyframe, one whose corrections at the pose
//! failed or did not settle or whose motion the contact could not follow, is followed again
//! with each step short of the pose corrected once at its own pose (two Newton iterations per
//! increment): the pose is reached nearer equilibrium. The attempt that ends better
//! ([`better`]) is kept. Keyframes that settle pay nothing.

use crate::state::{Frame, KeyframeStats};

/// How a keyframe ended, worst first when compared: how far its motion went (1 when it reached
/// its pose, or stopped by a bone's threshold, which is the grasp's limit, not the solver's),
/// whether no correction at its pose failed, and the last correction's change negated (0 when
/// settled).
fn outcome(stats: &KeyframeStats) -> (f64, bool, f64) {
    let reached = stats
        .stopped_short
        .as_ref()
        .filter(|s| s.solver_limit)
        .map_or(1.0, |s| s.reached);
    // (A change that is not a number counts as unsettled, the most.)
    let change = stats
        .unsettled_at_pose
        .map(|c| if c.is_nan() { f64::INFINITY } else { c })
        .filter(|&c| c > KeyframeStats::UNSETTLED_WARNING)
        .unwrap_or(0.0);
    (reached, stats.correction_failed.is_none(), -change)
}

/// Outcomes in their order (worse first), total over every value.
fn ordered(a: &(f64, bool, f64), b: &(f64, bool, f64)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0)
        .then(a.1.cmp(&b.1))
        .then(a.2.total_cmp(&b.2))
}

/// The stats in `frame` of the hands whose bodies are `bodies` (the keyframe's moving hands).
fn moving_stats<'f>(
    frame: &'f Frame,
    bodies: &'f [usize],
) -> impl Iterator<Item = &'f KeyframeStats> + 'f {
    bodies.iter().filter_map(move |&body| {
        frame
            .hands
            .iter()
            .find(|x| x.body == body)
            .map(|x| &x.stats)
    })
}

/// Whether a moving hand's keyframe (`bodies`: the moving hands' bodies) ended short of
/// settled: its motion stopped by the solver, a correction at its pose failed, or the last
/// changed its force by more than the report warns of.
pub(super) fn unsettled(frame: &Frame, bodies: &[usize]) -> bool {
    moving_stats(frame, bodies).any(|s| outcome(s) != (1.0, true, 0.0))
}

/// Whether `again` ended better than `first`: its worst moving hand's outcome is better
/// (further along the motion, then no correction failed, then settled closer).
pub(super) fn better(again: &Frame, first: &Frame, bodies: &[usize]) -> bool {
    let worst = |frame: &Frame| moving_stats(frame, bodies).map(outcome).min_by(ordered);
    match (worst(again), worst(first)) {
        (Some(a), Some(b)) => ordered(&a, &b).is_gt(),
        (Some(_), None) => true,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::{ordered, outcome};
    use crate::state::{KeyframeStats, StoppedShort};

    #[test]
    fn a_keyframe_further_along_then_without_failure_then_settled_closer_ends_better() {
        let settled = KeyframeStats::default();
        let swinging = KeyframeStats {
            unsettled_at_pose: Some(0.04),
            ..KeyframeStats::default()
        };
        let failed = KeyframeStats {
            correction_failed: Some("a point 0.9 mm inside".into()),
            ..KeyframeStats::default()
        };
        let short = KeyframeStats {
            stopped_short: Some(StoppedShort {
                reached: 0.88,
                reason: "the contact could not follow".into(),
                solver_limit: true,
            }),
            ..KeyframeStats::default()
        };
        let by_threshold = KeyframeStats {
            stopped_short: Some(StoppedShort {
                reached: 0.5,
                reason: "a bone's reaction overran its muscle threshold".into(),
                solver_limit: false,
            }),
            ..KeyframeStats::default()
        };
        assert_eq!(outcome(&settled), (1.0, true, 0.0));
        // A bone's threshold is the grasp's limit: as settled as a pose reached.
        assert_eq!(outcome(&by_threshold), outcome(&settled));
        let better =
            |a: &KeyframeStats, b: &KeyframeStats| ordered(&outcome(a), &outcome(b)).is_gt();
        assert!(better(&settled, &swinging));
        assert!(better(&swinging, &failed));
        assert!(better(&failed, &short));
        // A change that is not a number is the most unsettled.
        let nan = KeyframeStats {
            unsettled_at_pose: Some(f64::NAN),
            ..KeyframeStats::default()
        };
        assert!(better(&swinging, &nan) && better(&nan, &failed));
        // Under the report's warning, a change counts as settled.
        let within = KeyframeStats {
            unsettled_at_pose: Some(0.5 * KeyframeStats::UNSETTLED_WARNING),
            ..KeyframeStats::default()
        };
        assert_eq!(outcome(&within), outcome(&settled));
    }
}
