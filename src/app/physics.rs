//! The real computation behind the solver thread: builds the model when the scene changes,
//! solves the static bodies once per model, and moves the hands by increments
//! (the keyframe driver, [`Workspace::move_hands`]) from where it holds them to the pose asked
//! for — so a slider change costs
//! only the increments between the shown pose and the new one.

use super::jobs::{Failure, Job, Pose, Solution, Target};
use super::worker::{Cancel, Solve};
use crate::model::Model;
use crate::present::{draw_list_with, Overlay, SkinDetail};
use crate::solve::{complete_stress, skinned_preview, CancelCheck, Posed, SimError, Workspace};
use crate::state::Frame;
use crate::util::timing::ms;
use std::sync::Arc;
use std::time::Instant;

/// The model, its workspace and the hands kept between jobs.
#[derive(Default)]
pub struct Physics {
    revision: Option<u64>,
    model: Option<Arc<Model>>,
    /// The driver's workspace of the current model (static frame, flexion caches), kept for the
    /// model's life so that a change costs only the increments between the shown pose and the
    /// new one (and with the linear tier one solve, not a factorization).
    workspace: Option<Workspace>,
    hands: Posed,
    /// Hands of the last frame delivered, restored after a failure or a panic.
    last_good: Posed,
    /// Set while a job changes `hands`; still set at the next job means the last one panicked.
    dirty: bool,
    /// The last frame a pose job delivered (of the current model): what a preview moves.
    last_frame: Option<Arc<Frame>>,
    /// The model's first keyframe prepared ahead ([`Workspace::prepare`]).
    prepared: bool,
    /// The poses the last job's window offers next (its presets), flexed ahead while idle
    /// ([`Workspace::anticipate`]) from where the next pose job will start: the hands held, or
    /// `ahead_from` (the timeline's frame shown: [`super::jobs::Ahead`]).
    ahead: Vec<super::jobs::Pose>,
    ahead_from: Option<Arc<Frame>>,
    /// The poses of `ahead` flexed ahead.
    anticipated: bool,
}

/// How long the solver waits with nothing to do before it flexes the presets ahead: a pause in
/// the editing, not the gap between two slider steps (a knot of the whole hand, once begun,
/// holds the next job up to ≈ 200 ms).
const PAUSE: std::time::Duration = std::time::Duration::from_millis(700);

fn error(e: impl std::fmt::Display) -> Failure {
    Failure::Error(e.to_string())
}

impl Physics {
    /// Nothing built yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds the model and its workspace when the scene revision changed.
    fn ensure_model(&mut self, job: &Job) -> Result<Arc<Model>, Failure> {
        if self.revision != Some(job.scene_revision) || self.model.is_none() {
            self.model = None;
            self.workspace = None;
            self.last_frame = None;
            self.prepared = false;
            let model = Model::build(&job.scene, "scene").map_err(error)?;
            self.workspace = Some(Workspace::new(&model).map_err(error)?);
            self.hands = Posed::rest(&model);
            self.last_good = self.hands.clone();
            self.model = Some(Arc::new(model));
            self.revision = Some(job.scene_revision);
        }
        Ok(self.model.clone().expect("built above"))
    }

    /// The model of `job`, and the hands set to `start`'s when it is a frame of that model
    /// (returned then).
    fn prepare<'a>(
        &mut self,
        job: &Job,
        start: Option<&'a Arc<Frame>>,
    ) -> Result<(Arc<Model>, Option<&'a Arc<Frame>>), Failure> {
        let model = self.ensure_model(job)?;
        let start = start.filter(|s| starts(&model, s));
        if let Some(start) = start {
            self.hands = Posed::of_frame(&model, start);
        }
        Ok((model, start))
    }

    fn pose(
        &mut self,
        job: &Job,
        pose: &Pose,
        start: Option<&Arc<Frame>>,
        cancel: &Cancel,
        emit: &mut dyn FnMut(Result<Solution, Failure>),
    ) -> Result<Solution, Failure> {
        let started = Instant::now();
        let (model, start) = self.prepare(job, start)?;
        // A pose solved ahead (a preset, while the solver was idle) is shown at once: no preview.
        let solved_ahead = self
            .workspace
            .as_ref()
            .is_some_and(|w| w.has_solved_ahead(&self.hands, pose));
        if let Some(from) = start
            .or(self.last_frame.as_ref())
            .filter(|_| !cancel.is_stale() && !solved_ahead)
        {
            if let Some(preview) = preview(job, &model, from, pose, started) {
                emit(Ok(preview));
            }
        }
        let workspace = self.workspace.as_mut().expect("built with the model");
        if let Some(frame) = workspace.take_solved_ahead(&mut self.hands, pose) {
            return self.delivered(job, &model, Ok(frame), started, false);
        }
        self.dirty = true;
        // The frame the motion reached at the pose goes out while the corrections settle its
        // contact (drawn as a draft, marked as settling); the settled frame follows.
        let emit = std::cell::RefCell::new(emit);
        let reached = |mut frame: Frame| {
            if cancel.is_stale() {
                return;
            }
            // Its stresses only where they are drawn (the settled frame has them).
            if job.visual.overlay == Overlay::Stress {
                let completed = complete_stress(&model, &mut frame)
                    .and_then(|()| SimError::finite(&model, frame));
                match completed {
                    Ok(f) => frame = f,
                    Err(_) => return,
                }
            }
            if let Ok(mut solution) = deliver(job, &model, frame, started, None, false) {
                solution.settling = true;
                (emit.borrow_mut())(Ok(solution));
            }
        };
        let result = workspace.move_hands_showing(
            &model,
            &mut self.hands,
            pose,
            Some(&stale(cancel)),
            &reached,
        );
        self.dirty = false;
        // Cancelled, the hands stopped at a completed increment: the next job goes on from
        // there.
        self.delivered(job, &model, result, started, false)
    }

    /// The frame a pose or grasp job solved, delivered (the hands kept as the last good ones),
    /// or why not (the hands back at the last good ones; kept where a cancelled job left them
    /// when `restore_cancelled` is false).
    fn delivered(
        &mut self,
        job: &Job,
        model: &Arc<Model>,
        result: Result<Frame, SimError>,
        started: Instant,
        restore_cancelled: bool,
    ) -> Result<Solution, Failure> {
        match result {
            Ok(frame) => {
                self.last_good = self.hands.clone();
                let solution = deliver(job, model, frame, started, None, false)?;
                self.last_frame = Some(solution.frame.clone());
                Ok(solution)
            }
            Err(SimError::Cancelled) => {
                if restore_cancelled {
                    self.hands = self.last_good.clone();
                }
                Err(Failure::Cancelled)
            }
            Err(e) => {
                self.hands = self.last_good.clone();
                Err(error(e))
            }
        }
    }

    /// The gentlest grip of hand `body` on the object `grasp` names, from the pose the solver
    /// holds (or `start`'s).
    fn grasp(
        &mut self,
        job: &Job,
        body: usize,
        grasp: &crate::scene::GraspDef,
        start: Option<&Arc<Frame>>,
        cancel: &Cancel,
    ) -> Result<Solution, Failure> {
        let started = Instant::now();
        let (model, _) = self.prepare(job, start)?;
        let from = self
            .hands
            .hands
            .iter()
            .find(|h| h.body == body)
            .map(|h| h.state.angles.clone())
            .ok_or_else(|| error(format!("body {body} is not a hand of the scene")))?;
        let key = crate::model::grasp_keyframe(&model, body, &from, grasp).map_err(error)?;
        let workspace = self.workspace.as_mut().expect("built with the model");
        self.dirty = true;
        let result = workspace.close_grip(&model, &mut self.hands, &key, Some(&stale(cancel)));
        self.dirty = false;
        // A grasp cancelled half-way leaves the hands at its preshape: back to the last good.
        self.delivered(job, &model, result, started, true)
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
        let mut hands = match start {
            Some(f) if starts(&model, f) => Posed::of_frame(&model, f),
            _ => Posed::rest(&model),
        };
        for (i, pose) in poses.iter().enumerate() {
            if cancel.is_stale() {
                return Err(Failure::Cancelled);
            }
            let started = Instant::now();
            let workspace = self.workspace.as_mut().expect("built with the model");
            let frame = match workspace.move_hands(&model, &mut hands, pose, Some(&stale(cancel))) {
                Ok(f) => f,
                Err(SimError::Cancelled) => return Err(Failure::Cancelled),
                Err(e) => return Err(error(e)),
            };
            emit(deliver(job, &model, frame, started, Some(first + i), false));
        }
        Ok(())
    }
}

/// Whether `frame` is of `model` (a job starts from it then).
fn starts(model: &Model, frame: &Frame) -> bool {
    frame.solution.displacement.len() == 3 * model.mesh.node_count()
}

/// `frame` of `model` as the window takes it, with its draw list: a preview's drawn with the
/// hands' coarse skin ([`SkinDetail::Coarse`]), so that it is on screen at once even on a
/// software renderer.
fn deliver(
    job: &Job,
    model: &Arc<Model>,
    frame: Frame,
    started: Instant,
    timeline_frame: Option<usize>,
    preview: bool,
) -> Result<Solution, Failure> {
    let detail = if preview {
        SkinDetail::Coarse
    } else {
        SkinDetail::Full
    };
    // (The tactile map's peaks and the flesh pressed inside out on the other core meanwhile:
    // both on a settling frame's way.)
    let (list, (tactile, pressed_inside_out)) = rayon::join(
        || draw_list_with(model, &frame, &job.visual, detail),
        || {
            if preview {
                return (None, Vec::new());
            }
            rayon::join(
                || crate::state::tactile_peaks(model, &frame),
                || inside_out_hands(model, &frame),
            )
        },
    );
    let list = list.map_err(error)?;
    Ok(Solution {
        model: model.clone(),
        frame: Arc::new(frame),
        draw_list: Arc::new(list),
        solve_ms: ms(started),
        timeline_frame,
        visual: job.visual,
        preview,
        settling: false,
        tactile,
        pressed_inside_out,
    })
}

/// Each hand of `frame` (its body's name) whose flesh its contact pressed inside out, and where.
fn inside_out_hands(model: &Model, frame: &Frame) -> Vec<(String, crate::state::InsideOut)> {
    frame
        .hands
        .iter()
        .filter_map(|h| {
            let hand = model.bodies[h.body].hand.as_deref()?;
            crate::state::pressed_inside_out(hand, &h.positions, &h.contact_displacement)
                .map(|t| (model.bodies[h.body].name.clone(), t))
        })
        .collect()
}

/// The pose of `job` drawn at once from `from` by skinning, where the model has bodies besides
/// its hands (whose contact makes a pose cost seconds; in free air the solved pose comes as fast
/// as a preview would).
fn preview(
    job: &Job,
    model: &Arc<Model>,
    from: &Frame,
    pose: &Pose,
    started: Instant,
) -> Option<Solution> {
    if model.bodies.iter().all(|b| b.hand.is_some()) {
        return None;
    }
    let frame = skinned_preview(model, from, pose)?;
    deliver(job, model, frame, started, None, true).ok()
}

/// The flexion's cancel check of a job: true once a newer request made it stale.
fn stale(cancel: &Cancel) -> CancelCheck {
    let c = cancel.clone();
    Arc::new(move || c.is_stale())
}

impl Solve for Physics {
    fn run(&mut self, job: &Job, cancel: &Cancel, emit: &mut dyn FnMut(Result<Solution, Failure>)) {
        if self.dirty {
            // The previous job panicked half-way: go back to the last frame delivered.
            self.hands = self.last_good.clone();
            self.dirty = false;
        }
        self.ahead = job.ahead.poses.clone();
        self.ahead_from = job.ahead.start.clone();
        self.anticipated = false;
        match &job.target {
            Target::Pose { pose, start } => {
                let solved = self.pose(job, pose, start.as_ref(), cancel, emit);
                emit(solved);
            }
            Target::Grasp { body, grasp, start } => {
                let solved = self.grasp(job, *body, grasp, start.as_ref(), cancel);
                emit(solved);
            }
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

    /// Once per model, the first keyframe's memory acquired ahead; a failure (a factor beyond
    /// the memory budget) is left for that keyframe to report.
    /// Then, after a pause in the editing ([`PAUSE`]), the presets the window offers flexed
    /// ahead from where the next pose job will start ([`Workspace::anticipate`]), and then
    /// solved whole ([`Workspace::solve_ahead`]).
    fn idle(&mut self, cancel: &Cancel) {
        if self.dirty {
            return;
        }
        let (Some(model), Some(workspace)) = (self.model.clone(), self.workspace.as_mut()) else {
            return;
        };
        if !self.prepared {
            let _ = workspace.prepare(&model, &self.hands, Some(&stale(cancel)));
            self.prepared = !cancel.is_stale();
        }
        if !self.prepared || self.anticipated || self.ahead.is_empty() {
            return;
        }
        let mut waited = Instant::now();
        while waited.elapsed() < PAUSE {
            if cancel.is_stale() {
                return;
            }
            if cancel.is_held() {
                waited = Instant::now();
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let posed = match self.ahead_from.as_ref().filter(|f| starts(&model, f)) {
            Some(frame) => Posed::of_frame(&model, frame),
            None => self.hands.clone(),
        };
        // Asked in every increment: waits there while the user moves something.
        let check: CancelCheck = {
            let c = cancel.clone();
            Arc::new(move || c.wait_then_is_stale())
        };
        workspace.anticipate(&model, &posed, &self.ahead, Some(&check));
        // Then each preset's keyframe whole, its contact solved: taken at once when pressed.
        for pose in &self.ahead {
            if cancel.is_stale() {
                return;
            }
            workspace.solve_ahead(&model, &posed, pose, Some(&check));
        }
        self.anticipated = !cancel.is_stale();
    }
}
