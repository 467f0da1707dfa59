//! A keyframe's flexion along its motion, shared by its contact steps.
//!
//! The flexion of a hand does not see the contact (the contact's displacements are solved over
//! the flexed pose, src/solve/grasp.rs), so where the hand is along the keyframe is a matter of
//! its joint angles alone. The flexion is solved at its own increments — knots every
//! `max_step_deg` of the hand's largest joint motion, each one increment from the last, as
//! [`super::Flexion`] would march through the keyframe — and a contact step between two knots
//! takes the flesh carried by the bones from the knots on either side:
//!
//!   x(f) = Σ_b w_b · T_b(f) · [(1 − t) · T_b(f_i)⁻¹ · x_i + t · T_b(f_j)⁻¹ · x_j],
//!   t = (f − f_i) / (f_j − f_i),
//!
//! with w_b the node's skinning weights and T_b the bones' motions from rest (exact at the
//! knots and for flesh that moves rigidly with its bones); the reactions are interpolated
//! linearly. The contact steps along a motion (≤ 5° each) then cost no flexion of their own,
//! and a keyframe tried in one contact step and again in several flexes the hand once.

use super::error::SimError;
use super::proximity::PARTS;
use crate::hand::HandModel;
use crate::model::Model;
use crate::state::{HandState, KeyframeStats};
use nalgebra::{Point3, Vector3};

/// Flexes a hand body from a state to joint angles with some parts left to skinning: the
/// state reached, and what it cost.
pub(super) type Flex<'a> = dyn FnMut(usize, HandState, &[f64], [bool; PARTS]) -> Result<(HandState, KeyframeStats), SimError>
    + 'a;

/// One moving hand's flexion over a keyframe.
struct HandPath {
    /// The hand body.
    body: usize,
    /// Joint angles at the keyframe's start and end, degrees.
    from: Vec<f64>,
    to: Vec<f64>,
    /// Parts left to skinning over the whole keyframe (far from every other body, and not
    /// crushed by skinning).
    far: [bool; PARTS],
    /// Knots after the start.
    count: usize,
    /// The flexed states solved so far: the start, then knot j at fraction j / `count`.
    knots: Vec<HandState>,
    /// What the knots' flexion cost (`None` before the first).
    stats: Option<KeyframeStats>,
}

/// The flexion of a keyframe's moving hands, solved knot by knot as its contact steps need it.
pub(super) struct FlexionPath {
    hands: Vec<HandPath>,
}

impl FlexionPath {
    /// The path of each moving hand (body, angles from, angles to, its far parts) from `start`,
    /// its state at the keyframe's start; knots every `max_step_deg` of its largest motion.
    pub(super) fn new(
        model: &Model,
        moving: impl IntoIterator<Item = (usize, HandState, Vec<f64>, [bool; PARTS])>,
    ) -> FlexionPath {
        let hands = moving
            .into_iter()
            .map(|(body, start, to, far)| {
                let largest = start
                    .angles
                    .iter()
                    .zip(&to)
                    .map(|(a, b)| (b - a).abs())
                    .fold(0.0, f64::max);
                let count = (largest / model.flexion.max_step_deg - 1e-9)
                    .ceil()
                    .max(1.0) as usize;
                HandPath {
                    body,
                    from: start.angles.clone(),
                    to,
                    far,
                    count,
                    knots: vec![start],
                    stats: None,
                }
            })
            .collect();
        FlexionPath { hands }
    }

    /// What the flexion of hand `k` (in the order given to [`FlexionPath::new`]) cost so far.
    pub(super) fn stats(&self, k: usize) -> KeyframeStats {
        self.hands[k].stats.clone().unwrap_or_default()
    }

    /// Hand `k`'s state at fraction `f` of the keyframe: a knot's where `f` falls on one,
    /// carried by the bones from the knots on either side elsewhere. Knots not yet solved are
    /// flexed first by `flex` (hand body, the last knot's state, the next knot's angles, the
    /// parts left to skinning → the state reached and what it cost).
    pub(super) fn state_at(
        &mut self,
        model: &Model,
        k: usize,
        f: f64,
        flex: &mut Flex<'_>,
    ) -> Result<HandState, SimError> {
        let path = &mut self.hands[k];
        let count = path.count as f64;
        let position = (f * count).clamp(0.0, count);
        // The knot at or after f (round-off of the steps' fractions falls on the knot).
        let j = ((position - 1e-9).ceil().max(0.0) as usize).min(path.count);
        while path.knots.len() <= j {
            let next = path.knots.len();
            let angles = path.angles_at(next as f64 / count);
            let start = path.knots[next - 1].clone();
            let (state, stats) = flex(path.body, start, &angles, path.far)?;
            match &mut path.stats {
                Some(total) => total.absorb(&stats),
                None => path.stats = Some(stats),
            }
            path.knots.push(state);
        }
        if (position - j as f64).abs() < 1e-9 || j == 0 {
            return Ok(path.knots[j].clone());
        }
        let hand = model.bodies[path.body]
            .hand
            .as_deref()
            .expect("a hand body");
        let t = position - (j - 1) as f64;
        let angles = path.angles_at(f);
        Ok(between(
            hand,
            (&path.knots[j - 1], &path.knots[j]),
            t,
            angles,
        ))
    }
}

impl HandPath {
    /// The joint angles at fraction `f` (the end's exactly at 1).
    fn angles_at(&self, f: f64) -> Vec<f64> {
        if f >= 1.0 - 1e-12 {
            return self.to.clone();
        }
        self.from
            .iter()
            .zip(&self.to)
            .map(|(a, b)| a + (b - a) * f)
            .collect()
    }
}

/// The hand at `angles`, fraction `t` of the way between the flexed states `a` and `b`: each
/// node carried by its skinning bones from both (see the module's formula), the reactions
/// interpolated.
fn between(
    hand: &HandModel,
    (a, b): (&HandState, &HandState),
    t: f64,
    angles: Vec<f64>,
) -> HandState {
    let transforms = hand.skeleton.transforms(&angles);
    let positions = (0..a.positions.len())
        .map(|n| {
            let weights = &hand.weights.weights[n];
            let total: f64 = weights.iter().map(|w| w.1).sum();
            let mut x = Vector3::zeros();
            for &(bone, w) in weights {
                let from_a =
                    a.transforms[bone].inverse_transform_point(&Point3::from(a.positions[n]));
                let from_b =
                    b.transforms[bone].inverse_transform_point(&Point3::from(b.positions[n]));
                let local = from_a.coords * (1.0 - t) + from_b.coords * t;
                x += transforms[bone]
                    .transform_point(&Point3::from(local))
                    .coords
                    * (w / total);
            }
            x
        })
        .collect();
    let reaction = a
        .reaction
        .iter()
        .zip(&b.reaction)
        .map(|(ra, rb)| ra * (1.0 - t) + rb * t)
        .collect();
    HandState {
        angles,
        transforms,
        positions,
        reaction,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::Side;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    /// Flesh that moves rigidly with its bones between two states is carried exactly: every
    /// node of the hand turned with its bones as skinning moves it.
    #[test]
    fn flesh_moving_with_its_bones_is_carried_exactly_between_knots() {
        let hand = HandModel::new(Side::Right, 0.75).unwrap();
        let rest = HandState::rest(&hand);
        // A rigid motion of the whole hand: every bone alike, so skinning is that motion.
        let motion = |s: f64| {
            Isometry3::from_parts(
                Translation3::new(0.01 * s, -0.02 * s, 0.005 * s),
                UnitQuaternion::from_euler_angles(0.3 * s, -0.2 * s, 0.5 * s),
            )
        };
        let at = |s: f64| HandState {
            angles: rest.angles.clone(),
            transforms: vec![motion(s); rest.transforms.len()],
            positions: rest
                .positions
                .iter()
                .map(|p| motion(s).transform_point(&Point3::from(*p)).coords)
                .collect(),
            reaction: vec![Vector3::new(s, 0.0, -s); rest.positions.len()],
        };
        let (a, b) = (at(0.0), at(1.0));
        // `between` takes the angles' transforms; for a rigid motion of all bones, compare the
        // carried positions with the motion at the same fraction applied by hand.
        let carried = between(&hand, (&a, &b), 0.5, rest.angles.clone());
        for (n, p) in carried.positions.iter().enumerate() {
            assert!((p - rest.positions[n]).norm() < 1e-12, "node {n}");
        }
        assert!((carried.reaction[0] - Vector3::new(0.5, 0.0, -0.5)).norm() < 1e-15);
        // At the knots, the knots themselves.
        for (t, knot) in [(0.0, &a), (1.0, &b)] {
            let there = between(&hand, (&a, &b), t, rest.angles.clone());
            let moved = |p: &Vector3<f64>| {
                let m = if t == 0.0 { motion(0.0) } else { motion(1.0) };
                m.inverse_transform_point(&Point3::from(*p)).coords
            };
            for (n, p) in there.positions.iter().enumerate() {
                assert!((p - moved(&knot.positions[n])).norm() < 1e-12, "node {n}");
            }
        }
    }
}
