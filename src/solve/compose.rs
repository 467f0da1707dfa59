//! A frame composed of the static frame of the bodies and the hands' states: their displacements,
//! reactions and stresses (rotation-free for the flesh; Neo-Hookean with the nonlinear tier).

use super::error::SimError;
use crate::fem::hyperelastic_body::HyperelasticBody;
use crate::fem::stress::{from_gauss, stress_field_except, StressField};
use crate::model::Model;
use crate::state::{Frame, HandFrame};

/// The static frame with the hands' displacements, reactions and (rotation-free) stresses.
pub fn compose(model: &Model, still: &Frame, hands: Vec<HandFrame>) -> Result<Frame, SimError> {
    let mut frame = still.clone();
    for h in &hands {
        let body = &model.bodies[h.body];
        for (i, p) in h.positions.iter().enumerate() {
            let n = body.nodes.start + i;
            let u = p - model.mesh.nodes[n];
            frame.solution.displacement[3 * n..3 * n + 3].copy_from_slice(u.as_slice());
            frame.solution.reaction[3 * n..3 * n + 3].copy_from_slice(h.reaction[i].as_slice());
        }
    }
    let inverted = |c: usize, relative_det: f64| SimError::inverted(model, c, relative_det);
    frame.stress = if model.nonlinear_statics {
        // The Cauchy stress of the Neo-Hookean law the nonlinear tier solved with, for the
        // hands' flesh and the other bodies alike.
        nonlinear_stress(model, &frame.solution.displacement)
            .map_err(|(c, det_f)| inverted(c, det_f))?
    } else {
        let hand_cell = |c: usize| model.bodies[model.cell_body[c]].hand.is_some();
        // Flesh moved by skinning only (`flesh = "skinning"`, per part or the tier) has no
        // stress.
        let skinned = |c: usize| {
            let body = &model.bodies[model.cell_body[c]];
            body.hand.as_deref().is_some_and(|hand| {
                let part = hand.flesh.cell_digit[c - body.cells.start].map_or(0, |d| d + 1);
                model.flexion.methods[part] == crate::model::FleshMethod::Skinning
            })
        };
        stress_field_except(
            &model.mesh,
            &model.cell_materials,
            &frame.solution.displacement,
            &hand_cell,
            &skinned,
        )
        .map_err(|(c, e)| inverted(c, e.relative_det))?
    };
    frame.hands = hands;
    Ok(frame)
}

/// Cauchy stress of the Neo-Hookean law (`[solver] volumetric`) at the Gauss points of every cell of
/// the model displaced by `u` from rest; an inverted cell gives (cell, det F).
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
