//! A hand's skeleton described by its joints: where each joint is in the hand frame and how thick
//! each bone is. The built-in hand's comes from its anatomy tables; an imported rig's from its
//! joint nodes and its skin (`imported.rs`). `Skeleton::from_joints` builds bones and joint
//! axes from either alike.

use super::anatomy::{CARPUS, FINGERS, THUMB};
use super::form::HandForm;
use super::stretch::Stretch;
use nalgebra::{UnitQuaternion, Vector3};

/// The joints of a right hand in its frame (x from the wrist towards the finger tips, y towards
/// the thumb, z dorsal), m, and the sizes of its bones. A left hand is built as the right one and
/// mirrored in y.
#[derive(Clone, Debug, PartialEq)]
pub struct RigJoints {
    /// The carpus (the wrist bones as one rigid block): centre, half extents along its axes, and
    /// the rotation of its axes from the hand frame's.
    pub carpus: (Vector3<f64>, [f64; 3], UnitQuaternion<f64>),
    /// Per digit (thumb first), joint points from its carpometacarpal joint to its tip: four for
    /// the thumb (CMC, MCP, IP, tip), five for a finger (CMC, MCP, PIP, DIP, tip).
    pub digits: [Vec<Vector3<f64>>; 5],
    /// Per digit, the shaft radius of each of its bones (metacarpal first), m.
    pub shafts: [Vec<f64>; 5],
    /// Rotation of the thumb's nail about the thumb's axis away from the dorsal normal, degrees.
    pub thumb_pronation_deg: f64,
}

impl RigJoints {
    /// The built-in adult hand's joints (`anatomy.rs`).
    pub fn builtin() -> RigJoints {
        RigJoints::builtin_of(HandForm::Simple)
    }

    /// The built-in hand's joints in `form` (the anatomical form's thumb at its natural rest).
    fn builtin_of(form: HandForm) -> RigJoints {
        let d = form.thumb_direction();
        let mut thumb = vec![Vector3::from(THUMB.cmc)];
        for len in THUMB.bones {
            let last = *thumb.last().unwrap();
            thumb.push(last + d * len);
        }
        let mut digits: [Vec<Vector3<f64>>; 5] = Default::default();
        let mut shafts: [Vec<f64>; 5] = Default::default();
        digits[0] = thumb;
        shafts[0] = THUMB.shaft.to_vec();
        for (f, finger) in FINGERS.iter().enumerate() {
            let mcp = Vector3::new(finger.mcp[0], finger.mcp[1], 0.0);
            let mut points = vec![Vector3::new(finger.base[0], finger.base[1], 0.0), mcp];
            let mut start = mcp;
            for len in finger.phalanges {
                start += Vector3::x() * len;
                points.push(start);
            }
            digits[f + 1] = points;
            shafts[f + 1] = std::iter::once(finger.shaft[0] * 1.05)
                .chain(finger.shaft)
                .collect();
        }
        let (c, h) = CARPUS;
        RigJoints {
            carpus: (Vector3::from(c), h, UnitQuaternion::identity()),
            digits,
            shafts,
            thumb_pronation_deg: THUMB.pronation_deg,
        }
    }

    /// The built-in hand's joints stretched to another size: joint points and the carpus by
    /// `stretch`, bone radii by its radial factor.
    pub fn builtin_sized(stretch: Stretch) -> RigJoints {
        RigJoints::builtin_form(stretch, HandForm::Simple)
    }

    /// [`RigJoints::builtin_sized`] in `form`.
    pub fn builtin_form(stretch: Stretch, form: HandForm) -> RigJoints {
        let mut joints = RigJoints::builtin_of(form);
        let (c, h, axes) = joints.carpus;
        joints.carpus = (
            stretch.apply(&c),
            [0, 1, 2].map(|k| h[k] * stretch.scale[k]),
            axes,
        );
        for points in &mut joints.digits {
            for p in points.iter_mut() {
                *p = stretch.apply(p);
            }
        }
        for radii in &mut joints.shafts {
            for r in radii.iter_mut() {
                *r *= stretch.radial();
            }
        }
        joints
    }
}
