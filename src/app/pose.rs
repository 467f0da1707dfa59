//! The Joints panel's model: the hands of the scene (their skeletons give joint names and
//! limits without meshing anything), their angles, and the pose presets.

use super::jobs::Pose;
pub use crate::hand::digit_of;
use crate::hand::{HandForm, Side, Skeleton};
use crate::scene::{HandSide, Scene, Shape};

/// A hand body of the scene.
#[derive(Clone, Debug)]
pub struct HandInfo {
    /// Body index.
    pub body: usize,
    /// Body name.
    pub name: String,
    /// Its skeleton (joint names, limits and rests).
    pub skeleton: Skeleton,
}

/// The hands of `scene`.
pub fn hands_of(scene: &Scene) -> Vec<HandInfo> {
    scene
        .body
        .iter()
        .enumerate()
        .filter_map(|(b, def)| match &def.shape {
            Shape::Hand {
                side, gltf, form, ..
            } => {
                let mut skeleton = Skeleton::new(match side {
                    HandSide::Right => Side::Right,
                    HandSide::Left => Side::Left,
                });
                // The built-in hand's form decides its rest pose (the anatomical thumb's).
                let form = match (gltf, form) {
                    (None, form) => form
                        .as_deref()
                        .and_then(HandForm::from_name)
                        .unwrap_or_default(),
                    // An imported rig's thumb rests where the rig has it: no turn.
                    (Some(_), _) => HandForm::Simple,
                };
                skeleton.set_rest("thumb.cmc.abd", form.thumb_rest_abduction_deg());
                Some(HandInfo {
                    body: b,
                    name: def.name.clone(),
                    skeleton,
                })
            }
            _ => None,
        })
        .collect()
}

/// A named pose preset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Every joint at its rest (0°, but 20° for the anatomical thumb's abduction).
    Rest,
    /// A closed fist: every finger at MCP 88°, PIP 105°, DIP 70°, the thumb across
    /// ([`crate::hand::full_fist`]).
    Fist,
    /// Thumb and index tips brought together.
    Pinch,
    /// Fingers and thumb wrapped as around a ball.
    PowerGrasp,
}

impl Preset {
    /// Every preset.
    pub const ALL: [Preset; 4] = [
        Preset::Rest,
        Preset::Fist,
        Preset::Pinch,
        Preset::PowerGrasp,
    ];

    /// Button label.
    pub fn label(self) -> &'static str {
        match self {
            Preset::Rest => "Rest",
            Preset::Fist => "Fist",
            Preset::Pinch => "Pinch",
            Preset::PowerGrasp => "Power grasp",
        }
    }

    /// The angle of `joint` (degrees) in this preset, before clamping to its limits. Each preset
    /// is reached from rest in 10° increments without a crushed cell at resolution 1 (checked
    /// with `prehensile solve`: flesh volume change −0.89 % the full fist on the default
    /// scene's ball, +0.08 % pinch, −0.06 % power grasp).
    /// `None`: the preset leaves the joint at its rest ([`crate::hand::JointDof::rest`]: 0° but
    /// for the anatomical hand's thumb abduction).
    fn angle(self, joint: &str) -> Option<f64> {
        let finger = |mcp: f64, pip: f64, dip: f64| match joint.rsplit('.').next() {
            Some("flex") => mcp,
            Some("pip") => pip,
            Some("dip") => dip,
            _ => 0.0,
        };
        let thumb = |cmc_flex: f64, cmc_abd: f64, mcp: f64, ip: f64| match joint {
            "thumb.cmc.flex" => cmc_flex,
            "thumb.cmc.abd" => cmc_abd,
            "thumb.mcp" => mcp,
            "thumb.ip" => ip,
            _ => 0.0,
        };
        let is_thumb = digit_of(joint) == "thumb";
        match self {
            Preset::Rest => None,
            Preset::Fist => crate::hand::full_fist().get(joint).copied(),
            Preset::Pinch if is_thumb => Some(thumb(20.0, 40.0, 15.0, 20.0)),
            Preset::Pinch if digit_of(joint) == "index" => Some(finger(40.0, 45.0, 20.0)),
            Preset::Pinch => Some(finger(10.0, 15.0, 5.0)),
            Preset::PowerGrasp if is_thumb => Some(thumb(20.0, 35.0, 20.0, 15.0)),
            Preset::PowerGrasp => Some(finger(45.0, 50.0, 30.0)),
        }
    }

    /// The poses the preset goes through from `current` (joint angles of `skeleton`), each
    /// solved before the next is asked, within the joints' limits. One but for the Fist with the
    /// skin kept out of itself (`self_contact`): the fingers close first
    /// ([`crate::hand::four_finger_fist`], the thumb where it is), then the thumb folds over
    /// ([`crate::hand::thumb_over_fist`]) — the fist the flesh allows: closed together, the
    /// thumb's path runs through the index finger and its flesh is crushed.
    pub fn stages(self, skeleton: &Skeleton, current: &[f64], self_contact: bool) -> Vec<Vec<f64>> {
        if self != Preset::Fist || !self_contact {
            return vec![self.angles(skeleton)];
        }
        // `pose` over `from`: its joints set, the others of its digits (every finger, or the
        // thumb) at 0°, the rest as in `from`.
        let over = |pose: &crate::hand::Pose, thumb: bool, from: &[f64]| -> Vec<f64> {
            skeleton
                .dofs
                .iter()
                .zip(from)
                .map(|(d, a)| {
                    let angle = match pose.get(&d.name) {
                        Some(set) => *set,
                        None if (digit_of(&d.name) == "thumb") == thumb => d.rest,
                        None => *a,
                    };
                    angle.clamp(d.limits.min, d.limits.max)
                })
                .collect()
        };
        let fingers = over(&crate::hand::four_finger_fist(), false, current);
        let fingers_then = over(&crate::hand::thumb_over_fist(), true, &fingers);
        vec![fingers, fingers_then]
    }

    /// The joint angles of this preset for `skeleton`, within its limits.
    pub fn angles(self, skeleton: &Skeleton) -> Vec<f64> {
        skeleton
            .dofs
            .iter()
            .map(|d| {
                self.angle(&d.name)
                    .unwrap_or(d.rest)
                    .clamp(d.limits.min, d.limits.max)
            })
            .collect()
    }
}

/// What pressing `preset` asks from `pose` (every hand of `hands` at once): the first pose,
/// and the pose of its last stage ([`Preset::stages`]; the first again when it has one).
pub fn preset_poses(
    preset: Preset,
    hands: &[HandInfo],
    pose: &Pose,
    self_contact: bool,
) -> (Pose, Pose) {
    let mut first = pose.clone();
    let mut last = pose.clone();
    for (h, ((_, angles), (_, later))) in hands.iter().zip(first.iter_mut().zip(last.iter_mut())) {
        let mut stages = preset.stages(&h.skeleton, angles, self_contact).into_iter();
        *angles = stages.next().unwrap_or_default();
        *later = stages.last().unwrap_or_else(|| angles.clone());
    }
    (first, last)
}

/// The poses the presets would ask first from `pose`, but those it is at already, the
/// nearest first (by the largest joint change): what the solver may flex ahead while it waits.
pub fn preset_poses_ahead(hands: &[HandInfo], pose: &Pose, self_contact: bool) -> Vec<Pose> {
    let change = |to: &Pose| {
        pose.iter()
            .zip(to)
            .flat_map(|((_, a), (_, b))| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
            .fold(0.0, f64::max)
    };
    let mut ahead: Vec<(f64, Pose)> = Preset::ALL
        .iter()
        .map(|&p| preset_poses(p, hands, pose, self_contact).0)
        .map(|to| (change(&to), to))
        .filter(|(c, _)| *c > 0.0)
        .collect();
    ahead.sort_by(|a, b| a.0.total_cmp(&b.0));
    ahead.into_iter().map(|(_, to)| to).collect()
}

/// The pose of every hand at rest.
pub fn rest_pose(hands: &[HandInfo]) -> Pose {
    hands
        .iter()
        .map(|h| (h.body, h.skeleton.rest_angles()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::Side;

    #[test]
    fn presets_stay_within_limits_and_differ() {
        let s = Skeleton::new(Side::Right);
        let mut seen = Vec::new();
        for p in Preset::ALL {
            let a = p.angles(&s);
            assert_eq!(a.len(), 21);
            for (d, v) in s.dofs.iter().zip(&a) {
                assert!(*v >= d.limits.min && *v <= d.limits.max, "{} {v}", d.name);
            }
            assert!(!seen.contains(&a), "{p:?} repeats another preset");
            seen.push(a);
        }
        let fist = Preset::Fist.angles(&s);
        let pip = s.dofs.iter().position(|d| d.name == "index.pip").unwrap();
        assert_eq!(fist[pip], 105.0);
    }
}
