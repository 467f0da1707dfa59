//! A mesh of Neo-Hookean hexahedra as one hyperelastic body: total stored energy W(u), internal
//! forces ∂W/∂u and tangent ∂²W/∂u² at any displacement from the reference configuration, and
//! the Cauchy stress. This is what the Newton solver iterates on; it takes any mesh and any
//! current positions, so it can drive other bodies (the hand's flesh, with bone nodes
//! prescribed) as well.

use super::assembly::{assemble_elements, Stiffness, StiffnessPattern};
use super::hex8::{mapped_points, MappedPoint};
use super::hex8_hyperelastic::{
    element_state, element_state_with, gauss_cauchy_stress, ElementInverted, Tangent, Volumetric,
};
use super::hyperelastic::NeoHookean;
use super::material::Material;
use crate::mesh::Mesh;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use std::sync::Arc;

/// An element inverted (det F ≤ 0 at a Gauss point) at the positions evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InvertedElement {
    /// The cell.
    pub cell: usize,
    /// det F at its worst Gauss point.
    pub det_f: f64,
}

/// A cell that is inverted or flat in the reference configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InvertedReference {
    /// The cell.
    pub cell: usize,
    /// Its smallest relative det J.
    pub relative_det: f64,
}

/// The hyperelastic model of a mesh.
pub struct HyperelasticBody<'a> {
    mesh: &'a Mesh,
    laws: Vec<NeoHookean>,
    reference: Vec<[MappedPoint; 8]>,
    pattern: Arc<StiffnessPattern>,
    /// How the volumetric energy is integrated.
    pub volumetric: Volumetric,
}

impl<'a> HyperelasticBody<'a> {
    /// The body of `mesh` (its node positions are the reference configuration), with
    /// `materials[c]` turned into the Neo-Hookean law of cell c.
    pub fn new(
        mesh: &'a Mesh,
        materials: &[Material],
        volumetric: Volumetric,
    ) -> Result<Self, InvertedReference> {
        Self::with_pattern(
            mesh,
            materials,
            volumetric,
            Arc::new(StiffnessPattern::new(mesh)),
        )
    }

    /// As [`HyperelasticBody::new`], reusing the sparsity pattern of `mesh`.
    pub fn with_pattern(
        mesh: &'a Mesh,
        materials: &[Material],
        volumetric: Volumetric,
        pattern: Arc<StiffnessPattern>,
    ) -> Result<Self, InvertedReference> {
        assert_eq!(materials.len(), mesh.cell_count());
        assert_eq!(pattern.dofs, 3 * mesh.node_count());
        let reference = (0..mesh.cell_count())
            .into_par_iter()
            .map(|c| {
                mapped_points(&mesh.cell_coords(c)).map_err(|e| InvertedReference {
                    cell: c,
                    relative_det: e.relative_det,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            mesh,
            laws: materials.iter().map(NeoHookean::from_material).collect(),
            reference,
            pattern,
            volumetric,
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        self.mesh
    }

    /// The mean element size, (reference volume / cells)^⅓, m.
    pub fn element_size(&self) -> f64 {
        let volume: f64 = self.reference.iter().flatten().map(|p| p.volume).sum();
        (volume / self.reference.len().max(1) as f64).cbrt()
    }

    /// The sparsity pattern of the tangent.
    pub fn pattern(&self) -> &Arc<StiffnessPattern> {
        &self.pattern
    }

    /// Displacements of the nodes of cell `c` from `u` (3 per node).
    fn displacements(&self, c: usize, u: &[f64]) -> [Vector3<f64>; 8] {
        self.mesh.cells[c].map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
    }

    fn inverted(c: usize) -> impl Fn(ElementInverted) -> InvertedElement {
        move |e| InvertedElement {
            cell: c,
            det_f: e.det_f,
        }
    }

    /// Stored energy W(u), J, and internal forces ∂W/∂u, N (3 per node).
    pub fn internal_forces(&self, u: &[f64]) -> Result<(f64, Vec<f64>), InvertedElement> {
        let states = (0..self.mesh.cell_count())
            .into_par_iter()
            .map(|c| {
                element_state(
                    &self.reference[c],
                    &self.displacements(c, u),
                    &self.laws[c],
                    self.volumetric,
                    false,
                )
                .map_err(Self::inverted(c))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut f = vec![0.0; 3 * self.mesh.node_count()];
        let mut energy = 0.0;
        for (cell, s) in self.mesh.cells.iter().zip(&states) {
            energy += s.energy;
            for (a, &n) in cell.iter().enumerate() {
                for i in 0..3 {
                    f[3 * n + i] += s.force[a][i];
                }
            }
        }
        Ok((energy, f))
    }

    /// The tangent stiffness ∂²W/∂u² at displacement `u`.
    pub fn tangent(&self, u: &[f64]) -> Result<Stiffness, InvertedElement> {
        self.tangent_of(u, Tangent::Exact)
    }

    /// The tangent at displacement `u` without the pressure's Hessian
    /// ([`Tangent::WithoutPressureHessian`]).
    pub fn tangent_without_pressure_hessian(
        &self,
        u: &[f64],
    ) -> Result<Stiffness, InvertedElement> {
        self.tangent_of(u, Tangent::WithoutPressureHessian)
    }

    /// The tangent at displacement `u` with each element's negative eigenvalues turned
    /// positive ([`super::definite::absolute_eigenvalues`]): positive definite wherever the
    /// supports hold the body, for a Newton-like step where the exact tangent is not.
    pub fn tangent_definite(&self, u: &[f64]) -> Result<Stiffness, InvertedElement> {
        self.tangent_with(u, Tangent::Exact, true)
    }

    fn tangent_of(&self, u: &[f64], kind: Tangent) -> Result<Stiffness, InvertedElement> {
        self.tangent_with(u, kind, false)
    }

    fn tangent_with(
        &self,
        u: &[f64],
        kind: Tangent,
        definite: bool,
    ) -> Result<Stiffness, InvertedElement> {
        assemble_elements(&self.pattern, self.mesh, false, &|c| {
            element_state_with(
                &self.reference[c],
                &self.displacements(c, u),
                &self.laws[c],
                self.volumetric,
                kind,
            )
            .map(|s| {
                let ke = s.tangent.expect("asked for");
                let ke = if definite {
                    super::definite::absolute_eigenvalues(&ke)
                } else {
                    ke
                };
                (ke, None)
            })
            .map_err(Self::inverted(c))
        })
        .map(|(k, _)| k)
    }

    /// Cauchy stress at the Gauss points of every cell, Pa.
    pub fn cauchy_stress(&self, u: &[f64]) -> Result<Vec<[Matrix3<f64>; 8]>, InvertedElement> {
        (0..self.mesh.cell_count())
            .into_par_iter()
            .map(|c| {
                gauss_cauchy_stress(
                    &self.reference[c],
                    &self.displacements(c, u),
                    &self.laws[c],
                    self.volumetric,
                )
                .map_err(Self::inverted(c))
            })
            .collect()
    }
}
