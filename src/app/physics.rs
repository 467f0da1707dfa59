//! The real computation behind the solver thread: builds the model when the scene changes,
//! solves the static bodies once per model, and moves the hands by increments
//! ([`Flexion::move_to`]) from the state it holds to the pose asked for — so a slider change costs
//! only the increments between the shown pose and the new one.

use super::jobs::{Failure, Job, Pose, Solution, Target};
use super::worker::{Cancel, Solve};
use crate::fem::solve::PartitionedSolver;
use crate::model::Model;
use crate::present::draw_list;
use crate::solve::{
    frame_with_hands, hand_frame, set_far_parts, solve_static, still_frame, Flexion, LinearFactor,
    SimError,
};
use crate::state::{Frame, HandState, KeyframeStats};
use crate::util::timing::ms;
use std::sync::Arc;
use std::time::Instant;

/// Hand states by hand body index.
type States = Vec<(usize, HandState)>;

/// The linear tier's factored stiffness by hand body index, kept for the model's life so that
/// a change costs one solve, not a factorization.
type LinearFactors = Vec<(usize, LinearFactor)>;

/// The model and states kept between jobs.
#[derive(Default)]
pub struct Physics {
    revision: Option<u64>,
    model: Option<Arc<Model>>,
    still: Option<Frame>,
    states: States,
    /// States of the last frame delivered, restored after a failure or a panic.
    last_good: States,
    /// Set while a job changes `states`; still set at the next job means the last one panicked.
    dirty: bool,
    /// The linear tier's factors of the current model.
    linear: LinearFactors,
}

fn error(e: impl std::fmt::Display) -> Failure {
    Failure::Error(e.to_string())
}

/// The states of the hands of a solved frame (transforms recomputed from the angles).
fn states_of(model: &Model, frame: &Frame) -> States {
    frame
        .hands
        .iter()
        .map(|h| {
            let hand = model.bodies[h.body].hand.as_deref().expect("a hand body");
            (
                h.body,
                HandState {
                    angles: h.angles.clone(),
                    transforms: hand.skeleton.transforms(&h.angles),
                    positions: h.positions.clone(),
                    reaction: h.reaction.clone(),
                },
            )
        })
        .collect()
}

fn rest_states(model: &Model) -> States {
    model
        .bodies
        .iter()
        .enumerate()
        .filter_map(|(b, body)| body.hand.as_deref().map(|h| (b, HandState::rest(h))))
        .collect()
}

impl Physics {
    /// Nothing built yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds the model and its static frame when the scene revision changed.
    fn ensure_model(&mut self, job: &Job) -> Result<Arc<Model>, Failure> {
        if self.revision != Some(job.scene_revision) || self.model.is_none() {
            self.model = None;
            let model = Model::build(&job.scene, "scene").map_err(error)?;
            let still = if model.partition.free_count() == 0 {
                still_frame(&model)
            } else {
                solve_static(&model, &mut PartitionedSolver::new(model.ordering)).map_err(error)?
            };
            self.states = rest_states(&model);
            self.last_good = self.states.clone();
            self.linear.clear();
            self.still = Some(still);
            self.model = Some(Arc::new(model));
            self.revision = Some(job.scene_revision);
        }
        Ok(self.model.clone().expect("built above"))
    }

    /// Moves every hand of `states` to `pose`; returns the frame.
    fn move_hands(
        model: &Model,
        still: &Frame,
        states: &mut States,
        pose: &Pose,
        cancel: &Cancel,
        linear: &mut LinearFactors,
    ) -> Result<Frame, SimError> {
        let mut hands = Vec::new();
        for (b, state) in states.iter_mut() {
            let body = &model.bodies[*b];
            let hand = body.hand.as_deref().expect("a hand body");
            let stats = match pose.iter().find(|(pb, _)| pb == b) {
                Some((_, target)) => {
                    let c = cancel.clone();
                    let mut stepper = Flexion::new(
                        hand,
                        &body.name,
                        model.cell_materials[body.cells.clone()].to_vec(),
                        model.flexion.clone(),
                        model.ordering,
                    )
                    .with_cancel(Arc::new(move || c.is_stale()))
                    .with_linear_factor(
                        linear
                            .iter()
                            .position(|(lb, _)| lb == b)
                            .map(|i| linear.swap_remove(i).1),
                    );
                    set_far_parts(model, *b, &mut stepper, state, target);
                    let result = stepper.move_to(state, target);
                    if let Some(factor) = stepper.take_linear_factor() {
                        linear.push((*b, factor));
                    }
                    result?
                }
                None => KeyframeStats::default(),
            };
            hands.push(hand_frame(model, *b, state, stats));
        }
        frame_with_hands(model, Some(still), hands)
    }

    fn deliver(
        &self,
        job: &Job,
        model: &Arc<Model>,
        frame: Frame,
        started: Instant,
        timeline_frame: Option<usize>,
    ) -> Result<Solution, Failure> {
        let list = draw_list(model, &frame, &job.visual).map_err(error)?;
        Ok(Solution {
            model: model.clone(),
            frame: Arc::new(frame),
            draw_list: Arc::new(list),
            solve_ms: ms(started),
            timeline_frame,
            visual: job.visual,
        })
    }

    fn pose(
        &mut self,
        job: &Job,
        pose: &Pose,
        start: Option<&Arc<Frame>>,
        cancel: &Cancel,
    ) -> Result<Solution, Failure> {
        let started = Instant::now();
        let model = self.ensure_model(job)?;
        if let Some(start) = start {
            if start.solution.displacement.len() == 3 * model.mesh.node_count() {
                self.states = states_of(&model, start);
            }
        }
        let still = self.still.as_ref().expect("built with the model");
        self.dirty = true;
        let result = Self::move_hands(
            &model,
            still,
            &mut self.states,
            pose,
            cancel,
            &mut self.linear,
        );
        self.dirty = false;
        match result {
            Ok(frame) => {
                self.last_good = self.states.clone();
                self.deliver(job, &model, frame, started, None)
            }
            // The state stopped at a completed increment: the next job goes on from there.
            Err(SimError::Cancelled) => Err(Failure::Cancelled),
            Err(e) => {
                self.states = self.last_good.clone();
                Err(error(e))
            }
        }
    }

    fn timeline(
        &mut self,
        job: &Job,
        first: usize,
        start: Option<&Arc<Frame>>,
        poses: &[Pose],
        cancel: &Cancel,
        emit: &mut dyn FnMut(Result<Solution, Failure>),
    ) -> Result<(), Failure> {
        let model = self.ensure_model(job)?;
        let still = self.still.as_ref().expect("built with the model");
        let mut states = match start {
            Some(f) if f.solution.displacement.len() == 3 * model.mesh.node_count() => {
                states_of(&model, f)
            }
            _ => rest_states(&model),
        };
        for (i, pose) in poses.iter().enumerate() {
            if cancel.is_stale() {
                return Err(Failure::Cancelled);
            }
            let started = Instant::now();
            let frame = match Self::move_hands(
                &model,
                still,
                &mut states,
                pose,
                cancel,
                &mut self.linear,
            ) {
                Ok(f) => f,
                Err(SimError::Cancelled) => return Err(Failure::Cancelled),
                Err(e) => return Err(error(e)),
            };
            emit(self.deliver(job, &model, frame, started, Some(first + i)));
        }
        Ok(())
    }
}

impl Solve for Physics {
    fn run(&mut self, job: &Job, cancel: &Cancel, emit: &mut dyn FnMut(Result<Solution, Failure>)) {
        if self.dirty {
            // The previous job panicked half-way: go back to the last frame delivered.
            self.states = self.last_good.clone();
            self.dirty = false;
        }
        match &job.target {
            Target::Pose { pose, start } => emit(self.pose(job, pose, start.as_ref(), cancel)),
            Target::Timeline {
                first,
                start,
                poses,
            } => {
                if let Err(e) = self.timeline(job, *first, start.as_ref(), poses, cancel, emit) {
                    emit(Err(e));
                }
            }
        }
    }
}
