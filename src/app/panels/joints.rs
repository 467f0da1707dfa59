//! Joints: a slider per joint angle within its limits, grouped by digit; presets; reset.

use super::super::pose::{digit_of, preset_poses, Preset};
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
                let (first, then) =
                    preset_poses(p, &state.hands, &state.pose, state.solver.self_contact);
                state.pose = first;
                state.staged = (then != state.pose).then(|| (state.pose.clone(), then));
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
    grasp_row(state, ui);
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
                                .fixed_decimals(0)
                                // Clamped (and rounded to the degree) only when edited: a pose
                                // found by a grasp keeps its fractional angles.
                                .clamping(egui::SliderClamping::Edits),
                        );
                        if r.changed() {
                            state.pose_changed = true;
                        }
                    }
                });
        }
    }
}

/// The Grasp row: the hand closes on the object by itself, to the gentlest grip that holds it
/// (against gravity with the margin, or with the grip force asked).
fn grasp_row(state: &mut ViewerState, ui: &mut egui::Ui) {
    let objects: Vec<String> = state
        .scene
        .body
        .iter()
        .filter(|b| !matches!(b.shape, crate::scene::Shape::Hand { .. }))
        .map(|b| b.name.clone())
        .collect();
    if objects.is_empty() {
        return;
    }
    ui.separator();
    ui.horizontal_wrapped(|ui| {
        let g = &mut state.grasp;
        egui::ComboBox::from_label("object")
            .selected_text(g.object.as_str())
            .show_ui(ui, |ui| {
                for o in &objects {
                    ui.selectable_value(&mut g.object, o.clone(), o.as_str());
                }
            });
        egui::ComboBox::from_label("preshape")
            .selected_text(g.preshape.as_str())
            .show_ui(ui, |ui| {
                for p in crate::hand::synergy::Preshape::ALL {
                    ui.selectable_value(&mut g.preshape, p.name().to_string(), p.name());
                }
            });
        let mut by_force = g.force.is_some();
        ui.radio_value(&mut by_force, false, "hold against gravity");
        ui.radio_value(&mut by_force, true, "grip force");
        match (by_force, g.force) {
            (true, None) => g.force = Some(5.0),
            (false, Some(_)) => g.force = None,
            _ => {}
        }
        if let Some(f) = &mut g.force {
            ui.add(
                egui::DragValue::new(f)
                    .range(0.1..=1000.0)
                    .suffix(" N")
                    .speed(0.1),
            );
        } else {
            ui.add(
                egui::DragValue::new(&mut g.margin)
                    .range(1.0..=100.0)
                    .prefix("margin ")
                    .speed(0.05),
            );
        }
        if ui
            .button("Grasp")
            .on_hover_text(
                "close the hand on the object by itself: each digit along its synergy to first \
                 contact, then together to the gentlest grip that holds",
            )
            .clicked()
        {
            state.grasp_asked = true;
        }
        if ui
            .button("Does it hold?")
            .on_hover_text(
                "solve the pose the sliders set, let go of the object, and tell whether the hand \
                 holds it as asked (no closing; the pose stays yours)",
            )
            .clicked()
        {
            state.judge_asked = true;
        }
    });
}
