//! The egui panels: Joints on the left; Object, Solver, Display, Status and File on the right;
//! the timeline at the bottom; the 3D view in the middle. Each panel edits [`ViewerState`] and
//! raises its change flags; [`ViewerState::ui`] sends the resulting job at the end of the frame.

mod display;
mod file;
mod joints;
mod object;
mod solver;
mod status;
mod timeline;

use super::state::ViewerState;
use egui::{CentralPanel, CollapsingHeader, Panel, ScrollArea};
use std::time::Duration;

/// `true` when an edit of `r` is complete: a drag released, or a change not made by dragging
/// (typed, clicked, set by assistive technology). Edits that rebuild the model wait for this.
pub(crate) fn committed(r: &egui::Response) -> bool {
    r.drag_stopped() || (r.changed() && !r.dragged())
}

impl ViewerState {
    /// Draws the whole window into `ui` and acts on the edits: one frame of the viewer.
    pub fn ui(&mut self, ui: &mut egui::Ui) {
        let dt = ui.input(|i| i.stable_dt).clamp(0.0, 0.25) as f64;
        // Something held or scrolled (a slider, the camera): the solver's work ahead waits.
        let moving =
            ui.input(|i| i.pointer.any_down() || i.smooth_scroll_delta != egui::Vec2::ZERO);
        self.hold_idle_work(moving);
        self.step(dt);
        Panel::bottom("timeline")
            .resizable(false)
            .show(ui, |ui| timeline::ui(self, ui));
        Panel::left("joints")
            .default_size(270.0)
            .resizable(true)
            .show(ui, |ui| {
                ScrollArea::vertical().show(ui, |ui| joints::ui(self, ui));
            });
        Panel::right("settings")
            .default_size(320.0)
            .resizable(true)
            .show(ui, |ui| {
                ScrollArea::vertical().show(ui, |ui| {
                    CollapsingHeader::new("Object")
                        .default_open(true)
                        .show(ui, |ui| object::ui(self, ui));
                    CollapsingHeader::new("Solver")
                        .default_open(true)
                        .show(ui, |ui| solver::ui(self, ui));
                    CollapsingHeader::new("Display")
                        .default_open(true)
                        .show(ui, |ui| display::ui(self, ui));
                    CollapsingHeader::new("Status")
                        .default_open(true)
                        .show(ui, |ui| status::ui(self, ui));
                    CollapsingHeader::new("File")
                        .default_open(true)
                        .show(ui, |ui| file::ui(self, ui));
                });
            });
        CentralPanel::default().show(ui, |ui| match &mut self.view {
            Some(view) => view.ui(ui),
            None => {
                let text = match &self.shown {
                    Some(s) => format!("frame of request {}", s.version),
                    None => "no frame yet".to_string(),
                };
                ui.label(text);
            }
        });
        self.dispatch();
        if self.timeline.playing {
            ui.ctx().request_repaint();
        } else if self.computing() {
            ui.ctx().request_repaint_after(Duration::from_millis(100));
        }
    }
}
