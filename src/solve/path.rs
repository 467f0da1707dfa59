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
//! and a keyframe tried in one contact step and again in several flexes the hand once. Where
//! the flesh so carried turns a cell inside out that neither knot does (a crease cell nearly
//! flat at both), the step's pose is flexed from the knot before instead.
//!
//! The knots depend on the contact steps in nothing: while the contact steps solve, the knots
//! they will need next are flexed ahead on another thread ([`flex_ahead`]), one knot after the
//! other in the order of their fractions, and taken in that order as the steps ask for them.
//! The states are those flexed in turn (the same increments from the same states with the same
//! caches); only the waiting goes.

use super::error::SimError;
use super::proximity::PARTS;
use crate::hand::HandModel;
use crate::model::Model;
use crate::state::{HandState, KeyframeStats};
use nalgebra::{Point3, Vector3};
use std::collections::VecDeque;
use std::sync::mpsc::{Receiver, Sender};

/// Flexes a hand body from a state to joint angles with some parts left to skinning (its FEM
/// region chosen on given flesh positions): the state reached, and what it cost.
pub(super) type Flex<'a> = dyn FnMut(usize, HandState, &[f64], Parts<'_>) -> Result<(HandState, KeyframeStats), SimError>
    + 'a;

/// Which parts a knot leaves to skinning, and the flesh its FEM region is chosen on (where the
/// keyframe starts: every knot of a keyframe solves the same cells).
pub(super) type Parts<'a> = ([bool; PARTS], &'a [Vector3<f64>]);

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
    /// The thumb after the fingers: (the fingers' knots, which joints are the thumb's). The
    /// fingers (every joint but the thumb's) reach their angles at knot `fingers` (fraction
    /// fingers / count), where the thumb starts; that knot's flesh chooses the FEM region of the
    /// thumb's knots as the keyframe's start chooses the fingers' (as two keyframes would).
    /// `None`: every joint at once.
    staged: Option<(usize, Vec<bool>)>,
    /// The flexed states solved so far: the start, then knot j at fraction j / `count`.
    knots: Vec<HandState>,
    /// What the knots' flexion cost (`None` before the first).
    stats: Option<KeyframeStats>,
}

/// Where a knot a step needs is (`FlexionPath::knot_at`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Knot {
    /// Flexed (or received from the thread flexing ahead).
    Flexed,
    /// Still flexing on the thread flexing ahead.
    Ahead,
    /// To be flexed by the step's own thread.
    Here,
}

/// A knot flexed: its state and what it cost, or why it failed.
type Flexed = Result<(HandState, KeyframeStats), SimError>;

/// The flexion of a keyframe's moving hands, solved knot by knot as its contact steps need it.
pub(super) struct FlexionPath {
    hands: Vec<HandPath>,
    /// Knots flexed ahead on another thread (hand, knot), each hand's in its order; `None`
    /// without, or once that thread has ended and every knot it sent is taken.
    ahead: Option<Receiver<(usize, Flexed)>>,
    /// Knots received ahead of a hand's turn, by hand.
    waiting: Vec<VecDeque<Flexed>>,
}

/// What flexing one hand's knots ahead needs: the hand's index in the path, its body, its
/// start, the joint angles of each knot after it, the parts left to skinning and the flesh the
/// FEM region is chosen on.
pub(super) struct AheadHand {
    k: usize,
    body: usize,
    start: HandState,
    angles: Vec<Vec<f64>>,
    far: [bool; PARTS],
    region_at: Vec<Vector3<f64>>,
    /// The index in `angles` of the knot whose flexed flesh chooses the region of the knots
    /// after it (the thumb's stage starting there), if it is among them.
    region_after: Option<usize>,
}

/// Flexes the knots of `hands` one after the other by `flex`, in the order of their fractions
/// of the keyframe (a hand's in its own order), each from the last of its hand, and sends each
/// to the path as it is flexed. Stops at the first that fails, or when the path is gone.
pub(super) fn flex_ahead(
    hands: Vec<AheadHand>,
    flex: &mut Flex<'_>,
    to_path: Sender<(usize, Flexed)>,
) {
    let mut order: Vec<(f64, usize, usize)> = hands
        .iter()
        .enumerate()
        .flat_map(|(i, h)| {
            let count = h.angles.len();
            (0..count).map(move |j| ((j + 1) as f64 / count as f64, i, j))
        })
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut last: Vec<HandState> = hands.iter().map(|h| h.start.clone()).collect();
    let mut region: Vec<Vec<Vector3<f64>>> = hands.iter().map(|h| h.region_at.clone()).collect();
    for (_, i, j) in order {
        let h = &hands[i];
        let flexed = flex(h.body, last[i].clone(), &h.angles[j], (h.far, &region[i]));
        let failed = flexed.is_err();
        if let Ok((state, _)) = &flexed {
            last[i] = state.clone();
            if h.region_after == Some(j) {
                region[i] = state.positions.clone();
            }
        }
        if to_path.send((h.k, flexed)).is_err() || failed {
            return;
        }
    }
}

impl FlexionPath {
    /// The path of each moving hand (body, angles from, angles to, its far parts) from `start`,
    /// its state at the keyframe's start; knots every `max_step_deg` of its largest motion.
    /// `thumb_after_fingers`: where both the thumb and the fingers move, the fingers go first
    /// and the thumb after them ([`staged_count`]).
    pub(super) fn new(
        model: &Model,
        moving: impl IntoIterator<Item = (usize, HandState, Vec<f64>, [bool; PARTS])>,
        thumb_after_fingers: bool,
    ) -> FlexionPath {
        let step = model.flexion.max_step_deg;
        let hands = moving
            .into_iter()
            .map(|(body, start, to, far)| {
                let largest = largest_motion(&start.angles, &to, |_| true);
                let count = knots_for(largest, step);
                let staged = thumb_after_fingers
                    .then(|| {
                        let thumb = thumb_dofs(model, body);
                        staged_count(&start.angles, &to, &thumb, step).map(|c| (c, thumb))
                    })
                    .flatten();
                let (count, staged) = match staged {
                    Some(((fingers, thumbs), thumb)) => (fingers + thumbs, Some((fingers, thumb))),
                    None => (count, None),
                };
                HandPath {
                    body,
                    from: start.angles.clone(),
                    to,
                    far,
                    count,
                    staged,
                    knots: vec![start],
                    stats: None,
                }
            })
            .collect::<Vec<_>>();
        FlexionPath {
            waiting: hands.iter().map(|_| VecDeque::new()).collect(),
            hands,
            ahead: None,
        }
    }

    /// The knots still to flex, for [`flex_ahead`]; `None` where flexing them ahead gains
    /// nothing (no hand has more than one).
    pub(super) fn ahead_plan(&self) -> Option<Vec<AheadHand>> {
        if self.hands.iter().all(|h| h.count - (h.knots.len() - 1) < 2) {
            return None;
        }
        Some(self.knots_to_flex())
    }

    /// Every knot still to flex, as [`flex_ahead`] takes them.
    pub(super) fn knots_to_flex(&self) -> Vec<AheadHand> {
        self.hands
            .iter()
            .enumerate()
            .map(|(k, h)| {
                let first = h.knots.len();
                // The knot choosing the next one's region: already flexed, or flexed ahead
                // (then the knots after it take its flesh).
                let chooser = h.region_knot(first);
                let (region_at, region_after) = match h.staged.as_ref() {
                    Some(&(fingers, _)) if fingers >= first => {
                        (h.knots[0].positions.clone(), Some(fingers - first))
                    }
                    _ => (h.knots[chooser].positions.clone(), None),
                };
                AheadHand {
                    k,
                    body: h.body,
                    start: h.knots.last().expect("the start").clone(),
                    angles: (first..=h.count)
                        .map(|j| h.angles_at(j as f64 / h.count as f64))
                        .collect(),
                    far: h.far,
                    region_at,
                    region_after,
                }
            })
            .collect()
    }

    /// Takes the knots [`flex_ahead`] sends on `from` (planned by
    /// [`FlexionPath::ahead_plan`] on this path as it is now).
    pub(super) fn take_ahead(&mut self, from: Receiver<(usize, Flexed)>) {
        self.ahead = Some(from);
    }

    /// Stops taking knots flexed ahead (their thread is to end).
    pub(super) fn end_ahead(&mut self) {
        self.ahead = None;
    }

    /// Where the knot [`FlexionPath::state_at`] of hand `k` at fraction `f` needs is: flexed, on
    /// the other thread still, or to be flexed here.
    pub(super) fn knot_at(&mut self, k: usize, f: f64) -> Knot {
        let count = self.hands[k].count as f64;
        let position = (f * count).clamp(0.0, count);
        let j = ((position - 1e-9).ceil().max(0.0) as usize).min(self.hands[k].count);
        if self.hands[k].knots.len() > j {
            return Knot::Flexed;
        }
        if let Some(ahead) = self.ahead.as_ref() {
            // (Knots already sent are taken, in their order, as `next_ahead` takes them; a
            // thread that ended sends no more, and its knots are flexed here.)
            loop {
                match ahead.try_recv() {
                    Ok((i, knot)) => self.waiting[i].push_back(knot),
                    Err(std::sync::mpsc::TryRecvError::Empty) => break,
                    Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                        self.ahead = None;
                        break;
                    }
                }
            }
            if self.ahead.is_some() && self.waiting[k].is_empty() {
                return Knot::Ahead;
            }
        }
        if self.waiting[k].is_empty() {
            Knot::Here
        } else {
            Knot::Flexed
        }
    }

    /// Flexes hand `k`'s knots up to fraction `f` now, as [`Self::state_at`] would (a knot
    /// flexed before the step that needs it); a knot that fails is kept failed, for that step
    /// to tell why without flexing it again. Whether it was flexed.
    pub(super) fn flex_to(&mut self, model: &Model, k: usize, f: f64, flex: &mut Flex<'_>) -> bool {
        match self.state_at(model, k, f, flex) {
            Ok(_) => true,
            Err(e) => {
                self.waiting[k].push_front(Err(e));
                false
            }
        }
    }

    /// Hand `k`'s next knot flexed ahead, if any is still to come.
    fn next_ahead(&mut self, k: usize) -> Option<Flexed> {
        if let Some(knot) = self.waiting[k].pop_front() {
            return Some(knot);
        }
        loop {
            match self.ahead.as_ref()?.recv() {
                Ok((i, knot)) if i == k => return Some(knot),
                Ok((i, knot)) => self.waiting[i].push_back(knot),
                // The thread ended (a knot failed, or none is left): on here in turn.
                Err(_) => {
                    self.ahead = None;
                    return None;
                }
            }
        }
    }

    /// What the flexion of hand `k` (in the order given to [`FlexionPath::new`]) cost so far.
    pub(super) fn stats(&self, k: usize) -> KeyframeStats {
        let mut stats = self.hands[k].stats.clone().unwrap_or_default();
        stats.thumb_after_fingers = self.hands[k].is_staged();
        stats
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
        let count = self.hands[k].count as f64;
        let position = (f * count).clamp(0.0, count);
        // The knot at or after f (round-off of the steps' fractions falls on the knot).
        let j = ((position - 1e-9).ceil().max(0.0) as usize).min(self.hands[k].count);
        while self.hands[k].knots.len() <= j {
            let (state, stats) = match self.next_ahead(k) {
                Some(flexed) => flexed?,
                None => {
                    let path = &self.hands[k];
                    let next = path.knots.len();
                    let angles = path.angles_at(next as f64 / count);
                    let start = path.knots[next - 1].clone();
                    flex(
                        path.body,
                        start,
                        &angles,
                        (path.far, &path.knots[path.region_knot(next)].positions),
                    )?
                }
            };
            let path = &mut self.hands[k];
            match &mut path.stats {
                Some(total) => total.absorb(&stats),
                None => path.stats = Some(stats),
            }
            path.knots.push(state);
        }
        let path = &self.hands[k];
        if (position - j as f64).abs() < 1e-9 || j == 0 {
            return Ok(path.knots[j].clone());
        }
        let hand = model.bodies[path.body]
            .hand
            .as_deref()
            .expect("a hand body");
        let t = position - (j - 1) as f64;
        let angles = path.angles_at(f);
        let knots = (&path.knots[j - 1], &path.knots[j]);
        let carried = between(hand, knots, t, angles.clone());
        if !turned_inside_out(hand, knots, &carried) {
            return Ok(carried);
        }
        // Flesh nearly flat in a crease may be carried through zero volume between two knots
        // where it is not (a cell of the middle finger's MCP crease, the nonlinear Power grasp
        // at resolution 1.5, then refused by the contact step's linearisation): flexed from the
        // knot before instead, at this step's own angles (kept for this step only).
        let start = knots.0.clone();
        let (far, region) = (path.far, path.region_knot(j));
        let region = self.hands[k].knots[region].positions.clone();
        // (Where that flexion fails, the carried flesh as before: the step tells of it.)
        let (state, stats) = match flex(self.hands[k].body, start, &angles, (far, &region)) {
            Ok(flexed) => flexed,
            Err(SimError::Cancelled) => return Err(SimError::Cancelled),
            Err(_) => return Ok(carried),
        };
        if let Some(total) = &mut self.hands[k].stats {
            total.absorb(&stats);
        }
        Ok(state)
    }
}

/// Whether `carried`, the flesh carried between the knots `a` and `b`, turns a cell inside out
/// (a Gauss point's det J ≤ 0) that neither knot does.
fn turned_inside_out(
    hand: &HandModel,
    (a, b): (&HandState, &HandState),
    carried: &HandState,
) -> bool {
    use crate::fem::hex8::relative_min_jacobian;
    use rayon::prelude::*;
    let cells = &hand.flesh.mesh.cells;
    let flat = |state: &HandState, c: usize| {
        relative_min_jacobian(&cells[c].map(|n| state.positions[n])) <= 0.0
    };
    (0..cells.len())
        .into_par_iter()
        .any(|c| flat(carried, c) && !flat(a, c) && !flat(b, c))
}

/// The largest change of the joints `which` picks from `from` to `to`, degrees.
fn largest_motion(from: &[f64], to: &[f64], which: impl Fn(usize) -> bool) -> f64 {
    from.iter()
        .zip(to)
        .enumerate()
        .filter(|(i, _)| which(*i))
        .map(|(_, (a, b))| (b - a).abs())
        .fold(0.0, f64::max)
}

/// Knots for a motion of `largest` degrees at most `step` apart (at least one).
fn knots_for(largest: f64, step: f64) -> usize {
    (largest / step - 1e-9).ceil().max(1.0) as usize
}

/// Which joints of hand body `body` are its thumb's.
fn thumb_dofs(model: &Model, body: usize) -> Vec<bool> {
    let hand = model.bodies[body].hand.as_deref().expect("a hand body");
    hand.skeleton
        .dofs
        .iter()
        .map(|d| crate::hand::digit_of(&d.name) == "thumb")
        .collect()
}

/// The knots of a keyframe from `from` to `to` with the fingers first and the thumb after them
/// (`thumb`: its joints), each stage at most `step` degrees a knot: (the fingers', the
/// thumb's); `None` where only one of them moves.
fn staged_count(from: &[f64], to: &[f64], thumb: &[bool], step: f64) -> Option<(usize, usize)> {
    let fingers = largest_motion(from, to, |i| !thumb[i]);
    let thumbs = largest_motion(from, to, |i| thumb[i]);
    (fingers > 0.0 && thumbs > 0.0).then(|| (knots_for(fingers, step), knots_for(thumbs, step)))
}

/// Whether hand body `body` moving from `from` to `to` moves both its thumb and a finger (a
/// keyframe [`FlexionPath::new`] can stage).
pub(super) fn thumb_and_fingers_move(model: &Model, body: usize, from: &[f64], to: &[f64]) -> bool {
    staged_count(
        from,
        to,
        &thumb_dofs(model, body),
        model.flexion.max_step_deg,
    )
    .is_some()
}

impl HandPath {
    /// The joint angles at fraction `f` (the end's exactly at 1): every joint along its way
    /// at once, or in two stages, the fingers over the first, then the thumb.
    fn angles_at(&self, f: f64) -> Vec<f64> {
        if f >= 1.0 - 1e-12 {
            return self.to.clone();
        }
        let along = |i: usize| match &self.staged {
            None => f,
            Some((fingers, thumb)) => {
                let split = *fingers as f64 / self.count as f64;
                if thumb[i] {
                    ((f - split) / (1.0 - split)).clamp(0.0, 1.0)
                } else {
                    (f / split).min(1.0)
                }
            }
        };
        self.from
            .iter()
            .zip(&self.to)
            .enumerate()
            .map(|(i, (a, b))| a + (b - a) * along(i))
            .collect()
    }

    /// Whether the thumb closes after the fingers on this path.
    fn is_staged(&self) -> bool {
        self.staged.is_some()
    }

    /// The knot whose flesh chooses the FEM region of knot `j`: the keyframe's start, or in the
    /// thumb's stage the knot it starts from.
    fn region_knot(&self, j: usize) -> usize {
        match &self.staged {
            Some((fingers, _)) if j > *fingers => *fingers,
            _ => 0,
        }
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
        self_contact: crate::state::blend_forces(&a.self_contact, 1.0 - t, &b.self_contact, t),
        far_strained: if a.far_strained.is_empty() {
            b.far_strained.clone()
        } else if b.far_strained.is_empty() {
            a.far_strained.clone()
        } else {
            a.far_strained
                .iter()
                .zip(&b.far_strained)
                .map(|(x, y)| *x || *y)
                .collect()
        },
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
            self_contact: vec![s; 3],
            far_strained: Vec::new(),
        };
        let (a, b) = (at(0.0), at(1.0));
        // `between` takes the angles' transforms; for a rigid motion of all bones, compare the
        // carried positions with the motion at the same fraction applied by hand.
        let carried = between(&hand, (&a, &b), 0.5, rest.angles.clone());
        for (n, p) in carried.positions.iter().enumerate() {
            assert!((p - rest.positions[n]).norm() < 1e-12, "node {n}");
        }
        assert!((carried.reaction[0] - Vector3::new(0.5, 0.0, -0.5)).norm() < 1e-15);
        assert_eq!(carried.self_contact, vec![0.5; 3]);
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

    /// A stand-in flexion: the flesh at `rest` turned about z by `rate` times the angle of
    /// joint `joint` from rest, the bones at rest (so that the knots' flesh is carried between
    /// them by its positions alone); `calls` counts the flexions.
    fn turning<'a>(
        rest: &'a HandState,
        joint: usize,
        rate: f64,
        calls: &'a std::cell::Cell<usize>,
    ) -> impl FnMut(usize, HandState, &[f64], Parts<'_>) -> Flexed + 'a {
        move |_, _, angles, _| {
            calls.set(calls.get() + 1);
            let turn = stretched_turn(rate, angles[joint] - rest.angles[joint]);
            let mut state = rest.clone();
            state.angles = angles.to_vec();
            state.positions = rest.positions.iter().map(|p| turn * p).collect();
            Ok((state, KeyframeStats::default()))
        }
    }

    /// The stand-in flexion's map after `degrees` of its joint: a turn about z of `rate` degrees
    /// a degree, after a stretch along x and a squeeze along y of 2 % a degree (volume ratio
    /// 1 − (0.02·degrees)², whole at every angle). Two such states half a turn apart blend, halfway,
    /// into diag(−0.1, 0.1, 1) — inside out by a margin, where two turns alone would blend
    /// into flat flesh (det (R₁ + R₂)/2 ≥ 0 for any rotations), and only round-off could tell.
    fn stretched_turn(rate: f64, degrees: f64) -> nalgebra::Matrix3<f64> {
        let turn =
            nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), (rate * degrees).to_radians());
        let k = 0.02 * degrees;
        turn.matrix() * nalgebra::Matrix3::from_diagonal(&Vector3::new(1.0 + k, 1.0 - k, 1.0))
    }

    /// Flesh that the bones would carry through zero volume between two knots (the hand turned
    /// half a turn about z from one knot to the next, and stretched: carried halfway, it is
    /// inside out) is flexed at the step's own angles instead; where the carried flesh stays
    /// whole, no flexion is added.
    #[test]
    fn flesh_carried_inside_out_between_knots_is_flexed_there_instead() {
        let scene = crate::scene::Scene::parse(
            include_str!("../../assets/scenes/finger-flexion.toml"),
            "finger-flexion.toml",
        )
        .unwrap();
        let model = Model::build(&scene, "finger-flexion.toml").unwrap();
        let body = (0..model.bodies.len())
            .find(|&b| model.bodies[b].hand.is_some())
            .unwrap();
        let hand = model.bodies[body].hand.as_deref().unwrap();
        let rest = HandState::rest(hand);
        let joint = 0;
        let mut to = rest.angles.clone();
        to[joint] += 10.0;
        for (rate, flexions) in [(18.0, 2), (1.0, 1)] {
            let calls = std::cell::Cell::new(0);
            let mut flex = turning(&rest, joint, rate, &calls);
            let moving = [(body, rest.clone(), to.clone(), [false; PARTS])];
            let mut path = FlexionPath::new(&model, moving, false);
            let half = path.state_at(&model, 0, 0.5, &mut flex).unwrap();
            assert_eq!(calls.get(), flexions, "{rate}° a degree");
            let turn = stretched_turn(rate, 5.0);
            let off: f64 = half
                .positions
                .iter()
                .zip(&rest.positions)
                .map(|(p, r)| (p - turn * r).norm())
                .fold(0.0, f64::max);
            if flexions == 2 {
                // Flexed at 5°: the flesh turned 90° (and stretched 10 %), whole.
                assert!(off < 1e-12, "{off}");
            } else {
                // Carried: a chord of the 10° turn, not the arc, but whole.
                assert!(off > 1e-9, "{off}");
            }
            let flat = hand
                .flesh
                .mesh
                .cells
                .iter()
                .filter(|c| {
                    crate::fem::hex8::relative_min_jacobian(&c.map(|n| half.positions[n])) <= 0.0
                })
                .count();
            assert_eq!(flat, 0, "{rate}° a degree");
        }
    }

    /// A state standing for a flexed knot: its angles, and how many flexions led to it.
    fn knot(angles: &[f64], flexions: f64) -> HandState {
        HandState {
            angles: angles.to_vec(),
            transforms: Vec::new(),
            positions: vec![Vector3::new(flexions, 0.0, 0.0)],
            reaction: Vec::new(),
            self_contact: Vec::new(),
            far_strained: Vec::new(),
        }
    }

    /// A stand-in flexion: the state at `angles` one flexion after `start`, failing at the
    /// angle `fail_at` of hand body 1.
    fn flex_counting(
        fail_at: Option<f64>,
    ) -> impl FnMut(usize, HandState, &[f64], Parts<'_>) -> Flexed {
        move |body, start, angles, _| {
            if body == 1 && fail_at == Some(angles[0]) {
                return Err(SimError::Cancelled);
            }
            let stats = KeyframeStats {
                increments_taken: 1,
                ..Default::default()
            };
            Ok((knot(angles, start.positions[0].x + 1.0), stats))
        }
    }

    /// Knots flexed ahead on another thread are the knots flexed in turn, each hand's in its
    /// order (two hands of three and two knots, asked for out of the order they were flexed);
    /// a knot that failed ahead is that knot's error, and the path flexes on in turn after it.
    #[test]
    fn knots_flexed_ahead_are_those_flexed_in_turn() {
        let scene = crate::scene::Scene::parse(
            include_str!("../../assets/scenes/block-press.toml"),
            "block-press.toml",
        )
        .unwrap();
        let model = Model::build(&scene, "block-press.toml").unwrap();
        // 30° and 20° of motion: three and two knots of 10°.
        let hands = || {
            [(0, 30.0), (1, 20.0)]
                .map(|(body, to)| (body, knot(&[0.0], 0.0), vec![to], [false; PARTS]))
        };
        let asked = [(1, 1.0), (0, 1.0 / 3.0), (0, 1.0), (1, 0.5)];
        for fail_at in [None, Some(20.0)] {
            let mut in_turn = FlexionPath::new(&model, hands(), false);
            let mut ahead = FlexionPath::new(&model, hands(), false);
            let plan = ahead.ahead_plan().expect("more than one knot to flex");
            let (to_path, from_ahead) = std::sync::mpsc::channel();
            let worker = std::thread::spawn(move || {
                flex_ahead(plan, &mut flex_counting(fail_at), to_path);
            });
            ahead.take_ahead(from_ahead);
            for (k, f) in asked {
                let a = in_turn.state_at(&model, k, f, &mut flex_counting(fail_at));
                // In turn only after a failure ahead.
                let b = ahead.state_at(&model, k, f, &mut flex_counting(None));
                match (a, b) {
                    (Ok(a), Ok(b)) => {
                        assert_eq!((a.angles, a.positions), (b.angles, b.positions));
                    }
                    (Err(_), Err(_)) => {
                        // Asked again, the path flexes it in turn (here without failing).
                        let again = ahead
                            .state_at(&model, k, f, &mut flex_counting(None))
                            .unwrap();
                        assert_eq!(again.angles, vec![20.0]);
                        assert_eq!(again.positions[0].x, 2.0);
                    }
                    (a, b) => panic!("hand {k} at {f}: {:?} against {:?}", a.is_ok(), b.is_ok()),
                }
            }
            worker.join().unwrap();
            assert_eq!(in_turn.stats(0).increments_taken, 3);
            assert_eq!(ahead.stats(0).increments_taken, 3);
        }
    }
}
