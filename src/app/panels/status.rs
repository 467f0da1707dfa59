//! Status: model size, what the shown frame cost, whether it is current, failures, and the
//! bone forces table.

use super::super::state::ViewerState;
use egui::{Color32, Grid, RichText};

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    if state.computing() {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("computing request {}…", state.latest_version()));
        });
    } else if state.shown.is_some() && state.status.error.is_none() {
        ui.label(RichText::new("shown frame is current").color(Color32::LIGHT_GREEN));
    } else if state.shown.is_some() {
        ui.label(RichText::new("shown frame is the last good one").color(Color32::YELLOW));
    }
    if let Some(e) = &state.status.error {
        ui.label(RichText::new(format!("solver failed: {e}")).color(Color32::LIGHT_RED));
    }
    let Some(shown) = &state.shown else {
        ui.label("no frame yet");
        return;
    };
    let model = &shown.solution.model;
    let frame = &shown.solution.frame;
    let hands = &frame.hands;
    let increments: usize = hands.iter().map(|h| h.stats.increments_taken).sum();
    let factorizations: usize = hands.iter().map(|h| h.stats.factorizations).sum();
    let fem_dofs: usize = hands.iter().map(|h| h.stats.free_dofs).sum();
    let residual = hands
        .iter()
        .map(|h| h.stats.relative_residual)
        .fold(frame.solution.stats.relative_residual, f64::max);
    Grid::new("status grid").num_columns(2).show(ui, |ui| {
        ui.label("DOFs");
        ui.label(format!("{}", 3 * model.mesh.node_count()))
            .on_hover_text("all dofs of the model");
        ui.end_row();
        ui.label("free: static / flexion");
        ui.label(format!("{} / {}", frame.solution.stats.free_dofs, fem_dofs));
        ui.end_row();
        ui.label("increments / factorizations");
        ui.label(format!("{increments} / {factorizations}"));
        ui.end_row();
        ui.label("residual");
        let text = if residual.is_finite() {
            format!("{residual:.1e}")
        } else {
            "—".to_string()
        };
        if residual.is_finite() && residual <= state.solver.tolerance {
            ui.label(text);
        } else {
            ui.label(RichText::new(format!("{text} (above tolerance)")).color(Color32::YELLOW));
        }
        ui.end_row();
        ui.label("penetration");
        ui.label("— (no contact yet)");
        ui.end_row();
        ui.label("solve");
        ui.label(format!("{:.0} ms", shown.solution.solve_ms));
        ui.end_row();
        ui.label("requests");
        ui.label(format!(
            "{} shown, {} stale, {} cancelled",
            state.status.shown, state.status.discarded, state.status.cancelled
        ));
        ui.end_row();
    });
    let forces = state.bone_forces();
    if forces.is_empty() {
        return;
    }
    ui.label(RichText::new("bone forces (threshold flags come with contact)").strong());
    Grid::new("bone forces")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            for (_, bone, f) in forces.iter().take(20) {
                ui.label(bone);
                ui.label(format!("{f:.3} N"));
                ui.end_row();
            }
        });
}
