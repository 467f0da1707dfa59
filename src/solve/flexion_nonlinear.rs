//! The `nonlinear` tier of hand flexion: the paper's increments (Figures 2 and 6), each solved
//! to equilibrium at large strain.
//!
//! A keyframe's joint motion is split into increments of at most `max_step_deg`, the joint
//! angles interpolated linearly as in the other schemes, and the FEM region is the same (the
//! flesh near the joints that move; the rest follows its bones by skinning). Per increment:
//!
//! - the bones move; every bone node's position is prescribed (U_k of equation (6)), and so is
//!   every node the region shares with flesh outside it (where skinning put it);
//! - the region's flesh is a Neo-Hookean body with mean dilatation (`fem::hyperelastic`,
//!   `fem::hex8_hyperelastic`), total Lagrangian on the *rest* flesh mesh: its energy depends
//!   on the current positions only, so nothing accumulates from increment to increment and
//!   the result does not drift with the step size;
//! - Newton–Raphson with a line search (`fem::newton::solve_increment`) brings the free flesh
//!   to equilibrium, ∂W/∂u_u = 0: each iteration is the partitioned solve of equations
//!   (6)–(7) with the tangent K_T = ∂²W/∂u², K_T,11·Δu_u = R_u − K_T,12·Δu_k. It starts from
//!   the last equilibrium, the first iteration moving the bones (a linear increment on the
//!   current tangent, the better predictor: from rest to 10° of PIP, 5 iterations against 11
//!   from the skinning predictor, whose sheared joint flesh has an indefinite tangent); should
//!   that fail, from the skinning predictor (every free node where the blend of its bones'
//!   incremental motions puts it);
//! - an increment whose Newton fails (an element inverted at every step length, no
//!   convergence, a tangent that is not positive definite) is retried with half the step,
//!   up to [`MAX_HALVINGS`] times; two easy increments in a row double a halved step again.
//!
//! Reactions, equation (8) in its nonlinear form: R_k = f_int,k = ∂W/∂u_k, the internal force
//! of the flesh at the prescribed nodes, evaluated over every FEM cell of the hand (the flesh
//! outside the region included, which moved rigidly since it was last in equilibrium) at the
//! state reached. They are totals, not sums of increments; they balance (forces and moments)
//! up to the Newton residual left at the free nodes.

use super::error::SimError;
use super::far_strain::strained_by_far_skinning;
use super::flexion::{Flexion, Plan, Predicted};
use super::region::{local_displacements, SubProblem};
use super::self_contact::{barrier_kappa, OwnSkin};
use super::step_control::{count_newton, StepControl};
use crate::contact::SelfBarrier;
use crate::fem::added_energy::AddedEnergy;
use crate::fem::hex8::mapped_points;
use crate::fem::hex8_hyperelastic::{element_state, Volumetric};
use crate::fem::hyperelastic::NeoHookean;
use crate::fem::hyperelastic_body::HyperelasticBody;
use crate::fem::newton::{solve_increment_with, NewtonSettings, StepFailure};
use crate::fem::Material;
use crate::hand::HandModel;
use crate::model::FleshMethod;
use crate::state::{HandState, KeyframeStats};
use crate::util::timing::ms;
use nalgebra::{Isometry3, Vector3};
use rayon::prelude::*;
use std::time::Instant;

/// Halvings of an increment allowed before the flexion gives up: the smallest increment is
/// `max_step_deg` / 2⁵ (0.31° for the default 10°).
pub const MAX_HALVINGS: usize = 5;

/// Newton iterations allowed per increment before it is halved. Increments of the index PIP
/// flexion take 5–8 where the flesh is stable; where the palmar flesh creases (the tangent is
/// not positive definite on the way) 10–30, and up to 47 for ν = 0.4999 past 80°. Where two
/// creases close on themselves with the skin kept out of itself, the shifted tangents converge
/// linearly for longer: at 60 the index and middle PIP together stopped at 74.69° at
/// resolution 1.25 (at 61.56° without self-contact); at 150 both close, with it and without
/// (docs/hand.md). The limit is the tier's, with self-contact or not: a flexion that finds no
/// equilibrium takes longer to say so.
const MAX_ITERATIONS: usize = 150;

/// Why one increment found no equilibrium (cells and nodes numbered in the hand).
struct Failure {
    reason: String,
    /// The flesh cell to blame, if one inverted.
    cell: Option<usize>,
}

impl Flexion<'_> {
    /// Moves `state` to `target` by nonlinear increments (see the module documentation).
    pub(super) fn move_to_nonlinear(
        &mut self,
        state: &mut HandState,
        target: &[f64],
    ) -> Result<KeyframeStats, SimError> {
        let t_all = Instant::now();
        let mut stats = KeyframeStats::default();
        // (The bones where the keyframe starts: what skinning strains is their motion from.)
        let start = state.transforms.clone();
        let Some(plan) = self.plan(state, target, &mut stats) else {
            return Ok(stats);
        };
        let newton = NewtonSettings {
            volumetric: self.settings.volumetric,
            ..NewtonSettings::descent(MAX_ITERATIONS, self.ordering)
        };
        let body = match &plan.sub {
            Some(sub) => Some(
                HyperelasticBody::with_pattern(
                    &sub.mesh,
                    &sub.materials,
                    newton.volumetric,
                    sub.pattern.clone(),
                )
                .map_err(|e| SimError::InvertedElement {
                    body: self.body.clone(),
                    element: sub.cells[e.cell],
                    relative_det: e.relative_det,
                })?,
            ),
            None => None,
        };
        // The region's skin kept out of itself by a barrier in the energy Newton lowers.
        let barrier = match (&self.settings.self_contact, &plan.sub) {
            (Some(contact), Some(sub)) => OwnSkin::new(self.hand, sub, contact).map(|skin| {
                let young = sub.materials.iter().map(|m| m.young).fold(0.0, f64::max);
                let start = local_displacements(sub, &state.positions);
                let barrier = skin.barrier(&sub.mesh.nodes, barrier_kappa(young), &start);
                (skin, barrier)
            }),
            _ => None,
        };

        let mut control = StepControl::new(plan.steps, MAX_HALVINGS, true);
        let outcome = loop {
            if control.finished() {
                break Ok(());
            }
            if self.cancelled() {
                break Err(SimError::Cancelled);
            }
            let f = control.target();
            let angles = plan.angles_at(f);
            let t = Instant::now();
            let Predicted {
                transforms,
                mut next,
                ..
            } = self.predict(&plan, state, &angles);
            stats.update_ms += ms(t);
            let mut iterations = 0;
            if let (Some(sub), Some(body)) = (&plan.sub, &body) {
                let kept = barrier.as_ref().map(|b| &b.1);
                match self.equilibrium(sub, (body, kept), &newton, state, &mut next, &mut stats) {
                    Ok(n) => iterations = n,
                    Err(_) if control.halve() => {
                        stats.halvings += 1;
                        continue;
                    }
                    Err(failure) => {
                        let df = control.step();
                        break Err(self.no_equilibrium(&plan, state, &angles, df, failure));
                    }
                }
            }
            stats.increments_taken += 1;
            if let (Some(sub), Some((skin, barrier))) = (&plan.sub, &barrier) {
                let u = local_displacements(sub, &next);
                let press = (
                    &mut state.self_contact,
                    self.hand.contact_skin.vertex_count(),
                );
                (stats.self_contacts, stats.self_contact_force) =
                    skin.set_press(barrier, &u, press);
            }
            state.positions = next;
            state.transforms = transforms;
            state.angles = angles;
            control.accept(f, iterations <= 6);
        };
        // The reactions of the state reached: a consistent pose even when stopped early.
        let t = Instant::now();
        let kept = barrier.as_ref().map(|b| &b.1);
        let settled = self.settle_reactions(state, (plan.sub.as_ref(), &start), kept);
        stats.update_ms += ms(t);
        outcome?;
        settled?;
        state.angles = target.to_vec();
        stats.total_ms = ms(t_all);
        Ok(stats)
    }

    /// Newton on the region from the predictor `next` (the bones' positions there are the
    /// prescribed U_k); on success the free nodes of `next` hold the equilibrium and the
    /// Newton iterations are returned.
    fn equilibrium(
        &mut self,
        sub: &SubProblem,
        (body, barrier): (&HyperelasticBody, Option<&SelfBarrier>),
        newton: &NewtonSettings,
        state: &HandState,
        next: &mut [Vector3<f64>],
        stats: &mut KeyframeStats,
    ) -> Result<usize, Failure> {
        let dofs = 3 * sub.nodes.len();
        let rest = &sub.mesh.nodes;
        let mut predictor = vec![0.0; dofs];
        let mut target = vec![0.0; dofs];
        let mut previous = vec![0.0; dofs];
        for (i, &n) in sub.nodes.iter().enumerate() {
            let (p, q) = (next[n] - rest[i], state.positions[n] - rest[i]);
            let held = sub.partition.prescribed[3 * i];
            for a in 0..3 {
                predictor[3 * i + a] = p[a];
                previous[3 * i + a] = q[a];
                if held {
                    target[3 * i + a] = p[a];
                }
            }
        }
        // First the tangent predictor: the last equilibrium, the bones moved by the first
        // Newton iteration (a linear increment on the current tangent). Should Newton fail
        // from there, the skinning predictor (every node where its bones' blended motion puts
        // it), if it turns no element inside out.
        let loads = vec![0.0; dofs];
        let mut attempt = |start: &[f64], stats: &mut KeyframeStats| {
            let outcome = solve_increment_with(
                body,
                (&sub.partition, start, &target, &loads),
                barrier.map(|b| b as &dyn AddedEnergy),
                newton,
                &mut self.caches.solver,
            );
            count_newton(stats, &outcome.record);
            outcome
        };
        let mut outcome = attempt(&previous, stats);
        let inverted = matches!(outcome.result, Err(StepFailure::Inverted { .. }));
        // (With the skin kept out of itself, only a predictor it reaches without a point
        // passing through a facet: the barrier would hold such a point on the wrong side.)
        let clear = barrier.is_none_or(|b| {
            let jump: Vec<f64> = predictor
                .iter()
                .zip(&previous)
                .map(|(a, b)| a - b)
                .collect();
            let mut gradient = vec![0.0; dofs];
            b.largest_step(&previous, &jump) >= 1.0 && b.energy(&predictor, &mut gradient).is_some()
        });
        if inverted && clear && body.internal_forces(&predictor).is_ok() {
            outcome = attempt(&predictor, stats);
        }
        let record = &outcome.record;
        let u = match outcome.result {
            Ok(u) => u,
            Err(reason) => {
                let blamed = match &reason {
                    StepFailure::Inverted { cell, .. } => Some(*cell),
                    _ => outcome.inverted_in_trials.map(|e| e.cell),
                };
                let not_converged = matches!(reason, StepFailure::NotConverged { .. });
                let mut reason = self.explain(sub, &reason);
                let lowest = record
                    .residuals
                    .iter()
                    .skip(1)
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                let last = record.residuals.last().copied().unwrap_or(0.0);
                if not_converged && last > 100.0 * lowest {
                    reason += &format!(
                        "; its residual fell to {lowest:.1e}, then grew while the energy kept \
                         falling: the equilibrium followed so far vanishes (the flesh snaps \
                         into a new shape, a crease folding)"
                    );
                }
                if record.regularised > 0 {
                    reason += &format!(
                        "; the tangent stiffness was not positive definite {} times in this \
                         increment (regularised): the flesh is unstable there",
                        record.regularised
                    );
                }
                return Err(Failure {
                    reason,
                    cell: blamed.map(|c| sub.cells[c]),
                });
            }
        };
        if let Some(&r) = record.residuals.last() {
            stats.relative_residual = stats.relative_residual.max(r);
        }
        for (i, &n) in sub.nodes.iter().enumerate() {
            if !sub.partition.prescribed[3 * i] {
                next[n] = rest[i] + Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]);
            }
        }
        Ok(record.iterations)
    }

    /// A Newton failure in the hand's numbering.
    fn explain(&self, sub: &SubProblem, reason: &StepFailure) -> String {
        match reason {
            StepFailure::Inverted { cell, det_f } => {
                let c = sub.cells[*cell];
                let at = self.rest_centre_mm(c);
                format!(
                    "flesh element {c} (at rest near [{:.1}, {:.1}, {:.1}] mm) turns inside out \
                     at every step length (det F = {det_f:.3e} at a Gauss point)",
                    at[0], at[1], at[2]
                )
            }
            StepFailure::NotPositiveDefinite { node } => format!(
                "the tangent stiffness is not positive definite (pivot at flesh node {}): \
                 the flesh is unstable there (a fold, or elements close to collapse)",
                sub.nodes[*node]
            ),
            other => other.to_string(),
        }
    }

    /// The error of an increment that failed at the smallest step allowed.
    fn no_equilibrium(
        &self,
        plan: &Plan,
        state: &HandState,
        angles: &[f64],
        df: f64,
        failure: Failure,
    ) -> SimError {
        // The joint nearest to the blamed element, or the one moving most.
        let (joint, angle) = match failure.cell {
            Some(c) => self.nearest_moving_joint(plan, state, angles, c),
            None => {
                let i = (0..plan.start.len())
                    .max_by(|&a, &b| {
                        let m = |i: usize| (plan.target[i] - plan.start[i]).abs();
                        m(a).total_cmp(&m(b))
                    })
                    .unwrap_or(0);
                (self.hand.skeleton.dofs[i].name.clone(), angles[i])
            }
        };
        let largest = (0..plan.start.len())
            .map(|i| (plan.target[i] - plan.start[i]).abs())
            .fold(0.0, f64::max);
        let trials = match failure.cell {
            Some(c) if !failure.reason.starts_with("flesh element") => {
                let at = self.rest_centre_mm(c);
                format!(
                    "; flesh element {c} (at rest near [{:.1}, {:.1}, {:.1}] mm) turned inside \
                     out in trial steps",
                    at[0], at[1], at[2]
                )
            }
            _ => String::new(),
        };
        SimError::FlexionNoEquilibrium {
            body: self.body.clone(),
            joint,
            angle,
            step_deg: df * largest,
            halvings: MAX_HALVINGS,
            reason: format!("{}{trials}", failure.reason),
        }
    }

    /// Sets `state.reaction` to equation (8): the internal force of every FEM flesh cell at the
    /// state reached, at every node but the free nodes of the region `sub` (zero there, where
    /// the force is the Newton residual), plus the skin's press on itself where the `barrier`
    /// reaches a prescribed node (a bone's, or the region's edge). Outside the region, the
    /// cells a finger's skinning far from contact has strained since they were last solved
    /// (its bending joints and their blend into the palm, `far_strain`; kept in
    /// `state.far_strained`, the keyframe's from the bones at `start`) are left out: their
    /// positions are no equilibrium (the Power grasp's static frame at resolution 1, four
    /// digits skinned, read 9.75 N on the skinned index's metacarpal, where solved it holds
    /// 0.22 N). A finger skinned far from contact so bears no new flexion reaction, as in the
    /// other tiers; one solved before that keeps still keeps its own.
    fn settle_reactions(
        &self,
        state: &mut HandState,
        (sub, start): (Option<&SubProblem>, &[Isometry3<f64>]),
        barrier: Option<&SelfBarrier>,
    ) -> Result<(), SimError> {
        let now =
            strained_by_far_skinning(self.hand, (start, &state.transforms), &self.far_parts());
        let mut solved = vec![false; now.len()];
        for &c in sub.iter().flat_map(|s| &s.cells) {
            solved[c] = true;
        }
        let before = &state.far_strained;
        let strained: Vec<bool> = (0..now.len())
            .map(|c| (now[c] || before.get(c).copied().unwrap_or(false)) && !solved[c])
            .collect();
        let fem = |c: usize| self.cell_method(c) == FleshMethod::Fem && !strained[c];
        let forces = flesh_internal_forces(
            self.hand,
            &self.materials,
            self.settings.volumetric,
            &fem,
            &state.positions,
        )
        .map_err(|(cell, det_f)| SimError::InvertedElement {
            body: self.body.clone(),
            element: cell,
            relative_det: det_f,
        })?;
        let mut forces = forces;
        let mut free = vec![false; forces.len()];
        if let Some(sub) = sub {
            for (i, &n) in sub.nodes.iter().enumerate() {
                free[n] = !sub.partition.prescribed[3 * i];
            }
            if let Some(barrier) = barrier {
                let u = local_displacements(sub, &state.positions);
                let mut press = vec![0.0; u.len()];
                // (An admissible state: the increments reached it.)
                if barrier.energy(&u, &mut press).is_some() {
                    for (i, &n) in sub.nodes.iter().enumerate() {
                        forces[n] += Vector3::new(press[3 * i], press[3 * i + 1], press[3 * i + 2]);
                    }
                }
            }
        }
        for (n, f) in forces.into_iter().enumerate() {
            state.reaction[n] = if free[n] { Vector3::zeros() } else { f };
        }
        state.far_strained = if strained.iter().any(|&s| s) {
            strained
        } else {
            Vec::new()
        };
        Ok(())
    }
}

/// The internal forces ∂W/∂x of the Neo-Hookean flesh (total Lagrangian from the rest mesh,
/// `volumetric` integration) of the cells where `fem(c)` holds, at the node positions
/// `positions`, N per node; an inverted cell gives (cell, det F).
pub fn flesh_internal_forces(
    hand: &HandModel,
    materials: &[Material],
    volumetric: Volumetric,
    fem: &(dyn Fn(usize) -> bool + Sync),
    positions: &[Vector3<f64>],
) -> Result<Vec<Vector3<f64>>, (usize, f64)> {
    let mesh = &hand.flesh.mesh;
    let per_cell = (0..mesh.cells.len())
        .into_par_iter()
        .filter(|&c| fem(c))
        .map(|c| {
            let cell = &mesh.cells[c];
            let reference =
                mapped_points(&cell.map(|n| mesh.nodes[n])).map_err(|e| (c, e.relative_det))?;
            let u = cell.map(|n| positions[n] - mesh.nodes[n]);
            let law = NeoHookean::from_material(&materials[c]);
            element_state(&reference, &u, &law, volumetric, false)
                .map(|s| (c, s.force))
                .map_err(|e| (c, e.det_f))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut out = vec![Vector3::zeros(); mesh.nodes.len()];
    for (c, force) in per_cell {
        for (a, &n) in mesh.cells[c].iter().enumerate() {
            out[n] += force[a];
        }
    }
    Ok(out)
}
