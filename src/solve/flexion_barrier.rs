//! The self-contact of the linear increments (the corotated ones and the paper's): the region's
//! skin kept out of itself by the same barrier as the nonlinear tier's (`contact::SelfBarrier`:
//! point–facet and edge–edge pairs, incremental potential contact's log barrier), not by an
//! active set of point-on-facet rows, which holds no edge against an edge (the four fingers'
//! fist crossed itself in 318 triangle pairs with it).
//!
//! An increment's flesh is linear: alone its equilibrium is the minimum of the quadratic energy
//! ½ΔuᵀKΔu + f₀ᵀΔu (`fem::quadratic_body`), equations (7)–(8) in one solve. With the barrier B,
//! Newton (`fem::newton::solve_increment_with`) lowers
//!
//!   W(u) + B(u) − ∇B(u₀)ᵀ(u − u₀),
//!
//! u₀ where the increment starts: each increment's flesh starts unstressed from where the last
//! left it, the press it carried there balanced by the stress the increments before summed, so
//! only the change of the barrier's force is the increment's (as an increment's contact forces
//! are). Its reactions at the prescribed nodes are K·Δu's and the barrier's change there; summed
//! over the increments they are the flesh's and the press's totals (equation (8)). Every step is
//! cut short of a point passing through a facet or an edge through an edge (continuous
//! collision), and of a cell turning inside out. Beside the skin's barrier, the flesh's own
//! (`fem::crush_barrier`, the same treatment) resists a Gauss point's loss of more than half its
//! volume, which the linear flesh does not: a fingertip's pulp squeezed between its bone and the
//! palm's.

use super::error::SimError;
use super::flexion::Flexion;
use super::region::{local_displacements, SubProblem};
use super::step_control::count_newton;
use crate::contact::SelfBarrier;
use crate::fem::added_energy::{AddedEnergy, AddedSum};
use crate::fem::assembly::Stiffness;
use crate::fem::crush_barrier::CrushBarrier;
use crate::fem::elastic_energy::ElasticEnergy;
use crate::fem::newton::{solve_increment_with, NewtonSettings, StepFailure};
use crate::fem::quadratic_body::QuadraticBody;
use crate::fem::solve::{Solution, SolveError, SolveStats};
use crate::mesh::Mesh;
use crate::state::KeyframeStats;
use nalgebra::Vector3;

/// Newton iterations allowed an increment before it is halved. An increment whose skin does not
/// touch itself takes one; a pressed crease 6–10, fingers pressed on each other and the palm up
/// to about 50 (the four fingers' fist), the full fist at resolution 1.5 up to 57 with the
/// longer steps (79 with saddle escapes instead, allowed 150 as the nonlinear tier is).
const MAX_ITERATIONS: usize = 100;

/// Newton iterations allowed to put the bones in place. Increments that settle put them there
/// within 4 (the full fist at resolution 1.5, traced); where the flesh between two bones would
/// have to be crushed inside out every step toward them is cut short, and Newton crept on for
/// its 100 iterations at each of the five halvings.
const PLACING_ITERATIONS: usize = 12;

/// What one linear increment with the barrier gives: the solution, as the linear solve's — the
/// new positions (corotated) or the displacements (the paper's) at every dof, the reactions at
/// the prescribed ones (the factorizations and their cost counted in the keyframe's statistics
/// already) — with the displacements from the region's rest mesh the barrier takes; or the cell
/// that turned inside out at every step length tried (the hand's cell, its det J).
pub(super) type BarrierIncrement = Result<(Solution, Vec<f64>), (usize, f64)>;

impl Flexion<'_> {
    /// The increment K·x = `loads` (`absolute`: x the new positions, else the displacements
    /// from `start`) with the region's skin kept out of itself by `barrier` (its displacements
    /// from `sub`'s rest mesh), from the region at `start` to the prescribed positions in
    /// `next` (the hand's nodes).
    pub(super) fn barrier_increment(
        &mut self,
        sub: &SubProblem,
        barrier: &SelfBarrier,
        (k, loads, absolute): (&Stiffness, &[f64], bool),
        (start, next): (&Mesh, &[Vector3<f64>]),
        stats: &mut KeyframeStats,
    ) -> Result<BarrierIncrement, SimError> {
        let rest = &sub.mesh.nodes;
        let dofs = 3 * rest.len();
        let x0: Vec<f64> = start.nodes.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
        let u0: Vec<f64> = x0
            .iter()
            .zip(rest.iter().flat_map(|v| [v.x, v.y, v.z]))
            .map(|(x, r)| x - r)
            .collect();
        // (Newton takes the target at the prescribed dofs only.)
        let target = local_displacements(sub, next);
        // f₀: the quadratic energy's gradient where the increment starts, less the barrier's
        // force there (carried by the increments before).
        let mut force: Vec<f64> = if absolute {
            k.mul(&x0).iter().zip(loads).map(|(f, r)| f - r).collect()
        } else {
            loads.iter().map(|r| -r).collect()
        };
        // The flesh kept from being crushed inside out beside it (`fem::crush_barrier`: a pulp
        // squeezed between two bones).
        let crush = CrushBarrier::new(&sub.mesh, &sub.materials);
        let added = AddedSum(vec![barrier as &dyn AddedEnergy, &crush]);
        let mut press = vec![0.0; dofs];
        if added.energy(&u0, &mut press).is_none() {
            return Err(self.unsettled(
                "the skin touches or crosses itself where the increment starts".into(),
            ));
        }
        for (f, b) in force.iter_mut().zip(&press) {
            *f -= b;
        }
        let body = QuadraticBody::new(k, &sub.mesh, u0.clone(), force);
        // The flesh's energy is convex: an indefinite tangent is the barrier's (skin pressed on
        // skin sliding over a ridge, a crease buckling), left by longer steps down it, not by
        // the escape from a saddle of the body.
        let newton = NewtonSettings {
            escape_saddles: false,
            expand_steps: true,
            placing_iterations: PLACING_ITERATIONS,
            ..NewtonSettings::descent(MAX_ITERATIONS, self.ordering)
        };
        let outcome = solve_increment_with(
            &body,
            (&sub.partition, &u0, &target, &vec![0.0; dofs]),
            Some(&added as &dyn AddedEnergy),
            &newton,
            &mut self.caches.solver,
        );
        let record = &outcome.record;
        count_newton(stats, record);
        let u = match outcome.result {
            Ok(u) => u,
            Err(StepFailure::Inverted { cell, det_f }) => return Ok(Err((sub.cells[cell], det_f))),
            // The bones come too close for the flesh between them: it would have to be crushed
            // inside out (as a cell that turns inside out, the increment is halved).
            // (Blamed on the flesh only where its collapse, not the skin's crossing, set the
            // length of the last step taken.)
            Err(StepFailure::NotPlaced { .. })
                if crush.limiting().is_some_and(|(_, _, allowed)| {
                    record
                        .step_lengths
                        .last()
                        .is_some_and(|&taken| (taken - allowed).abs() <= 1e-9 * allowed)
                }) =>
            {
                let (cell, q, _) = crush.limiting().unwrap();
                return Ok(Err((sub.cells[cell], q)));
            }
            // The factorization itself failed (memory refused, a value not finite): not the
            // self-contact's doing, and no smaller increment helps.
            Err(StepFailure::Tangent(reason)) => {
                return Err(SimError::Solve {
                    body: self.body.clone(),
                    source: SolveError::Faer(reason),
                })
            }
            Err(reason) => {
                let reason = match reason {
                    StepFailure::NotPositiveDefinite { node } => format!(
                        "the tangent stiffness is not positive definite (pivot at flesh node {})",
                        sub.nodes[node]
                    ),
                    other => other.to_string(),
                };
                let mut reason =
                    format!("with the skin kept out of itself by its barrier, {reason}");
                if record.regularised > 0 {
                    reason += &format!(
                        "; the tangent was not positive definite {} times in this increment",
                        record.regularised
                    );
                }
                return Err(self.unsettled(reason));
            }
        };
        if let Some(&r) = record.residuals.last() {
            stats.relative_residual = stats.relative_residual.max(r);
        }
        // The reactions: the flesh's increment and the change of the press, at the prescribed
        // dofs (ΔU, or the positions, at every dof, as the linear solve gives).
        let mut reaction = match body.internal_forces(&u) {
            Ok((_, f)) => f,
            Err(e) => return Ok(Err((sub.cells[e.cell], e.det_f))),
        };
        if added.energy(&u, &mut reaction).is_none() {
            return Err(self.unsettled("the barrier's equilibrium is not admissible".into()));
        }
        // (∇B(u₀) was taken out with f₀.)
        for (r, &held) in reaction.iter_mut().zip(&sub.partition.prescribed) {
            if !held {
                *r = 0.0;
            }
        }
        let displacement = (0..dofs)
            .map(|d| {
                let x = rest[d / 3][d % 3] + u[d];
                if absolute {
                    x
                } else {
                    x - x0[d]
                }
            })
            .collect();
        let solution = Solution {
            displacement,
            reaction,
            stats: SolveStats::default(),
        };
        Ok(Ok((solution, u)))
    }

    /// The error of an increment whose self-contact found no equilibrium (its joint and angle
    /// filled in by the keyframe).
    fn unsettled(&self, reason: String) -> SimError {
        SimError::SelfContactUnsettled {
            body: self.body.clone(),
            joint: String::new(),
            angle: 0.0,
            reason,
            share: None,
        }
    }
}
