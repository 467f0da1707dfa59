//! A mesh of Neo-Hookean hexahedra as one hyperelastic body: total stored energy W(u), internal
//! forces ∂W/∂u and tangent ∂²W/∂u² at any displacement from the reference configuration, and
//! the Cauchy stress. This is what the Newton solver iterates on; it takes any mesh and any
//! current positions, so it can drive other bodies (the hand's flesh, with bone nodes
//! prescribed) as well.

use super::assembly::{assemble_elements, Stiffness, StiffnessPattern};
use super::hex8::{mapped_points, ElementStiffness, MappedPoint};
use super::hex8_hyperelastic::{
    element_state, element_state_with, gauss_cauchy_stress, ElementInverted, Tangent, Volumetric,
};
use super::hyperelastic::NeoHookean;
use super::material::Material;
use crate::mesh::Mesh;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use std::sync::{Arc, Mutex};

/// The most bytes of element tangents a body keeps from its last exact tangent for the
/// definite one at the same displacement (`HyperelasticBody::tangent_definite`): 128 MiB,
/// about 29 000 cells; a larger body computes them again.
const KEPT_TANGENTS_BYTES: usize = 128 << 20;

/// The element tangents of the last exact tangent and the displacement they were taken at.
struct KeptTangents {
    u: Vec<f64>,
    elements: Vec<ElementStiffness>,
}

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
    /// The element tangents of the last exact tangent, kept for a definite one asked for at
    /// the same displacement (Newton's ladder asks for it where the exact one does not
    /// factor): it then turns their negative eigenvalues instead of computing them again.
    kept: Mutex<Option<KeptTangents>>,
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
            kept: Mutex::new(None),
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
        // (The kept element tangents let go first: the states below take as much, and the
        // memory estimate of the nonlinear tier counts one of the two at a time.)
        *self.kept.lock().unwrap_or_else(|e| e.into_inner()) = None;
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

    /// The tangent stiffness ∂²W/∂u² at displacement `u`. Its element tangents are kept (up
    /// to [`KEPT_TANGENTS_BYTES`]) for [`HyperelasticBody::tangent_definite`] at the same `u`.
    pub fn tangent(&self, u: &[f64]) -> Result<Stiffness, InvertedElement> {
        let cells = self.mesh.cell_count();
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        *kept = None;
        if cells.saturating_mul(std::mem::size_of::<ElementStiffness>()) > KEPT_TANGENTS_BYTES {
            return self.tangent_of(u, Tangent::Exact);
        }
        let elements = (0..cells)
            .into_par_iter()
            .map(|c| self.element_tangent(c, u, Tangent::Exact))
            .collect::<Result<Vec<_>, _>>()?;
        let (k, _) = assemble_elements(&self.pattern, self.mesh, false, &|c| {
            Ok::<_, InvertedElement>((elements[c], None))
        })?;
        *kept = Some(KeptTangents {
            u: u.to_vec(),
            elements,
        });
        Ok(k)
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
        let kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        // The exact tangent's elements at this very displacement, bit for bit: turned.
        if let Some(kept) = kept.as_ref().filter(|k| same_bits(&k.u, u)) {
            let (k, _) = assemble_elements(&self.pattern, self.mesh, false, &|c| {
                Ok::<_, InvertedElement>((
                    super::definite::absolute_eigenvalues(&kept.elements[c]),
                    None,
                ))
            })?;
            return Ok(k);
        }
        drop(kept);
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
            let ke = self.element_tangent(c, u, kind)?;
            Ok((
                match definite {
                    true => super::definite::absolute_eigenvalues(&ke),
                    false => ke,
                },
                None,
            ))
        })
        .map(|(k, _)| k)
    }

    /// The tangent of cell `c` at displacement `u`.
    fn element_tangent(
        &self,
        c: usize,
        u: &[f64],
        kind: Tangent,
    ) -> Result<ElementStiffness, InvertedElement> {
        element_state_with(
            &self.reference[c],
            &self.displacements(c, u),
            &self.laws[c],
            self.volumetric,
            kind,
        )
        .map(|s| s.tangent.expect("asked for"))
        .map_err(Self::inverted(c))
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

/// Whether `a` and `b` hold the same values to the bit.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_mesh;

    /// A 2×2×2 block squeezed to `squeeze` of its height with a shear: its elements are in
    /// compression, so their tangents are indefinite (the rigid turns of a compressed element
    /// lower its energy).
    fn squeezed(mesh: &Mesh, squeeze: f64) -> Vec<f64> {
        mesh.nodes
            .iter()
            .flat_map(|p| [0.2 * p.z * p.z, 0.0, (squeeze - 1.0) * p.z])
            .collect()
    }

    #[test]
    fn the_definite_tangent_from_the_kept_elements_is_the_one_computed_again() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(0.01, 0.01, 0.01), [2, 2, 2]);
        let materials = vec![
            Material {
                young: 5.0e4,
                poisson: 0.45,
                density: 1000.0,
            };
            mesh.cell_count()
        ];
        let body = |mesh| HyperelasticBody::new(mesh, &materials, Volumetric::default()).unwrap();
        let (u, v) = (squeezed(&mesh, 0.6), squeezed(&mesh, 0.7));
        // Computed again: a body that kept nothing.
        let fresh = body(&mesh).tangent_definite(&u).unwrap();
        let kept = body(&mesh);
        let exact = kept.tangent(&u).unwrap();
        let from_kept = kept.tangent_definite(&u).unwrap();
        let bits = |k: &Stiffness| k.values.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&from_kept), bits(&fresh));
        // Not a tangent definite already: the elements were turned.
        let turned = exact
            .values
            .iter()
            .zip(&from_kept.values)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let largest = exact.values.iter().map(|x| x.abs()).fold(0.0, f64::max);
        assert!(turned > 1e-3 * largest, "{turned} of {largest}");
        // At another displacement the kept elements are not used.
        let at_v = kept.tangent_definite(&v).unwrap();
        let fresh_v = body(&mesh).tangent_definite(&v).unwrap();
        assert_eq!(at_v.values, fresh_v.values);
        assert_ne!(at_v.values, from_kept.values);
    }
}
