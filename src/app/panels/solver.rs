//! Solver: tier, contact method, tolerance, far fingers, self-contact, increment size, mesh
//! resolution and cells split (nested refinement), the built-in hand's size.

use super::super::settings::{tier_label, Tier};
use super::super::state::ViewerState;
use super::committed;
use crate::hand::size::{ansur_ii, ANSUR_II};
use crate::hand::{HandForm, MAX_SUBDIVISIONS};
use crate::scene::{ContactMethodName, HandSizeDef};
use egui::{DragValue, Slider};

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    let s = &mut state.solver;
    let mut done = false;
    ui.label("tier");
    for t in Tier::ALL {
        done |= ui.radio_value(&mut s.tier, t, tier_label(t)).changed();
    }
    egui::ComboBox::from_label("contact method")
        .selected_text(s.contact.name())
        .show_ui(ui, |ui| {
            for m in [ContactMethodName::Lagrange, ContactMethodName::Paper] {
                done |= ui.selectable_value(&mut s.contact, m, m.name()).changed();
            }
        })
        .response
        .on_hover_text(
            "lagrange: active set through the Schur complement, exact, one factorization; \
             paper: the published repel–prescribe–release iteration",
        );
    ui.horizontal(|ui| {
        ui.label("tolerance");
        let r = ui
            .add(
                DragValue::new(&mut s.tolerance)
                    .speed(0.0)
                    .range(1e-14..=1e-2)
                    .custom_formatter(|v, _| format!("{v:.0e}")),
            )
            .on_hover_text("largest relative residual accepted; larger ones are flagged");
        if r.clicked() {
            s.tolerance = if s.tolerance <= 1e-12 {
                1e-4
            } else {
                s.tolerance * 0.01
            };
        }
    });
    done |= ui
        .checkbox(&mut s.skin_far_fingers, "skin fingers far from contact")
        .on_hover_text(
            "a finger farther than near_contact (10 mm) from every object over a keyframe \
             follows its bones by skinning unless skinning would crush its flesh; FEM goes \
             where contact is",
        )
        .changed();
    done |= ui
        .checkbox(&mut s.self_contact, "skin kept out of itself")
        .on_hover_text(
            "self-contact: the skin may not pass through itself — a crease's two sides, a \
             fingertip on the palm, fingers side by side; its press goes to the bones and the \
             contact pressure overlay (corotational and incremental tiers; the flexion takes \
             7–16 times longer)",
        )
        .changed();
    let r = ui.add(
        Slider::new(&mut s.max_step_deg, 1.0..=45.0)
            .text("max step")
            .suffix("°"),
    );
    done |= committed(&r);
    let r = ui
        .add(Slider::new(&mut s.resolution, 0.5..=2.0).text("mesh resolution"))
        .on_hover_text("hand lattice: 3.2 mm / resolution (1.6 mm on the finger-tip pads)");
    done |= committed(&r);
    let r = ui
        .add(Slider::new(&mut s.subdivisions, 1..=MAX_SUBDIVISIONS).text("cells split"))
        .on_hover_text(
            "nested refinement: every cell of the hand's lattice split n × n × n along its own \
             shape — the same hand (the same skin, joints and bone attachments) with finer \
             elements, so the bone reactions converge as n grows; costs as a resolution n times \
             finer",
        );
    done |= committed(&r);
    egui::ComboBox::from_label("hand size")
        .selected_text(size_label(&s.hand_size))
        .show_ui(ui, |ui| {
            done |= ui
                .selectable_value(&mut s.hand_size, None, size_label(&None))
                .changed();
            for (sex, p, _, _) in ANSUR_II {
                let size = Some(HandSizeDef::Percentile(format!("{sex}-{p}")));
                let label = size_label(&size);
                done |= ui.selectable_value(&mut s.hand_size, size, label).changed();
            }
        })
        .response
        .on_hover_text(
            "the built-in hand stretched to an ANSUR II percentile of hand length (wrist \
             crease to the middle finger's tip) and breadth (across the knuckles); the flesh \
             is meshed again",
        );
    egui::ComboBox::from_label("hand form")
        .selected_text(s.hand_form.name())
        .show_ui(ui, |ui| {
            for form in [HandForm::Simple, HandForm::Anatomical] {
                done |= ui
                    .selectable_value(&mut s.hand_form, form, form.name())
                    .changed();
            }
        })
        .response
        .on_hover_text(
            "the built-in hand's shape: simple (a rounded palm, round fingers) or anatomical \
             (the thumb at its natural rest out of the palm, the palm's hollow and eminences, \
             knuckles, pulps); the same bones and joint angles, the flesh meshed again",
        );
    if done {
        state.scene_changed = true;
    }
}

/// How the hand size menu names `size`.
fn size_label(size: &Option<HandSizeDef>) -> String {
    match size {
        None => {
            let r = crate::hand::HandSize::reference();
            format!(
                "built-in ({:.1} × {:.1} mm)",
                r.length * 1e3,
                r.breadth * 1e3
            )
        }
        Some(HandSizeDef::Percentile(name)) => ansur_ii(name)
            .map(|(sex, p, l, b)| {
                let who = if sex == "female" { "women" } else { "men" };
                format!("ANSUR II {who} {p}th: {l:.0} × {b:.0} mm")
            })
            .unwrap_or_else(|| name.clone()),
        Some(HandSizeDef::Measured { length, breadth }) => match breadth {
            Some(b) => format!("{:.1} × {:.1} mm", length * 1e3, b * 1e3),
            None => format!("{:.1} mm long", length * 1e3),
        },
    }
}
