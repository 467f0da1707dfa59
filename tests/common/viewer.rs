//! The viewer on the built-in default scene with the real solver thread, in a test harness.

use egui_kittest::Harness;
use prehensile::app::physics::Physics;
use prehensile::app::worker::ThreadSolver;
use prehensile::app::ViewerState;
use prehensile::scene::{Scene, DEFAULT_SCENE};
use std::sync::Arc;

/// The viewer's state on the default scene, solving on a real solver thread (the timeline not
/// solved in the background), in a 1600 × 900 harness.
pub fn default_viewer() -> Harness<'static, ViewerState> {
    let scene = Scene::parse(DEFAULT_SCENE, "default").unwrap();
    let port = ThreadSolver::spawn(Physics::new(), Arc::new(|| {}));
    let mut state = ViewerState::new(scene, "default", Box::new(port)).unwrap();
    state.timeline_solving = false;
    Harness::builder()
        .with_size([1600.0, 900.0])
        .build_ui_state(|ui, state: &mut ViewerState| state.ui(ui), state)
}
