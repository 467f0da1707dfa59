//! Joints: a slider per joint angle within its limits, grouped by digit; presets; reset.

use super::super::pose::{digit_of, Preset};
use super::super::state::ViewerState;
use egui::{CollapsingHeader, Slider};

const DIGITS: [&str; 5] = ["thumb", "index", "middle", "ring", "little"];

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    ui.heading("Joints");
    if state.hands.is_empty() {
        ui.label("This scene has no hand.");
        return;
    }
    ui.horizontal_wrapped(|ui| {
        for p in Preset::ALL {
            if ui.button(p.label()).clicked() {
                for (h, (_, angles)) in state.hands.iter().zip(state.pose.iter_mut()) {
                    *angles = p.angles(&h.skeleton);
                }
                state.pose_changed = true;
            }
        }
        if ui
            .button("Reset")
            .on_hover_text("the scene's initial pose")
            .clicked()
        {
            state.pose = state.timeline.keys[0].pose.clone();
            state.pose_changed = true;
        }
    });
    ui.separator();
    let many = state.hands.len() > 1;
    for (h, (_, angles)) in state.hands.iter().zip(state.pose.iter_mut()) {
        if many {
            ui.strong(&h.name);
        }
        for digit in DIGITS {
            CollapsingHeader::new(digit)
                .id_salt((h.body, digit))
                .default_open(true)
                .show(ui, |ui| {
                    for (d, angle) in h.skeleton.dofs.iter().zip(angles.iter_mut()) {
                        if digit_of(&d.name) != digit {
                            continue;
                        }
                        let r = ui.add(
                            Slider::new(angle, d.limits.min..=d.limits.max)
                                .text(d.name.as_str())
                                .suffix("°")
                                .fixed_decimals(0),
                        );
                        if r.changed() {
                            state.pose_changed = true;
                        }
                    }
                });
        }
    }
}
