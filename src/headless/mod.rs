//! Front-ends without a window: a scene solved into report and files, frames rendered to PNG.
//! May import scene, model, solve, state, present, render, export, the kernels and util.

mod inputs;
mod render;
mod solve;
mod unsolved;

pub use inputs::refuse_writing_over_inputs;
pub use render::{camera_for, draw_lists, render_frame, scene_camera, HeadlessError};
pub use solve::{
    solve_scene, solve_scene_file, write_solved, write_solved_as, PipelineError, Solved,
};
pub use unsolved::unsolved;
