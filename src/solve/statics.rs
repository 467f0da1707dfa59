//! The static solve of one frame: assemble K on the current geometry, solve equations (7)–(8),
//! then recover stresses. The result is the frame's state.

use super::error::SimError;
use super::gas::solve_with_gas;
use crate::contact::{solve_with_obstacles, ContactError, ContactResult, Obstacle};
use crate::fem::assembly::{assemble_kind, Stiffness};
use crate::fem::solve::{PartitionedSolver, Solution, SolveError};
use crate::fem::stress::stress_field_kind;
use crate::model::{GasCavity, Model};
use crate::state::Frame;
use crate::util::timing::ms;
use std::time::Instant;

/// Solves the static equilibrium of the model (equation (5) partitioned as (6)–(8)).
pub fn solve_static(model: &Model, solver: &mut PartitionedSolver) -> Result<Frame, SimError> {
    solve_static_with(model, solver, true)
}

/// The static equilibrium of the bodies under their loads alone, the rigid obstacles ignored
/// (what the loads do to the bodies, where contact with the obstacles failed).
pub fn solve_static_alone(
    model: &Model,
    solver: &mut PartitionedSolver,
) -> Result<Frame, SimError> {
    solve_static_with(model, solver, false)
}

fn solve_static_with(
    model: &Model,
    solver: &mut PartitionedSolver,
    obstacles: bool,
) -> Result<Frame, SimError> {
    if model.nonlinear_statics {
        return super::statics_nonlinear::solve_static_nonlinear(model);
    }
    // Refused before anything is assembled.
    if model.obstacles.is_empty() || !obstacles {
        super::stabilize::falls_untouched(model)?;
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
    let (solution, contact) = if model.obstacles.is_empty() || !obstacles {
        let solution = match &model.gas {
            None => solver
                .solve(
                    &k,
                    &model.partition,
                    &model.prescribed,
                    &model.load_vector,
                    &model.mesh.nodes,
                )
                .map_err(solve_error)?,
            Some(cavity) => solve_with_cavity(model, cavity, solver, &k)?,
        };
        (solution, None)
    } else {
        let obstacles: Vec<Obstacle> = model.obstacles.iter().map(|o| o.1.clone()).collect();
        let mut contact_solve = |loads: &[f64]| {
            solve_with_obstacles(
                solver,
                &k,
                &model.partition,
                &model.prescribed,
                loads,
                &model.mesh.nodes,
                &model.contact_candidates,
                &obstacles,
                model.contact,
            )
            .map_err(|e| match e {
                ContactError::Solve(source) => solve_error(source),
                other => SimError::Contact(other),
            })
        };
        let result = match &model.gas {
            None => contact_solve(&model.load_vector)?,
            // The contact's active set may change with the pressure: one contact solve per
            // pressure tried.
            Some(cavity) => solve_with_gas(
                cavity,
                |p| contact_solve(&cavity.with_gauge(&model.load_vector, p)),
                |r| cavity.volume(&model.mesh.nodes, &r.solution.displacement),
            )?,
        };
        super::stabilize::check_held(model, &springs, &result, None).map_err(SimError::Contact)?;
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
        stress_pending: None,
        assembly_ms,
        stress_ms,
        hands: Vec::new(),
        contact,
    })
}

/// The static solve with a gas cavity and no contact. The solve is linear in the cavity's
/// pressure: U(p) = U_rest + (p − p_rest)·U_a with K11·U_a = a (the unit-pressure load, a second
/// right-hand side on the same factor), and likewise the reactions; only the scalar gas law is
/// iterated.
fn solve_with_cavity(
    model: &Model,
    cavity: &GasCavity,
    solver: &mut PartitionedSolver,
    k: &Stiffness,
) -> Result<Solution, SimError> {
    let solve_error = |source: SolveError| SimError::solve(model, source);
    let partition = &model.partition;
    let rest = solver
        .solve(
            k,
            partition,
            &model.prescribed,
            &model.load_vector,
            &model.mesh.nodes,
        )
        .map_err(solve_error)?;
    let mut free: Vec<f64> = partition
        .free
        .iter()
        .map(|&d| cavity.unit_load[d])
        .collect();
    solver.solve_factored(&mut free, 1).map_err(solve_error)?;
    let mut unit = vec![0.0; rest.displacement.len()];
    for (&d, u) in partition.free.iter().zip(free) {
        unit[d] = u;
    }
    // Equation (8) for the unit load: the supports' share K·U_a − a at the prescribed dofs.
    let unit_reaction: Vec<f64> = k
        .mul(&unit)
        .iter()
        .zip(&cavity.unit_load)
        .enumerate()
        .map(
            |(d, (ku, a))| {
                if partition.prescribed[d] {
                    ku - a
                } else {
                    0.0
                }
            },
        )
        .collect();
    let at = |p: f64| -> Result<Solution, SimError> {
        let dp = p - cavity.rest_gauge;
        let add = |x: &[f64], y: &[f64]| -> Vec<f64> {
            x.iter().zip(y).map(|(x, y)| x + dp * y).collect()
        };
        Ok(Solution {
            displacement: add(&rest.displacement, &unit),
            reaction: add(&rest.reaction, &unit_reaction),
            stats: rest.stats.clone(),
        })
    };
    solve_with_gas(cavity, at, |s| {
        cavity.volume(&model.mesh.nodes, &s.displacement)
    })
}
