//! The static solve of one frame: assemble K on the current geometry, solve equations (7)–(8),
//! then recover stresses. The result is the frame's state.

use super::error::SimError;
use crate::contact::{solve_with_obstacles, ContactError, ContactResult, Obstacle};
use crate::fem::assembly::assemble_kind;
use crate::fem::solve::{PartitionedSolver, SolveError};
use crate::fem::stress::stress_field_kind;
use crate::model::Model;
use crate::state::Frame;
use crate::util::timing::ms;
use std::time::Instant;

/// Solves the static equilibrium of the model (equation (5) partitioned as (6)–(8)).
pub fn solve_static(model: &Model, solver: &mut PartitionedSolver) -> Result<Frame, SimError> {
    if model.nonlinear_statics {
        return super::statics_nonlinear::solve_static_nonlinear(model);
    }
    let inverted = |cell: usize, relative_det: f64| SimError::inverted(model, cell, relative_det);
    let t = Instant::now();
    let mut k = assemble_kind(
        &model.pattern,
        &model.mesh,
        &model.cell_materials,
        model.element,
    )
    .map_err(|e| inverted(e.cell, e.inverted.relative_det))?;
    let springs = super::stabilize::stabilize(model, &mut k, &model.partition);
    let assembly_ms = ms(t);
    let solve_error = |source: SolveError| SimError::solve(model, source);
    let (solution, contact) = if model.obstacles.is_empty() {
        let solution = solver
            .solve(
                &k,
                &model.partition,
                &model.prescribed,
                &model.load_vector,
                &model.mesh.nodes,
            )
            .map_err(solve_error)?;
        (solution, None)
    } else {
        let obstacles: Vec<Obstacle> = model.obstacles.iter().map(|o| o.1.clone()).collect();
        let result = solve_with_obstacles(
            solver,
            &k,
            &model.partition,
            &model.prescribed,
            &model.load_vector,
            &model.mesh.nodes,
            &model.contact_candidates,
            &obstacles,
            model.contact,
        )
        .map_err(|e| match e {
            ContactError::Solve(source) => solve_error(source),
            other => SimError::Contact(other),
        })?;
        super::stabilize::check_held(model, &springs, &result).map_err(SimError::Contact)?;
        let ContactResult { solution, summary } = result;
        (solution, Some(summary))
    };
    let t = Instant::now();
    let stress = stress_field_kind(
        &model.mesh,
        &model.cell_materials,
        &solution.displacement,
        model.element,
    )
    .map_err(|(c, e)| inverted(c, e.relative_det))?;
    let stress_ms = ms(t);
    Ok(Frame {
        solution,
        stress,
        assembly_ms,
        stress_ms,
        hands: Vec::new(),
        contact,
    })
}
