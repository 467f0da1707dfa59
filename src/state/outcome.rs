//! The outcome of a grasp for the animator: which bone's reaction overruns the force its muscles
//! can hold, by how much, and which way the finger should move (the paper's "the reacting force
//! on bones can be used to suggest solutions to the animator"); and the contact force each part
//! of the hand receives.

use crate::hand::HandModel;
use nalgebra::{Isometry3, Point3, Vector3};
use serde::Serialize;

/// The parts of a hand the contact forces are summed over: palm, then the digits.
pub const PARTS: [&str; 6] = ["palm", "thumb", "index", "middle", "ring", "little"];

/// A bone whose reaction overruns its threshold.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Overload {
    /// The bone.
    pub bone: String,
    /// Magnitude of its reaction, N.
    pub reaction: f64,
    /// Its threshold, N.
    pub threshold: f64,
    /// By how much the reaction overruns it, N.
    pub excess: f64,
    /// Unit direction in which the flesh pushes the bone: what the object presses on it and the
    /// flesh's own resistance to the flexion (the finger should give way along it).
    pub push: [f64; 3],
    /// The joint whose muscles the push loads most.
    pub joint: String,
    /// Moment of the push about that joint, N·m (positive: towards larger angles).
    pub moment: f64,
    /// What to do, in words.
    pub advice: String,
}

/// Bones whose reaction magnitude exceeds their threshold (largest excess first).
/// `reactions` are the bones' reactions (equation (8): the force each bone exerts on the flesh),
/// `transforms` the bones' poses.
pub fn overloads(
    hand: &HandModel,
    transforms: &[Isometry3<f64>],
    reactions: &[Vector3<f64>],
    thresholds: &[f64],
) -> Vec<Overload> {
    let skeleton = &hand.skeleton;
    let mut out = Vec::new();
    for (b, r) in reactions.iter().enumerate() {
        let magnitude = r.norm();
        if magnitude <= thresholds[b] || magnitude == 0.0 {
            continue;
        }
        // The flesh pushes the bone with −R.
        let push = -r;
        let bone = &skeleton.bones[b];
        let at = (transforms[b] * Point3::from((bone.start + bone.end) / 2.0)).coords;
        // The joint (of this bone or one nearer the palm) on which the push turns hardest.
        let mut best: Option<(usize, f64)> = None;
        let mut chain = Some(b);
        while let Some(c) = chain {
            for (d, dof) in skeleton.dofs.iter().enumerate() {
                if dof.bone != c {
                    continue;
                }
                let centre = (transforms[c] * Point3::from(dof.center)).coords;
                let axis = transforms[c].rotation * dof.axis.into_inner();
                let moment = (at - centre).cross(&push).dot(&axis);
                if best.is_none_or(|(_, m)| moment.abs() > m.abs()) {
                    best = Some((d, moment));
                }
            }
            chain = skeleton.bones[c]
                .parent
                .filter(|&p| skeleton.bones[p].digit.is_some());
        }
        let (joint, moment) = match best {
            Some((d, m)) => (skeleton.dofs[d].name.clone(), m),
            None => (String::new(), 0.0),
        };
        let dir = push / push.norm();
        let advice = if joint.is_empty() {
            format!(
                "move the hand along ({:.2}, {:.2}, {:.2})",
                dir.x, dir.y, dir.z
            )
        } else {
            format!(
                "{} {joint}: the flesh pushes {} along ({:.2}, {:.2}, {:.2}) with {:.1} N, {:.1} N \
                 more than its muscles hold",
                if moment < 0.0 { "decrease" } else { "increase" },
                bone.name,
                dir.x,
                dir.y,
                dir.z,
                magnitude,
                magnitude - thresholds[b]
            )
        };
        out.push(Overload {
            bone: bone.name.clone(),
            reaction: magnitude,
            threshold: thresholds[b],
            excess: magnitude - thresholds[b],
            push: [dir.x, dir.y, dir.z],
            joint,
            moment,
            advice,
        });
    }
    out.sort_by(|a, b| b.excess.total_cmp(&a.excess));
    out
}

/// The bone a flesh node follows most (its attachment, or its largest skinning weight).
pub fn node_bone(hand: &HandModel, n: usize) -> usize {
    hand.flesh.node_bone[n].unwrap_or(hand.weights.weights[n][0].0)
}

/// Index into [`PARTS`] of contact-skin vertex `v`: the part of the bone leading its heaviest
/// node.
pub fn part_of_skin_vertex(hand: &HandModel, v: usize) -> usize {
    part_of_bone(hand, node_bone(hand, hand.contact_skin.heaviest_node(v)))
}

/// Index into [`PARTS`] of bone `b`.
pub fn part_of_bone(hand: &HandModel, b: usize) -> usize {
    hand.skeleton.bones[b].digit.map_or(0, |d| d + 1)
}

/// Why corrections at a pose ended unsettled, from where the last moved the bodies most `m`.
fn unsettled_cause(m: &super::UnsettledMotion) -> String {
    let node = format!(
        "node {} of body \"{}\" moved {:.3} mm in the last",
        m.node,
        m.body,
        m.moved * 1e3
    );
    if m.growing {
        format!(
            " (the last three corrections moved the bodies ever more, each more than the one \
             before: they drift away from the pose's contact rather than settle on it, {node}; a body \
             held at few nodes or a coarse, very soft body can turn or fold there)"
        )
    } else {
        format!(" (the corrections still swing: {node})")
    }
}

/// One warning per hand and frame whose keyframe ended short of its pose
/// ([`super::StoppedShort`]): how far its motion went and why; and one where the corrections at
/// the pose ended with its contact force still changing by more than
/// [`super::KeyframeStats::UNSETTLED_WARNING`], with how much; and one
/// per frame whose contact's active set was kept at the iteration cap.
pub fn keyframe_warnings(model: &crate::model::Model, frames: &[super::Frame]) -> Vec<String> {
    let mut out = Vec::new();
    for (i, frame) in frames.iter().enumerate() {
        if let Some(c) = frame.contact.as_ref().filter(|c| c.at_iteration_cap) {
            out.push(format!(
                "frame {i}: the contact's active set still changed after {} iterations \
                 (contacts that hardly touch joining and leaving in turn); the last settled set \
                 was kept: every contact pushes, penetration {:.1} µm (limit {:.1} µm)",
                c.iterations,
                c.max_penetration * 1e6,
                model.contact.penetration_limit() * 1e6
            ));
        }
        for h in &frame.hands {
            if let Some(change) = h
                .stats
                .unsettled_at_pose
                .filter(|&c| c > super::KeyframeStats::UNSETTLED_WARNING)
            {
                out.push(format!(
                    "frame {i}: the contact force of hand \"{}\" still changed by {:.2} % in the \
                     last of its {} corrections at the pose: its contact and bone forces are \
                     uncertain by about that much{}",
                    model.bodies[h.body].name,
                    change * 100.0,
                    h.stats.pose_corrections,
                    h.stats
                        .unsettled_motion
                        .as_ref()
                        .map(unsettled_cause)
                        .unwrap_or_default()
                ));
            }
            if let Some(reason) = &h.stats.correction_failed {
                out.push(format!(
                    "frame {i}: a correction at the pose of hand \"{}\" failed ({reason}); the \
                     frame is the last settled one ({} correction(s) kept){}",
                    model.bodies[h.body].name,
                    h.stats.pose_corrections,
                    match h.stats.unsettled_at_pose {
                        Some(c) => format!(
                            ": its contact and bone forces are uncertain by about {:.2} %",
                            c * 100.0
                        ),
                        None => String::new(),
                    }
                ));
            }
            if let Some(s) = &h.stats.stopped_short {
                out.push(format!(
                    "frame {i}: hand \"{}\" stopped at {:.0} % of its keyframe's motion (the \
                     grasp is not realisable further; the frame shows where it stopped): {}",
                    model.bodies[h.body].name,
                    s.reached * 100.0,
                    s.reason
                ));
            }
        }
    }
    out
}
