//! The linear tier of hand flexion: small-strain linear elasticity on the rest geometry.
//!
//! The stiffness K of every FEM flesh cell (bone nodes prescribed) is assembled on the rest
//! geometry and factored once per hand. Each keyframe is then one solve, with no increments:
//! the bones' total displacement from rest, u_k = T_b·X − X, is prescribed and equation (7),
//! K11·u_u = −K12·u_k, gives the flesh displacement by forward and back substitution with the
//! kept factor; equation (8) gives the reactions. The result depends on the target pose only,
//! not on the path to it.
//!
//! The region is the whole FEM flesh, fixed for the life of the stepper. The region of the
//! incremental tiers depends on which joints move in a keyframe, and a region that changed
//! between keyframes would need a new factorization; a fixed region covering every joint's
//! blend zone would take most of the hand anyway. The whole flesh costs one factorization per
//! hand (≈0.4 s at resolution 1) and leaves no boundary where skinned flesh meets the FEM.
//!
//! The price is geometric: a finite rotation R of flesh that turns with a bone is not a
//! zero-energy motion of linear elasticity (its small strain is sym(R − I) = (cos θ − 1) in the
//! plane of rotation). Where the flesh is free to relax, it drifts towards the infinitesimal
//! rotation I + sin θ·[a]×, whose volume ratio is 1 + sin²θ: flesh that turns with a bone swells.

use super::error::SimError;
use super::region::{sub_problem, SubProblem};
use crate::fem::assembly::{assemble, Stiffness};
use crate::fem::hex8::relative_min_jacobian;
use crate::fem::solve::{FillOrdering, PartitionedSolver, SolveError};
use crate::fem::Material;
use crate::hand::{Blend, HandModel};
use crate::model::{FleshMethod, FlexionSettings};
use crate::state::{HandState, KeyframeStats};
use crate::util::timing::ms;
use nalgebra::{Point3, Vector3};
use std::time::Instant;

/// The factored rest stiffness of a hand's FEM flesh: built by a stepper's first linear
/// keyframe, reusable by later steppers of the same hand, materials and settings
/// ([`super::FlexionCaches`]).
pub struct LinearFactor {
    body: String,
    blend: Blend,
    /// The FEM cells (every cell whose method is FEM) on the rest geometry; `None` when the
    /// whole hand is skinned.
    sub: Option<SubProblem>,
    /// K of `sub` on the rest geometry.
    k: Option<Stiffness>,
    /// Holds the factor of `k`'s K11 once `factored`.
    solver: PartitionedSolver,
    /// Whether the solver holds the factor of `k`'s K11.
    factored: bool,
    /// Free nodes outside the FEM cells: they follow skinning from rest.
    skinned: Vec<usize>,
    /// Time spent assembling K (paid by the first keyframe), ms.
    assembly_ms: f64,
}

impl LinearFactor {
    /// Assembles K of the FEM flesh of `hand` on its rest geometry (not yet factored).
    pub(super) fn new(
        hand: &HandModel,
        body: &str,
        materials: &[Material],
        settings: &FlexionSettings,
        ordering: FillOrdering,
    ) -> Result<LinearFactor, SimError> {
        let flesh = &hand.flesh;
        let method = |c: usize| settings.methods[flesh.cell_digit[c].map_or(0, |d| d + 1)];
        let active: Vec<bool> = (0..flesh.mesh.cells.len())
            .map(|c| method(c) == FleshMethod::Fem)
            .collect();
        let sub = sub_problem(hand, materials, &active);
        let mut in_fem = vec![false; flesh.mesh.nodes.len()];
        if let Some(sub) = &sub {
            for &n in &sub.nodes {
                in_fem[n] = true;
            }
        }
        let skinned = (0..flesh.mesh.nodes.len())
            .filter(|&n| flesh.node_bone[n].is_none() && !in_fem[n])
            .collect();
        let t = Instant::now();
        let k =
            match &sub {
                Some(sub) => Some(assemble(&sub.pattern, &sub.mesh, &sub.materials).map_err(
                    |e| SimError::InvertedElement {
                        body: body.to_string(),
                        element: sub.cells[e.cell],
                        relative_det: e.inverted.relative_det,
                    },
                )?),
                None => None,
            };
        Ok(LinearFactor {
            body: body.to_string(),
            blend: settings.blend,
            sub,
            k,
            solver: PartitionedSolver::new(ordering),
            factored: false,
            skinned,
            assembly_ms: ms(t),
        })
    }

    /// Moves `state` to the joint angles `target` (degrees) in one linear solve from rest;
    /// `hand` is the one the tier was built for.
    pub(super) fn move_to(
        &mut self,
        hand: &HandModel,
        state: &mut HandState,
        target: &[f64],
    ) -> Result<KeyframeStats, SimError> {
        if target == state.angles.as_slice() {
            return Ok(KeyframeStats::default());
        }
        let t_all = Instant::now();
        let flesh = &hand.flesh;
        let rest = &flesh.mesh.nodes;
        let mut stats = KeyframeStats {
            increments: 1,
            increments_taken: 1,
            ..Default::default()
        };
        let t = Instant::now();
        let transforms = hand.skeleton.transforms(target);
        // Bone nodes move rigidly with their bone; flesh outside the FEM cells by skinning.
        let mut next = rest.clone();
        for (n, b) in flesh.node_bone.iter().enumerate() {
            if let Some(b) = b {
                next[n] = (transforms[*b] * Point3::from(rest[n])).coords;
            }
        }
        let boundary = self.sub.iter().flat_map(|sub| {
            sub.nodes
                .iter()
                .enumerate()
                .filter(|&(i, &n)| sub.partition.prescribed[3 * i] && flesh.node_bone[n].is_none())
                .map(|(_, &n)| n)
        });
        let skinned: Vec<usize> = self.skinned.iter().copied().chain(boundary).collect();
        hand.weights.apply(
            self.blend,
            &transforms,
            rest,
            skinned.into_iter(),
            &mut next,
        );
        stats.update_ms += ms(t);

        let mut reaction = vec![Vector3::zeros(); rest.len()];
        if let (Some(sub), Some(k)) = (&self.sub, &self.k) {
            stats.fem_cells = sub.cells.len();
            stats.free_dofs = sub.partition.free_count();
            stats.prescribed_dofs = sub.partition.prescribed_count();
            let dofs = 3 * sub.nodes.len();
            // u_k = x − X at the prescribed dofs, zero elsewhere.
            let mut u = vec![0.0; dofs];
            for (i, &n) in sub.nodes.iter().enumerate() {
                if sub.partition.prescribed[3 * i] {
                    u[3 * i..3 * i + 3].copy_from_slice((next[n] - rest[n]).as_slice());
                }
            }
            let solve_error = |source| SimError::Solve {
                body: self.body.clone(),
                source,
            };
            let ku = if !self.factored {
                // First keyframe: factor K11 (kept by the solver) and solve.
                let solution = self
                    .solver
                    .solve(k, &sub.partition, &u, &vec![0.0; dofs], &sub.mesh.nodes)
                    .map_err(solve_error)?;
                let s = &solution.stats;
                stats.symbolic_ms += s.symbolic_ms;
                stats.factorization_ms += s.factorization_ms;
                stats.solve_ms += s.solve_ms;
                stats.relative_residual = s.relative_residual;
                stats.factorizations = 1;
                stats.assembly_ms = self.assembly_ms;
                self.factored = true;
                u = solution.displacement;
                solution.reaction
            } else {
                // Later keyframes: substitutions with the kept factor.
                let t = Instant::now();
                let ku = k.mul(&u);
                let rhs: Vec<f64> = sub.partition.free.iter().map(|&d| -ku[d]).collect();
                let mut x = rhs.clone();
                self.solver.solve_factored(&mut x, 1).map_err(solve_error)?;
                for (e, &d) in sub.partition.free.iter().enumerate() {
                    u[d] = x[e];
                }
                let ku = k.mul(&u);
                let residual: f64 = sub.partition.free.iter().map(|&d| ku[d] * ku[d]).sum();
                let reference: f64 = rhs.iter().map(|v| v * v).sum();
                stats.relative_residual = if reference > 0.0 {
                    (residual / reference).sqrt()
                } else {
                    residual.sqrt()
                };
                if u.iter().chain(&ku).any(|v| !v.is_finite()) {
                    return Err(solve_error(SolveError::NonFinite(
                        "the linear tier's displacement",
                    )));
                }
                stats.solve_ms += ms(t);
                ku
            };
            for (i, &n) in sub.nodes.iter().enumerate() {
                let ui = Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]);
                if sub.partition.prescribed[3 * i] {
                    // Equation (8): R_u = K21·u_u + K22·u_k, no external load on the flesh.
                    reaction[n] = Vector3::new(ku[3 * i], ku[3 * i + 1], ku[3 * i + 2]);
                } else {
                    next[n] = rest[n] + ui;
                }
            }
            // One solve, no step to halve: a cell turned inside out is an error naming it.
            for (local, cell) in sub.mesh.cells.iter().enumerate() {
                let q = relative_min_jacobian(&cell.map(|i| next[sub.nodes[i]]));
                if q <= 0.0 || q.is_nan() {
                    return Err(self.inverted(hand, sub.cells[local], target));
                }
            }
        }
        state.positions = next;
        state.reaction = reaction;
        state.transforms = transforms;
        state.angles = target.to_vec();
        stats.total_ms = ms(t_all);
        Ok(stats)
    }
}

impl LinearFactor {
    /// The error for hand cell `cell` turned inside out at the pose `target`, naming the moved
    /// joint nearest to it (rest geometry).
    fn inverted(&self, hand: &HandModel, cell: usize, target: &[f64]) -> SimError {
        let rest = &hand.flesh.mesh.nodes;
        let at = hand.flesh.mesh.cells[cell]
            .iter()
            .map(|&n| rest[n])
            .sum::<Vector3<f64>>()
            / 8.0;
        let rest_angles = hand.skeleton.rest_angles();
        let (joint, angle) = hand
            .skeleton
            .dofs
            .iter()
            .enumerate()
            .filter(|(i, _)| target[*i] != rest_angles[*i])
            .min_by(|a, b| {
                (a.1.center - at)
                    .norm()
                    .total_cmp(&(b.1.center - at).norm())
            })
            .map(|(i, d)| (d.name.clone(), target[i]))
            .unwrap_or_default();
        SimError::LinearTierInverted {
            body: self.body.clone(),
            element: cell,
            rest_position_mm: [at.x * 1e3, at.y * 1e3, at.z * 1e3],
            joint,
            angle,
        }
    }
}
