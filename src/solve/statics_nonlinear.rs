//! The static frame with `[solver] tier = "nonlinear"`: the same model (mesh, prescribed
//! displacements, dead loads) solved at large deformation with the Neo-Hookean hexahedron and
//! Newton–Raphson (`fem::newton`), stresses as Cauchy stress at the Gauss points. With rigid
//! obstacles, each Newton iteration solves the obstacles' contact on its linearisation
//! (`with_obstacles`): K_T(U)·ΔU = R − f(U) + Cᵀλ, the gaps measured where U puts the nodes.

use super::error::{scaled_back, SimError};
use super::stabilize::{check_held, stabilize};
use crate::contact::{solve_with_obstacles, ContactError, ContactResult, Obstacle};
use crate::fem::hyperelastic_body::HyperelasticBody;
use crate::fem::newton::{solve_body, NewtonSettings, NonlinearError, StepFailure};
use crate::fem::solve::{PartitionedSolver, SolveError};
use crate::fem::solve::{Solution, SolveStats};
use crate::fem::stress::from_gauss;
use crate::model::Model;
use crate::state::Frame;
use crate::util::timing::ms;
use nalgebra::Vector3;
use std::time::Instant;

/// Solves the static equilibrium of the model with the nonlinear tier.
pub fn solve_static_nonlinear(model: &Model) -> Result<Frame, SimError> {
    let body_of_cell = |cell: usize| {
        let b = model.cell_body[cell];
        (
            model.bodies[b].name.clone(),
            cell - model.bodies[b].cells.start,
        )
    };
    // Without contact or a gas cavity (solved with the stabilising springs, which say whether
    // contact holds a body), a floating body under a load falls: refused before anything is
    // built.
    if model.obstacles.is_empty() && model.gas.is_none() {
        super::stabilize::falls_untouched(model)?;
    }
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
    if !model.obstacles.is_empty() || model.gas.is_some() {
        let (solution, contact) = match &model.gas {
            None => with_obstacles(model, &body, None)?,
            // A gas cavity: the frame solved at each pressure tried until the gas law holds
            // (src/solve/gas.rs), the cavity's pressure on the wall where it is.
            Some(cavity) => super::gas::solve_with_gas(
                cavity,
                |p| with_obstacles(model, &body, Some(p)),
                |(solution, _)| cavity.volume(&model.mesh.nodes, &solution.displacement),
            )?,
        };
        let contact = (!model.obstacles.is_empty()).then_some(contact);
        let t = Instant::now();
        let gauss = body
            .cauchy_stress(&solution.displacement)
            .map_err(|e| SimError::inverted(model, e.cell, e.det_f))?;
        return Ok(Frame {
            solution,
            stress: from_gauss(&model.mesh, gauss),
            stress_pending: None,
            assembly_ms: 0.0,
            stress_ms: ms(t),
            hands: Vec::new(),
            contact,
        });
    }
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
            _ => (all_bodies(model), None),
        };
        let advice = match &source {
            NonlinearError::StepFailed { from, .. } => scaled_back(model, *from),
            _ => String::new(),
        };
        SimError::Nonlinear {
            body,
            element,
            source: Box::new(source),
            advice,
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
        stress_pending: None,
        assembly_ms: 0.0,
        stress_ms,
        hands: Vec::new(),
        contact: None,
    })
}

/// Newton iterations at most for the static frame against the obstacles.
const OBSTACLE_NEWTON_ITERATIONS: usize = 30;

/// Newton has converged when an iteration moves no dof by more than this share of the largest
/// displacement.
const OBSTACLE_NEWTON_TOLERANCE: f64 = 1e-8;

/// Load increments tried, in turn, for the static frame against the obstacles: the whole load
/// at once, then in ever more increments where Newton fails.
const OBSTACLE_LOAD_INCREMENTS: [usize; 5] = [1, 2, 4, 8, 16];

/// The static frame against the rigid obstacles, by Newton–Raphson with the contact of each
/// iteration solved exactly on its linearisation: K_T(U)·ΔU = t·R − f(U) − S·U + Cᵀλ (S the
/// stabilising springs of floating bodies, `stabilize.rs`; t the load factor), the gaps
/// measured where U puts the nodes, until ΔU vanishes. The multipliers are the whole contact
/// forces (f(U) is in the right-hand side), and the reactions K_T·ΔU − (t·R − f(U) − S·U) − Cᵀλ
/// at the supports are theirs at the converged U. The loads are dead (on the rest geometry),
/// as without obstacles, except a gas cavity's pressure (`gas`: its gauge pressure, Pa), which
/// acts on the wall where each iteration puts it (a follower load; its load stiffness is left
/// out of the tangent, so Newton converges linearly where the pressure matters). Where Newton
/// fails (no convergence, an element turned inside out) the loads and prescribed displacements
/// are applied in increments, 2, 4 … 16.
fn with_obstacles(
    model: &Model,
    body: &HyperelasticBody,
    gas: Option<f64>,
) -> Result<(Solution, crate::contact::ContactSummary), SimError> {
    let t = Instant::now();
    let mut failure = None;
    for increments in OBSTACLE_LOAD_INCREMENTS {
        let mut u = vec![0.0; model.load_vector.len()];
        let mut last = None;
        for i in 1..=increments {
            match newton_at(model, body, &mut u, i as f64 / increments as f64, gas) {
                Ok(result) => last = Some(result),
                Err(mut e @ (SimError::Nonlinear { .. } | SimError::InvertedElement { .. })) => {
                    // What the increments before it reached.
                    if let SimError::Nonlinear { advice, .. } = &mut e {
                        if advice.is_empty() {
                            *advice = scaled_back(model, (i - 1) as f64 / increments as f64);
                        }
                    }
                    failure = Some(e);
                    last = None;
                    break;
                }
                Err(e) => return Err(e),
            }
        }
        if let Some(mut result) = last {
            result.solution.stats.solve_ms = ms(t);
            result.summary.contact_ms = ms(t);
            return Ok((result.solution, result.summary));
        }
    }
    Err(failure.expect("a failure when no increment count succeeded"))
}

/// Newton iterations from `u` to the equilibrium under the load factor `factor` (loads and
/// prescribed displacements scaled alike) with the obstacles' contact, and the gas cavity at
/// gauge pressure `gas` on the wall where it is; `u` ends there.
fn newton_at(
    model: &Model,
    body: &HyperelasticBody,
    u: &mut [f64],
    factor: f64,
    gas: Option<f64>,
) -> Result<ContactResult, SimError> {
    let nodes = &model.mesh.nodes;
    let obstacles: Vec<Obstacle> = model.obstacles.iter().map(|o| o.1.clone()).collect();
    let mut solver = PartitionedSolver::new(model.ordering);
    let mut last_change = f64::INFINITY;
    for _ in 0..OBSTACLE_NEWTON_ITERATIONS {
        let positions: Vec<Vector3<f64>> = (0..nodes.len())
            .map(|n| nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
            .collect();
        let external = external_loads(model, &positions, gas);
        let (_, internal) = body
            .internal_forces(u)
            .map_err(|e| SimError::inverted(model, e.cell, e.det_f))?;
        let prescribed: Vec<f64> = (0..u.len())
            .map(|d| factor * model.prescribed[d] - u[d])
            .collect();
        // The exact tangent; where it is not positive definite (a squeezed shell's wall in
        // compression, which the obstacles restrain), each element's made definite: the
        // residual stays exact, so the iterations still converge to the equilibrium.
        let mut definite = false;
        let (mut result, springs) = loop {
            let mut k = if definite {
                body.tangent_definite(u)
            } else {
                body.tangent(u)
            }
            .map_err(|e| SimError::inverted(model, e.cell, e.det_f))?;
            let without_springs = k.mul(u);
            let springs = stabilize(model, &mut k, &model.partition);
            let with_springs = k.mul(u);
            let loads: Vec<f64> = (0..u.len())
                .map(|d| {
                    factor * external[d] - internal[d] - (with_springs[d] - without_springs[d])
                })
                .collect();
            match solve_with_obstacles(
                &mut solver,
                &k,
                &model.partition,
                &prescribed,
                &loads,
                &positions,
                &model.contact_candidates,
                &obstacles,
                model.contact,
            ) {
                Ok(result) => break (result, springs),
                Err(ContactError::Solve(SolveError::NotPositiveDefinite { .. })) if !definite => {
                    definite = true;
                }
                Err(ContactError::Solve(source)) => return Err(SimError::solve(model, source)),
                Err(other) => return Err(SimError::Contact(other)),
            }
        };
        let du = &result.solution.displacement;
        let change = du.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in u.iter_mut().zip(du) {
            *a += b;
        }
        if u.iter().any(|v| !v.is_finite()) {
            return Err(SimError::Nonlinear {
                body: all_bodies(model),
                element: None,
                source: Box::new(NonlinearError::NonFinite("the computed displacement")),
                advice: String::new(),
            });
        }
        let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        last_change = change / scale.max(f64::MIN_POSITIVE);
        if change <= OBSTACLE_NEWTON_TOLERANCE * scale {
            result.solution.displacement = u.to_vec();
            check_held(model, &springs, &result, None).map_err(SimError::Contact)?;
            return Ok(result);
        }
    }
    Err(SimError::Nonlinear {
        body: all_bodies(model),
        element: None,
        source: Box::new(NonlinearError::StepFailed {
            from: 0.0,
            to: factor,
            step: factor,
            cuts: 0,
            reason: StepFailure::NotConverged {
                iterations: OBSTACLE_NEWTON_ITERATIONS,
                residual: last_change,
            },
            inverted: None,
        }),
        advice: String::new(),
    })
}

/// The model's loads with the nodes at `positions`: dead, except the gas cavity's pressure at
/// gauge `gas`, which acts on the wall where it is: R − p_rest·a(X) + p·a(x).
fn external_loads(model: &Model, positions: &[Vector3<f64>], gas: Option<f64>) -> Vec<f64> {
    match (&model.gas, gas) {
        (Some(cavity), Some(p)) => {
            let now = crate::mesh::Mesh {
                nodes: positions.to_vec(),
                cells: model.mesh.cells.clone(),
            };
            let at_rest = cavity.with_gauge(&model.load_vector, 0.0);
            let unit_now = cavity.unit_load_on(&now);
            at_rest
                .iter()
                .zip(&unit_now)
                .map(|(r, a)| r + p * a)
                .collect()
        }
        _ => model.load_vector.clone(),
    }
}

/// The names of every body, for an error that concerns them all.
fn all_bodies(model: &Model) -> String {
    model
        .bodies
        .iter()
        .map(|b| b.name.clone())
        .collect::<Vec<_>>()
        .join(", ")
}
