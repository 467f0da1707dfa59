//! One timed solve of a scene: the model is built (meshing, not timed), then every frame is
//! solved (timed). A scene the solver refuses for its tier is told apart from a solve that
//! fails.

use crate::headless::PipelineError;
use crate::model::Model;
use crate::scene::{Scene, SceneError};
use crate::solve::{solve_frames, SimError};
use crate::state::Frame;
use crate::util::timing::ms;
use std::time::Instant;

/// A solved scene.
pub struct Solved {
    /// The model.
    pub model: Model,
    /// Its frames (time 0 first).
    pub frames: Vec<Frame>,
    /// Time of `solve_frames`, ms.
    pub solve_ms: f64,
    /// Time of `Model::build` (meshing, assembly pattern), ms.
    pub build_ms: f64,
    /// Frames that cost a solve: 1 without hands; with hands, the keyframes, plus the initial
    /// pose when it is not the rest pose.
    pub keyframes: usize,
}

/// Why a scene gave no result.
#[derive(Debug)]
pub enum RunError {
    /// The solver does not take this tier for this scene (yet): its reason.
    Refused(String),
    /// The solve stopped: the solver's message.
    Failed(String),
}

/// Builds and solves `scene`; `name` names it in messages.
pub fn run_scene(scene: &Scene, name: &str) -> Result<Solved, RunError> {
    let t = Instant::now();
    let model = Model::build(scene, name).map_err(|e| match e {
        SceneError::Invalid { field, message, .. } if field == "solver.tier" => {
            RunError::Refused(message)
        }
        other => RunError::Failed(other.to_string()),
    })?;
    let build_ms = ms(t);
    let t = Instant::now();
    let (_, frames) = solve_frames(&model).map_err(|e| match e {
        SimError::Unsupported(why) => RunError::Refused(why),
        other => RunError::Failed(
            PipelineError::Sim {
                file: name.to_string(),
                error: Box::new(other),
            }
            .to_string(),
        ),
    })?;
    let solve_ms = ms(t);
    let posed = model
        .bodies
        .iter()
        .filter_map(|b| b.hand.as_deref().map(|h| (b, h)))
        .filter(|(b, h)| b.initial_angles != h.skeleton.rest_angles())
        .count();
    let keyframes = if model.keyframes.is_empty() {
        1
    } else {
        model.keyframes.len() + posed.min(1)
    };
    Ok(Solved {
        model,
        frames,
        solve_ms,
        build_ms,
        keyframes,
    })
}
