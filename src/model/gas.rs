//! A gas cavity: a pressure load (`gas = true`) whose pressure follows the volume of the cavity
//! it encloses, isothermally (Boyle–Mariotte: p·V = P0·V0 in absolute pressure). The paper's
//! remark under its Figure 3c: the ball, submitted to internal pressure, returns to its shape
//! when the finger is released.

use crate::fem::cavity::{check_closed, enclosed_volume};
use crate::fem::loads::add_pressure;
use crate::mesh::{Facet, Mesh};
use nalgebra::Vector3;

/// The standard atmosphere, Pa: the ambient pressure when the scene gives none.
pub const STANDARD_AMBIENT: f64 = 101_325.0;

/// A sealed gas cavity: what the solve needs to find its pressure.
#[derive(Clone, Debug)]
pub struct GasCavity {
    /// The load's name.
    pub name: String,
    /// The body whose wall encloses it.
    pub body: usize,
    /// The facets bounding it (the wall's boundary facets, normals out of the wall).
    pub facets: Vec<Facet>,
    /// The gauge pressure at the rest volume, Pa (the load's `pressure`, which the load vector
    /// holds).
    pub rest_gauge: f64,
    /// The absolute ambient pressure, Pa.
    pub ambient: f64,
    /// The cavity's volume in the mesh as given (rest), m³.
    pub rest_volume: f64,
    /// The consistent nodal load of a unit gauge pressure on the facets (N per Pa), over every
    /// dof: the load is p·a (equation (4), the surface term RS).
    pub unit_load: Vec<f64>,
}

impl GasCavity {
    /// The cavity enclosed by `facets` (checked closed) with gauge pressure `gauge` at rest.
    pub fn new(
        name: String,
        body: usize,
        mesh: &Mesh,
        facets: Vec<Facet>,
        gauge: f64,
        ambient: f64,
    ) -> Result<GasCavity, String> {
        check_closed(&facets).map_err(|e| {
            format!(
                "gas = true needs the selection to enclose a cavity (a closed surface, such as \
                 surface = \"inner\" of a shell): {e}"
            )
        })?;
        let signed = enclosed_volume(&facets, |n| mesh.nodes[n]);
        if !signed.is_finite() || signed == 0.0 {
            return Err(format!(
                "gas = true: the selected surface encloses no volume ({signed:e} m³)"
            ));
        }
        // The boundary facets' normals point out of the body's material: into a cavity the
        // facets enclose (the enclosed volume then counts negative), away from the material
        // when they wrap the body itself (a shell's outer surface, a solid's boundary).
        if signed > 0.0 {
            return Err(format!(
                "gas = true: the selected surface wraps the body's own material ({} m³), not a \
                 cavity inside it: select the surface that bounds the cavity (surface = \"inner\" \
                 of a shell), or remove `gas` for a plain pressure",
                crate::util::readable(signed)
            ));
        }
        let mut unit_load = vec![0.0; 3 * mesh.node_count()];
        add_pressure(&mut unit_load, mesh, &facets, 1.0);
        Ok(GasCavity {
            name,
            body,
            facets,
            rest_gauge: gauge,
            ambient,
            rest_volume: -signed,
            unit_load,
        })
    }

    /// P0 = p_gauge + p_ambient at the rest volume, Pa.
    pub fn rest_absolute(&self) -> f64 {
        self.rest_gauge + self.ambient
    }

    /// The volume of the cavity with the nodes at `rest` moved by `displacement`, m³ (exact for
    /// the deformed bilinear facets).
    pub fn volume(&self, rest: &[Vector3<f64>], displacement: &[f64]) -> f64 {
        let u = |n: usize| {
            Vector3::new(
                displacement[3 * n],
                displacement[3 * n + 1],
                displacement[3 * n + 2],
            )
        };
        // The facets face into the cavity (checked when it was made): their enclosed volume
        // counts negative.
        -enclosed_volume(&self.facets, |n| rest[n] + u(n))
    }

    /// The volume of the cavity after a step `step` from the displacements `carried` (both
    /// over every dof), the nodes at `rest` moved by their sum, m³.
    pub fn volume_after(&self, rest: &[Vector3<f64>], carried: &[f64], step: &[f64]) -> f64 {
        let u: Vec<f64> = step.iter().zip(carried).map(|(s, c)| s + c).collect();
        self.volume(rest, &u)
    }

    /// The gauge pressure of the gas at volume `volume`: p = P0·V0/V − p_ambient, Pa.
    pub fn gauge_at(&self, volume: f64) -> f64 {
        self.rest_absolute() * self.rest_volume / volume - self.ambient
    }

    /// How far gauge pressure `gauge` at volume `volume` is from the gas law:
    /// (p + p_ambient)·V / (P0·V0) − 1.
    pub fn gas_law_residual(&self, gauge: f64, volume: f64) -> f64 {
        (gauge + self.ambient) * volume / (self.rest_absolute() * self.rest_volume) - 1.0
    }

    /// `loads` (which hold the rest gauge pressure's load) with the gauge pressure `gauge`
    /// instead: loads + (p − p_rest)·a.
    pub fn with_gauge(&self, loads: &[f64], gauge: f64) -> Vec<f64> {
        self.with_gauge_on(loads, gauge, &self.unit_load)
    }

    /// As [`GasCavity::with_gauge`], with `unit_load` the load of a unit pressure on the
    /// facets where they are now ([`GasCavity::unit_load_on`]).
    pub fn with_gauge_on(&self, loads: &[f64], gauge: f64, unit_load: &[f64]) -> Vec<f64> {
        let dp = gauge - self.rest_gauge;
        loads
            .iter()
            .zip(unit_load)
            .map(|(r, a)| r + dp * a)
            .collect()
    }

    /// The nodal load of a unit gauge pressure on the facets of `mesh` (its nodes where the
    /// wall is now), N per Pa.
    pub fn unit_load_on(&self, mesh: &Mesh) -> Vec<f64> {
        let mut unit = vec![0.0; 3 * mesh.node_count()];
        add_pressure(&mut unit, mesh, &self.facets, 1.0);
        unit
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{boundary_facets, box_mesh};

    /// A body's own boundary wraps its material, not a cavity: refused, naming the volume. The
    /// same facets facing inwards (as a wall around a cube of air would) enclose 1 m³.
    #[test]
    fn only_a_surface_facing_into_what_it_encloses_is_a_cavity() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::repeat(1.0), [2, 2, 2]);
        let outward = boundary_facets(&mesh);
        let err = GasCavity::new("air".into(), 0, &mesh, outward.clone(), 1e3, 1e5).unwrap_err();
        assert!(
            err.contains("wraps the body's own material (1 m³)"),
            "{err}"
        );
        let inward = outward
            .into_iter()
            .map(|mut f| {
                f.nodes.reverse();
                f
            })
            .collect();
        let cavity = GasCavity::new("air".into(), 0, &mesh, inward, 1e3, 1e5).unwrap();
        assert!((cavity.rest_volume - 1.0).abs() < 1e-12);
        let rest = &mesh.nodes;
        assert!((cavity.volume(rest, &vec![0.0; 3 * rest.len()]) - 1.0).abs() < 1e-12);
    }
}
