//! Whether a solved scene reached what it asks: the keyframes the contact could not follow to
//! their pose, and those whose contact could not be solved again at the pose. The command line
//! exits non-zero with these messages; tests assert there are none.

use super::solve::Solved;

/// Why `solved` did not reach what it asks ([`stopped_by_the_solver`], else
/// [`failed_at_a_pose`]), or `None`: the error `prehensile solve` exits with (code 2).
pub fn unsolved(solved: &Solved) -> Option<String> {
    stopped_by_the_solver(solved).or_else(|| failed_at_a_pose(solved))
}

/// The keyframes the contact solve could not follow to their pose (not those a bone's
/// threshold ended: a result), told as the error the command exits with (code 2: the frames are
/// written, up to where the motion stopped).
fn stopped_by_the_solver(solved: &Solved) -> Option<String> {
    let stops: Vec<String> = solved
        .frames
        .iter()
        .enumerate()
        .flat_map(|(i, f)| {
            f.hands
                .iter()
                .filter_map(move |h| {
                    let s = h.stats.stopped_short.as_ref().filter(|s| s.solver_limit)?;
                    // Frame 0 is the motion from rest to the body's `pose`: no keyframe.
                    let motion = if i == 0 {
                        "motion from rest to its `pose`"
                    } else {
                        "keyframe's motion"
                    };
                    Some(format!(
                        "frame {i} (t = {} s): hand \"{}\" stopped at {:.0} % of its {motion}: \
                             {}",
                        solved.report.frames[i].time,
                        solved.model.bodies[h.body].name,
                        s.reached * 100.0,
                        s.reason
                    ))
                })
                .collect::<Vec<_>>()
        })
        .collect();
    (!stops.is_empty()).then(|| {
        format!(
            "{}: the scene was not solved to its poses. {}. The frames written hold the motion \
             up to where it stopped; report.json gives the pose reached",
            solved.report.scene,
            stops.join("; "),
        )
    })
}

/// The keyframes where a correction at the pose failed (its contact solve could not be done:
/// a skin point deeper than the contact searches, an active set that did not settle) or the
/// corrections ended with the contact force still changing by more than
/// `KeyframeStats::UNSETTLED_WARNING`: told as the error the command exits with (code 2: the
/// frames are written, each the last settled state).
fn failed_at_a_pose(solved: &Solved) -> Option<String> {
    let mut causes = Vec::new();
    for (i, f) in solved.frames.iter().enumerate() {
        for h in &f.hands {
            let at = format!(
                "frame {i} (t = {} s), hand \"{}\"",
                solved.report.frames[i].time, solved.model.bodies[h.body].name
            );
            if h.stats.correction_failed.is_some() {
                causes.push(format!("{at}: a correction at the pose failed"));
            } else if let Some(c) = h
                .stats
                .unsettled_at_pose
                .filter(|&c| c > crate::state::KeyframeStats::UNSETTLED_WARNING)
            {
                causes.push(format!(
                    "{at}: the corrections at the pose did not settle ({:.2} % in the last)",
                    c * 100.0
                ));
            }
        }
    }
    (!causes.is_empty()).then(|| {
        format!(
            "{}: the contact could not be solved again at every pose ({}; the warnings above say \
             why). The frames are written, each the last settled state; report.json gives each \
             hand's `motion.correction_failed` and `motion.unsettled_at_pose`",
            solved.report.scene,
            causes.join("; "),
        )
    })
}
