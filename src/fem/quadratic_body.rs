//! A linear increment's elastic energy as a body Newton can lower (`fem::newton`): the paper's
//! small-strain increment, or a corotated one, is the minimum of
//!
//!   W(u) = ½ (u − u₀)ᵀ K (u − u₀) + f₀ᵀ (u − u₀)
//!
//! over the displacements u from the mesh's reference positions, u₀ where the increment starts
//! and f₀ = ∂W/∂u there (K·x₀ − R for a corotated increment K·x = R in positions x). Alone its
//! minimum is equations (7)–(8) on K, one Newton step; with an energy added (the skin's barrier
//! against itself, `fem::added_energy`) Newton lowers their sum. Measured from u₀, not from the
//! reference, so that the line search compares energies that differ by far less than K·x·x.
//! A state where a cell turns inside out (its smallest det J ≤ 0) is not admissible.

use super::assembly::Stiffness;
use super::elastic_energy::ElasticEnergy;
use super::hex8::relative_min_jacobian;
use super::hyperelastic_body::InvertedElement;
use crate::mesh::Mesh;
use nalgebra::Vector3;
use rayon::prelude::*;

/// The quadratic energy of one linear increment on a mesh.
pub struct QuadraticBody<'a> {
    k: &'a Stiffness,
    mesh: &'a Mesh,
    start: Vec<f64>,
    force: Vec<f64>,
}

impl<'a> QuadraticBody<'a> {
    /// The energy with stiffness `k` on `mesh` (u from its node positions), about `start` (u₀),
    /// where its gradient is `force` (f₀, N).
    pub fn new(k: &'a Stiffness, mesh: &'a Mesh, start: Vec<f64>, force: Vec<f64>) -> Self {
        let dofs = 3 * mesh.node_count();
        assert_eq!(k.pattern.dofs, dofs);
        assert_eq!(start.len(), dofs);
        assert_eq!(force.len(), dofs);
        QuadraticBody {
            k,
            mesh,
            start,
            force,
        }
    }

    /// The first cell turned inside out at `u`, with its smallest relative det J.
    fn inverted(&self, u: &[f64]) -> Option<InvertedElement> {
        let at = |n: usize| self.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
        self.mesh
            .cells
            .par_iter()
            .enumerate()
            .filter_map(|(c, cell)| {
                let q = relative_min_jacobian(&cell.map(at));
                (q <= 0.0).then_some(InvertedElement { cell: c, det_f: q })
            })
            .min_by_key(|e| e.cell)
    }
}

impl ElasticEnergy for QuadraticBody<'_> {
    fn internal_forces(&self, u: &[f64]) -> Result<(f64, Vec<f64>), InvertedElement> {
        if let Some(e) = self.inverted(u) {
            return Err(e);
        }
        let du: Vec<f64> = u.iter().zip(&self.start).map(|(a, b)| a - b).collect();
        let mut f = self.k.mul(&du);
        let elastic: f64 = 0.5 * f.iter().zip(&du).map(|(a, b)| a * b).sum::<f64>();
        let linear: f64 = self.force.iter().zip(&du).map(|(a, b)| a * b).sum();
        for (f, f0) in f.iter_mut().zip(&self.force) {
            *f += f0;
        }
        Ok((elastic + linear, f))
    }

    fn tangent(&self, _u: &[f64]) -> Result<Stiffness, InvertedElement> {
        Ok(self.k.clone())
    }

    fn tangent_without_pressure_hessian(&self, u: &[f64]) -> Result<Stiffness, InvertedElement> {
        self.tangent(u)
    }

    fn mesh(&self) -> &Mesh {
        self.mesh
    }

    fn element_size(&self) -> f64 {
        let volume: f64 = (0..self.mesh.cell_count())
            .map(|c| {
                let x = self.mesh.cell_coords(c);
                let (lo, hi) = x
                    .iter()
                    .fold((x[0], x[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
                (hi - lo).product()
            })
            .sum();
        (volume / self.mesh.cell_count().max(1) as f64).cbrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::added_energy::{AddedEnergy, NodeBlock};
    use crate::fem::assembly::{assemble, StiffnessPattern};
    use crate::fem::newton::{solve_increment_with, NewtonSettings};
    use crate::fem::solve::FillOrdering;
    use crate::fem::{DofPartition, Material, PartitionedSolver};
    use crate::mesh::box_mesh;
    use nalgebra::DMatrix;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;

    /// A hill under each of some dofs: h(u) = A·exp(−u²/(2σ²)), whose curvature is negative
    /// within σ of its top (u = 0, where the increment starts).
    /// Beyond `wall` (if any) no state is admissible: its energy is not finite, a step is cut
    /// at 0.8 of the way to it (as continuous collision cuts one), and `past_wall` tells
    /// whether a state beyond it was ever evaluated.
    struct Hills {
        dofs: Vec<usize>,
        height: f64,
        width: f64,
        wall: Option<f64>,
        past_wall: AtomicBool,
    }

    impl Hills {
        fn at(&self, u: f64) -> (f64, f64, f64) {
            let s2 = self.width * self.width;
            let h = self.height * (-u * u / (2.0 * s2)).exp();
            (h, -u / s2 * h, (u * u / s2 - 1.0) / s2 * h)
        }
    }

    impl AddedEnergy for Hills {
        fn energy(&self, u: &[f64], gradient: &mut [f64]) -> Option<f64> {
            if let Some(wall) = self.wall {
                if self.dofs.iter().any(|&d| u[d] >= wall) {
                    self.past_wall.store(true, Ordering::Relaxed);
                    return None;
                }
            }
            let mut e = 0.0;
            for &d in &self.dofs {
                let (h, g, _) = self.at(u[d]);
                e += h;
                gradient[d] += g;
            }
            Some(e)
        }

        fn hessian(&self, u: &[f64], projected: bool) -> Vec<NodeBlock> {
            self.dofs
                .iter()
                .map(|&d| {
                    let (_, _, c) = self.at(u[d]);
                    let mut matrix = DMatrix::zeros(3, 3);
                    matrix[(d % 3, d % 3)] = if projected { c.max(0.0) } else { c };
                    NodeBlock {
                        nodes: vec![d / 3],
                        matrix,
                    }
                })
                .collect()
        }

        fn largest_step(&self, u: &[f64], du: &[f64]) -> f64 {
            let Some(wall) = self.wall else {
                return 1.0;
            };
            let first = self
                .dofs
                .iter()
                .filter(|&&d| u[d] + du[d] >= wall)
                .map(|&d| (wall - u[d]) / du[d])
                .fold(1.0, f64::min);
            if first >= 1.0 {
                1.0
            } else {
                0.8 * first
            }
        }
    }

    /// A bar clamped at x = 0, its free end's nodes pushed along x by a small load off the top
    /// of hills steeper than the bar is stiff: from the top the tangent (the bar's plus the
    /// hills' curvature) is indefinite, the hills' projected curvature (0) is used, and each
    /// Newton step is the bar's alone — far too short down the hills. Lengthened while the
    /// potential keeps falling, Newton reaches the same equilibrium in fewer iterations (6
    /// against 21; at most half asserted).
    #[test]
    fn longer_steps_down_a_negative_curvature_reach_the_same_equilibrium_sooner() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(4.0, 1.0, 1.0), [4, 1, 1]);
        let material = Material {
            young: 1.0e3,
            poisson: 0.3,
            density: 1.0,
        };
        let materials = vec![material; mesh.cells.len()];
        let k = assemble(&Arc::new(StiffnessPattern::new(&mesh)), &mesh, &materials).unwrap();
        let dofs = 3 * mesh.node_count();
        let clamped = |n: usize| mesh.nodes[n].x == 0.0;
        let partition = DofPartition::new((0..dofs).map(|d| clamped(d / 3)).collect());
        let end: Vec<usize> = (0..mesh.node_count())
            .filter(|&n| mesh.nodes[n].x == 4.0)
            .map(|n| 3 * n)
            .collect();
        // The bar's axial stiffness per end node: E·A/L over four nodes, 62.5 N/m.
        let per_node = material.young * 1.0 / 4.0 / 4.0;
        let width = 0.05;
        // The hills' largest negative curvature, A/σ², over the bar's k.
        const STEEP: f64 = 1.5;
        let hills = |wall: Option<f64>| Hills {
            dofs: end.clone(),
            height: STEEP * per_node * width * width,
            width,
            wall,
            past_wall: AtomicBool::new(false),
        };
        let mut loads = vec![0.0; dofs];
        for &d in &end {
            loads[d] = 1e-3 * per_node * width;
        }
        let body = QuadraticBody::new(&k, &mesh, vec![0.0; dofs], vec![0.0; dofs]);
        let zeros = vec![0.0; dofs];
        let solve = |expand: bool, hills: &Hills| {
            let settings = NewtonSettings {
                escape_saddles: false,
                expand_steps: expand,
                ..NewtonSettings::descent(200, FillOrdering::Auto)
            };
            let mut solver = PartitionedSolver::new(FillOrdering::Auto);
            let outcome = solve_increment_with(
                &body,
                (&partition, &zeros, &zeros, &loads),
                Some(hills as &dyn AddedEnergy),
                &settings,
                &mut solver,
            );
            let u = outcome.result.expect("Newton converges");
            (u, outcome.record.iterations)
        };
        let (plain, plain_iterations) = solve(false, &hills(None));
        let (longer, longer_iterations) = solve(true, &hills(None));
        // Down the hills, where the bar's pull k·u balances their push A·u/σ²·exp(−u²/(2σ²)),
        // A/σ² = 1.5k: u = σ·√(2 ln 1.5) ≈ 0.90 σ (k the bar's stiffness per node, the end's
        // nodes moving together; the load a thousandth of kσ).
        let reached = plain[end[0]];
        let balance = width * (2.0 * STEEP.ln()).sqrt();
        assert!(
            (reached / balance - 1.0).abs() < 0.05,
            "{reached} against {balance}"
        );
        // The same equilibrium as the plain steps', to 10⁻⁹ of the move.
        let same = |other: &[f64]| {
            let difference = plain
                .iter()
                .zip(other)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(difference < 1e-9 * reached, "{difference} of {reached}");
        };
        same(&longer);
        assert!(
            2 * longer_iterations <= plain_iterations,
            "{longer_iterations} against {plain_iterations} iterations"
        );
        // A wall a little past the equilibrium: the longer steps stop short of it (no state
        // beyond it is ever evaluated) and reach the same equilibrium.
        let walled = hills(Some(1.2 * balance));
        let (held, held_iterations) = solve(true, &walled);
        assert!(!walled.past_wall.load(Ordering::Relaxed));
        same(&held);
        eprintln!(
            "iterations: {plain_iterations} plain, {longer_iterations} with longer steps, \
             {held_iterations} with them before a wall"
        );
    }
}
