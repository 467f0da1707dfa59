//! The interactive viewer: egui panels, timeline and interaction, the solver thread.
//! May import every stage and kernel, render, export and headless; not cli or bench.
//!
//! The interactive viewer (issue 6): egui panels over the project's renderer, the physics on a
//! background thread, a keyframe timeline.
//!
//! - [`state::ViewerState`] holds the inputs and the shown frame; [`panels`] draw and edit it.
//! - [`worker::ThreadSolver`] runs [`physics::Physics`] on a thread behind the
//!   [`worker::SolverPort`] trait (tests use [`testing::FakePort`]); [`jobs`] are the messages.
//! - [`view3d::View3d`] draws the shown draw list with [`crate::render::Renderer`] into a texture
//!   that egui shows; [`window::run_viewer`] opens the native window.

pub mod files;
pub mod jobs;
pub mod object;
mod panels;
pub mod physics;
pub mod pose;
pub mod settings;
pub mod state;
pub mod testing;
pub mod timeline;
pub mod view3d;
pub mod window;
pub mod worker;

pub use state::{SceneView, Shown, Source, ViewerState};
pub use window::{run_viewer, ViewOptions, ViewerError};
