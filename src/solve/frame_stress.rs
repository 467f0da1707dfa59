//! A frame's stresses, computed once it is the frame a keyframe ends with. The contact steps
//! along a motion and the corrections at its pose are states on the way to the next: their
//! stresses (a polar decomposition at every Gauss point of the model, 12–25 ms a step for the
//! default scene) were computed and thrown away. Nothing in a step depends on the stresses of
//! the step before, so a frame is solved with its stresses pending ([`PendingStress`]) and
//! [`complete`] computes them by the rule of the solve that made it. (Where the stresses are
//! also a check — Neo-Hookean objects, whose det F ≤ 0 halves a contact step — the step computes
//! them at once.)

use super::error::SimError;
use super::hyperelastic_objects::{neo_hookean_objects, with_neo_hookean_stress};
use crate::contact::ContactError;
use crate::fem::hyperelastic_body::HyperelasticBody;
use crate::fem::stress::{from_gauss, stress_field_except, StressField};
use crate::model::Model;
use crate::state::{Frame, PendingStress};
use crate::util::timing::ms;
use std::time::Instant;

/// Computes `frame`'s stresses if they are pending (the time they took goes to its
/// `stress_ms`, and to its contact's split).
pub fn complete(model: &Model, frame: &mut Frame) -> Result<(), SimError> {
    let Some(rule) = frame.stress_pending else {
        return Ok(());
    };
    let t = Instant::now();
    let u = &frame.solution.displacement;
    frame.stress = match rule {
        PendingStress::Composed => composed(model, u)?,
        PendingStress::Contact { objects_turned } => contact_stress(model, u, objects_turned)?,
    };
    frame.stress_pending = None;
    frame.stress_ms = ms(t);
    if let Some(c) = frame.contact.as_mut() {
        c.times.stress = frame.stress_ms;
    }
    Ok(())
}

/// The static frame with the hands composed into it: rotation-free strain in the flesh, none
/// where it only follows skinning; the Neo-Hookean law's Cauchy stress everywhere with the
/// nonlinear tier.
fn composed(model: &Model, u: &[f64]) -> Result<StressField, SimError> {
    let inverted = |c: usize, relative_det: f64| SimError::inverted(model, c, relative_det);
    if model.nonlinear_statics {
        // The Cauchy stress of the Neo-Hookean law the nonlinear tier solved with, for the
        // hands' flesh and the other bodies alike.
        return nonlinear_stress(model, u).map_err(|(c, det_f)| inverted(c, det_f));
    }
    let hand_cell = |c: usize| model.bodies[model.cell_body[c]].hand.is_some();
    // Flesh moved by skinning only (`flesh = "skinning"`, per part or the tier) has no stress.
    let skinned = |c: usize| {
        let body = &model.bodies[model.cell_body[c]];
        body.hand.as_deref().is_some_and(|hand| {
            let part = hand.flesh.cell_digit[c - body.cells.start].map_or(0, |d| d + 1);
            model.flexion.methods[part] == crate::model::FleshMethod::Skinning
        })
    };
    stress_field_except(&model.mesh, &model.cell_materials, u, &hand_cell, &skinned)
        .map_err(|(c, e)| inverted(c, e.relative_det))
}

/// A contact step's frame: rotation-free strain in the flesh, and in the other bodies where
/// the step corotated them; their Cauchy stress where they are Neo-Hookean (the contact step
/// computes these at once: they tell whether an object's cell turned inside out).
pub(super) fn contact_stress(
    model: &Model,
    u: &[f64],
    objects_turned: bool,
) -> Result<StressField, SimError> {
    let inverted = |c: usize, det: f64| inverted_by_step(model, c, det);
    let turned = |c: usize| objects_turned || model.bodies[model.cell_body[c]].hand.is_some();
    // (Neo-Hookean bodies get theirs below, not the small-strain one first.)
    let neo_hookean =
        |c: usize| neo_hookean_objects(model) && model.bodies[model.cell_body[c]].hand.is_none();
    let stress = stress_field_except(&model.mesh, &model.cell_materials, u, &turned, &neo_hookean)
        .map_err(|(c, e)| inverted(c, e.relative_det))?;
    if neo_hookean_objects(model) {
        return with_neo_hookean_stress(model, stress, u).map_err(|(c, det)| inverted(c, det));
    }
    Ok(stress)
}

/// A cell the contact step's displacements turn inside out: an object's is this step's failure
/// (the press went further than its mesh follows in one linearised step; a smaller step may
/// not), told as a contact error so that the motion halves its step; the flesh's stays an
/// inverted element.
fn inverted_by_step(model: &Model, cell: usize, relative_det: f64) -> SimError {
    let b = &model.bodies[model.cell_body[cell]];
    if b.hand.is_some() {
        return SimError::inverted(model, cell, relative_det);
    }
    SimError::Contact(ContactError::Inverts {
        body: b.name.clone(),
        element: cell - b.cells.start,
        relative_det,
    })
}

/// Cauchy stress of the Neo-Hookean law (`[solver] volumetric`) at the Gauss points of every
/// cell of the model displaced by `u` from rest; an inverted cell gives (cell, det F).
fn nonlinear_stress(model: &Model, u: &[f64]) -> Result<StressField, (usize, f64)> {
    let body = HyperelasticBody::with_pattern(
        &model.mesh,
        &model.cell_materials,
        model.flexion.volumetric,
        model.pattern.clone(),
    )
    .map_err(|e| (e.cell, e.relative_det))?;
    let gauss = body.cauchy_stress(u).map_err(|e| (e.cell, e.det_f))?;
    Ok(from_gauss(&model.mesh, gauss))
}
