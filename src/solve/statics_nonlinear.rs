//! The static frame with `[solver] tier = "nonlinear"`: the same model (mesh, prescribed
//! displacements, dead loads) solved at large deformation with the Neo-Hookean hexahedron and
//! Newton–Raphson (`fem::newton`), stresses as Cauchy stress at the Gauss points. Contact with
//! obstacles is not yet supported with this tier.

use super::error::SimError;
use crate::fem::hyperelastic_body::HyperelasticBody;
use crate::fem::newton::{solve_body, NewtonSettings, NonlinearError, StepFailure};
use crate::fem::solve::{Solution, SolveStats};
use crate::fem::stress::from_gauss;
use crate::model::Model;
use crate::state::Frame;
use crate::util::timing::ms;
use std::time::Instant;

/// Solves the static equilibrium of the model with the nonlinear tier.
pub fn solve_static_nonlinear(model: &Model) -> Result<Frame, SimError> {
    let all_bodies = || {
        model
            .bodies
            .iter()
            .map(|b| b.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if !model.obstacles.is_empty() {
        return Err(SimError::Unsupported(format!(
            "[solver] tier = \"nonlinear\" with obstacles (contact) is not yet supported: remove \
             the [[obstacle]] tables or use the linear tier (bodies: {})",
            all_bodies()
        )));
    }
    let body_of_cell = |cell: usize| {
        let b = model.cell_body[cell];
        (
            model.bodies[b].name.clone(),
            cell - model.bodies[b].cells.start,
        )
    };
    let settings = NewtonSettings {
        ordering: model.ordering,
        volumetric: model.flexion.volumetric,
        ..Default::default()
    };
    let t = Instant::now();
    let body = HyperelasticBody::with_pattern(
        &model.mesh,
        &model.cell_materials,
        settings.volumetric,
        model.pattern.clone(),
    )
    .map_err(|e| {
        let (body, element) = body_of_cell(e.cell);
        SimError::InvertedElement {
            body,
            element,
            relative_det: e.relative_det,
        }
    })?;
    let result = solve_body(
        &body,
        &model.partition,
        &model.prescribed,
        &model.load_vector,
        &settings,
    );
    let solved = result.map_err(|source| {
        let (body, element) = match &source {
            NonlinearError::StepFailed {
                reason: StepFailure::Inverted { cell, .. },
                ..
            } => {
                let (body, element) = body_of_cell(*cell);
                (body, Some(element))
            }
            _ => (all_bodies(), None),
        };
        SimError::Nonlinear {
            body,
            element,
            source: Box::new(source),
        }
    })?;
    let solve_ms = ms(t);
    let t = Instant::now();
    let gauss = body.cauchy_stress(&solved.displacement).map_err(|e| {
        let (body, element) = body_of_cell(e.cell);
        SimError::InvertedElement {
            body,
            element,
            relative_det: e.det_f,
        }
    })?;
    let stress = from_gauss(&model.mesh, gauss);
    let stress_ms = ms(t);
    let last = solved
        .steps
        .last()
        .and_then(|s| s.residuals.last())
        .copied();
    Ok(Frame {
        solution: Solution {
            displacement: solved.displacement,
            reaction: solved.reaction,
            stats: SolveStats {
                solve_ms,
                free_dofs: model.partition.free_count(),
                prescribed_dofs: model.partition.prescribed_count(),
                relative_residual: last.unwrap_or(0.0),
                ..Default::default()
            },
        },
        stress,
        assembly_ms: 0.0,
        stress_ms,
        hands: Vec::new(),
        contact: None,
    })
}
