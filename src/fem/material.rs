//! Isotropic linear elastic materials.

use serde::{Deserialize, Serialize};

/// An isotropic linear elastic material (the paper's linear constitutive law for flesh and ball).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Young's modulus E in Pa.
    pub young: f64,
    /// Poisson's ratio ν, in (−1, 0.5).
    pub poisson: f64,
    /// Mass density ρ in kg/m³.
    pub density: f64,
}

impl Material {
    /// The shipped scenes' rubber ball (E = 2 MPa, ν = 0.4, ρ = 1100 kg/m³), for unit tests.
    #[cfg(test)]
    pub(crate) fn rubber() -> Material {
        Material {
            young: 2.0e6,
            poisson: 0.4,
            density: 1100.0,
        }
    }

    /// Lamé's first parameter λ = Eν / ((1+ν)(1−2ν)).
    pub fn lambda(&self) -> f64 {
        self.young * self.poisson / ((1.0 + self.poisson) * (1.0 - 2.0 * self.poisson))
    }

    /// The shear modulus μ = E / (2(1+ν)).
    pub fn mu(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// Why the material is not admissible, if it is not.
    pub fn check(&self) -> Result<(), String> {
        if !(self.young.is_finite() && self.young > 0.0) {
            return Err(format!(
                "young = {} must be a positive number of pascals",
                self.young
            ));
        }
        if !(self.poisson.is_finite() && self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(format!(
                "poisson = {} must lie strictly between -1 and 0.5",
                self.poisson
            ));
        }
        if !(self.density.is_finite() && self.density >= 0.0) {
            return Err(format!(
                "density = {} must be zero or positive (kg/m^3)",
                self.density
            ));
        }
        Ok(())
    }
}
