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
        if state.showing_preview() {
            // Nothing below would be about the pose shown: its solve is what is awaited.
            ui.label("shown: a preview (the hands moved by skinning); its forces are being solved");
            return;
        }
        if state.showing_settling() {
            ui.label("shown: solved at the pose; its contact is being settled (a few per mille)");
        }
    } else if state.shown.is_some() && state.status.error.is_none() {
        ui.label(RichText::new("shown frame is current").color(Color32::LIGHT_GREEN));
    } else if state.shown.is_some() {
        ui.label(RichText::new("shown frame is the last good one").color(Color32::YELLOW));
    }
    if let Some(e) = &state.status.error {
        ui.label(RichText::new(format!("solver failed: {e}")).color(Color32::LIGHT_RED));
    }
    if let Some(g) = &state.status.grasp {
        ui.label(format!("grasp: {g}"));
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
    // A keyframe that ended short of its pose: said first, in red, with how far it went.
    for h in hands {
        if let Some(s) = &h.stats.stopped_short {
            ui.label(
                RichText::new(format!(
                    "not realisable: the hand stopped at {:.0} % of the motion",
                    s.reached * 100.0
                ))
                .color(Color32::LIGHT_RED),
            )
            .on_hover_text(&s.reason);
        }
        if let Some(change) = h
            .stats
            .unsettled_at_pose
            .filter(|&c| c > crate::state::KeyframeStats::UNSETTLED_WARNING)
        {
            ui.label(
                RichText::new(format!(
                    "contact forces uncertain by {:.2} % (unsettled at the pose)",
                    change * 100.0
                ))
                .color(Color32::YELLOW),
            )
            .on_hover_text(
                "the corrections at the pose ended while the hand's contact force still changed",
            );
        }
        if let Some(reason) = &h.stats.correction_failed {
            ui.label(
                RichText::new("a correction at the pose failed: the last settled frame is shown")
                    .color(Color32::YELLOW),
            )
            .on_hover_text(reason);
        }
    }
    // Flesh a contact pressed inside out: the press is deeper than the flesh near a contact
    // follows (docs/contact.md, "Flesh pressed inside out").
    for (name, t) in &shown.solution.pressed_inside_out {
        ui.label(
            RichText::new(format!(
                "flesh pressed inside out: {} point{}, the most in the {} (volume ratio {:.2})",
                t.points,
                if t.points == 1 { "" } else { "s" },
                t.part_named(),
                t.ratio
            ))
            .color(Color32::LIGHT_RED),
        )
        .on_hover_text(format!(
            "hand \"{name}\", element {}: the flesh near a contact is solved linearised about \
             the hand's pose, and this press is deeper than that follows — the forces there are \
             not flesh's; press the {} less deep",
            t.cell,
            t.part_named()
        ));
    }
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
        // A preset solved ahead while the solver had nothing to do: its costs were spent then.
        let knots: usize = hands.iter().map(|h| h.stats.knots_flexed_ahead).sum();
        if hands.iter().any(|h| h.stats.solved_ahead) {
            ui.label("done ahead");
            ui.label("solved while the solver was idle").on_hover_text(
                "the solver solves the presets ahead after a pause in the editing: the same \
                 computation from the same pose, shown at once when pressed",
            );
            ui.end_row();
        } else if knots > 0 {
            ui.label("done ahead");
            ui.label(format!("{knots} flexion knots flexed while idle"));
            ui.end_row();
        }
        let far: Vec<&str> = hands
            .iter()
            .flat_map(|h| h.stats.far_digits.iter().map(String::as_str))
            .collect();
        if !far.is_empty() {
            ui.label("skinned, far from contact");
            ui.label(far.join(", ")).on_hover_text(
                "digits farther than near_contact from every object in this keyframe: they \
                 follow their bones by skinning and bear no new flexion reaction",
            );
            ui.end_row();
        }
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
        ui.label("contact");
        match &frame.contact {
            Some(c) => {
                ui.label(format!(
                    "{} points, depth {:.3} mm",
                    c.contacts.len(),
                    c.max_penetration * 1e3
                ))
                .on_hover_text(format!(
                    "{}: {} iterations, {} factorizations; depth: the largest penetration left",
                    c.method.name(),
                    c.iterations,
                    c.factorizations
                ));
                ui.end_row();
                let force: nalgebra::Vector3<f64> =
                    hands.iter().flat_map(|h| &h.contact_force).sum();
                ui.label("contact force on the hands");
                ui.label(format!("{:.3} N", force.norm()));
            }
            None => {
                ui.label("none");
            }
        }
        ui.end_row();
        if let Some(peaks) = &shown.solution.tactile {
            ui.label("skin pressure");
            ui.label(format!(
                "{:.1} kPa over {:.1} mm",
                peaks.patch * 1e-3,
                crate::state::TACTILE_PATCH_RADIUS * 1e3
            ))
            .on_hover_text(format!(
                "the press on the hands' skin (other bodies' and its own), its peak read over \
                 patches of skin {:.1} mm in radius: how much, converged under refinement; at a \
                 single point of the skin {:.1} kPa (where the skins first meet; it grows as the \
                 mesh is refined)",
                crate::state::TACTILE_PATCH_RADIUS * 1e3,
                peaks.vertex * 1e-3
            ));
            ui.end_row();
        }
        if let Some(gas) = crate::state::cavity_state(model, frame) {
            // The sealed air of a gas cavity: squeezing raises its pressure (p·V constant).
            ui.label(format!("air \"{}\"", gas.load));
            ui.label(format!(
                "{:.2} kPa, {:.1} cm³",
                gas.gauge_pressure * 1e-3,
                gas.volume * 1e6
            ))
            .on_hover_text(format!(
                "gauge pressure (above the ambient {:.0} Pa) and volume of the sealed cavity; \
                 {:.1} cm³ as meshed",
                gas.ambient,
                gas.rest_volume * 1e6
            ));
            ui.end_row();
        }
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
    let overloads: Vec<&crate::state::outcome::Overload> =
        hands.iter().flat_map(|h| &h.overloads).collect();
    ui.label(RichText::new("bone forces (equation 8)").strong());
    if !overloads.is_empty() {
        ui.label(
            RichText::new(format!(
                "not realisable: {} bone(s) over their muscle threshold",
                overloads.len()
            ))
            .color(Color32::LIGHT_RED),
        );
    }
    Grid::new("bone forces")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            for (_, bone, f) in forces.iter().take(20) {
                ui.label(bone);
                match overloads.iter().find(|o| &o.bone == bone) {
                    Some(o) => ui.label(
                        RichText::new(format!("{f:.3} N > {:.1} N", o.threshold))
                            .color(Color32::LIGHT_RED),
                    ),
                    None => ui.label(format!("{f:.3} N")),
                };
                ui.end_row();
            }
        });
}
