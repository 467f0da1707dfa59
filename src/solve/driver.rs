//! The one keyframe driver, for the CLI, the viewer and the benches: a [`Workspace`] per model
//! (the static frame of the bodies, the flexion caches), hands moved by flexion increments from
//! where they are to the angles asked for, and the frame with their contact solved. The timeline
//! of a scene ([`solve_frames`]) is the driver run over its keyframes.

use super::error::SimError;
use super::flexion::{CancelCheck, Flexion, FlexionCaches};
use super::grasp::frame_with_hands;
use super::statics::solve_static;
use crate::fem::solve::{PartitionedSolver, Solution, SolveStats};
use crate::fem::stress::StressField;
use crate::model::Model;
use crate::state::{Frame, HandFrame, HandState, KeyframeStats};
use nalgebra::Matrix3;

/// What changes while a model is solved, besides the hands' states (the `mjData` of this
/// project, with [`PosedHand`]): the static frame of the bodies that no hand moves, and the caches
/// every hand's flexion reuses between keyframes. Built once per model; the model stays immutable.
pub struct Workspace {
    /// The static frame of the other bodies; `None` when one of them can only be held by a hand.
    still: Option<Frame>,
    /// The flexion caches by hand body.
    caches: Vec<(usize, FlexionCaches)>,
}

/// A hand body where the driver left it: its state, and its part of the last frame.
#[derive(Clone, Debug)]
pub struct PosedHand {
    /// The hand body.
    pub body: usize,
    /// Angles, bone motions, flesh positions, accumulated reactions.
    pub state: HandState,
    /// The hand's part of the last frame (what reaching `state` cost included).
    pub frame: HandFrame,
}

impl Workspace {
    /// Solves the static frame of the bodies no hand moves (equations (6)–(8)), unless nothing
    /// is free, or a floating body can only be held by a hand (then the frames are solved with
    /// the hands' contact, [`frame_with_hands`]).
    pub fn new(model: &Model) -> Result<Workspace, SimError> {
        let has_hands = model.bodies.iter().any(|b| b.hand.is_some());
        let floating = model.bodies.iter().any(|b| b.floating);
        let still = if model.partition.free_count() == 0 {
            Some(still_frame(model))
        } else if floating && has_hands {
            None
        } else {
            Some(solve_static(
                model,
                &mut PartitionedSolver::new(model.ordering),
            )?)
        };
        Ok(Workspace {
            still,
            caches: Vec::new(),
        })
    }

    /// The static frame of the bodies no hand moves.
    pub fn still(&self) -> Option<&Frame> {
        self.still.as_ref()
    }

    /// Moves each hand of `targets` (hand body, joint angles in degrees) from where `hands` holds
    /// it by flexion increments, then solves the frame with every hand (the contact step where
    /// a hand touches a body). Hands not in `targets` stay as they are. `cancel` is asked before
    /// every increment: a cancelled hand stays at its last completed increment.
    pub fn move_hands(
        &mut self,
        model: &Model,
        hands: &mut [PosedHand],
        targets: &[(usize, Vec<f64>)],
        cancel: Option<&CancelCheck>,
    ) -> Result<Frame, SimError> {
        for (body, target) in targets {
            let h = hands
                .iter()
                .position(|h| h.body == *body)
                .expect("targets name hand bodies");
            self.move_hand(model, &mut hands[h], target, cancel)?;
        }
        frame_with_hands(
            model,
            self.still.as_ref(),
            hands.iter().map(|h| h.frame.clone()).collect(),
        )
    }

    /// Moves one hand to `target` (see [`Workspace::move_hands`]).
    fn move_hand(
        &mut self,
        model: &Model,
        posed: &mut PosedHand,
        target: &[f64],
        cancel: Option<&CancelCheck>,
    ) -> Result<(), SimError> {
        let b = posed.body;
        let body = &model.bodies[b];
        let hand = body.hand.as_deref().expect("a hand body");
        let caches = match self.caches.iter().position(|(cb, _)| *cb == b) {
            Some(i) => self.caches.swap_remove(i).1,
            None => FlexionCaches::new(model.ordering),
        };
        let mut stepper = Flexion::new(
            hand,
            &body.name,
            model.cell_materials[body.cells.clone()].to_vec(),
            model.flexion.clone(),
            model.ordering,
        )
        .with_caches(caches);
        if let Some(cancel) = cancel {
            stepper = stepper.with_cancel(cancel.clone());
        }
        set_far_parts(model, b, &mut stepper, &posed.state, target);
        let result = stepper.move_to(&mut posed.state, target);
        self.caches.push((b, stepper.into_caches()));
        // The hand's frame follows its state, also where a failed or cancelled keyframe left it.
        let stats = result.as_ref().cloned().unwrap_or_default();
        posed.frame = hand_frame(model, b, &posed.state, stats);
        result.map(|_| ())
    }
}

/// Every hand of the model at rest.
pub fn rest_hands(model: &Model) -> Vec<PosedHand> {
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
pub fn hands_of(model: &Model, frame: &Frame) -> Vec<PosedHand> {
    frame
        .hands
        .iter()
        .map(|h| {
            let hand = model.bodies[h.body].hand.as_deref().expect("a hand body");
            PosedHand {
                body: h.body,
                state: HandState {
                    angles: h.angles.clone(),
                    transforms: hand.skeleton.transforms(&h.angles),
                    positions: h.positions.clone(),
                    reaction: h.reaction.clone(),
                },
                frame: h.clone(),
            }
        })
        .collect()
}

/// Solves every frame of the model: the static frame of the other bodies, every hand carried
/// from rest to its initial pose, then through the keyframes. One frame per distinct keyframe
/// time (time 0 first); returns the times and the frames.
pub fn solve_frames(model: &Model) -> Result<(Vec<f64>, Vec<Frame>), SimError> {
    let mut workspace = Workspace::new(model)?;
    let mut hands = rest_hands(model);
    if hands.is_empty() {
        let still = workspace.still.take().expect("solved without hands");
        return Ok((vec![0.0], vec![still]));
    }
    let initial: Vec<(usize, Vec<f64>)> = hands
        .iter()
        .map(|h| (h.body, model.bodies[h.body].initial_angles.clone()))
        .collect();
    let mut times = vec![0.0];
    let mut frames = vec![workspace.move_hands(model, &mut hands, &initial, None)?];
    let mut k = 0;
    while k < model.keyframes.len() {
        let time = model.keyframes[k].time;
        let mut targets = Vec::new();
        while k < model.keyframes.len() && model.keyframes[k].time == time {
            let key = &model.keyframes[k];
            targets.push((key.body, key.angles.clone()));
            k += 1;
        }
        let frame = workspace.move_hands(model, &mut hands, &targets, None)?;
        if time == 0.0 {
            frames[0] = frame;
        } else {
            times.push(time);
            frames.push(frame);
        }
    }
    Ok((times, frames))
}

/// Tells `stepper` which parts of hand `body` stay far from contact on the way from `state`
/// to `target` (none when `[solver] far_from_contact = "solve"`).
pub fn set_far_parts(
    model: &Model,
    body: usize,
    stepper: &mut Flexion,
    state: &HandState,
    target: &[f64],
) {
    let far = match model.flexion.near_contact {
        Some(distance) => super::proximity::far_parts(model, body, state, target, distance),
        None => [false; super::proximity::PARTS],
    };
    stepper.set_far_parts(far);
}

/// The frame of a model with nothing free (only hands): every displacement and reaction zero.
pub fn still_frame(model: &Model) -> Frame {
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
        assembly_ms: 0.0,
        stress_ms: 0.0,
        hands: Vec::new(),
        contact: None,
    }
}

/// The frame of hand body `body` in `state`, with what reaching it cost.
pub fn hand_frame(
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
        bone_reactions: bone_reactions.clone(),
        reaction: state.reaction.clone(),
        volume: state.flesh_volume(hand),
        stats,
        contact_force: vec![nalgebra::Vector3::zeros(); hand.skeleton.bones.len()],
        overloads: crate::state::outcome::overloads(
            hand,
            &state.transforms,
            &bone_reactions,
            &model.bodies[body].thresholds,
        ),
    }
}
