//! The other bodies of a contact step as Neo-Hookean solids (issue 15, item 2), with
//! `[solver] tier = "nonlinear"`: a power grasp squashes a soft ball by a third of its radius,
//! where even a corotated linear element (`corotated.rs`) keeps a small-strain law. Each contact
//! step linearises the bodies about the displacements U_c the last step left (total
//! Lagrangian, from their rest geometry): the tangent K_T(U_c) = ∂²W/∂U² of the Neo-Hookean
//! hexahedra (`fem::hex8_hyperelastic`) and the internal force f(U_c) = ∂W/∂U, so the step
//! solves K_T·ΔU = R(x_c) − f(U_c) + Cᵀλ — one Newton iteration of the bodies per step. The
//! corrections at the pose (`Workspace::correct`: contact steps without motion until the force
//! settles) are the further Newton iterations of the last pose, so a corrected frame is the
//! Neo-Hookean equilibrium with its contact. The air acts on the wall where it is now (a
//! follower load, as in the corotational tier); in a step without motion to follow (a
//! correction) the symmetric part of its load stiffness −∂(pressure load)/∂x joins the
//! tangent (`pressure_stiffness`), as the corotational tier's does: without it the inflated
//! wall's tension was missing from the Newton step and the Power grasp's corrections wandered
//! (7.8 % apart after nine). The hands' flesh keeps its linear stiffness on the pose that
//! flexion gave it (its own nonlinear solve is the flexion's).

use super::corotated::{add_pressure_stiffness, Linearised};
use crate::fem::assembly::{assemble_elements, AssemblyError};
use crate::fem::definite::absolute_eigenvalues;
use crate::fem::hex8::{element_stiffness, mapped_points, InvertedCell};
use crate::fem::hex8_hyperelastic::{element_state_with, gauss_cauchy_stress, Tangent};
use crate::fem::hyperelastic::NeoHookean;
use crate::fem::stress::{from_gauss, StressField};
use crate::mesh::Mesh;
use crate::model::{FlexionScheme, Model};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Whether the contact steps of `model` take its other bodies as Neo-Hookean solids.
pub(super) fn neo_hookean_objects(model: &Model) -> bool {
    model.flexion.scheme == FlexionScheme::Nonlinear
}

/// An element whose det F fell to zero or below, told as an inverted cell (its det F in place
/// of the relative det J).
fn inverted(cell: usize, det_f: f64) -> AssemblyError {
    AssemblyError {
        cell,
        inverted: InvertedCell {
            relative_det: det_f,
        },
    }
}

/// The displacements of the nodes of cell `c` from `u` (zero without `u`).
fn cell_displacements(mesh: &Mesh, c: usize, u: Option<&[f64]>) -> [Vector3<f64>; 8] {
    mesh.cells[c].map(|n| match u {
        Some(u) => Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]),
        None => Vector3::zeros(),
    })
}

/// K and f(U_c) − K·U_c for a contact step of `model` on `mesh` (the hands posed, the other
/// bodies at rest): the other bodies' Neo-Hookean tangent and internal force at `carried`
/// (at rest without), the hands' linear stiffness on their pose (no offset). Each element
/// hands the assembly b_e = K_e·(X_e + U_e) − f_e, so that K·X − b = f(U_c) − K·U_c.
/// `definite`: each Neo-Hookean element's tangent with its negative eigenvalues turned
/// positive (`fem::definite`), for a step from a state where the exact one is indefinite.
/// `pressure_stiffness`: the pressures' load stiffness at `carried` joins the tangent (the
/// offset keeping f(U_c)), for a step without motion to follow.
pub(super) fn linearise_neo_hookean(
    model: &Model,
    mesh: &Mesh,
    carried: Option<&[f64]>,
    definite: bool,
    pressure_stiffness: bool,
) -> Result<Linearised, AssemblyError> {
    let volumetric = model.flexion.volumetric;
    let (mut k, b) = assemble_elements(&model.pattern, mesh, true, &|c| {
        let coords = mesh.cell_coords(c);
        let material = &model.cell_materials[c];
        if model.bodies[model.cell_body[c]].hand.is_some() {
            let ke = element_stiffness(&coords, material)
                .map_err(|inverted| AssemblyError { cell: c, inverted })?;
            let b = std::array::from_fn(|a| (0..8).map(|j| ke[a][j] * coords[j]).sum());
            return Ok((ke, Some(b)));
        }
        let reference =
            mapped_points(&coords).map_err(|inverted| AssemblyError { cell: c, inverted })?;
        let u = cell_displacements(mesh, c, carried);
        let law = NeoHookean::from_material(material);
        let state = element_state_with(&reference, &u, &law, volumetric, Tangent::Exact)
            .map_err(|e| inverted(c, e.det_f))?;
        let exact = state.tangent.expect("asked for");
        // The step's matrix; the offset keeps the exact internal forces either way.
        let ke = if definite {
            absolute_eigenvalues(&exact)
        } else {
            exact
        };
        let b = std::array::from_fn(|a| {
            (0..8)
                .map(|j| ke[a][j] * (coords[j] + u[j]))
                .sum::<Vector3<f64>>()
                - state.force[a]
        });
        Ok((ke, Some(b)))
    })?;
    let b = b.expect("asked for");
    let x: Vec<f64> = mesh.nodes.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    let mut offset: Vec<f64> = k.mul(&x).iter().zip(&b).map(|(a, b)| a - b).collect();
    if let (true, Some(u)) = (pressure_stiffness, carried) {
        add_pressure_stiffness(model, mesh, u, &mut k, &mut offset);
    }
    Ok(Linearised {
        k,
        offset: Some(offset),
    })
}

/// `field` (the frame's stresses) with the other bodies' cells given their Neo-Hookean Cauchy
/// stress at the displacements `u` from rest.
pub(super) fn with_neo_hookean_stress(
    model: &Model,
    field: StressField,
    u: &[f64],
) -> Result<StressField, (usize, f64)> {
    let mesh = &model.mesh;
    let volumetric = model.flexion.volumetric;
    let mut gauss = field.gauss;
    let objects: Vec<(usize, [Matrix3<f64>; 8])> = (0..mesh.cell_count())
        .into_par_iter()
        .filter(|&c| model.bodies[model.cell_body[c]].hand.is_none())
        .map(|c| {
            let reference = mapped_points(&mesh.cell_coords(c)).map_err(|e| (c, e.relative_det))?;
            let law = NeoHookean::from_material(&model.cell_materials[c]);
            let ue = cell_displacements(mesh, c, Some(u));
            gauss_cauchy_stress(&reference, &ue, &law, volumetric)
                .map(|s| (c, s))
                .map_err(|e| (c, e.det_f))
        })
        .collect::<Result<_, _>>()?;
    for (c, s) in objects {
        gauss[c] = s;
    }
    Ok(from_gauss(mesh, gauss))
}
