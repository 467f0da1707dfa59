//! The timeline: keys, a strip showing which frames are solved, scrub, play, loop; add, move,
//! delete keys.

use super::super::state::ViewerState;
use egui::{Color32, DragValue, Sense, Slider, Stroke, Vec2};

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        ui.strong("Timeline");
        let play = if state.timeline.playing {
            "Pause"
        } else {
            "Play"
        };
        if ui.button(play).clicked() {
            state.timeline.playing = !state.timeline.playing;
            state.timeline.elapsed = 0.0;
        }
        ui.checkbox(&mut state.timeline.looping, "loop");
        ui.separator();
        if ui.button("Add current pose as key").clicked() {
            let k = state.timeline.add_key(state.pose.clone());
            state.scrub_to(k);
        }
        let k = state.timeline.current;
        if ui
            .add_enabled(k > 0, egui::Button::new("Set key to current pose"))
            .clicked()
        {
            state.timeline.set_pose(k, state.pose.clone());
        }
        if ui
            .add_enabled(k > 0, egui::Button::new("Delete key"))
            .clicked()
        {
            state.timeline.delete_key(k);
            let k = state.timeline.current;
            state.scrub_to(k);
        }
        ui.separator();
        ui.add_enabled_ui(k > 0, |ui| {
            ui.label("key time");
            let mut t = state.timeline.keys[k].time;
            if ui
                .add(DragValue::new(&mut t).speed(0.01).suffix(" s"))
                .on_hover_text("time of the current key")
                .changed()
            {
                state.timeline.move_key(k, t);
            }
        });
        ui.checkbox(&mut state.timeline_solving, "solve in background");
    });
    let n = state.timeline.keys.len();
    let mut k = state.timeline.current;
    let r = ui.add(
        Slider::new(&mut k, 0..=n.saturating_sub(1))
            .text("key")
            .custom_formatter(|v, _| {
                let i = (v as usize).min(n - 1);
                format!("{i} ({:.2} s)", state.timeline.keys[i].time)
            }),
    );
    if r.changed() {
        state.scrub_to(k);
    }
    strip(state, ui);
}

/// One cell per key: green when its frame is solved, grey when not; the current key outlined.
/// Clicking a cell scrubs to it.
fn strip(state: &mut ViewerState, ui: &mut egui::Ui) {
    let n = state.timeline.keys.len();
    let width = ui.available_width().max(50.0);
    let (rect, response) = ui.allocate_exact_size(Vec2::new(width, 16.0), Sense::click());
    let painter = ui.painter_at(rect);
    let cell = rect.width() / n.max(1) as f32;
    for i in 0..n {
        let r = egui::Rect::from_min_size(
            rect.min + Vec2::new(i as f32 * cell + 1.0, 0.0),
            Vec2::new(cell - 2.0, rect.height()),
        );
        let solved = state.timeline.frames.get(i).is_some_and(Option::is_some);
        let fill = if solved {
            Color32::from_rgb(70, 150, 80)
        } else {
            Color32::from_gray(70)
        };
        painter.rect_filled(r, 2.0, fill);
        if i == state.timeline.current {
            painter.rect_stroke(
                r,
                2.0,
                Stroke::new(2.0, Color32::WHITE),
                egui::StrokeKind::Inside,
            );
        }
    }
    let solved = state.timeline.frames.iter().flatten().count();
    let response = response.on_hover_text(format!("{solved} of {n} frames solved"));
    if response.clicked() {
        if let Some(p) = response.interact_pointer_pos() {
            let i = ((p.x - rect.min.x) / cell).floor() as usize;
            state.scrub_to(i.min(n - 1));
        }
    }
}
