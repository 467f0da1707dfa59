//! External loads assembled into the load vector R of equation (5): body forces (RB), surface
//! pressure (RS) and concentrated forces (RF) of equation (4).

use super::assembly::AssemblyError;
use super::hex8::element_body_force;
use super::material::Material;
use crate::mesh::{Facet, Mesh};
use nalgebra::Vector3;

/// Adds the consistent nodal forces of gravity, f_a = ∫ N_a ρ g dV, to `r`; returns the total.
pub fn add_gravity(
    r: &mut [f64],
    mesh: &Mesh,
    materials: &[Material],
    cells: impl IntoIterator<Item = usize>,
    gravity: &Vector3<f64>,
) -> Result<Vector3<f64>, AssemblyError> {
    let mut total = Vector3::zeros();
    for c in cells {
        let b = gravity * materials[c].density;
        let f = element_body_force(&mesh.cell_coords(c), &b)
            .map_err(|inverted| AssemblyError { cell: c, inverted })?;
        for (a, &n) in mesh.cells[c].iter().enumerate() {
            add(r, n, &f[a]);
            total += f[a];
        }
    }
    Ok(total)
}

/// Adds the consistent nodal forces of a pressure `p` (Pa) acting on `facets`, pushing against
/// their outward normal like a gas: f_a = −p ∫ N_a n dA (the surface term RS of equation (4)).
/// Returns the total force.
pub fn add_pressure(r: &mut [f64], mesh: &Mesh, facets: &[Facet], p: f64) -> Vector3<f64> {
    add_surface_load(r, mesh, facets, |normal_area| normal_area * (-p))
}

/// Adds the consistent nodal forces of a uniform traction `t` (Pa, a force per unit area in a
/// fixed direction) on `facets`: f_a = ∫ N_a t dA. Returns the total force.
pub fn add_traction(
    r: &mut [f64],
    mesh: &Mesh,
    facets: &[Facet],
    t: &Vector3<f64>,
) -> Vector3<f64> {
    add_surface_load(r, mesh, facets, |normal_area| t * normal_area.norm())
}

/// Integrates a surface load over bilinear facets with 2×2 Gauss points. `density` maps the
/// outward normal scaled by the area element (∂x/∂s × ∂x/∂t) to the force per unit (s, t).
fn add_surface_load(
    r: &mut [f64],
    mesh: &Mesh,
    facets: &[Facet],
    density: impl Fn(Vector3<f64>) -> Vector3<f64>,
) -> Vector3<f64> {
    const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let g = 1.0 / 3f64.sqrt();
    let mut total = Vector3::zeros();
    for facet in facets {
        let x = facet.nodes.map(|n| mesh.nodes[n]);
        let mut f = [Vector3::zeros(); 4];
        for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
            let mut dxs = Vector3::zeros();
            let mut dxt = Vector3::zeros();
            let mut n = [0.0; 4];
            for (a, c) in CORNERS.iter().enumerate() {
                n[a] = (1.0 + c[0] * s) * (1.0 + c[1] * t) / 4.0;
                dxs += x[a] * (c[0] * (1.0 + c[1] * t) / 4.0);
                dxt += x[a] * (c[1] * (1.0 + c[0] * s) / 4.0);
            }
            let load = density(dxs.cross(&dxt));
            for a in 0..4 {
                f[a] += load * n[a];
            }
        }
        for a in 0..4 {
            add(r, facet.nodes[a], &f[a]);
            total += f[a];
        }
    }
    total
}

/// Adds a total force shared equally by `nodes` (the paper's concentrated forces RF).
pub fn add_shared_force(r: &mut [f64], nodes: &[usize], total: &Vector3<f64>) {
    let share = total / nodes.len() as f64;
    for &n in nodes {
        add(r, n, &share);
    }
}

fn add(r: &mut [f64], node: usize, f: &Vector3<f64>) {
    for i in 0..3 {
        r[3 * node + i] += f[i];
    }
}
