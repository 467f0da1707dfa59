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
