//! Object: the ball's radius, Young's modulus (logarithmic, 100 Pa to 1 TPa), Poisson ratio,
//! internal pressure, shell or solid, the skin's friction on it, and centre. A completed edit
//! rebuilds the ball body.

use super::super::state::ViewerState;
use super::committed;
use egui::{DragValue, Slider};

fn sci(v: f64, _: std::ops::RangeInclusive<usize>) -> String {
    format!("{v:.2e}")
}

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    let Some(ball) = &mut state.ball else {
        ui.label("This scene has no ball (shell or sphere body).");
        return;
    };
    let mut done = false;
    let mut radius_mm = ball.radius * 1e3;
    let r = ui.add(
        Slider::new(&mut radius_mm, 10.0..=80.0)
            .text("radius")
            .suffix(" mm"),
    );
    ball.radius = radius_mm * 1e-3;
    done |= committed(&r);
    let r = ui.add(
        Slider::new(&mut ball.young, 1.0e2..=1.0e12)
            .logarithmic(true)
            .custom_formatter(sci)
            .text("Young's modulus")
            .suffix(" Pa"),
    );
    done |= committed(&r);
    let r = ui.add(Slider::new(&mut ball.poisson, 0.0..=0.49).text("Poisson ratio"));
    done |= committed(&r);
    ui.horizontal(|ui| {
        done |= ui.radio_value(&mut ball.shell, true, "shell").changed();
        done |= ui.radio_value(&mut ball.shell, false, "solid").changed();
    });
    let mut kpa = ball.pressure * 1e-3;
    let r = ui.add_enabled(
        ball.shell,
        Slider::new(&mut kpa, 0.0..=200.0)
            .text("internal pressure")
            .suffix(" kPa"),
    );
    ball.pressure = kpa * 1e3;
    done |= committed(&r);
    let r = ui
        .add(Slider::new(&mut ball.friction, 0.0..=2.0).text("skin friction μ"))
        .on_hover_text(
            "Coulomb's μ between the hand's skin and the ball (skin on rubber: about 0.8); a grasp \
             that holds the ball against gravity needs it",
        );
    done |= committed(&r);
    ui.horizontal(|ui| {
        ui.label("centre (mm)");
        for (axis, c) in ["x", "y", "z"].iter().zip(ball.center.iter_mut()) {
            let mut mm = *c * 1e3;
            let r = ui
                .add(
                    DragValue::new(&mut mm)
                        .speed(0.5)
                        .prefix(format!("{axis} ")),
                )
                .on_hover_text(format!("ball centre {axis}, mm"));
            *c = mm * 1e-3;
            done |= committed(&r);
        }
    });
    if done {
        state.scene_changed = true;
    }
}
