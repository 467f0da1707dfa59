//! The front-ends without a window: a scene file solved into its report and output files
//! (`prehensile solve`), and frames rendered to PNG (`prehensile render`).

mod render;
mod solve;

pub use render::{camera_for, draw_lists, render_frame, scene_camera, HeadlessError};
pub use solve::{solve_scene, solve_scene_file, write_solved, PipelineError, Solved};
