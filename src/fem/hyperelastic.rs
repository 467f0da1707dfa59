//! A compressible Neo-Hookean material for large deformations, with the volume change decoupled
//! from the shape change (Simo & Taylor 1991; Holzapfel, *Nonlinear Solid Mechanics*, §6.5):
//!
//! ψ(F) = μ/2 (Ī₁ − 3) + U(J),   Ī₁ = J^(−2/3) tr(F Fᵀ),   U(J) = κ/4 (J² − 1 − 2 ln J),
//!
//! with J = det F. U is convex, U(1) = U′(1) = 0, U″(1) = κ, and U → ∞ as J → 0⁺, so the energy
//! stays well defined for every admissible (J > 0) deformation and forbids collapse to zero
//! volume. For small strain ψ → μ ε_dev:ε_dev + κ/2 (tr ε)², the linear isotropic law with
//! μ = E/(2(1+ν)) and κ = E/(3(1−2ν)) ([`Material::mu`], λ = κ − 2μ/3 = [`Material::lambda`]).

use super::material::Material;
use nalgebra::Matrix3;

/// The material constants of the Neo-Hookean law, Pa.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NeoHookean {
    /// Shear modulus μ.
    pub mu: f64,
    /// Bulk modulus κ.
    pub kappa: f64,
}

/// The isochoric (shape-changing) part of the law at one point.
#[derive(Clone, Copy, Debug)]
pub struct Isochoric {
    /// ψ_iso = μ/2 (Ī₁ − 3), J/m³ of reference volume.
    pub energy: f64,
    /// Kirchhoff stress τ_iso = μ dev(b̄), with b̄ = J^(−2/3) F Fᵀ.
    pub tau: Matrix3<f64>,
    /// μ̄ = μ tr(b̄)/3, the effective shear modulus of the spatial tangent.
    pub mu_bar: f64,
}

impl NeoHookean {
    /// The law with the small-strain moduli of `material`: μ = E/(2(1+ν)), κ = E/(3(1−2ν)).
    pub fn from_material(material: &Material) -> Self {
        Self {
            mu: material.mu(),
            kappa: material.young / (3.0 * (1.0 - 2.0 * material.poisson)),
        }
    }

    /// U(J), U′(J) (the pressure, Pa) and U″(J) at J = 1 + `dj` > 0. Written in J − 1 so that
    /// they keep full relative precision at small strain: U = κ/4 (dj² + 2(dj − ln(1 + dj))),
    /// U′ = κ/2 · dj(2 + dj)/(1 + dj).
    pub fn volumetric(&self, dj: f64) -> (f64, f64, f64) {
        let k = self.kappa;
        let j = 1.0 + dj;
        // dj − ln(1 + dj), by its series where the direct form would cancel.
        let gap = if dj.abs() < 1e-3 {
            dj * dj * (0.5 - dj / 3.0 + dj * dj / 4.0 - dj * dj * dj / 5.0)
        } else {
            dj - dj.ln_1p()
        };
        (
            0.25 * k * (dj * dj + 2.0 * gap),
            0.5 * k * dj * (2.0 + dj) / j,
            0.5 * k * (1.0 + 1.0 / (j * j)),
        )
    }

    /// The isochoric part at displacement gradient H = F − I with J − 1 = `dj` (from
    /// [`det_minus_one`]): b − I = H + Hᵀ + HHᵀ and τ_iso = μ J^(−2/3) dev(b − I), free of the
    /// cancellation that F Fᵀ − I would suffer at small strain.
    pub fn isochoric(&self, h: &Matrix3<f64>, dj: f64) -> Isochoric {
        let s_minus_one = (-2.0 / 3.0 * dj.ln_1p()).exp_m1();
        let s = 1.0 + s_minus_one;
        let b_minus_i = h + h.transpose() + h * h.transpose();
        let tr = b_minus_i.trace();
        Isochoric {
            energy: 0.5 * self.mu * (3.0 * s_minus_one + s * tr),
            tau: (b_minus_i - Matrix3::identity() * (tr / 3.0)) * (self.mu * s),
            mu_bar: self.mu * s * (3.0 + tr) / 3.0,
        }
    }

    /// Strain energy ψ per unit reference volume at displacement gradient H = F − I, J/m³;
    /// `None` when det F ≤ 0.
    pub fn energy(&self, h: &Matrix3<f64>) -> Option<f64> {
        let dj = det_minus_one(h);
        (dj > -1.0).then(|| self.isochoric(h, dj).energy + self.volumetric(dj).0)
    }

    /// Cauchy stress σ = τ/J = (μ dev(b̄) + J U′(J) I)/J at displacement gradient H = F − I;
    /// `None` when det F ≤ 0.
    pub fn cauchy(&self, h: &Matrix3<f64>) -> Option<Matrix3<f64>> {
        let dj = det_minus_one(h);
        (dj > -1.0).then(|| {
            self.isochoric(h, dj).tau / (1.0 + dj) + Matrix3::identity() * self.volumetric(dj).1
        })
    }
}

/// det(I + H) − 1 = I₁(H) + I₂(H) + I₃(H), computed without forming I + H (exact identity; keeps
/// the relative precision of small volume changes).
pub fn det_minus_one(h: &Matrix3<f64>) -> f64 {
    let tr = h.trace();
    let i2 = 0.5 * (tr * tr - (h * h).trace());
    tr + i2 + h.determinant()
}
