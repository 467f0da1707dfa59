//! The hexahedron with incompatible modes (Wilson, Taylor, Doherty & Ghaboussi 1973), with
//! Taylor's correction that makes it pass the patch test (Taylor, Beresford & Wilson 1976, the
//! "QM6" element; see also Hughes, *The Finite Element Method*, §4.7).
//!
//! The trilinear field is enriched, inside each element only, by the three bubble modes
//! P_k = 1 − ξ_k² per displacement component: u = Σ_a N_a u_a + Σ_k P_k α_k. They supply the
//! quadratic displacement of pure bending that the trilinear hexahedron lacks, and which it
//! otherwise fakes with parasitic shear (shear locking). The modes are discontinuous between
//! elements, so their gradients are evaluated with the Jacobian J₀ at the element centre,
//!
//! ∇P_k(ξ) = (det J₀ / det J(ξ)) J₀⁻ᵀ ∂P_k/∂ξ,
//!
//! which makes ∫_Ve ∇P_k dV = det J₀ J₀⁻ᵀ Σ_g ∂P_k/∂ξ(ξ_g) = 0 for every element shape: a
//! constant strain field is then reproduced with α = 0 (the patch test). The nine internal
//! unknowns are condensed out statically, K = K_uu − K_uα K_αα⁻¹ K_αu, so the element plugs into
//! the same assembly and solver as the standard one.

use super::hex8::{
    element_stiffness as hex8_stiffness, jacobian, mapped_points, relative_min_jacobian,
    shape_derivatives, ElementStiffness, InvertedCell, GAUSS_POINTS,
};
use super::material::Material;
use nalgebra::{Matrix3, SMatrix, Vector3};

type Coupling = SMatrix<f64, 24, 9>;
type Internal = SMatrix<f64, 9, 9>;
/// At one Gauss point, the physical gradients of the eight nodal shape functions and of the three
/// incompatible modes.
type PointGradients = ([Vector3<f64>; 8], [Vector3<f64>; 3]);

/// The block ∂f_a/∂u_b of ∫ Bᵀ D B for gradients g_a, g_b of an isotropic material:
/// λ g_a g_bᵀ + μ g_b g_aᵀ + μ (g_a·g_b) I.
fn pair(ga: &Vector3<f64>, gb: &Vector3<f64>, lambda: f64, mu: f64) -> Matrix3<f64> {
    ga * gb.transpose() * lambda
        + gb * ga.transpose() * mu
        + Matrix3::identity() * (mu * ga.dot(gb))
}

/// The pieces of the element before condensation.
struct Parts {
    /// ∫ Bᵀ D B_α, 24 × 9 (dof 3a+i, mode 3k+j).
    coupling: Coupling,
    /// ∫ B_αᵀ D B_α, 9 × 9.
    internal: Internal,
    /// Per Gauss point: physical gradients of the nodal shape functions and of the three modes.
    gradients: [PointGradients; 8],
}

fn parts(coords: &[Vector3<f64>; 8], material: &Material) -> Result<Parts, InvertedCell> {
    let points = mapped_points(coords)?;
    let j0 = jacobian(coords, &shape_derivatives(&Vector3::zeros()));
    let det0 = j0.determinant();
    let inv0_t = match j0.try_inverse() {
        Some(inv) if det0 > 0.0 => inv.transpose(),
        _ => {
            return Err(InvertedCell {
                relative_det: relative_min_jacobian(coords),
            })
        }
    };
    let (lambda, mu) = (material.lambda(), material.mu());
    let mut coupling = Coupling::zeros();
    let mut internal = Internal::zeros();
    let mut gradients = [([Vector3::zeros(); 8], [Vector3::zeros(); 3]); 8];
    for (g, p) in points.iter().enumerate() {
        let xi = GAUSS_POINTS[g];
        // ∂P_k/∂ξ = −2ξ_k e_k, mapped with Taylor's centre Jacobian.
        let modes: [Vector3<f64>; 3] = std::array::from_fn(|k| {
            let mut d = Vector3::zeros();
            d[k] = -2.0 * xi[k];
            inv0_t * d * (det0 / p.volume)
        });
        for a in 0..8 {
            for k in 0..3 {
                let block = pair(&p.gradients[a], &modes[k], lambda, mu) * p.volume;
                let mut view = coupling.fixed_view_mut::<3, 3>(3 * a, 3 * k);
                view += block;
            }
        }
        for k in 0..3 {
            for l in 0..3 {
                let block = pair(&modes[k], &modes[l], lambda, mu) * p.volume;
                let mut view = internal.fixed_view_mut::<3, 3>(3 * k, 3 * l);
                view += block;
            }
        }
        gradients[g] = (p.gradients, modes);
    }
    Ok(Parts {
        coupling,
        internal,
        gradients,
    })
}

/// Condensed element stiffness K_uu − K_uα K_αα⁻¹ K_αu of the incompatible-modes hexahedron.
pub fn element_stiffness(
    coords: &[Vector3<f64>; 8],
    material: &Material,
) -> Result<ElementStiffness, InvertedCell> {
    let mut k = hex8_stiffness(coords, material)?;
    let p = parts(coords, material)?;
    let inverted = || InvertedCell {
        relative_det: relative_min_jacobian(coords),
    };
    let chol = p.internal.cholesky().ok_or_else(inverted)?;
    let x = chol.solve(&p.coupling.transpose()); // K_αα⁻¹ K_αu, 9 × 24
    let correction = p.coupling * x;
    for a in 0..8 {
        for b in 0..8 {
            k[a][b] -= correction.fixed_view::<3, 3>(3 * a, 3 * b);
        }
    }
    // Restore exact symmetry lost to round-off in the condensation.
    for a in 0..8 {
        for b in a..8 {
            let s = (k[a][b] + k[b][a].transpose()) * 0.5;
            k[a][b] = s;
            k[b][a] = s.transpose();
        }
    }
    Ok(k)
}

/// Small strain at the Gauss points including the incompatible modes, whose amplitudes are
/// recovered from the nodal displacements `u`: α = −K_αα⁻¹ K_αu u.
pub fn gauss_strains(
    coords: &[Vector3<f64>; 8],
    u: &[Vector3<f64>; 8],
    material: &Material,
) -> Result<[Matrix3<f64>; 8], InvertedCell> {
    let p = parts(coords, material)?;
    let chol = p.internal.cholesky().ok_or(InvertedCell {
        relative_det: relative_min_jacobian(coords),
    })?;
    let ue = SMatrix::<f64, 24, 1>::from_fn(|r, _| u[r / 3][r % 3]);
    let alpha = -chol.solve(&(p.coupling.transpose() * ue));
    Ok(p.gradients.map(|(nodal, modes)| {
        let mut grad = Matrix3::zeros();
        for a in 0..8 {
            grad += u[a] * nodal[a].transpose();
        }
        for k in 0..3 {
            let ak = Vector3::new(alpha[3 * k], alpha[3 * k + 1], alpha[3 * k + 2]);
            grad += ak * modes[k].transpose();
        }
        (grad + grad.transpose()) * 0.5
    }))
}
