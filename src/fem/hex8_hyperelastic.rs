//! The total Lagrangian 8-node hexahedron for the Neo-Hookean law of [`super::hyperelastic`]:
//! the element's stored energy, internal forces and consistent tangent at any current nodal
//! positions (Bonet & Wood, *Nonlinear Continuum Mechanics for FEA*, ch. 7–8).
//!
//! With reference gradients G_a = ∇_X N_a at the 2×2×2 Gauss points, F = Σ_a x_a ⊗ G_a and the
//! spatial gradients g_a = F⁻ᵀ G_a = ∇_x N_a:
//!
//! - internal force f_a = ∫_V τ g_a dV, τ = J σ the Kirchhoff stress;
//! - tangent K_ab = ∫_V [g_a·(J𝕔)·g_b + (g_a·τ g_b) I] dV, material plus geometric (initial
//!   stress) parts, the exact Hessian of the element energy, hence symmetric.
//!
//! Volumetric locking. Integrating U(J) at the eight Gauss points imposes eight volume
//! constraints per element, about three per node: as ν → ½ the element freezes (locks). With
//! [`Volumetric::MeanDilatation`] the volumetric energy is V·U(J̄) with J̄ = v/V the element's
//! current over reference volume (Nagtegaal, Parks & Rice 1974; Simo, Taylor & Pister 1985): one
//! constraint per element, the Q1/P0 element, the finite-strain form of selective (B̄)
//! integration. It is still an exact energy, so the tangent stays symmetric:
//! K_vol = U″(J̄)/V · d_a d_bᵀ + U′(J̄) ∂²v/∂x_a∂x_b with d_a = ∂v/∂x_a = ∫_V J g_a dV and
//! ∂²v/∂x_a∂x_b = ∫_V J (g_a g_bᵀ − g_b g_aᵀ) dV.

use super::hex8::{ElementStiffness, MappedPoint};
use super::hyperelastic::{det_minus_one, NeoHookean};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// How the volumetric energy U(J) is integrated over an element.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Volumetric {
    /// U(J) at each of the 2×2×2 Gauss points: locks as ν → ½.
    Full,
    /// U(J̄) of the element's mean dilatation J̄ = v/V (Q1/P0): free of volumetric locking.
    #[default]
    MeanDilatation,
}

/// Energy, internal forces and (optionally) tangent of one element.
#[derive(Clone, Debug)]
pub struct ElementState {
    /// Stored energy, J.
    pub energy: f64,
    /// Internal nodal forces ∂W/∂x_a, N.
    pub force: [Vector3<f64>; 8],
    /// Tangent ∂²W/∂x_a∂x_b, N/m, when asked for.
    pub tangent: Option<ElementStiffness>,
}

/// det F ≤ 0 (or not a number) at a Gauss point: the element is inverted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementInverted {
    /// The Gauss point (0..8, ordered like the nodes).
    pub gauss_point: usize,
    /// det F there.
    pub det_f: f64,
}

/// Which tangent [`element_state_with`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tangent {
    /// None: energy and forces only.
    None,
    /// The exact Hessian of the energy.
    Exact,
    /// The Hessian without the pressure's part, U′·∂²v/∂x_a∂x_b (per Gauss point, or of the
    /// element's volume under mean dilatation): indefinite, and as large as the pressure,
    /// which in a nearly incompressible material is huge at an iterate that changes the
    /// volume. What is left (isochoric material and geometric parts, U″ d_a d_bᵀ) keeps the
    /// shear stiffness; Newton uses it where the exact tangent is not positive definite.
    WithoutPressureHessian,
}

/// The state of the element whose reference Gauss points are `reference` (from
/// [`super::hex8::mapped_points`] of the reference coordinates X) when its nodes have moved by
/// `u`, to current positions x = X + u.
pub fn element_state(
    reference: &[MappedPoint; 8],
    u: &[Vector3<f64>; 8],
    law: &NeoHookean,
    volumetric: Volumetric,
    with_tangent: bool,
) -> Result<ElementState, ElementInverted> {
    let tangent = if with_tangent {
        Tangent::Exact
    } else {
        Tangent::None
    };
    element_state_with(reference, u, law, volumetric, tangent)
}

/// As [`element_state`], with the choice of tangent.
pub fn element_state_with(
    reference: &[MappedPoint; 8],
    u: &[Vector3<f64>; 8],
    law: &NeoHookean,
    volumetric: Volumetric,
    tangent: Tangent,
) -> Result<ElementState, ElementInverted> {
    let with_tangent = tangent != Tangent::None;
    // The factor of the pressure Hessian terms: 1, or 0 without them.
    let ph = if tangent == Tangent::WithoutPressureHessian {
        0.0
    } else {
        1.0
    };
    let (h, dj) = kinematics(reference, u)?;
    let mut g = [[Vector3::zeros(); 8]; 8];
    let det = dj.map(|d| 1.0 + d);
    for (q, p) in reference.iter().enumerate() {
        let inv_t = (Matrix3::identity() + h[q])
            .try_inverse()
            .ok_or(ElementInverted {
                gauss_point: q,
                det_f: det[q],
            })?
            .transpose();
        for a in 0..8 {
            g[q][a] = inv_t * p.gradients[a];
        }
    }

    let mean = volumetric == Volumetric::MeanDilatation;
    let v_ref: f64 = reference.iter().map(|p| p.volume).sum();
    let (u_bar, p_bar, dp_bar) = law.volumetric(mean_dilatation(reference, &dj));

    let mut energy = if mean { v_ref * u_bar } else { 0.0 };
    let mut force = [Vector3::zeros(); 8];
    let mut k = with_tangent.then(|| [[Matrix3::zeros(); 8]; 8]);
    for q in 0..8 {
        let (w, j, ga_q) = (reference[q].volume, det[q], &g[q]);
        let iso = law.isochoric(&h[q], dj[q]);
        energy += w * iso.energy;
        // Pressure p = U′ and its slope, at the point (full) or of the element (mean dilatation;
        // the U″ term of the mean is added once, below).
        let (p, dp) = if mean {
            (p_bar, 0.0)
        } else {
            let (u, p, dp) = law.volumetric(dj[q]);
            energy += w * u;
            (p, dp)
        };
        let tau = iso.tau + Matrix3::identity() * (j * p);
        for a in 0..8 {
            force[a] += tau * ga_q[a] * w;
        }
        let Some(k) = k.as_mut() else { continue };
        let mb = iso.mu_bar;
        let two_thirds = 2.0 / 3.0;
        for a in 0..8 {
            let ga = ga_q[a];
            let ta = iso.tau * ga;
            for b in a..8 {
                let gb = ga_q[b];
                let tb = iso.tau * gb;
                // Isochoric material part, J𝕔_iso = 2μ̄(𝕀 − ⅓ 1⊗1) − ⅔(τ_iso⊗1 + 1⊗τ_iso)...
                let mut block = gb * ga.transpose() * mb
                    - ga * gb.transpose() * (two_thirds * mb)
                    - (ta * gb.transpose() + ga * tb.transpose()) * two_thirds
                    // ...and the volumetric Hessian J²U″ g_a g_bᵀ + J U′ (g_a g_bᵀ − g_b g_aᵀ).
                    + ga * gb.transpose() * (j * j * dp + ph * j * p)
                    - gb * ga.transpose() * (ph * j * p);
                // μ̄ (g_a·g_b) I of the material part plus the geometric (g_a·τ_iso g_b) I; the
                // geometric term of the pressure, J p (g_a·g_b) I, cancels against 𝕔_vol's
                // −2Jp𝕀 and is already folded into the Hessian above.
                let diag = mb * ga.dot(&gb) + ga.dot(&tb);
                block[(0, 0)] += diag;
                block[(1, 1)] += diag;
                block[(2, 2)] += diag;
                k[a][b] += block * w;
            }
        }
    }
    if let Some(k) = k.as_mut() {
        if mean {
            let mut d = [Vector3::zeros(); 8];
            for q in 0..8 {
                for a in 0..8 {
                    d[a] += g[q][a] * (reference[q].volume * det[q]);
                }
            }
            for a in 0..8 {
                for b in a..8 {
                    k[a][b] += d[a] * d[b].transpose() * (dp_bar / v_ref);
                }
            }
        }
        for a in 0..8 {
            for b in 0..a {
                k[a][b] = k[b][a].transpose();
            }
        }
    }
    Ok(ElementState {
        energy,
        force,
        tangent: k,
    })
}

/// Cauchy stress σ = τ/J at the eight Gauss points of the element (with the element's mean
/// pressure U′(J̄) under [`Volumetric::MeanDilatation`]).
pub fn gauss_cauchy_stress(
    reference: &[MappedPoint; 8],
    u: &[Vector3<f64>; 8],
    law: &NeoHookean,
    volumetric: Volumetric,
) -> Result<[Matrix3<f64>; 8], ElementInverted> {
    let (h, dj) = kinematics(reference, u)?;
    let p_bar = law.volumetric(mean_dilatation(reference, &dj)).1;
    Ok(std::array::from_fn(|q| {
        let p = match volumetric {
            Volumetric::MeanDilatation => p_bar,
            Volumetric::Full => law.volumetric(dj[q]).1,
        };
        law.isochoric(&h[q], dj[q]).tau / (1.0 + dj[q]) + Matrix3::identity() * p
    }))
}

/// Displacement gradients H = ∇_X u = F − I and J − 1 at the Gauss points; an error when
/// det F ≤ 0 at one of them. Working with u rather than x = X + u keeps small strains exact.
fn kinematics(
    reference: &[MappedPoint; 8],
    u: &[Vector3<f64>; 8],
) -> Result<([Matrix3<f64>; 8], [f64; 8]), ElementInverted> {
    let mut h = [Matrix3::zeros(); 8];
    let mut dj = [0.0; 8];
    for (q, p) in reference.iter().enumerate() {
        for a in 0..8 {
            h[q] += u[a] * p.gradients[a].transpose();
        }
        dj[q] = det_minus_one(&h[q]);
        if !(dj[q] > -1.0 && dj[q].is_finite()) {
            return Err(ElementInverted {
                gauss_point: q,
                det_f: 1.0 + dj[q],
            });
        }
    }
    Ok((h, dj))
}

/// J̄ − 1 = (v − V)/V, the element's mean dilatation.
fn mean_dilatation(reference: &[MappedPoint; 8], dj: &[f64; 8]) -> f64 {
    let v_ref: f64 = reference.iter().map(|p| p.volume).sum();
    reference
        .iter()
        .zip(dj)
        .map(|(p, d)| p.volume * d)
        .sum::<f64>()
        / v_ref
}
