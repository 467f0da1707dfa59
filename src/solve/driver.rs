//! The one keyframe driver, for the CLI, the viewer and the benches: a [`Workspace`] per model
//! (the static frame of the bodies, the flexion caches), hands moved by flexion increments from
//! where they are to the angles asked for, and the frame with their contact solved. The timeline
//! of a scene ([`solve_frames`]) is the driver run over its keyframes.

use super::error::SimError;
use super::flexion::{CancelCheck, Flexion, FlexionCaches};
use super::grasp::{frame_with_hands, Carried, ContactCache};
use super::hyperelastic_objects::neo_hookean_objects;
use super::iterated_steps;
use super::path::{flex_ahead, FlexionPath, Knot, Parts};
use super::proximity::{crushed_by_skinning, deeper_on_the_way, PARTS};
use super::statics::{solve_static, solve_static_alone};
use super::step_control::StepControl;
use super::untouched::untouched_step;
use crate::contact::ContactMethod;
use crate::fem::solve::{PartitionedSolver, Solution, SolveStats};
use crate::fem::stress::StressField;
use crate::model::Model;
use crate::state::{
    largest_strains, Frame, HandFrame, HandState, KeyframeStats, StoppedShort, UnsettledMotion,
    STRAIN_WARNING,
};
use nalgebra::{Matrix3, Vector3};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// What changes while a model is solved, besides the hands' states (the `mjData` of this
/// project, with [`PosedHand`]): the static frame of the bodies that no hand moves, and the caches
/// every hand's flexion reuses between keyframes. Built once per model; the model stays immutable.
pub struct Workspace {
    /// The static frame of the other bodies; `None` when one of them can only be held by a hand.
    still: Option<Frame>,
    /// The flexion caches by hand body.
    pub(super) caches: Vec<(usize, FlexionCaches)>,
    /// What the contact steps keep from one to the next (their solver, the nodes held).
    pub(super) contact: ContactCache,
    /// Keyframes solved ahead while the solver was idle ([`Workspace::solve_ahead`]).
    pub(super) solved_ahead: Vec<SolvedAhead>,
}

/// A keyframe solved ahead (src/solve/anticipate.rs): where it started (the hands, what the
/// contact carried), its targets, and where it ended (the hands, what the contact carries on,
/// the frame).
pub(super) struct SolvedAhead {
    pub(super) from: (Posed, Carried),
    pub(super) targets: Vec<(usize, Vec<f64>)>,
    pub(super) to: (Posed, Carried),
    pub(super) frame: Frame,
}

/// A hand body where the driver left it: its state, and its part of the last frame.
#[derive(Clone, Debug)]
pub struct PosedHand {
    /// The hand body.
    pub body: usize,
    /// Angles, bone motions, flesh positions as flexed (without the contact's displacement),
    /// accumulated reactions.
    pub state: HandState,
    /// The hand's frame as flexed (what reaching `state` cost included).
    pub frame: HandFrame,
}

/// Where the driver left a model's hands and what touches them: the state that one keyframe
/// hands to the next (the viewer keeps one for the pose shown, the timeline its own).
#[derive(Clone, Debug, Default)]
pub struct Posed {
    /// Every hand body.
    pub hands: Vec<PosedHand>,
    /// The displacements the last contact step left, over every dof: the other bodies' from
    /// rest, the flesh's over its flexed pose. `None` when nothing touched.
    pub contact: Option<Vec<f64>>,
}

impl Posed {
    /// Every hand of the model at rest, nothing touching.
    pub fn rest(model: &Model) -> Posed {
        Posed {
            hands: rest_hands(model),
            contact: None,
        }
    }

    /// The hands and the contact of a solved `frame` of `model`, to go on from there.
    pub fn of_frame(model: &Model, frame: &Frame) -> Posed {
        Posed {
            hands: hands_of(model, frame),
            contact: carried_by(model, frame),
        }
    }
}

/// What a solved `frame` leaves to carry into the next contact step, over every dof: the other
/// bodies' displacements from rest, the flesh's contact displacements over its flexed pose;
/// `None` without contact.
fn carried_by(model: &Model, frame: &Frame) -> Option<Vec<f64>> {
    frame.contact.as_ref()?;
    let mut carried = frame.solution.displacement.clone();
    for h in &frame.hands {
        let nodes = model.bodies[h.body].nodes.clone();
        for (i, n) in nodes.enumerate() {
            let v = h
                .contact_displacement
                .get(i)
                .copied()
                .unwrap_or_else(Vector3::zeros);
            carried[3 * n..3 * n + 3].copy_from_slice(v.as_slice());
        }
    }
    Some(carried)
}

/// A keyframe's motion: each moving hand (index into `Posed::hands`, angles from, angles to),
/// and their flexion along it.
type Motion<'a, 'p> = (&'a [(usize, Vec<f64>, Vec<f64>)], &'p mut FlexionPath);

/// What watches a keyframe being solved: its cancel check, and what is shown the frame its
/// motion reached before the corrections at its pose settle the contact
/// ([`Workspace::move_hands_showing`]).
type Watch<'a> = (Option<&'a CancelCheck>, Option<&'a dyn Fn(Frame)>);

/// Largest joint rotation between two contact steps of a keyframe in a scene with other bodies,
/// degrees: the skin of a fingertip 8 cm from the joint moves ≈ 7 mm, within what one contact
/// step resolves from the last converged state.
pub const CONTACT_STEP_DEG: f64 = 5.0;

/// A keyframe ending in contact is corrected at its pose (contact steps without motion, each
/// detecting and linearising the contact about the last: a fixed-point iteration on the contact
/// geometry) until its normal contact force changes by less than this fraction of itself…
pub const CONTACT_CORRECTION: f64 = 1e-3;

/// … or this many corrections were made.
const CONTACT_CORRECTIONS: usize = 6;

/// …or, while each correction changes the force, or the carried state, less than the one
/// before, this many.
const CONTACT_CORRECTIONS_EXTENDED: usize = 12;

/// The relaxation factor of the second correction at the pose, before two changes give
/// [`aitken`] its own. Plain (measured 2026-11-28, `bench grasp`): damped by 0.7, the second
/// correction changed the force little and the third by more again (Power grasp preset
/// 15.6 %, 0.8 %, 3.4 %, 0.18 %, 0.07 %: five corrections; the Fist still swinging by 2.5 % at
/// its sixth), plain the Power grasp and Pinch presets settle in three (15.6 %, 3.9 %, 0.09 %),
/// the Fist in six, 70 contact steps over the eight grasps instead of 76; where they stop is
/// within 0.2 % of the fixed point (corrections run on to 10⁻⁷: the Power grasp 9.908 against
/// 9.890 N, Pinch and the five-digit grasp within 0.01 %).
const FIRST_RELAXATION: f64 = 1.0;

/// Bounds of the corrections' relaxation factor (see [`aitken`]).
const RELAXATION: (f64, f64) = (0.1, 10.0);

/// On the nonlinear tier a keyframe whose hands let go of a body is settled at its pose
/// ([`Workspace::settle_released`]) until the bodies' displacements change by less than this
/// fraction of their largest…
const RELEASE_SETTLED: f64 = 1e-8;

/// …or this many steps were made.
const RELEASE_CORRECTIONS: usize = 8;

/// Halvings of a contact step whose contact does not settle before the keyframe gives up
/// (the smallest step is [`CONTACT_STEP_DEG`] / 2⁴).
const CONTACT_HALVINGS: usize = 4;

impl Workspace {
    /// Solves the static frame of the bodies no hand moves (equations (6)–(8)), unless nothing
    /// is free, or a floating body can only be held by a hand (then the frames are solved with
    /// the hands' contact, [`frame_with_hands`]).
    pub fn new(model: &Model) -> Result<Workspace, SimError> {
        crate::fem::memory::set_budget(model.max_memory);
        // The nonlinear tier keeps every element's state (forces, tangent) while it assembles,
        // after its factor is planned: left out of what the factor may take.
        crate::fem::memory::set_reserve(if model.nonlinear_statics {
            (model.mesh.cell_count() as u64).saturating_mul(std::mem::size_of::<
                crate::fem::hex8_hyperelastic::ElementState,
            >() as u64)
        } else {
            0
        });
        let has_hands = model.bodies.iter().any(|b| b.hand.is_some());
        let floating = model.bodies.iter().any(|b| b.floating);
        let still = if model.partition.free_count() == 0 {
            Some(still_frame(model))
        } else if floating && has_hands {
            None
        } else {
            let mut solver = PartitionedSolver::new(model.ordering);
            match solve_static(model, &mut solver) {
                Ok(frame) => Some(frame),
                // Contact with the obstacles failed: told as the strain of the bodies under
                // their loads alone, where that is beyond small strain.
                Err(e) if !model.obstacles.is_empty() => {
                    return Err(match solve_static_alone(model, &mut solver) {
                        Ok(alone) => beyond_small_strain(model, &alone, false, e),
                        Err(_) => e,
                    })
                }
                Err(e) => return Err(e),
            }
        };
        let still = still.map(|f| SimError::finite(model, f)).transpose()?;
        Ok(Workspace {
            still,
            caches: Vec::new(),
            contact: ContactCache::new(model),
            solved_ahead: Vec::new(),
        })
    }

    /// `error`, met by a keyframe, told as the static frame's strain where that frame already
    /// strains a body beyond [`STRAIN_WARNING`]: contact on a ball inflated by its own air
    /// far past small strain fails in ways (a runaway, an inverted element) whose own advice
    /// does not help. Errors of the hands' flexion, and cancellations, are left as they are.
    fn beyond_small_strain(&self, model: &Model, error: SimError) -> SimError {
        match self.still.as_ref() {
            Some(still) => beyond_small_strain(model, still, true, error),
            None => error,
        }
    }
    /// Moves each hand of `targets` (hand body, joint angles in degrees) from where `posed`
    /// holds it by flexion increments, and solves the frame with every hand. In a scene with
    /// other bodies the motion goes in contact steps of at most [`CONTACT_STEP_DEG`]: after each,
    /// the bodies, the flesh near the contact and their contacts are solved from where the last
    /// step left them (a step whose contact does not settle is halved), so that however deep the
    /// keyframe's pose would put the skin into a body, each step resolves only its own motion —
    /// the animator's "fingers inside the ball" pushes the ball away. Hands not in `targets` stay
    /// as they are. `cancel` is asked before every increment: a cancelled hand stays at its last
    /// completed increment.
    pub fn move_hands(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        targets: &[(usize, Vec<f64>)],
        cancel: Option<&CancelCheck>,
    ) -> Result<Frame, SimError> {
        self.move_hands_watched(model, posed, targets, (cancel, None))
    }

    /// [`Workspace::move_hands`], showing `reached` the frame the motion reached at the pose
    /// before the corrections at the pose settle its contact (its values finite, its stresses
    /// pending: [`super::complete_stress`] computes them where they are drawn), where there are
    /// corrections to make: a frame at the pose, in contact, whose
    /// contact force the first correction changes by a few per mille (a finger in contact
    /// dragged by 2°: under 0.1 %). The viewer shows it while the corrections run; the frame
    /// returned is the settled one.
    pub fn move_hands_showing(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        targets: &[(usize, Vec<f64>)],
        cancel: Option<&CancelCheck>,
        reached: &dyn Fn(Frame),
    ) -> Result<Frame, SimError> {
        self.move_hands_watched(model, posed, targets, (cancel, Some(reached)))
    }

    /// [`Workspace::move_hands`] watched by `watch`.
    fn move_hands_watched(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        targets: &[(usize, Vec<f64>)],
        watch: Watch<'_>,
    ) -> Result<Frame, SimError> {
        // Where each moving hand starts the keyframe from, for a flexion error's share.
        let from: Vec<(usize, Vec<f64>)> = targets
            .iter()
            .filter_map(|(b, _)| posed.hands.iter().find(|h| h.body == *b))
            .map(|h| (h.body, h.state.angles.clone()))
            .collect();
        // With the skin kept out of itself, a keyframe closing the thumb and the fingers at once
        // whose skin does not settle (the thumb folding over fingers still closing: the full
        // fist stopped at 76.7 % with a crushed cell) goes again from its start with the fingers
        // first and the thumb after them, as a hand makes a fist.
        let stageable = model.flexion.self_contact.is_some()
            && targets.iter().any(|(b, to)| {
                posed.hands.iter().find(|h| h.body == *b).is_some_and(|h| {
                    super::path::thumb_and_fingers_move(model, *b, &h.state.angles, to)
                })
            });
        let start = stageable.then(|| posed.clone());
        // Where that fails too, the first error stands: its share of the motion is of the
        // straight path, which its advice (the keyframe short of that share) follows.
        let result = match self.move_hands_as_asked(model, posed, targets, watch, false) {
            Err(e @ (SimError::FleshCrushed { .. } | SimError::SelfContactUnsettled { .. }))
                if start.is_some() =>
            {
                *posed = start.expect("kept above");
                match self.move_hands_as_asked(model, posed, targets, watch, true) {
                    Err(SimError::Cancelled) => Err(SimError::Cancelled),
                    Err(_) => Err(e),
                    ok => ok,
                }
            }
            other => other,
        };
        // The stresses of the frame kept only (its steps' were not needed).
        result
            .and_then(|mut frame| super::frame_stress::complete(model, &mut frame).map(|()| frame))
            .and_then(|frame| SimError::finite(model, frame))
            .map_err(|e| keyframe_share(model, e, &from, targets))
            .map_err(|e| self.beyond_small_strain(model, e))
    }

    /// [`Workspace::move_hands`] without the static frame's strain told.
    fn move_hands_as_asked(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        targets: &[(usize, Vec<f64>)],
        watch: Watch<'_>,
        thumb_after_fingers: bool,
    ) -> Result<Frame, SimError> {
        let cancel = watch.0;
        let moving = moving_hands(posed, targets);
        let has_objects = model.bodies.iter().any(|b| b.hand.is_none());
        // The keyframe in one step first (its contact linearised about the flexed pose and what
        // the last frame carried): exact where the pose brings the skin just onto the bodies. Where that
        // contact does not settle, the keyframe again in contact steps along the motion.
        let start = has_objects.then(|| posed.clone());
        // A pose that skinning already puts deeper into a body than contact searches cannot be
        // solved in one step (that contact never finds the deepest skin): straight to steps.
        // Nor a keyframe whose skin goes deeper than that on the way, at one of the poses the
        // steps along it would take, whatever its end (a finger swung through a ball and out of
        // it, which one step at the end would find touching nothing). (Judged once the flexion
        // ahead has started: it is 24 ms of skinning and inside tests a pose, the end first.)
        let deep = start.is_some();
        let too_deep = |posed: &Posed| {
            deep && moving.iter().any(|(h, from, to)| {
                let hand = &posed.hands[*h];
                let carried = posed.contact.as_deref();
                let depth = model.contact.search_depth;
                let samples = contact_steps(largest_change(from, to));
                deeper_on_the_way(model, hand.body, &hand.state, to, (depth, samples), carried)
            })
        };
        // The hands' flexion over the keyframe, shared by both ways of solving its contact. A
        // part that skinning would crush over the whole keyframe is solved in each of its
        // increments, although no increment alone would crush it.
        let mut path = flexion_path(model, posed, &moving, thumb_after_fingers);
        let Some(plan) = path.ahead_plan() else {
            // A keyframe of one knot (a slider nudged) from a frame in contact: whether it goes
            // too deep judged and its knot flexed now, and beside both (on the other core) the
            // objects' part of its one step (src/solve/objects_factor.rs; where it goes too
            // deep, its steps along the motion take another tangent and make their own). A
            // knot that fails here is kept failed for the step, which tells why.
            let too_deep = if has_objects && presses(model, posed, posed.contact.as_deref()) {
                let (contact, caches) = (&mut self.contact, &mut self.caches);
                let carried = posed.contact.as_deref();
                let path = &mut path;
                let flexed_here = || {
                    let deep = too_deep(posed);
                    let mut flex = |body: usize, state: HandState, angles: &[f64], parts: Parts| {
                        flex_hand((model, caches, cancel), body, state, angles, parts)
                    };
                    for k in 0..moving.len() {
                        if !path.flex_to(model, k, 1.0, &mut flex) {
                            break;
                        }
                    }
                    deep
                };
                rayon::join(flexed_here, || {
                    contact.prepare_objects(model, carried, true)
                })
                .0
            } else {
                too_deep(posed)
            };
            self.know_untouched_motion(model, has_objects);
            return self.move_along(model, posed, (&moving, &mut path), (too_deep, start), watch);
        };
        // The knots flexed ahead on another thread while the contact steps solve (the caches of
        // the moving hands go with it, and come back).
        let bodies = moving_bodies(posed, &moving);
        let (ahead_caches, kept): (Vec<_>, Vec<_>) = std::mem::take(&mut self.caches)
            .into_iter()
            .partition(|(b, _)| bodies.contains(b));
        self.caches = kept;
        let stop = Arc::new(AtomicBool::new(false));
        let check: CancelCheck = {
            let (stop, asked) = (stop.clone(), cancel.cloned());
            Arc::new(move || stop.load(Ordering::Relaxed) || asked.as_ref().is_some_and(|c| c()))
        };
        std::thread::scope(|scope| {
            let (to_path, from_ahead) = std::sync::mpsc::channel();
            let worker = scope.spawn(move || {
                let mut caches = ahead_caches;
                let mut flex = |body: usize, state: HandState, angles: &[f64], parts: Parts| {
                    flex_hand(
                        (model, &mut caches, Some(&check)),
                        body,
                        state,
                        angles,
                        parts,
                    )
                };
                flex_ahead(plan, &mut flex, to_path);
                caches
            });
            path.take_ahead(from_ahead);
            let too_deep = too_deep(posed);
            self.know_untouched_motion(model, has_objects);
            let result =
                self.move_along(model, posed, (&moving, &mut path), (too_deep, start), watch);
            // A knot still flexing stops at its next increment; none is flexed after it.
            stop.store(true, Ordering::Relaxed);
            path.end_ahead();
            match worker.join() {
                Ok(caches) => {
                    for (b, c) in caches {
                        self.caches.retain(|(cb, _)| *cb != b);
                        self.caches.push((b, c));
                    }
                }
                Err(panic) => std::panic::resume_unwind(panic),
            }
            result
        })
    }

    /// The step the bodies other than the hands take from the static frame where nothing
    /// touches them (src/solve/untouched.rs), solved once per workspace (in a scene with such
    /// bodies) while the knots flex ahead: what tells the steps along a motion that come near a
    /// body without touching it that they need no solve.
    fn know_untouched_motion(&mut self, model: &Model, has_objects: bool) {
        if !has_objects || self.contact.untouched.is_some() {
            return;
        }
        let Some(still) = self.still.as_ref() else {
            return;
        };
        let step = untouched_step(model, still, self.contact.anchor.as_deref());
        self.contact.untouched = Some(step.ok());
    }

    /// The keyframe's motion once its flexion path is planned: in one contact step, then along
    /// the motion where that does not settle (`too_deep`: along the motion at once; `start`:
    /// the hands where the keyframe starts, when there are bodies to touch).
    fn move_along(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        (too_deep, start): (bool, Option<Posed>),
        watch: Watch<'_>,
    ) -> Result<Frame, SimError> {
        let largest = moving
            .iter()
            .map(|(_, from, to)| largest_change(from, to))
            .fold(0.0, f64::max);
        let steps = contact_steps(largest);
        // Retried along the motion in at least two steps: a keyframe shorter than one step
        // (a degree of flexion against a thin wall) may need halving too.
        let along = steps.max(2);
        // On the nonlinear tier, where the keyframe ends unsettled, it is followed again with
        // each step iterated at its own pose (`super::iterated_steps`): from where it started,
        // the hands and what the contact steps carry alike.
        let nonlinear = neo_hookean_objects(model);
        let cache = nonlinear.then(|| self.contact.carried()).flatten();
        let ended = self.move_once_along(
            model,
            posed,
            (moving, path),
            (too_deep, start.as_ref()),
            along,
            watch,
        );
        let bodies = moving_bodies(posed, moving);
        match (ended, start, cache) {
            (Ok(frame), Some(restart), Some(cache))
                if hand_contact_force(model, &frame) > 0.0
                    && iterated_steps::unsettled(&frame, &bodies) =>
            {
                // (A keyframe whose hands let go is settled from the static frame, whatever
                // the steps: nothing to redo.)
                let first = (posed.clone(), self.contact.carried(), frame);
                *posed = restart;
                self.contact.restore(cache);
                let carried = posed.contact.clone();
                let again =
                    self.move_in_steps(model, posed, (moving, path), (along, true), carried, watch);
                match again {
                    Ok(mut frame) if iterated_steps::better(&frame, &first.2, &bodies) => {
                        // The first attempt's contact solves were all redone.
                        count_retry(posed, moving, &mut frame, Some(&first.2));
                        Ok(frame)
                    }
                    Err(SimError::Cancelled) => Err(SimError::Cancelled),
                    _ => {
                        *posed = first.0;
                        if let Some(carried) = first.1 {
                            self.contact.restore(carried);
                        }
                        Ok(first.2)
                    }
                }
            }
            (ended, _, _) => ended,
        }
    }

    /// [`Workspace::move_along`] with its steps as planned: in one contact step, then along
    /// the motion in `along` steps where that does not settle.
    fn move_once_along(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        (too_deep, start): (bool, Option<&Posed>),
        along: usize,
        watch: Watch<'_>,
    ) -> Result<Frame, SimError> {
        if too_deep {
            let carried = posed.contact.clone();
            return self.move_in_steps(
                model,
                posed,
                (moving, path),
                (along, false),
                carried,
                watch,
            );
        }
        // Going on from a frame in contact, from the state it carries (the same formulation
        // as its own steps: the pose again gives the frame again).
        let carried = posed.contact.clone();
        match self.move_in_steps(model, posed, (moving, path), (1, false), carried, watch) {
            // The one-step attempt did not settle: the keyframe in steps along the motion. If
            // that fails too, its error is the one returned (it failed at its first contact, in
            // its smallest step: the cause); the one-step error only says that the whole motion
            // was too large a step.
            Err(SimError::Contact(_)) if start.is_some() => {
                *posed = start.expect("kept above").clone();
                let carried = posed.contact.clone();
                self.move_in_steps(model, posed, (moving, path), (along, false), carried, watch)
                    .map(|mut frame| {
                        // The one-step attempt was a contact solve redone.
                        count_retry(posed, moving, &mut frame, None);
                        frame
                    })
            }
            other => other,
        }
    }

    /// The motion of `moving` (hand, from, to) in `steps` contact steps (halved where contact
    /// does not settle), each from the displacements the last one left, starting from
    /// `carried`; with `iterated`, each step in contact short of the pose is followed by a
    /// correction at its own pose (`super::iterated_steps`).
    fn move_in_steps(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        (steps, iterated): (usize, bool),
        carried: Option<Vec<f64>>,
        (cancel, reached): Watch<'_>,
    ) -> Result<Frame, SimError> {
        // Whether the motion pressed a body: what it carries in from a frame in contact (the
        // flesh's contact displacements), or a step in contact.
        let mut pressed = presses(model, posed, carried.as_deref());
        posed.contact = carried;
        let mut control = StepControl::new(steps, CONTACT_HALVINGS, true);
        let (mut kept, mut retries) = (0, 0);
        // The frame of the last step kept, when it was in contact, and the fraction it reached:
        // where the keyframe ends if the contact cannot follow the motion further.
        let mut last: Option<(Frame, f64)> = None;
        loop {
            let f = control.target();
            let before = (steps > 1).then(|| posed.clone());
            match self.contact_step(model, posed, (moving, path), f, steps > 1, cancel) {
                // A step after which a bone's reaction overruns its muscle threshold is halved
                // while it may, so that the motion stops close to where the threshold is
                // crossed (a stiff object's reaction grows fast within a step).
                Ok(frame)
                    if stopped_by_threshold(&frame)
                        && !control.finished_with(f)
                        && before.is_some()
                        && control.halve() =>
                {
                    retries += 1;
                    *posed = before.expect("kept above");
                }
                // A step after which a bone's reaction overruns its muscle threshold ends the
                // keyframe there (the paper: the grasp is not realisable beyond it): the frame
                // reports the overloads and that the motion stopped by a threshold.
                Ok(frame) if control.finished_with(f) || stopped_by_threshold(&frame) => {
                    let mut frame = frame;
                    let mut short = None;
                    if !control.finished_with(f) {
                        if let Some(c) = frame.contact.as_mut() {
                            c.stopped_by_threshold = true;
                        }
                        short = Some(StoppedShort {
                            reached: f,
                            reason: "a bone's reaction overran its muscle threshold".into(),
                            solver_limit: false,
                        });
                    }
                    let touched = usize::from(frame.contact.is_some());
                    let mut corrections = 0;
                    let mut unsettled = Unsettled::default();
                    if short.is_none() {
                        if let Some(reached) = reached {
                            let counts = Counts {
                                steps: kept + touched,
                                retries,
                                corrections: 0,
                                unsettled: Unsettled::default(),
                            };
                            show_reached(model, posed, (moving, path), &frame, counts, reached);
                        }
                        (frame, corrections, unsettled) =
                            self.correct(model, posed, (moving, path), frame, pressed, cancel)?;
                    }
                    let counts = Counts {
                        steps: kept + touched + corrections,
                        retries,
                        corrections,
                        unsettled,
                    };
                    finish(model, posed, (moving, path), &mut frame, counts, short);
                    return Ok(frame);
                }
                Ok(mut frame) => {
                    if iterated && hand_contact_force(model, &frame) > 0.0 {
                        if let Some(next) =
                            self.step_again(model, posed, (moving, path), (f, &frame), cancel)?
                        {
                            kept += 1;
                            frame = next;
                        }
                    }
                    kept += usize::from(frame.contact.is_some());
                    pressed |= hand_contact_force(model, &frame) > 0.0;
                    posed.contact = carried_by(model, &frame);
                    control.accept(f, true);
                    last = frame.contact.is_some().then_some((frame, f));
                }
                Err(SimError::Contact(_)) if before.is_some() && control.halve() => {
                    retries += 1;
                    *posed = before.expect("kept above");
                }
                // The paper's iteration failing is a failure of the method: the exact method
                // may follow the motion, so it is an error (the command exits non-zero), not
                // the grasp's limit.
                Err(SimError::Contact(cause))
                    if before.is_some() && model.contact.method == ContactMethod::Paper =>
                {
                    return Err(SimError::PaperCannotFollow {
                        reached: control.reached(),
                        cause,
                    });
                }
                // The contact cannot follow the motion beyond the last step kept, even in the
                // smallest step: the keyframe ends there, short of its pose — the grasp is not
                // realisable further with these bodies (a ball squeezed beyond what its tier
                // represents, skin folded onto itself), and the frame says how far it went.
                Err(SimError::Contact(e)) if before.is_some() && last.is_some() => {
                    *posed = before.expect("kept above");
                    let (mut frame, reached) = last.take().expect("kept above");
                    let short = StoppedShort {
                        reached,
                        reason: format!("the contact could not follow the motion further ({e})"),
                        solver_limit: true,
                    };
                    let counts = Counts {
                        steps: kept,
                        retries: retries + 1,
                        corrections: 0,
                        unsettled: Unsettled::default(),
                    };
                    finish(
                        model,
                        posed,
                        (moving, path),
                        &mut frame,
                        counts,
                        Some(short),
                    );
                    return Ok(frame);
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// The contact step to fraction `f` that ended on `frame` taken again at its own pose, from
    /// the state it reached: a second Newton iteration on the same increment
    /// (`super::iterated_steps`). `None` where it fails, lets go or overruns a bone's threshold
    /// (the step's own control judges that): the step stands as it was, `posed` and what the
    /// contact steps carry as `frame` left them.
    fn step_again(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        (f, frame): (f64, &Frame),
        cancel: Option<&CancelCheck>,
    ) -> Result<Option<Frame>, SimError> {
        let step = posed.clone();
        posed.contact = carried_by(model, frame);
        let held = self.contact.carried();
        match self.contact_step(model, posed, (moving, path), f, false, cancel) {
            Ok(next) if hand_contact_force(model, &next) > 0.0 && !stopped_by_threshold(&next) => {
                Ok(Some(next))
            }
            Ok(_) | Err(SimError::Contact(_)) => {
                *posed = step;
                if let Some(held) = held {
                    self.contact.restore(held);
                }
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }

    /// `frame`, reached by the motion's last contact step and in contact, corrected at its pose:
    /// contact steps without motion, each from the state the last left, until the hands' normal
    /// contact force changes by less than [`CONTACT_CORRECTION`] of itself (at most
    /// [`CONTACT_CORRECTIONS`], or [`CONTACT_CORRECTIONS_EXTENDED`] while each changes it, or
    /// the carried state, less than the one before). From the second on, a correction starts
    /// from the last one's start moved by ω times the change it made, ω by Aitken's Δ² on the
    /// carried state ([`aitken`]):
    /// the corotated ball's corrections alternate in sign and are damped, the Neo-Hookean ball's
    /// shrink in one sign and are extended. A step linearises the contact (gaps, normals) about
    /// where it starts; at the pose it converges to the frame whose contact is in equilibrium on
    /// its own geometry, so that the pose solved again from the frame gives the frame again. A
    /// frame whose hands touch nothing (an object only on its table) needs no correction: the
    /// obstacles' contact is solved with the bodies at rest. A correction started past the last
    /// one's end (ω > 1) that fails or loses the contact is redone plainly from the last frame;
    /// another that does not settle leaves the last frame; cancelling stops it. Returns the
    /// frame, the corrections kept and, when the last one still changed the force by more than
    /// [`CONTACT_CORRECTION`], that relative change with where it moved the bodies most; when a
    /// correction failed, its error.
    fn correct(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        mut frame: Frame,
        pressed: bool,
        cancel: Option<&CancelCheck>,
    ) -> Result<(Frame, usize, Unsettled), SimError> {
        let mut kept = 0;
        let mut unsettled = Unsettled::default();
        // The state the last correction started from, the change the correction before made to
        // its own start, and the relaxation factor.
        let mut started_from: Option<Vec<f64>> = None;
        let mut last_change: Option<Vec<f64>> = None;
        let mut omega = FIRST_RELAXATION;
        // The relative force changes of the corrections kept: they may go on past
        // CONTACT_CORRECTIONS while these shrink.
        let mut changes: Vec<f64> = Vec::new();
        // The size of the change each correction made to the carried state it started from,
        // |S(x) − x|: while these shrink the corrections converge, also where the force swings.
        let mut moves: Vec<f64> = Vec::new();
        // The error of a correction started past the last one's end, until one redone plainly
        // succeeds (reported if none is left to).
        let mut retry_failed: Option<String> = None;
        // The change the last correction kept made to the carried state it started from.
        let mut made: Option<Vec<f64>> = None;
        let mut done = 0;
        // (A frame without contact is already the bodies' static frame.)
        if pressed && frame.contact.is_some() && hand_contact_force(model, &frame) <= 0.0 {
            let released;
            (frame, released, unsettled.failed) =
                self.settle_released(model, posed, (moving, path), frame, cancel)?;
            kept += released;
        }
        while done < CONTACT_CORRECTIONS
            || (done < CONTACT_CORRECTIONS_EXTENDED
                && (matches!(changes[..], [.., a, b] if b < a)
                    || matches!(moves[..], [.., a, b] if b < a)))
        {
            done += 1;
            let force = hand_contact_force(model, &frame);
            if force <= 0.0 {
                break;
            }
            let before = posed.clone();
            let mut carried = carried_by(model, &frame);
            // The factor this correction's start is relaxed by (1: not relaxed).
            let mut applied = 1.0;
            if let (Some(x), Some(from), Some(r)) = (carried.as_mut(), &started_from, made.take()) {
                // r = S(x) − x, the change the last correction made to where it started.
                if let Some(previous) = &last_change {
                    omega = aitken(omega, previous, &r);
                }
                for ((x, from), r) in x.iter_mut().zip(from).zip(&r) {
                    *x = from + omega * r;
                }
                applied = omega;
                last_change = Some(r);
            }
            started_from = carried.clone();
            posed.contact = carried;
            let step = self.contact_step(model, posed, (moving, path), 1.0, false, cancel);
            match step.map(|next| (hand_contact_force(model, &next), next)) {
                Ok((now, next)) if now > 0.0 => {
                    let change = (now - force).abs() / force;
                    changes.push(change);
                    retry_failed = None;
                    // How far this correction moved the carried state from where it started.
                    if let (Some(end), Some(from)) = (carried_by(model, &next), &started_from) {
                        let r: Vec<f64> = end.iter().zip(from).map(|(s, x)| s - x).collect();
                        moves.push(r.iter().map(|v| v * v).sum::<f64>().sqrt());
                        let growing = matches!(moves[..], [.., a, b, c] if a < b && b < c);
                        unsettled.moved = largest_move(model, &r, growing);
                        made = Some(r);
                    }
                    frame = next;
                    kept += 1;
                    // A damped start changes the force less by itself: the change is measured
                    // as if undamped, so that damping does not pass for settling.
                    if change <= CONTACT_CORRECTION * applied.min(1.0) {
                        unsettled.change = None;
                        break;
                    }
                    unsettled.change = Some(change);
                }
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                // Started beyond the last correction's end (ω > 1, extrapolated): a state
                // no correction reached, which can lie past what the bodies bear (a tangent
                // that is no longer positive definite), or out of contact. Redone plainly from the
                // last frame; its error is reported if no correction is left to redo it.
                ended @ (Ok(_) | Err(_)) if applied > 1.0 => {
                    if let Err(e) = ended {
                        retry_failed = Some(e.to_string());
                    }
                    *posed = before;
                    started_from = None;
                    last_change = None;
                    omega = 1.0;
                }
                // Out of contact: the last frame stands.
                Ok(_) => {
                    *posed = before;
                    break;
                }
                // Not settled: the last frame stands, and the report says why.
                Err(e) => {
                    *posed = before;
                    unsettled.failed = Some(e.to_string());
                    break;
                }
            }
        }
        if unsettled.failed.is_none() {
            unsettled.failed = retry_failed;
        }
        Ok((frame, kept, unsettled))
    }

    /// `frame`, reached by a motion that pressed a body and whose hands end near it without
    /// pressing it (they let go). Nothing remembers the grasp — the contact is elastic — so the
    /// frame is solved as one that was never touched: on the small-strain and corotational
    /// tiers one contact step from the bodies at rest, as the frames before the hands touched;
    /// on the nonlinear tier Newton iterations at the pose from the bodies' static frame until
    /// their displacements change by less than [`RELEASE_SETTLED`] of their largest (at most
    /// [`RELEASE_CORRECTIONS`]). The motion's last step alone, linearised about the squeezed
    /// state it started from (the corotated ball turned with its dent), left them a step short
    /// (the five-digit ball grasp opened: the ball tilted by 1.5–2.6° and its top 3 mm off its
    /// static frame). The pairs within the search stay in the frame. A step that touches again
    /// ends it with that frame (then corrected as any frame in contact); one that fails leaves
    /// the last frame and says why, as does a nonlinear settle still changing after its last
    /// step. Returns the frame, the steps kept and that failure.
    fn settle_released(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        mut frame: Frame,
        cancel: Option<&CancelCheck>,
    ) -> Result<(Frame, usize, Option<String>), SimError> {
        let nonlinear = model.nonlinear_statics;
        let hand_dof = hand_dofs(model, posed);
        // Without a static frame (a floating body held by the hands) Newton starts from rest;
        // the flesh carries no contact displacement.
        let mut start = nonlinear.then(|| {
            let mut x = self.still.as_ref().map_or_else(
                || vec![0.0; hand_dof.len()],
                |still| still.solution.displacement.clone(),
            );
            for (x, _) in x.iter_mut().zip(&hand_dof).filter(|(_, h)| **h) {
                *x = 0.0;
            }
            x
        });
        let mut failed = None;
        let mut kept = 0;
        while kept < RELEASE_CORRECTIONS {
            let before = posed.clone();
            posed.contact = start.clone();
            match self.contact_step(model, posed, (moving, path), 1.0, false, cancel) {
                Ok(next) => {
                    let now = carried_by(model, &next);
                    let touching = hand_contact_force(model, &next) > 0.0;
                    frame = next;
                    kept += 1;
                    let (Some(now), Some(from), false) = (now, start.as_ref(), touching) else {
                        break;
                    };
                    let (change, size) = (0..now.len())
                        .filter(|&i| !hand_dof[i])
                        .fold((0.0_f64, 0.0_f64), |(c, s), i| {
                            (c.max((now[i] - from[i]).abs()), s.max(now[i].abs()))
                        });
                    if !nonlinear || change <= RELEASE_SETTLED * size {
                        break;
                    }
                    if kept == RELEASE_CORRECTIONS {
                        failed = Some(format!(
                            "the bodies let go of still moved {change:.3e} m in the last of \
                             {kept} Newton iterations at the pose"
                        ));
                    }
                    start = Some(now);
                }
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(e) => {
                    *posed = before;
                    failed = Some(format!("settling the bodies let go of: {e}"));
                    break;
                }
            }
        }
        Ok((frame, kept, failed))
    }

    /// One contact step: the moving hands flexed to fraction `f` of their motion, then the frame
    /// with the contact solved from what `posed` carries; with `along`, skin whose path over the
    /// step went into a body is held where it went through.
    #[allow(clippy::too_many_arguments)]
    fn contact_step(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (moving, path): Motion<'_, '_>,
        f: f64,
        along: bool,
        cancel: Option<&CancelCheck>,
    ) -> Result<Frame, SimError> {
        let previous: Vec<Vec<Vector3<f64>>> = posed
            .hands
            .iter()
            .map(|h| h.frame.positions.clone())
            .collect();
        // (Only where the step goes on from a frame in contact: one that touches nothing, on
        // the way to the objects, is rarely solved.)
        let knots: Vec<Knot> = if presses(model, posed, posed.contact.as_deref()) {
            (0..moving.len()).map(|k| path.knot_at(k, f)).collect()
        } else {
            Vec::new()
        };
        // The hands at `f`: their knots flexed where not yet (here, or taken from the thread
        // flexing them ahead).
        let caches = &mut self.caches;
        let hands = &mut posed.hands;
        let mut pose_hands = || -> Result<(), SimError> {
            for (k, (h, _, _)) in moving.iter().enumerate() {
                let mut flex = |body: usize, state: HandState, angles: &[f64], parts: Parts| {
                    flex_hand((model, caches, cancel), body, state, angles, parts)
                };
                let state = path.state_at(model, k, f, &mut flex)?;
                let hand = &mut hands[*h];
                hand.frame = hand_frame(model, hand.body, &state, path.stats(k));
                hand.state = state;
            }
            Ok(())
        };
        // Beside a knot's flexion (`knots`), the objects' part of the step's K and its factor,
        // which do not depend on it (src/solve/objects_factor.rs): while the other thread
        // flexes it, here first; while it is flexed here, on the other core. (A step from a
        // frame in contact only, above.)
        let contact = &mut self.contact;
        let carried = posed.contact.as_deref();
        if knots.contains(&Knot::Ahead) {
            contact.prepare_objects(model, carried, !along);
            pose_hands()?;
        } else if knots.contains(&Knot::Here) {
            let (posed_hands, ()) = rayon::join(pose_hands, || {
                contact.prepare_objects(model, carried, !along)
            });
            posed_hands?;
        } else {
            pose_hands()?;
        }
        frame_with_hands(
            model,
            self.still.as_ref(),
            posed.hands.iter().map(|h| h.frame.clone()).collect(),
            (
                posed.contact.as_deref(),
                along.then_some(previous.as_slice()),
            ),
            &mut self.contact,
        )
    }
}

/// The largest change of a joint angle from `from` to `to`, degrees.
fn largest_change(from: &[f64], to: &[f64]) -> f64 {
    from.iter()
        .zip(to)
        .map(|(a, b)| (b - a).abs())
        .fold(0.0, f64::max)
}

/// The contact steps of at most [`CONTACT_STEP_DEG`] a motion whose joints change by at most
/// `largest` degrees goes in along its path (at least one).
fn contact_steps(largest: f64) -> usize {
    (largest / CONTACT_STEP_DEG).ceil().max(1.0) as usize
}

/// The hands `targets` moves (their index in `posed.hands`, the angles they start from, their
/// targets).
pub(super) fn moving_hands(
    posed: &Posed,
    targets: &[(usize, Vec<f64>)],
) -> Vec<(usize, Vec<f64>, Vec<f64>)> {
    targets
        .iter()
        .map(|(b, target)| {
            let h = posed
                .hands
                .iter()
                .position(|h| h.body == *b)
                .expect("targets name hand bodies");
            (h, posed.hands[h].state.angles.clone(), target.clone())
        })
        .collect()
}

/// The flexion of the hands `moving` ([`moving_hands`]) over a keyframe from `posed`: knots
/// every `max_step_deg`, the parts far from every other body over the whole keyframe left to
/// skinning (but not those skinning would crush).
pub(super) fn flexion_path(
    model: &Model,
    posed: &Posed,
    moving: &[(usize, Vec<f64>, Vec<f64>)],
    thumb_after_fingers: bool,
) -> FlexionPath {
    FlexionPath::new(
        model,
        moving.iter().map(|(h, _, to)| {
            let hand = &posed.hands[*h];
            // (Each skins the hand over the keyframe: on both cores.)
            let (mut far, crushed) = rayon::join(
                || far_parts_of(model, hand.body, &hand.state, to),
                || crushed_parts_of(model, hand.body, &hand.state, to),
            );
            for (f, c) in far.iter_mut().zip(crushed) {
                *f &= !c;
            }
            (hand.body, hand.state.clone(), to.clone(), far)
        }),
        thumb_after_fingers,
    )
}

/// Flexes hand body `b` from `state` to `target` (a knot of [`FlexionPath`]: the parts `far`
/// left to skinning, its FEM region chosen on the flesh at `region_at`), with the flexion caches
/// of `caches` (taken for the hand and put back): the state reached and what it cost.
pub(super) fn flex_hand(
    (model, caches, cancel): (
        &Model,
        &mut Vec<(usize, FlexionCaches)>,
        Option<&CancelCheck>,
    ),
    b: usize,
    mut state: HandState,
    target: &[f64],
    (far, region_at): Parts<'_>,
) -> Result<(HandState, KeyframeStats), SimError> {
    if let Some(kept) = caches
        .iter()
        .find(|(cb, _)| *cb == b)
        .and_then(|(_, c)| c.knots.get((&state, target, far, region_at)))
    {
        return Ok(kept);
    }
    let mut stepper = hand_stepper(model, caches, b);
    if let Some(cancel) = cancel {
        stepper = stepper.with_cancel(cancel.clone());
    }
    stepper.set_far_parts(far);
    stepper.set_region_geometry(Some(region_at.to_vec()));
    let result = stepper.move_to(&mut state, target);
    caches.push((b, stepper.into_caches()));
    result.map(|stats| (state, stats))
}

/// The flexion stepper of hand body `b`, with its caches taken out of `caches` (or new ones):
/// put them back with [`Flexion::into_caches`].
pub(super) fn hand_stepper<'m>(
    model: &'m Model,
    caches: &mut Vec<(usize, FlexionCaches)>,
    b: usize,
) -> Flexion<'m> {
    let body = &model.bodies[b];
    let hand = body.hand.as_deref().expect("a hand body");
    let kept = match caches.iter().position(|(cb, _)| *cb == b) {
        Some(i) => caches.swap_remove(i).1,
        None => FlexionCaches::new(model.ordering),
    };
    Flexion::new(
        hand,
        &body.name,
        model.cell_materials[body.cells.clone()].to_vec(),
        model.flexion.clone(),
        model.ordering,
    )
    .with_caches(kept)
}

/// The relaxation factor of the next correction at the pose by Aitken's Δ² on vectors (Irons
/// and Tuck 1969; as in partitioned fluid–structure coupling, Küttler and Wall 2008): with
/// `r_prev` and `r` the changes the last two corrections made to the carried state they started
/// from (r = S(x) − x) and `omega` the factor the last one was started with,
/// ω ← −ω·r_prev·(r − r_prev) / |r − r_prev|². Corrections that alternate in sign (the
/// corotated ball: +2.6, −1.0, +0.4 %) are damped towards their fixed point, those that shrink
/// steadily in one sign (the Neo-Hookean ball under its air, ratio ≈ 0.75) are extended; the
/// factor stays within [`RELAXATION`], and 1 where the two changes are equal.
fn aitken(omega: f64, r_prev: &[f64], r: &[f64]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in r_prev.iter().zip(r) {
        let d = b - a;
        num += a * d;
        den += d * d;
    }
    let next = -omega * num / den;
    if next.is_finite() {
        next.clamp(RELAXATION.0, RELAXATION.1)
    } else {
        1.0
    }
}

/// What a keyframe's contact steps came to: the contact steps kept (along the motion and at
/// the pose), those redone, the corrections at the pose and, when they did not settle, the
/// last one's relative change of force.
struct Counts {
    steps: usize,
    retries: usize,
    corrections: usize,
    unsettled: Unsettled,
}

/// How the corrections at the pose ended, when not settled: the last kept one's relative
/// change of the hands' contact force, and the error of a correction that failed (the frame
/// is then the last one kept).
#[derive(Default)]
struct Unsettled {
    change: Option<f64>,
    failed: Option<String>,
    /// Where the last correction moved the carried state most: its node, how far, and whether
    /// the corrections moved it ever more.
    moved: Option<UnsettledMotion>,
}

/// The node the change `r` of the carried state moves most, and how far (`None` when nothing
/// moves); `growing`: the last three corrections moved it ever more.
fn largest_move(model: &Model, r: &[f64], growing: bool) -> Option<UnsettledMotion> {
    let (node, metres) = r
        .chunks_exact(3)
        .map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
        .enumerate()
        .filter(|(_, m)| m.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let body = model.bodies.iter().find(|b| b.nodes.contains(&node))?;
    (metres > 0.0).then(|| UnsettledMotion {
        body: body.name.clone(),
        node: node - body.nodes.start,
        moved: metres,
        growing,
    })
}

/// Ends a keyframe at `frame`: each moving hand's cost (its flexion along `path`, the contact
/// steps `counts`) and where its motion stopped short, in the frame and in `posed`, which
/// carries the frame's contact on.
fn finish(
    model: &Model,
    posed: &mut Posed,
    (moving, path): Motion<'_, '_>,
    frame: &mut Frame,
    counts: Counts,
    short: Option<StoppedShort>,
) {
    for (k, total) in keyframe_stats(posed, (moving, path), frame, &counts, short) {
        posed.hands[moving[k].0].frame.stats = total;
    }
    posed.contact = carried_by(model, frame);
}

/// Each moving hand's cost of the keyframe (its flexion along `path`, the contact steps
/// `counts`, where it stopped short), written into `frame`'s hands: (the hand's index in
/// `moving`, its stats).
fn keyframe_stats(
    posed: &Posed,
    (moving, path): Motion<'_, '_>,
    frame: &mut Frame,
    counts: &Counts,
    short: Option<StoppedShort>,
) -> Vec<(usize, KeyframeStats)> {
    let mut out = Vec::new();
    for (k, (h, _, _)) in moving.iter().enumerate() {
        let body = posed.hands[*h].body;
        let mut total = path.stats(k);
        total.contact_steps = counts.steps;
        total.contact_retries = counts.retries;
        total.pose_corrections = counts.corrections;
        total.unsettled_at_pose = counts.unsettled.change;
        total.unsettled_motion = counts.unsettled.change.and(counts.unsettled.moved.clone());
        total.correction_failed = counts.unsettled.failed.clone();
        total.stopped_short = short.clone();
        if let Some(fh) = frame.hands.iter_mut().find(|x| x.body == body) {
            fh.stats = total.clone();
        }
        out.push((k, total));
    }
    out
}

/// Shows `reached` the frame a motion reached at its pose, before its corrections, where it is
/// in contact with force on a hand (else no correction follows): a copy with the hands' costs so
/// far (`counts`, as [`finish`] writes them), its stresses left pending (the settled frame has
/// them; the window computes the draft's only where it draws them, [`super::complete_stress`]:
/// 12–15 ms of a drag's first frame); not shown where a value is not finite (the corrections
/// then decide).
fn show_reached(
    model: &Model,
    posed: &Posed,
    (moving, path): Motion<'_, '_>,
    frame: &Frame,
    counts: Counts,
    reached: &dyn Fn(Frame),
) {
    if hand_contact_force(model, frame) <= 0.0 {
        return;
    }
    let mut frame = frame.clone();
    keyframe_stats(posed, (moving, path), &mut frame, &counts, None);
    if let Ok(frame) = SimError::finite(model, frame) {
        reached(frame);
    }
}

/// Whether `carried` (a frame's state carried into a step) presses the hands of `posed`: the
/// flesh's contact displacements are not all zero.
fn presses(model: &Model, posed: &Posed, carried: Option<&[f64]>) -> bool {
    carried.is_some_and(|c| {
        let hand_dof = hand_dofs(model, posed);
        c.iter().zip(&hand_dof).any(|(u, h)| *h && *u != 0.0)
    })
}

/// Whether each dof is a hand's (their carried displacements are the flesh's contact
/// displacements, the others the bodies' own).
fn hand_dofs(model: &Model, posed: &Posed) -> Vec<bool> {
    let mut of_hand = vec![false; 3 * model.mesh.node_count()];
    for h in &posed.hands {
        for n in model.bodies[h.body].nodes.clone() {
            of_hand[3 * n..3 * n + 3].fill(true);
        }
    }
    of_hand
}

/// The normal contact force on the hands in `frame`, N: the contacts one of whose nodes (skin
/// point's cell, or facet) belongs to a hand body; an object on its table alone gives 0.
fn hand_contact_force(model: &Model, frame: &Frame) -> f64 {
    let Some(contact) = frame.contact.as_ref() else {
        return 0.0;
    };
    let on_hand = |n: usize| model.bodies[model.body_of_node(n)].hand.is_some();
    contact
        .contacts
        .iter()
        .filter(|c| c.terms.iter().any(|&(n, _)| on_hand(n)))
        .map(|c| c.force)
        .sum()
}

/// Whether `frame` is a grasp past the muscles: in contact, a bone of a hand overruns its
/// threshold.
fn stopped_by_threshold(frame: &Frame) -> bool {
    frame.contact.is_some() && frame.hands.iter().any(|h| !h.overloads.is_empty())
}

/// Every hand of the model at rest.
fn rest_hands(model: &Model) -> Vec<PosedHand> {
    model
        .bodies
        .iter()
        .enumerate()
        .filter_map(|(b, body)| {
            body.hand.as_deref().map(|hand| {
                let state = HandState::rest(hand);
                PosedHand {
                    body: b,
                    frame: hand_frame(model, b, &state, KeyframeStats::default()),
                    state,
                }
            })
        })
        .collect()
}

/// The hands of a solved `frame` of `model` (bone motions recomputed from the angles), to go on
/// from there.
fn hands_of(model: &Model, frame: &Frame) -> Vec<PosedHand> {
    frame
        .hands
        .iter()
        .map(|h| {
            let hand = model.bodies[h.body].hand.as_deref().expect("a hand body");
            // As flexed: the contact's displacements and reactions taken off (the next contact
            // step adds them again from what is carried).
            let less = |values: &[Vector3<f64>], contact: &[Vector3<f64>]| -> Vec<Vector3<f64>> {
                values
                    .iter()
                    .enumerate()
                    .map(|(i, v)| v - contact.get(i).copied().unwrap_or_else(Vector3::zeros))
                    .collect()
            };
            let state = HandState {
                angles: h.angles.clone(),
                transforms: hand.skeleton.transforms(&h.angles),
                positions: less(&h.positions, &h.contact_displacement),
                reaction: less(&h.reaction, &h.contact_reaction),
                self_contact: h.self_contact.clone(),
                // (Not in a frame: a finger skinned far from contact before it counts as
                // solved.)
                far_strained: Vec::new(),
            };
            PosedHand {
                body: h.body,
                frame: hand_frame(model, h.body, &state, h.stats.clone()),
                state,
            }
        })
        .collect()
}

/// A flexion `error` of a keyframe whose hands (body, angles) moved from `from` towards
/// `targets`, told with the share of the keyframe's motion where it failed.
fn keyframe_share(
    model: &Model,
    error: SimError,
    from: &[(usize, Vec<f64>)],
    targets: &[(usize, Vec<f64>)],
) -> SimError {
    super::error::with_keyframe_share(error, |body, joint, angle| {
        let b = model.bodies.iter().position(|x| x.name == body)?;
        let hand = model.bodies[b].hand.as_ref()?;
        let i = hand.skeleton.dofs.iter().position(|d| d.name == joint)?;
        let start = from.iter().find(|(x, _)| *x == b)?.1.get(i)?;
        let end = targets.iter().find(|(x, _)| *x == b)?.1.get(i)?;
        let span = end - start;
        (span.abs() > 1e-9).then(|| ((angle - start) / span).clamp(0.0, 1.0))
    })
}

/// An obstacle whose surface lies deeper than this fraction of a body's size inside it at rest
/// is told as the cause of the body's strain (a shallower overlap is a squeeze, as the plates
/// of tests/gas_cavity.rs).
const OBSTACLE_CUT: f64 = 0.02;

/// `error` told as the strain of `still`, the static frame, where it strains a body beyond
/// [`STRAIN_WARNING`] (see [`Workspace::beyond_small_strain`]); otherwise `error`. With
/// `obstacles` (`still` was solved in contact with them), an obstacle cutting the body at rest
/// is named as the cause.
fn beyond_small_strain(model: &Model, still: &Frame, obstacles: bool, error: SimError) -> SimError {
    let object = |name: &str| {
        model
            .bodies
            .iter()
            .any(|b| b.name == name && b.hand.is_none())
    };
    let relevant = match &error {
        SimError::Contact(_) | SimError::Gas { .. } => true,
        SimError::InvertedElement { body, .. } => object(body),
        _ => false,
    };
    if !relevant {
        return error;
    }
    let worst = largest_strains(model, still)
        .into_iter()
        .enumerate()
        .filter_map(|(b, s)| Some((b, s?)))
        .filter(|(_, s)| s.is_finite() && *s > STRAIN_WARNING)
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let Some((b, strain)) = worst else {
        return error;
    };
    // An obstacle cutting the body at rest by more than a squeeze: that is the cause.
    let body = &model.bodies[b];
    let cut = model
        .obstacles
        .iter()
        .filter(|_| obstacles)
        .map(|(name, o)| {
            let depth = body
                .nodes
                .clone()
                .map(|n| -o.nearest(&model.mesh.nodes[n]).0)
                .fold(0.0_f64, f64::max);
            (name, depth)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1));
    if let Some((obstacle, depth)) = cut.filter(|&(_, d)| d > OBSTACLE_CUT * body.size) {
        return SimError::ObstacleCutsBody {
            obstacle: obstacle.clone(),
            body: body.name.clone(),
            depth,
            size: body.size,
            strain,
            cause: Box::new(error),
        };
    }
    // Linear elasticity scales exactly: E × factor brings the loads' strain to half the
    // warning, a margin for what contact with the obstacles adds (the table under a ball).
    let factor = strain / (0.5 * STRAIN_WARNING);
    let advice = super::error::stiffer_materials(model, b, factor);
    SimError::BeyondSmallStrain {
        body: model.bodies[b].name.clone(),
        hands: model.bodies.iter().any(|b| b.hand.is_some()),
        strain,
        factor,
        advice,
        cause: Box::new(error),
    }
}

/// Solves every frame of the model: the static frame of the other bodies, every hand carried
/// from rest to its initial pose, then through the keyframes. One frame per distinct keyframe
/// time (time 0 first); returns the times and the frames.
pub fn solve_frames(model: &Model) -> Result<(Vec<f64>, Vec<Frame>), SimError> {
    let mut workspace = Workspace::new(model)?;
    let mut posed = Posed::rest(model);
    if posed.hands.is_empty() {
        let still = workspace.still.take().expect("solved without hands");
        return Ok((vec![0.0], vec![still]));
    }
    let initial: Vec<(usize, Vec<f64>)> = posed
        .hands
        .iter()
        .map(|h| (h.body, model.bodies[h.body].initial_angles.clone()))
        .collect();
    let mut times = vec![0.0];
    let mut frames = vec![workspace.move_hands(model, &mut posed, &initial, None)?];
    let mut k = 0;
    while k < model.keyframes.len() {
        let time = model.keyframes[k].time;
        let mut targets = Vec::new();
        let mut grasps = Vec::new();
        while k < model.keyframes.len() && model.keyframes[k].time == time {
            let key = &model.keyframes[k];
            if key.grasp.is_some() {
                grasps.push(key);
            } else {
                targets.push((key.body, key.angles.clone()));
            }
            k += 1;
        }
        // The hands posed first, then each grasp closes its hand on its object.
        let mut frame = None;
        if !targets.is_empty() || grasps.is_empty() {
            frame = Some(workspace.move_hands(model, &mut posed, &targets, None)?);
        }
        for key in grasps {
            let mut closed = workspace.close_grip(model, &mut posed, key, None)?;
            // A frame of several hands keeps what each grasp found.
            if let Some(before) = &frame {
                for h in &before.hands {
                    if let (Some(g), Some(now)) =
                        (&h.grasp, closed.hands.iter_mut().find(|c| c.body == h.body))
                    {
                        now.grasp.get_or_insert_with(|| g.clone());
                    }
                }
            }
            frame = Some(closed);
        }
        let frame = frame.expect("a frame per keyframe time");
        if time == 0.0 {
            frames[0] = frame;
        } else {
            times.push(time);
            frames.push(frame);
        }
    }
    Ok((times, frames))
}

/// Which parts of hand `body` stay far from contact on the way from `state` to `target` (none
/// when `[solver] far_from_contact = "solve"`).
fn far_parts_of(model: &Model, body: usize, state: &HandState, target: &[f64]) -> [bool; PARTS] {
    match model.flexion.near_contact {
        Some(distance) => super::proximity::far_parts(model, body, state, target, distance),
        None => [false; PARTS],
    }
}

/// Which parts of hand `body` skinning would crush on the way from `state` to `target` (none
/// when `[solver] far_from_contact = "solve"`: nothing is skinned then).
fn crushed_parts_of(
    model: &Model,
    body: usize,
    state: &HandState,
    target: &[f64],
) -> [bool; PARTS] {
    match model.flexion.near_contact {
        Some(_) => {
            let hand = model.bodies[body].hand.as_deref().expect("a hand body");
            crushed_by_skinning(model, hand, state, target)
        }
        None => [false; PARTS],
    }
}

/// The frame of a model with nothing free (only hands): every displacement and reaction zero.
fn still_frame(model: &Model) -> Frame {
    let dofs = 3 * model.mesh.node_count();
    Frame {
        solution: Solution {
            displacement: vec![0.0; dofs],
            reaction: vec![0.0; dofs],
            stats: SolveStats {
                prescribed_dofs: model.partition.prescribed_count(),
                ..Default::default()
            },
        },
        stress: StressField {
            gauss: vec![[Matrix3::zeros(); 8]; model.mesh.cell_count()],
            nodal: vec![Matrix3::zeros(); model.mesh.node_count()],
            cell_von_mises: vec![0.0; model.mesh.cell_count()],
        },
        stress_pending: None,
        assembly_ms: 0.0,
        stress_ms: 0.0,
        hands: Vec::new(),
        contact: None,
    }
}

/// The frame of hand body `body` in `state`, with what reaching it cost.
fn hand_frame(
    model: &Model,
    body: usize,
    state: &HandState,
    stats: crate::state::KeyframeStats,
) -> HandFrame {
    let hand = model.bodies[body].hand.as_deref().unwrap();
    let bone_reactions = state.bone_reactions(hand);
    HandFrame {
        body,
        angles: state.angles.clone(),
        positions: state.positions.clone(),
        contact_displacement: Vec::new(),
        contact_reaction: Vec::new(),
        bone_reactions: bone_reactions.clone(),
        reaction: state.reaction.clone(),
        self_contact: state.self_contact.clone(),
        volume: state.flesh_volume(hand),
        stats,
        contact_force: vec![nalgebra::Vector3::zeros(); hand.skeleton.bones.len()],
        overloads: crate::state::outcome::overloads(
            hand,
            &state.transforms,
            &bone_reactions,
            &model.bodies[body].thresholds,
        ),
        grasp: None,
    }
}

/// The bodies of the hands `moving` (hand index in `posed`, angles from, to).
fn moving_bodies(posed: &Posed, moving: &[(usize, Vec<f64>, Vec<f64>)]) -> Vec<usize> {
    moving
        .iter()
        .map(|(h, _, _)| posed.hands[*h].body)
        .collect()
}

/// Contact solves of the keyframe redone, counted in each moving hand's stats, in `posed` and
/// in `frame`: a one-step attempt (`first` `None`), or every solve of a `first` attempt (its
/// steps kept and those it redid itself).
fn count_retry(
    posed: &mut Posed,
    moving: &[(usize, Vec<f64>, Vec<f64>)],
    frame: &mut Frame,
    first: Option<&Frame>,
) {
    for h in moving {
        let body = posed.hands[h.0].body;
        let n = first
            .and_then(|f| f.hands.iter().find(|x| x.body == body))
            .map_or(1, |x| x.stats.contact_steps + x.stats.contact_retries);
        posed.hands[h.0].frame.stats.contact_retries += n;
        if let Some(fh) = frame.hands.iter_mut().find(|x| x.body == body) {
            fh.stats.contact_retries += n;
        }
    }
}
