//! What Newton (`fem::newton`) needs of a body: its stored energy, internal forces and tangent
//! at a displacement, the mesh they live on. The Neo-Hookean body (`hyperelastic_body`) is one;
//! a linear increment's quadratic energy (`quadratic_body`: the corotated flexion increment,
//! lowered together with the skin's self-contact barrier) is another.

use super::assembly::Stiffness;
use super::hyperelastic_body::{HyperelasticBody, InvertedElement};
use crate::mesh::Mesh;

/// A body's elastic energy W(u) over the displacements u of its mesh's nodes (3 per node, m).
pub trait ElasticEnergy: Sync {
    /// W(u), J, and the internal forces ∂W/∂u, N; the cell that turns inside out at `u`, if
    /// one does.
    fn internal_forces(&self, u: &[f64]) -> Result<(f64, Vec<f64>), InvertedElement>;

    /// The tangent ∂²W/∂u² at `u`.
    fn tangent(&self, u: &[f64]) -> Result<Stiffness, InvertedElement>;

    /// A tangent more likely positive definite than [`ElasticEnergy::tangent`] where that one
    /// is not (the Neo-Hookean body's without its pressure's Hessian); the tangent itself
    /// where it has nothing to leave out.
    fn tangent_without_pressure_hessian(&self, u: &[f64]) -> Result<Stiffness, InvertedElement>;

    /// A tangent positive semi-definite element by element (the Neo-Hookean body's with each
    /// element's negative eigenvalues turned positive, `fem::definite`): positive definite
    /// wherever the prescribed nodes hold the body. `None` where the body has none other than
    /// its tangent (a linear increment's quadratic energy, whose tangent is its stiffness).
    fn tangent_definite(&self, _u: &[f64]) -> Option<Result<Stiffness, InvertedElement>> {
        None
    }

    /// The mesh (its node positions the reference configuration u is measured from).
    fn mesh(&self) -> &Mesh;

    /// The mean element size, m.
    fn element_size(&self) -> f64;
}

impl ElasticEnergy for HyperelasticBody<'_> {
    fn internal_forces(&self, u: &[f64]) -> Result<(f64, Vec<f64>), InvertedElement> {
        HyperelasticBody::internal_forces(self, u)
    }

    fn tangent(&self, u: &[f64]) -> Result<Stiffness, InvertedElement> {
        HyperelasticBody::tangent(self, u)
    }

    fn tangent_without_pressure_hessian(&self, u: &[f64]) -> Result<Stiffness, InvertedElement> {
        HyperelasticBody::tangent_without_pressure_hessian(self, u)
    }

    fn tangent_definite(&self, u: &[f64]) -> Option<Result<Stiffness, InvertedElement>> {
        Some(HyperelasticBody::tangent_definite(self, u))
    }

    fn mesh(&self) -> &Mesh {
        HyperelasticBody::mesh(self)
    }

    fn element_size(&self) -> f64 {
        HyperelasticBody::element_size(self)
    }
}
