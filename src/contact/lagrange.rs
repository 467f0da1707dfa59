//! Frictionless contact against rigid obstacles, exact at convergence: an active set of
//! Lagrange multipliers solved through the Schur complement of the factored stiffness.
//!
//! With K11 factored once (equation (7) without contact, U⁰), each active contact i adds the
//! linearised constraint nᵢ·uᵢ ≥ bᵢ = nᵢ·(cᵢ − Xᵢ) (node i stays on the outer side of the
//! obstacle's surface at its nearest point cᵢ) and a multiplier λᵢ ≥ 0, the normal contact force:
//!
//!   K·U = R + Cᵀλ,  C·U = b on the active set  ⇒  S·λ = b − C·U⁰,  S = C·K11⁻¹·Cᵀ,
//!   U = U⁰ + K11⁻¹·Cᵀ·λ.
//!
//! K11⁻¹ applied to the unit vectors of a contact node's dofs is computed once per node by
//! substitution with the existing factor (no refactorization). Nodes that penetrate join the set,
//! nodes whose multiplier turns negative (pulled, not pushed) leave it, until the set is stable:
//! then no node penetrates by more than the tolerance and every contact force is compressive.

use super::obstacle::Obstacle;
use crate::fem::assembly::Stiffness;
use crate::fem::solve::{PartitionedSolver, Solution, SolveError};
use crate::fem::DofPartition;
use nalgebra::{DMatrix, DVector, Vector3};
use std::collections::HashMap;
use std::time::Instant;
use thiserror::Error;

/// Settings of the contact iteration.
#[derive(Clone, Copy, Debug)]
pub struct ContactSettings {
    /// Penetration allowed at convergence, m.
    pub tolerance: f64,
    /// Most active-set iterations.
    pub max_iterations: usize,
}

/// One node in contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPoint {
    /// The node.
    pub node: usize,
    /// The obstacle.
    pub obstacle: usize,
    /// Outward normal of the obstacle at the contact, unit.
    pub normal: Vector3<f64>,
    /// Normal contact force on the node, N (≥ 0; the force vector is `force · normal`).
    pub force: f64,
    /// Gap at convergence, m (≥ −tolerance).
    pub gap: f64,
}

/// The solved contact problem.
#[derive(Clone, Debug)]
pub struct ContactResult {
    /// Displacements and support reactions (contact forces excluded).
    pub solution: Solution,
    /// Active contacts.
    pub contacts: Vec<ContactPoint>,
    /// Active-set iterations.
    pub iterations: usize,
    /// Factorizations (one: the stiffness is factored once).
    pub factorizations: usize,
    /// Substitutions with the reused factor (three per contact node).
    pub substitutions: usize,
    /// Largest penetration at convergence, m (0 when none).
    pub max_penetration: f64,
    /// Time spent in the contact iterations (after the first solve), ms.
    pub contact_ms: f64,
}

/// Why contact could not be resolved.
#[derive(Debug, Error)]
pub enum ContactError {
    /// The linear solve failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// The active set did not settle.
    #[error(
        "contact did not converge in {iterations} iterations: {active} nodes active, largest \
         penetration {penetration:.3e} m (tolerance {tolerance:.1e} m); raise the iteration limit \
         or refine the mesh where the bodies touch"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Active nodes at the end.
        active: usize,
        /// Largest penetration, m.
        penetration: f64,
        /// Tolerance, m.
        tolerance: f64,
    },
    /// The constraints are dependent (e.g. a node prescribed and in contact).
    #[error(
        "the contact constraints are not independent (Schur complement not positive definite)"
    )]
    Singular,
}

/// Solves K·U = R with the prescribed dofs of `partition` and the nodes `candidates` kept out of
/// `obstacles`.
#[allow(clippy::too_many_arguments)]
pub fn solve_with_obstacles(
    solver: &mut PartitionedSolver,
    k: &Stiffness,
    partition: &DofPartition,
    prescribed: &[f64],
    loads: &[f64],
    positions: &[Vector3<f64>],
    candidates: &[usize],
    obstacles: &[Obstacle],
    settings: ContactSettings,
) -> Result<ContactResult, ContactError> {
    let base = solver.solve(k, partition, prescribed, loads, positions)?;
    let t = Instant::now();
    let u0 = base.displacement.clone();
    let neq = partition.free_count();
    // K11⁻¹·e for the free dofs of a node, cached: column per local axis (None if prescribed).
    let mut columns: HashMap<usize, [Option<Vec<f64>>; 3]> = HashMap::new();
    let mut substitutions = 0;
    let mut active: Vec<(usize, usize, Vector3<f64>, f64)> = Vec::new(); // node, obstacle, n, b
    let mut u = u0.clone();
    let mut lambda = DVector::zeros(0);
    let mut iterations = 0;
    loop {
        iterations += 1;
        if iterations > settings.max_iterations {
            let penetration = max_penetration(&u, positions, candidates, obstacles);
            return Err(ContactError::NotConverged {
                iterations: settings.max_iterations,
                active: active.len(),
                penetration,
                tolerance: settings.tolerance,
            });
        }
        // Join: nodes that penetrate an obstacle.
        let mut joined = false;
        for &node in candidates {
            if (0..3).all(|i| partition.prescribed[3 * node + i]) {
                continue;
            }
            let x = positions[node] + Vector3::new(u[3 * node], u[3 * node + 1], u[3 * node + 2]);
            for (o, obstacle) in obstacles.iter().enumerate() {
                if active.iter().any(|a| a.0 == node && a.1 == o) {
                    continue;
                }
                let (gap, n, c) = obstacle.nearest(&x);
                if gap < -settings.tolerance {
                    active.push((node, o, n, n.dot(&(c - positions[node]))));
                    joined = true;
                }
            }
        }
        if !joined && iterations > 1 {
            break;
        }
        if active.is_empty() {
            break;
        }
        // K11⁻¹ on the unit vectors of the new contact nodes' free dofs, all in one
        // multi-column substitution with the existing factor.
        let mut wanted: Vec<(usize, usize)> = Vec::new();
        for &(node, ..) in &active {
            if columns.contains_key(&node) || wanted.iter().any(|w| w.0 == node) {
                continue;
            }
            for axis in 0..3 {
                if !partition.prescribed[3 * node + axis] {
                    wanted.push((node, axis));
                }
            }
        }
        if !wanted.is_empty() {
            let mut block = vec![0.0; neq * wanted.len()];
            for (j, &(node, axis)) in wanted.iter().enumerate() {
                block[j * neq + partition.equation[3 * node + axis]] = 1.0;
            }
            solver.solve_factored(&mut block, wanted.len())?;
            substitutions += wanted.len();
            for (j, &(node, axis)) in wanted.iter().enumerate() {
                let entry = columns.entry(node).or_insert([None, None, None]);
                entry[axis] = Some(block[j * neq..(j + 1) * neq].to_vec());
            }
        }
        // Solve the Schur system; drop the most negative multiplier until all are compressive.
        loop {
            let m = active.len();
            let w: Vec<Vec<f64>> = active
                .iter()
                .map(|&(node, _, n, _)| {
                    let mut wj = vec![0.0; neq];
                    for (axis, col) in columns[&node].iter().enumerate() {
                        if let Some(col) = col {
                            for (x, c) in wj.iter_mut().zip(col) {
                                *x += n[axis] * c;
                            }
                        }
                    }
                    wj
                })
                .collect();
            let c_dot = |i: usize, v: &[f64]| -> f64 {
                let (node, _, n, _) = active[i];
                (0..3)
                    .filter(|&a| !partition.prescribed[3 * node + a])
                    .map(|a| n[a] * v[partition.equation[3 * node + a]])
                    .sum()
            };
            let s = DMatrix::from_fn(m, m, |i, j| c_dot(i, &w[j]));
            let r = DVector::from_fn(m, |i, _| {
                let (node, _, n, b) = active[i];
                b - (0..3).map(|a| n[a] * u0[3 * node + a]).sum::<f64>()
            });
            let Some(chol) = s.clone().cholesky() else {
                return Err(ContactError::Singular);
            };
            lambda = chol.solve(&r);
            let (worst, value) =
                lambda.iter().enumerate().fold(
                    (0, 0.0),
                    |acc, (i, &l)| if l < acc.1 { (i, l) } else { acc },
                );
            if value < 0.0 {
                active.remove(worst);
                if active.is_empty() {
                    lambda = DVector::zeros(0);
                    break;
                }
                continue;
            }
            u = u0.clone();
            for (j, wj) in w.iter().enumerate() {
                for (e, &d) in partition.free.iter().enumerate() {
                    u[d] += lambda[j] * wj[e];
                }
            }
            break;
        }
        if active.is_empty() {
            u = u0.clone();
        }
    }
    // Reactions at the prescribed dofs (contact forces act on free dofs only).
    let ku = k.mul(&u);
    let mut solution = base;
    for d in 0..u.len() {
        solution.reaction[d] = if partition.prescribed[d] {
            ku[d] - loads[d]
        } else {
            0.0
        };
    }
    solution.displacement = u;
    let contacts = active
        .iter()
        .zip(lambda.iter())
        .map(|(&(node, o, n, _), &force)| {
            let x = positions[node]
                + Vector3::new(
                    solution.displacement[3 * node],
                    solution.displacement[3 * node + 1],
                    solution.displacement[3 * node + 2],
                );
            ContactPoint {
                node,
                obstacle: o,
                normal: n,
                force,
                gap: obstacles[o].nearest(&x).0,
            }
        })
        .collect();
    let max_penetration = max_penetration(&solution.displacement, positions, candidates, obstacles);
    Ok(ContactResult {
        solution,
        contacts,
        iterations,
        factorizations: 1,
        substitutions,
        max_penetration,
        contact_ms: t.elapsed().as_secs_f64() * 1e3,
    })
}

fn max_penetration(
    u: &[f64],
    positions: &[Vector3<f64>],
    candidates: &[usize],
    obstacles: &[Obstacle],
) -> f64 {
    let mut worst: f64 = 0.0;
    for &node in candidates {
        let x = positions[node] + Vector3::new(u[3 * node], u[3 * node + 1], u[3 * node + 2]);
        for o in obstacles {
            worst = worst.max(-o.nearest(&x).0);
        }
    }
    worst
}
