//! Keyframes: the full joint angles of a hand at given times.

use super::names::shown;
use super::{BodyModel, KeyframeModel};
use crate::scene::Scene;

/// The keyframes, validated: increasing times, an existing hand, known joints within limits.
pub fn keyframes(
    scene: &Scene,
    bodies: &[BodyModel],
) -> Result<Vec<KeyframeModel>, (String, String)> {
    let hands: Vec<usize> = (0..bodies.len())
        .filter(|&b| bodies[b].hand.is_some())
        .collect();
    let mut angles: Vec<Vec<f64>> = bodies.iter().map(|b| b.initial_angles.clone()).collect();
    let mut out: Vec<KeyframeModel> = Vec::new();
    for (i, k) in scene.keyframe.iter().enumerate() {
        let field = format!("keyframe[{i}]");
        if !(k.time.is_finite() && k.time >= 0.0 && (k.time as f32).is_finite()) {
            return Err((
                format!("{field}.time"),
                format!("must be a time ≥ 0 s and below 3.4e38 s, got {}", k.time),
            ));
        }
        // Distinct times stay distinct in the animation's 32-bit floats (glTF), the first
        // frame's 0 s included.
        let before = out.last().map_or(0.0, |l| l.time);
        if k.time > before && (k.time as f32) <= (before as f32) {
            return Err((
                format!("{field}.time"),
                format!(
                    "{} s and the previous frame's {} s are one time in an animation's 32-bit \
                     floats: keep keyframe times between 1e-6 s and 1e6 s, or further apart",
                    k.time, before
                ),
            ));
        }
        if let Some(last) = out.last() {
            if k.time < last.time {
                return Err((
                    format!("{field}.time"),
                    format!(
                        "{} s comes before the previous keyframe's {} s: list keyframes in time order",
                        k.time, last.time
                    ),
                ));
            }
        }
        let body =
            match &k.body {
                Some(name) => {
                    let Some(b) = bodies.iter().position(|b| &b.name == name) else {
                        return Err((
                            format!("{field}.body"),
                            format!("no body named \"{}\"", shown(name)),
                        ));
                    };
                    if bodies[b].hand.is_none() {
                        return Err((
                            format!("{field}.body"),
                            format!("body \"{}\" is not a hand", shown(name)),
                        ));
                    }
                    b
                }
                None => match hands.as_slice() {
                    [b] => *b,
                    [] => return Err((
                        field,
                        "the scene has no hand to pose (add a body with shape = { hand = { side \
                         = \"right\" } })"
                            .into(),
                    )),
                    _ => {
                        return Err((
                            format!("{field}.body"),
                            "the scene has several hands: name the one this keyframe poses".into(),
                        ))
                    }
                },
            };
        if out
            .last()
            .is_some_and(|l| l.time == k.time && l.body == body)
        {
            return Err((
                format!("{field}.time"),
                format!("a keyframe at {} s already poses this hand", k.time),
            ));
        }
        let hand = bodies[body].hand.as_ref().unwrap();
        let grasp = match &k.grasp {
            Some(def) => Some(Box::new(super::grasp::grasp(
                def,
                &k.pose,
                &field,
                bodies,
                scene.world.gravity,
                &hand.skeleton,
                &mut angles[body],
            )?)),
            None => {
                angles[body] = hand
                    .skeleton
                    .apply_pose(&angles[body], &k.pose)
                    .map_err(|e| (format!("{field}.pose"), e.to_string()))?;
                None
            }
        };
        out.push(KeyframeModel {
            time: k.time,
            body,
            angles: angles[body].clone(),
            grasp,
        });
    }
    Ok(out)
}
