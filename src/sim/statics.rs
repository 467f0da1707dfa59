//! The static solve of one frame: assemble K on the current geometry, solve equations (7)–(8),
//! then recover stresses. The result is the frame's state.

use super::model::Model;
use crate::contact::{solve_with_obstacles, ContactError, ContactResult, Obstacle};
use crate::fem::assembly::assemble_kind;
use crate::fem::newton::StaticTier;
use crate::fem::solve::{PartitionedSolver, Solution, SolveError};
use crate::fem::stress::{stress_field_kind, StressField};
use std::time::Instant;
use thiserror::Error;

/// Why a frame could not be solved.
#[derive(Debug, Error)]
pub enum SimError {
    /// An element is inverted or flat.
    #[error("body \"{body}\": element {element} is inverted or has zero volume (smallest det J / size³ = {relative_det:.3e})")]
    InvertedElement {
        /// The body.
        body: String,
        /// The element, numbered within its body.
        element: usize,
        /// Its smallest relative Jacobian.
        relative_det: f64,
    },
    /// A flexion increment would turn a flesh element inside out even after halving the step.
    #[error(
        "body \"{body}\": flesh element {element} (at rest near [{:.1}, {:.1}, {:.1}] mm) would turn \
         inside out as {joint} reaches {angle:.1}°, even with the increment halved four times: \
         the flesh is crushed in a crease of the joint; use a coarser mesh resolution or a \
         smaller joint angle",
        rest_position_mm[0], rest_position_mm[1], rest_position_mm[2]
    )]
    FleshCrushed {
        /// The hand body.
        body: String,
        /// The element, numbered within the hand.
        element: usize,
        /// Its centre in the rest pose, mm.
        rest_position_mm: [f64; 3],
        /// The joint moving most.
        joint: String,
        /// Its angle at the failing increment, degrees.
        angle: f64,
    },
    /// A nonlinear flexion increment found no equilibrium, even at the smallest step allowed.
    #[error(
        "body \"{body}\": the nonlinear flexion found no equilibrium as {joint} reaches \
         {angle:.2}°, with the increment halved {halvings} times (to {step_deg:.3}°): {reason}"
    )]
    FlexionNoEquilibrium {
        /// The hand body.
        body: String,
        /// The moved joint nearest to the trouble (or the one moving most).
        joint: String,
        /// That joint's angle at the failing increment, degrees.
        angle: f64,
        /// The size of the failing increment, degrees of the joint moving most.
        step_deg: f64,
        /// Halvings done.
        halvings: usize,
        /// Why Newton failed.
        reason: String,
    },
    /// The linear tier's one solve from rest turns a flesh element inside out (no increment to
    /// halve: the rotation is too large for small-strain elasticity on the rest geometry).
    #[error(
        "body \"{body}\": the linear tier (small strain on the rest geometry) turns flesh element \
         {element} (at rest near [{:.1}, {:.1}, {:.1}] mm) inside out as {joint} reaches \
         {angle:.1}°: a rotation this large is outside linear elasticity; use tier \
         \"corotational\" or \"incremental\"",
        rest_position_mm[0], rest_position_mm[1], rest_position_mm[2]
    )]
    LinearTierInverted {
        /// The hand body.
        body: String,
        /// The element, numbered within the hand.
        element: usize,
        /// Its centre in the rest pose, mm.
        rest_position_mm: [f64; 3],
        /// The moved joint nearest to it.
        joint: String,
        /// That joint's angle, degrees.
        angle: f64,
    },
    /// Contact could not be resolved.
    #[error(transparent)]
    Contact(ContactError),
    /// A newer request made this solve stale: it stopped between two increments.
    #[error("cancelled: a newer request replaced this solve")]
    Cancelled,
    /// A combination of settings the solver does not support yet.
    #[error("{0}")]
    Unsupported(String),
    /// The nonlinear tier failed (`[solver] tier = "nonlinear"`).
    #[error("body \"{body}\"{}: {source}", element_note(.element))]
    Nonlinear {
        /// The body (all bodies' names when no element is to blame).
        body: String,
        /// The inverted element, numbered within its body, if one is to blame.
        element: Option<usize>,
        /// Why.
        source: Box<crate::fem::NonlinearError>,
    },
    /// The linear solve failed.
    #[error("body \"{body}\": {source}")]
    Solve {
        /// The body the failing dof belongs to.
        body: String,
        /// Why.
        source: SolveError,
    },
}

fn element_note(element: &Option<usize>) -> String {
    element.map_or(String::new(), |e| format!(" (its element {e})"))
}

/// The state after solving one frame.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Displacements and reactions.
    pub solution: Solution,
    /// Stresses.
    pub stress: StressField,
    /// Time spent assembling K, ms.
    pub assembly_ms: f64,
    /// Time spent on stresses, ms.
    pub stress_ms: f64,
    /// The hands' state (empty without hands).
    pub hands: Vec<HandFrame>,
    /// Contact against the obstacles (None without obstacles).
    pub contact: Option<ContactResult>,
}

/// A hand in a frame.
#[derive(Clone, Debug)]
pub struct HandFrame {
    /// The body.
    pub body: usize,
    /// Joint angles, degrees.
    pub angles: Vec<f64>,
    /// Flesh node positions, m.
    pub positions: Vec<nalgebra::Vector3<f64>>,
    /// Reaction of every bone (sum of R_u over its nodes, equation (8)), N.
    pub bone_reactions: Vec<nalgebra::Vector3<f64>>,
    /// Accumulated reaction at every flesh node, N.
    pub reaction: Vec<nalgebra::Vector3<f64>>,
    /// Flesh volume, m³.
    pub volume: f64,
    /// What reaching this frame's pose cost.
    pub stats: super::flexion::KeyframeStats,
    /// Contact force on the flesh following each bone, N (zero without contact).
    pub contact_force: Vec<nalgebra::Vector3<f64>>,
    /// Bones whose reaction overruns their muscle force threshold: the grasp is not realisable.
    pub overloads: Vec<super::outcome::Overload>,
}

/// Solves the static equilibrium of the model (equation (5) partitioned as (6)–(8)).
pub fn solve_static(model: &Model, solver: &mut PartitionedSolver) -> Result<Frame, SimError> {
    if model.tier == StaticTier::Nonlinear {
        return super::statics_nonlinear::solve_static_nonlinear(model);
    }
    let inverted = |cell: usize, relative_det: f64| {
        let b = model.cell_body[cell];
        SimError::InvertedElement {
            body: model.bodies[b].name.clone(),
            element: cell - model.bodies[b].cells.start,
            relative_det,
        }
    };
    let t = Instant::now();
    let mut k = assemble_kind(
        &model.pattern,
        &model.mesh,
        &model.cell_materials,
        model.element,
    )
    .map_err(|e| inverted(e.cell, e.inverted.relative_det))?;
    let springs = super::stabilize::stabilize(model, &mut k, &model.partition);
    let assembly_ms = t.elapsed().as_secs_f64() * 1e3;
    let solve_error = |source: SolveError| {
        let body = match &source {
            SolveError::NotPositiveDefinite { node, .. } => {
                model.bodies[model.body_of_node(*node)].name.clone()
            }
            _ => model
                .bodies
                .iter()
                .map(|b| b.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        };
        SimError::Solve { body, source }
    };
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
        let solution = result.solution.clone();
        (solution, Some(result))
    };
    let t = Instant::now();
    let stress = stress_field_kind(
        &model.mesh,
        &model.cell_materials,
        &solution.displacement,
        model.element,
    )
    .map_err(|(c, e)| inverted(c, e.relative_det))?;
    let stress_ms = t.elapsed().as_secs_f64() * 1e3;
    Ok(Frame {
        solution,
        stress,
        assembly_ms,
        stress_ms,
        hands: Vec::new(),
        contact,
    })
}
