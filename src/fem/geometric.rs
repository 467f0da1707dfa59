//! The geometric part of a corotated body's tangent: what its stress and a pressure on its moving
//! surface add to the stiffness when the body is displaced further.
//!
//! - **The turn's stiffness** ([`turn_stiffness`]): a corotated element's forces f = R·K̂·û
//!   turn with its polar rotation R, and its strain û = Rᵀ(X + u) − X is seen from the turned
//!   frame; differentiating R gives the blocks K̃ = R·K̂·Rᵀ lacks — the consistent corotational
//!   tangent's geometric part, the discrete form of the initial-stress stiffness (a pressurised
//!   shell's wall in tension stiffens against a dent).
//! - **Pressure load stiffness** ([`pressure_load_stiffness`]): a pressure following its facets
//!   (f_a = −p ∫ N_a (x_,s × x_,t) ds dt, `loads::add_pressure`) changes when they move:
//!   ∂f_a/∂x_b = −p ∫ N_a (N_b,t [x_,s]× − N_b,s [x_,t]×) ds dt. Over a closed surface under a
//!   uniform pressure the assembled matrix is symmetric; its symmetric part is taken.
//!
//! Neither changes an equilibrium: a fixed-point iteration on a corotated body (solve, turn,
//! solve again) whose step carries them converges to the same state in fewer iterations.

use super::hex8::{
    jacobian, relative_min_jacobian, shape_derivatives, ElementStiffness, InvertedCell,
};
use crate::mesh::{Facet, Mesh};
use nalgebra::{Matrix3, Vector3};

/// What the turn of a corotated hex8 adds to its tangent: with f_a = R·K̂_a·û (û = Rᵀ(X + u) − X,
/// K̂ the element's stiffness at rest, R the polar rotation at its centre), turning it by a
/// spin ω changes the forces by −[f_a]×·ω (the stressed element's forces turn with it) and by
/// Σ_c K̃_ac·[R·û_c]×·ω (its strain seen from the turned frame), with ω = Σ_b G_b·δy_b,
/// G_b = R·(tr U·I − U)⁻¹·[∇N_b]×·Rᵀ (the polar decomposition F = R·U at the centre, ∇N_b the
/// reference gradients there). Returns those blocks: the exact tangent's correction to
/// K̃ = R·K̂·Rᵀ (not symmetric away from equilibrium), zero for an element at rest
/// (Crisfield, *Non-linear Finite Element
/// Analysis of Solids and Structures*, vol. 2, ch. 17; Felippa and Haugen 2005).
pub fn turn_stiffness(
    coords: &[Vector3<f64>; 8],
    local_stiffness: &ElementStiffness,
    rotation: &Matrix3<f64>,
    u: &[Vector3<f64>; 8],
) -> Result<ElementStiffness, InvertedCell> {
    let r = rotation;
    let turned_stiffness = local_stiffness.map(|row| row.map(|k| r * k * r.transpose()));
    turn_stiffness_of(coords, (local_stiffness, &turned_stiffness), rotation, u)
}

/// [`turn_stiffness`] with K̃ = R·K̂·Rᵀ already made (the assembly turns K̂ itself).
fn turn_stiffness_of(
    coords: &[Vector3<f64>; 8],
    (local_stiffness, turned_stiffness): (&ElementStiffness, &ElementStiffness),
    rotation: &Matrix3<f64>,
    u: &[Vector3<f64>; 8],
) -> Result<ElementStiffness, InvertedCell> {
    let r = rotation;
    let dn = shape_derivatives(&Vector3::zeros());
    let inverted = || InvertedCell {
        relative_det: relative_min_jacobian(coords),
    };
    let inv_t = jacobian(coords, &dn)
        .try_inverse()
        .ok_or_else(inverted)?
        .transpose();
    let g: [Vector3<f64>; 8] = std::array::from_fn(|a| inv_t * dn[a]);
    let mut f_grad = Matrix3::identity();
    for a in 0..8 {
        f_grad += u[a] * g[a].transpose();
    }
    let stretch = r.transpose() * f_grad;
    let stretch = (stretch + stretch.transpose()) * 0.5;
    let m = (Matrix3::identity() * stretch.trace() - stretch)
        .try_inverse()
        .ok_or_else(inverted)?;
    // G_b: the spin per unit displacement of node b.
    let spin: [Matrix3<f64>; 8] =
        std::array::from_fn(|b| r * m * g[b].cross_matrix() * r.transpose());
    let local: [Vector3<f64>; 8] =
        std::array::from_fn(|a| r.transpose() * (coords[a] + u[a]) - coords[a]);
    let turned: [Matrix3<f64>; 8] = std::array::from_fn(|c| (r * local[c]).cross_matrix());
    let mut k = [[Matrix3::zeros(); 8]; 8];
    for a in 0..8 {
        let mut force = Vector3::zeros();
        let mut seen = Matrix3::zeros();
        for c in 0..8 {
            force += local_stiffness[a][c] * local[c];
            seen += turned_stiffness[a][c] * turned[c];
        }
        let per_spin = seen - (r * force).cross_matrix();
        for b in 0..8 {
            k[a][b] = per_spin * spin[b];
        }
    }
    Ok(k)
}

/// The symmetric part of [`turn_stiffness`]: what the contact step's symmetric solve adds to K̃
/// (`stiffness`: K̂ and K̃ = R·K̂·Rᵀ, each R·K̂_ac·Rᵀ made as the assembly makes it).
pub fn symmetric_turn_stiffness(
    coords: &[Vector3<f64>; 8],
    stiffness: (&ElementStiffness, &ElementStiffness),
    rotation: &Matrix3<f64>,
    u: &[Vector3<f64>; 8],
) -> Result<ElementStiffness, InvertedCell> {
    let k = turn_stiffness_of(coords, stiffness, rotation, u)?;
    Ok(std::array::from_fn(|a| {
        std::array::from_fn(|b| (k[a][b] + k[b][a].transpose()) * 0.5)
    }))
}

/// The symmetric part of the load stiffness ∂f/∂x of a pressure `p` (Pa) following `facets` of
/// `now` (the positions where they are), as (node a, node b, block) for every pair of a facet's
/// nodes; blocks of one pair from several facets are to be summed.
pub fn pressure_load_stiffness(
    now: &Mesh,
    facets: &[Facet],
    p: f64,
) -> Vec<(usize, usize, Matrix3<f64>)> {
    const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let g = 1.0 / 3f64.sqrt();
    let mut out = Vec::with_capacity(16 * facets.len());
    for facet in facets {
        let x = facet.nodes.map(|n| now.nodes[n]);
        let mut k = [[Matrix3::zeros(); 4]; 4];
        for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
            let mut dxs = Vector3::zeros();
            let mut dxt = Vector3::zeros();
            let mut n = [0.0; 4];
            let mut ns = [0.0; 4];
            let mut nt = [0.0; 4];
            for (a, c) in CORNERS.iter().enumerate() {
                n[a] = (1.0 + c[0] * s) * (1.0 + c[1] * t) / 4.0;
                ns[a] = c[0] * (1.0 + c[1] * t) / 4.0;
                nt[a] = c[1] * (1.0 + c[0] * s) / 4.0;
                dxs += x[a] * ns[a];
                dxt += x[a] * nt[a];
            }
            let (cs, ct) = (dxs.cross_matrix(), dxt.cross_matrix());
            for a in 0..4 {
                for b in 0..4 {
                    k[a][b] += (cs * nt[b] - ct * ns[b]) * (-p * n[a]);
                }
            }
        }
        for a in 0..4 {
            for b in 0..4 {
                let sym = (k[a][b] + k[b][a].transpose()) * 0.5;
                out.push((facet.nodes[a], facet.nodes[b], sym));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::hex8::element_stiffness;
    use crate::fem::loads::add_pressure;
    use crate::fem::Material;
    use crate::mesh::box_mesh;
    use nalgebra::Rotation3;

    fn rubber() -> Material {
        Material::rubber()
    }

    /// The corotated internal force of one cell at positions y (R from the centre's polar
    /// decomposition, as the contact step turns it).
    fn corotated_force(coords: &[Vector3<f64>; 8], y: &[Vector3<f64>; 8]) -> [Vector3<f64>; 8] {
        let u: [Vector3<f64>; 8] = std::array::from_fn(|a| y[a] - coords[a]);
        let r = crate::fem::hex8::centre_rotation(coords, &u).unwrap();
        let k = element_stiffness(coords, &rubber()).unwrap();
        let local: [Vector3<f64>; 8] = std::array::from_fn(|a| r.transpose() * y[a] - coords[a]);
        std::array::from_fn(|a| {
            let mut f = Vector3::zeros();
            for b in 0..8 {
                f += k[a][b] * local[b];
            }
            r * f
        })
    }

    /// A cell stretched by 5 % along x and turned by 20°: a sideways nudge of one node changes
    /// the corotated forces by what R·K·Rᵀ (the stiffness the step had) plus the turn's
    /// stiffness give, to within 10⁻⁴ of what R·K·Rᵀ alone misses — the turn's stiffness is
    /// the missing part of the tangent, measured by central differences.
    #[test]
    fn the_stress_stiffness_is_what_a_turned_stressed_cell_lacks() {
        let mesh = box_mesh(
            Vector3::zeros(),
            Vector3::new(0.01, 0.004, 0.004),
            [1, 1, 1],
        );
        let coords = mesh.cell_coords(0);
        let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), 20f64.to_radians());
        let stretch = Matrix3::from_diagonal(&Vector3::new(1.05, 1.0, 1.0));
        let y: [Vector3<f64>; 8] = std::array::from_fn(|a| turn * (stretch * coords[a]));
        let u: [Vector3<f64>; 8] = std::array::from_fn(|a| y[a] - coords[a]);
        let r = crate::fem::hex8::centre_rotation(&coords, &u).unwrap();
        let k = element_stiffness(&coords, &rubber()).unwrap();
        let ks = turn_stiffness(&coords, &k, &r, &u).unwrap();
        // Nudge node 1 (at x = L) sideways, across the stretched fibre.
        let (node, dir) = (1, turn * Vector3::y());
        let h = 1e-7;
        let mut plus = y;
        let mut minus = y;
        plus[node] += dir * h;
        minus[node] -= dir * h;
        let (fp, fm) = (
            corotated_force(&coords, &plus),
            corotated_force(&coords, &minus),
        );
        let (mut miss_without, mut miss_with) = (0.0f64, 0.0f64);
        for a in 0..8 {
            let exact = (fp[a] - fm[a]) / (2.0 * h);
            let warped = r * k[a][node] * r.transpose() * dir;
            let geometric = ks[a][node] * dir;
            miss_without = miss_without.max((exact - warped).norm());
            miss_with = miss_with.max((exact - warped - geometric).norm());
        }
        assert!(
            miss_without > 1.0,
            "the warped stiffness misses {miss_without} N/m"
        );
        assert!(
            miss_with < 1e-4 * miss_without,
            "with the stress stiffness {miss_with} N/m against {miss_without} N/m"
        );
    }

    /// The load stiffness against central differences of the pressure's nodal forces on a
    /// closed surface (a box's six faces, displaced irregularly): the assembled matrix is
    /// symmetric there, so its symmetric part is the whole derivative.
    #[test]
    fn the_pressure_load_stiffness_is_the_derivative_of_the_follower_load() {
        let mut mesh = box_mesh(Vector3::zeros(), Vector3::new(0.02, 0.015, 0.01), [2, 2, 1]);
        for (i, p) in mesh.nodes.iter_mut().enumerate() {
            let f = i as f64;
            *p += Vector3::new((f * 1.3).sin(), (f * 0.7).cos(), (f * 2.1).sin()) * 1e-3;
        }
        let facets = crate::mesh::boundary_facets(&mesh);
        let p = 3.0e4;
        let n = mesh.node_count();
        let mut k = vec![vec![0.0; 3 * n]; 3 * n];
        for (a, b, block) in pressure_load_stiffness(&mesh, &facets, p) {
            for i in 0..3 {
                for j in 0..3 {
                    k[3 * a + i][3 * b + j] += block[(i, j)];
                }
            }
        }
        let h = 1e-7;
        let mut worst = 0.0f64;
        let mut scale = 0.0f64;
        for d in 0..3 * n {
            let mut plus = mesh.clone();
            let mut minus = mesh.clone();
            plus.nodes[d / 3][d % 3] += h;
            minus.nodes[d / 3][d % 3] -= h;
            let mut fp = vec![0.0; 3 * n];
            let mut fm = vec![0.0; 3 * n];
            add_pressure(&mut fp, &plus, &facets, p);
            add_pressure(&mut fm, &minus, &facets, p);
            for i in 0..3 * n {
                let exact = (fp[i] - fm[i]) / (2.0 * h);
                scale = scale.max(exact.abs());
                worst = worst.max((exact - k[i][d]).abs());
            }
        }
        assert!(scale > 1.0, "{scale}");
        assert!(worst < 1e-6 * scale, "off by {worst} of {scale} N/m");
    }
}
