//! Display: skin translucency, bones, wireframe, overlay and its colour range.

use super::super::settings::OVERLAYS;
use super::super::state::ViewerState;
use egui::{DragValue, Slider};

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    let d = &mut state.display;
    ui.add(Slider::new(&mut d.skin_opacity, 0.05..=1.0).text("skin opacity"));
    ui.checkbox(&mut d.bones, "bones");
    ui.checkbox(&mut d.wireframe, "wireframe");
    egui::ComboBox::from_label("overlay")
        .selected_text(
            OVERLAYS
                .iter()
                .find(|(o, _)| *o == d.overlay)
                .map_or("none", |o| o.1),
        )
        .show_ui(ui, |ui| {
            for (o, label) in OVERLAYS {
                ui.selectable_value(&mut d.overlay, o, label);
            }
        });
    let mut range_changed = ui
        .checkbox(&mut d.auto_range, "automatic colour range")
        .changed();
    ui.add_enabled_ui(!d.auto_range, |ui| {
        ui.horizontal(|ui| {
            ui.label("range");
            let [lo, hi] = &mut d.fixed_range;
            range_changed |= ui
                .add(DragValue::new(lo).speed(10.0))
                .on_hover_text("lower end of the colour range")
                .changed();
            range_changed |= ui
                .add(DragValue::new(hi).speed(10.0))
                .on_hover_text("upper end of the colour range")
                .changed();
        });
    });
    if range_changed {
        state.range_changed = true;
    }
}
