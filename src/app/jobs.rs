//! What the window asks of the solver thread, and what comes back. Every request carries the
//! version of the inputs it was made from; every result carries that version back, so that the
//! window shows only the newest.

use crate::model::Model;
use crate::present::VisualOptions;
use crate::render::DrawList;
use crate::scene::Scene;
use crate::state::Frame;
use std::sync::Arc;

/// Joint angles (degrees) of every hand body, by body index.
pub type Pose = Vec<(usize, Vec<f64>)>;

/// A request to the solver thread.
#[derive(Clone)]
pub struct Job {
    /// Version of the window's inputs this job was made from (strictly increasing).
    pub version: u64,
    /// The scene, with the object and solver edits of the panels applied.
    pub scene: Arc<Scene>,
    /// Changes whenever `scene` changes (the solver rebuilds its model then).
    pub scene_revision: u64,
    /// How to draw the result.
    pub visual: VisualOptions,
    /// What to compute.
    pub target: Target,
    /// What the window may ask next, which the solver may solve ahead while it has nothing to
    /// do.
    pub ahead: Ahead,
}

/// The poses the window offers next (its presets, from the pose asked), and where a pose job
/// would start from after this job: solved ahead while the solver has nothing to do
/// (`solve::Workspace::anticipate`, `solve::Workspace::solve_ahead`), taken when asked.
#[derive(Clone, Default)]
pub struct Ahead {
    /// The poses, the likeliest first.
    pub poses: Vec<Pose>,
    /// The frame the next pose job would start from (the timeline's frame shown, which a
    /// timeline job leaves shown); `None`: the hands where this job leaves them.
    pub start: Option<Arc<Frame>>,
}

/// What a job computes.
#[derive(Clone)]
pub enum Target {
    /// The hands at this pose, reached by increments from the pose the solver holds (or from
    /// `start`, the frame the window shows, when it did not come from the solver's own state).
    Pose {
        /// Joint angles of every hand.
        pose: Pose,
        /// The frame to start from (its hands' states), if not the solver's current one.
        start: Option<Arc<Frame>>,
    },
    /// Hand `body` closes on an object by itself (the gentlest grip: `solve::Workspace::
    /// close_grip`) from the pose the solver holds (or from `start`).
    Grasp {
        /// The hand body.
        body: usize,
        /// What to grasp, from which preshape, holding how.
        grasp: crate::scene::GraspDef,
        /// The frame to start from (its hands' states), if not the solver's current one.
        start: Option<Arc<Frame>>,
    },
    /// Timeline frames `first..first + poses.len()`, in order, from `start` (the pose of frame
    /// `first - 1` as cached, or rest when `None`); one result per frame.
    Timeline {
        /// Index of the first frame to solve.
        first: usize,
        /// Hand states of frame `first - 1` (`None`: start from the scene's initial pose).
        start: Option<Arc<Frame>>,
        /// The poses of the frames to solve.
        poses: Vec<Pose>,
    },
}

/// A solved frame ready to show.
#[derive(Clone)]
pub struct Solution {
    /// The model it belongs to.
    pub model: Arc<Model>,
    /// The frame.
    pub frame: Arc<Frame>,
    /// The draw list (built on the solver thread, so that the window never waits for it).
    pub draw_list: Arc<DrawList>,
    /// Wall time of the solve, ms.
    pub solve_ms: f64,
    /// Timeline frame index, for timeline jobs.
    pub timeline_frame: Option<usize>,
    /// The options the draw list was built with.
    pub visual: VisualOptions,
    /// A preview of a pose job, drawn at once while the pose is solved (the hands moved by
    /// skinning, nothing else computed: `solve::skinned_preview`); the solved frame follows.
    pub preview: bool,
    /// The frame a pose job's motion reached at the pose, solved, before the corrections at
    /// the pose settle its contact (`solve::Workspace::move_hands_showing`): shown while they
    /// run, drawn as a draft; the settled frame follows.
    pub settling: bool,
    /// The peaks of the press on the hands' skin (`state::tactile_peaks`, made on the solver
    /// thread with the draw list); `None` for a preview or where no skin is pressed.
    pub tactile: Option<crate::state::TactilePeaks>,
    /// Per hand (its body's name), the flesh its contact pressed inside out
    /// (`state::pressed_inside_out`, made on the solver thread with the draw list); empty for a
    /// preview or where none is.
    pub pressed_inside_out: Vec<(String, crate::state::InsideOut)>,
}

/// Why a job produced no frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    /// A newer job replaced it.
    Cancelled,
    /// The solve failed (a typed error, shown in the status panel).
    Error(String),
    /// The solve panicked (caught; the solver thread goes on).
    Panic(String),
}

/// What the solver thread sends back.
#[derive(Clone)]
pub struct JobResult {
    /// The version of the job.
    pub version: u64,
    /// A frame, or why not.
    pub outcome: Result<Solution, Failure>,
    /// `true` on the job's last message (a timeline job sends one per frame).
    pub finished: bool,
}
