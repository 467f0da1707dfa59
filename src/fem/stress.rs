//! Cauchy stress (small strain: σ = λ tr(ε) I + 2μ ε) at the Gauss points, extrapolated to the
//! corners of each cell and averaged at the nodes, and the von Mises equivalent stress.

use super::assembly::ElementKind;
use super::hex8::{gauss_biot_strains, gauss_strains, shape, InvertedCell, NODE_SIGNS};
use super::incompatible;
use super::material::Material;
use crate::mesh::Mesh;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Cauchy stress from small strain for an isotropic material.
pub fn cauchy_stress(strain: &Matrix3<f64>, material: &Material) -> Matrix3<f64> {
    Matrix3::identity() * (material.lambda() * strain.trace()) + strain * (2.0 * material.mu())
}

/// Von Mises equivalent stress √(3/2 s:s), with s the deviatoric part of σ.
pub fn von_mises(sigma: &Matrix3<f64>) -> f64 {
    let dev = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
    (1.5 * dev.component_mul(&dev).sum()).max(0.0).sqrt()
}

/// Stresses of a solved displacement field (empty by default: none computed).
#[derive(Clone, Debug, Default)]
pub struct StressField {
    /// Per cell, the stress at its eight Gauss points.
    pub gauss: Vec<[Matrix3<f64>; 8]>,
    /// Per node, the average of the corner values extrapolated from the Gauss points of every
    /// cell that uses the node.
    pub nodal: Vec<Matrix3<f64>>,
    /// Per cell, the von Mises stress of the mean Gauss-point stress.
    pub cell_von_mises: Vec<f64>,
}

/// Computes the stresses of displacement `u` (3 per node) on `mesh`.
pub fn stress_field(
    mesh: &Mesh,
    materials: &[Material],
    u: &[f64],
) -> Result<StressField, (usize, InvertedCell)> {
    stress_field_with(mesh, materials, u, &|_| false)
}

/// As [`stress_field`], with the rotation-free (Biot) strain in the cells where `rotated(c)`
/// holds (cells that turn through large angles, such as the flesh of a flexed finger).
pub fn stress_field_with(
    mesh: &Mesh,
    materials: &[Material],
    u: &[f64],
    rotated: &(dyn Fn(usize) -> bool + Sync),
) -> Result<StressField, (usize, InvertedCell)> {
    stress_field_except(mesh, materials, u, rotated, &|_| false)
}

/// As [`stress_field_with`], with no stress in the cells where `unsolved(c)` holds (flesh that
/// only follows its bones by skinning: geometry, no mechanics; skinning may even fold a cell
/// over at a crease).
pub fn stress_field_except(
    mesh: &Mesh,
    materials: &[Material],
    u: &[f64],
    rotated: &(dyn Fn(usize) -> bool + Sync),
    unsolved: &(dyn Fn(usize) -> bool + Sync),
) -> Result<StressField, (usize, InvertedCell)> {
    let gauss: Vec<[Matrix3<f64>; 8]> = (0..mesh.cell_count())
        .into_par_iter()
        .map(|c| {
            if unsolved(c) {
                return Ok([Matrix3::zeros(); 8]);
            }
            let ue = mesh.cells[c].map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]));
            let strains = if rotated(c) {
                gauss_biot_strains(&mesh.cell_coords(c), &ue)
            } else {
                gauss_strains(&mesh.cell_coords(c), &ue)
            }
            .map_err(|e| (c, e))?;
            Ok(strains.map(|e| cauchy_stress(&e, &materials[c])))
        })
        .collect::<Result<_, _>>()?;
    Ok(from_gauss(mesh, gauss))
}

/// Small-strain stresses of `u` computed with the strains of the element `kind` (with
/// [`ElementKind::IncompatibleModes`], including the recovered internal modes).
pub fn stress_field_kind(
    mesh: &Mesh,
    materials: &[Material],
    u: &[f64],
    kind: ElementKind,
) -> Result<StressField, (usize, InvertedCell)> {
    if kind == ElementKind::Hex8 {
        return stress_field(mesh, materials, u);
    }
    let gauss: Vec<[Matrix3<f64>; 8]> = (0..mesh.cell_count())
        .into_par_iter()
        .map(|c| {
            let ue = mesh.cells[c].map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]));
            let strains = incompatible::gauss_strains(&mesh.cell_coords(c), &ue, &materials[c])
                .map_err(|e| (c, e))?;
            Ok(strains.map(|e| cauchy_stress(&e, &materials[c])))
        })
        .collect::<Result<_, _>>()?;
    Ok(from_gauss(mesh, gauss))
}

/// The field of given Gauss-point stresses (any constitutive law, e.g. the Cauchy stress of the
/// nonlinear tier): extrapolated to the corners, averaged at the nodes, von Mises per cell.
pub fn from_gauss(mesh: &Mesh, gauss: Vec<[Matrix3<f64>; 8]>) -> StressField {
    // Corner a sits at √3·NODE_SIGNS[a] in the coordinates of the Gauss-point lattice.
    let s3 = 3f64.sqrt();
    let extrapolate: [[f64; 8]; 8] =
        NODE_SIGNS.map(|p| shape(&Vector3::new(p[0] * s3, p[1] * s3, p[2] * s3)));
    let mut nodal = vec![Matrix3::zeros(); mesh.node_count()];
    let mut count = vec![0u32; mesh.node_count()];
    for (c, cell) in mesh.cells.iter().enumerate() {
        for a in 0..8 {
            let mut s = Matrix3::zeros();
            for g in 0..8 {
                s += gauss[c][g] * extrapolate[a][g];
            }
            nodal[cell[a]] += s;
            count[cell[a]] += 1;
        }
    }
    for (s, &k) in nodal.iter_mut().zip(&count) {
        if k > 0 {
            *s /= k as f64;
        }
    }
    let cell_von_mises = gauss
        .iter()
        .map(|g| von_mises(&(g.iter().sum::<Matrix3<f64>>() / 8.0)))
        .collect();
    StressField {
        gauss,
        nodal,
        cell_von_mises,
    }
}
