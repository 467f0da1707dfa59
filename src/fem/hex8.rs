//! The 8-node isoparametric hexahedron: trilinear shape functions, 2×2×2 Gauss quadrature,
//! element stiffness, consistent body force, and strains at the Gauss points.
//!
//! Prisms and tetrahedra are hexahedra with repeated nodes (the paper: "these elements are easily
//! modified to prismatic or tetrahedral elements"). The trilinear map still reproduces every linear
//! field, and its Jacobian vanishes only on the collapsed edges, never at a Gauss point of a
//! well-shaped degenerate cell, so the same quadrature serves them.

use super::material::Material;
use nalgebra::{Matrix3, Vector3};
use std::sync::LazyLock;

/// Natural coordinates (ξ, η, ζ) of the eight nodes, VTK order.
pub const NODE_SIGNS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The 2×2×2 Gauss points (weights all 1), ordered like the nodes: point g sits at
/// `NODE_SIGNS[g] / √3`.
pub static GAUSS_POINTS: LazyLock<[Vector3<f64>; 8]> = LazyLock::new(|| {
    let s = 1.0 / 3f64.sqrt();
    NODE_SIGNS.map(|p| Vector3::new(p[0] * s, p[1] * s, p[2] * s))
});

/// Shape-function derivatives ∂N_a/∂ξ at each Gauss point: `[point][node]`.
static GAUSS_DERIVATIVES: LazyLock<[[Vector3<f64>; 8]; 8]> =
    LazyLock::new(|| GAUSS_POINTS.map(|xi| shape_derivatives(&xi)));

/// The shape-function derivatives ∂N_a/∂ξ at the 2×2×2 Gauss points (`[point][node]`).
pub fn gauss_derivatives() -> &'static [[Vector3<f64>; 8]; 8] {
    &GAUSS_DERIVATIVES
}

/// Trilinear shape functions N_a(ξ) = (1 + ξ_a ξ)(1 + η_a η)(1 + ζ_a ζ)/8.
pub fn shape(xi: &Vector3<f64>) -> [f64; 8] {
    NODE_SIGNS.map(|s| (1.0 + s[0] * xi.x) * (1.0 + s[1] * xi.y) * (1.0 + s[2] * xi.z) / 8.0)
}

/// Derivatives ∂N_a/∂ξ of the shape functions.
pub fn shape_derivatives(xi: &Vector3<f64>) -> [Vector3<f64>; 8] {
    NODE_SIGNS.map(|s| {
        let (a, b, c) = (1.0 + s[0] * xi.x, 1.0 + s[1] * xi.y, 1.0 + s[2] * xi.z);
        Vector3::new(s[0] * b * c, a * s[1] * c, a * b * s[2]) / 8.0
    })
}

/// Local coordinates ξ of point `x` in the trilinear cell `coords`: Newton on x(ξ) = x, each
/// iterate kept within ±2 (a point beyond the cell gets ξ outside the reference cube).
pub fn local_coordinates(coords: &[Vector3<f64>; 8], x: &Vector3<f64>) -> Vector3<f64> {
    let mut xi = Vector3::zeros();
    for _ in 0..20 {
        let (n, dn) = (shape(&xi), shape_derivatives(&xi));
        let mut r = -x;
        let mut j = Matrix3::zeros();
        for a in 0..8 {
            r += coords[a] * n[a];
            j += coords[a] * dn[a].transpose();
        }
        let Some(inv) = j.try_inverse() else { break };
        let step = inv * r;
        xi = (xi - step).map(|c| c.clamp(-2.0, 2.0));
        if step.norm() < 1e-12 {
            break;
        }
    }
    xi
}

/// The Jacobian matrix J_ij = ∂x_i/∂ξ_j of the map from natural to physical coordinates.
pub fn jacobian(coords: &[Vector3<f64>; 8], dn: &[Vector3<f64>; 8]) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for a in 0..8 {
        j += coords[a] * dn[a].transpose();
    }
    j
}

/// A Gauss point mapped onto a cell: det J times the weight, and ∂N_a/∂x.
#[derive(Clone, Copy, Debug)]
pub struct MappedPoint {
    /// det J · w: the volume this point stands for.
    pub volume: f64,
    /// Physical gradients of the shape functions.
    pub gradients: [Vector3<f64>; 8],
}

/// A cell whose map is not one-to-one at a Gauss point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InvertedCell {
    /// The smallest det J at a Gauss point divided by the cell size cubed (see
    /// [`relative_min_jacobian`]).
    pub relative_det: f64,
}

/// Smallest det J at a Gauss point divided by the cell's size cubed (L³ with L the longest
/// edge of the bounding box); a value ≤ 1e−12 means an inverted or flat cell.
pub fn relative_min_jacobian(coords: &[Vector3<f64>; 8]) -> f64 {
    let mut lo = coords[0];
    let mut hi = coords[0];
    for c in coords {
        lo = lo.inf(c);
        hi = hi.sup(c);
    }
    let size = (hi - lo).max();
    let scale = (size * size * size).max(f64::MIN_POSITIVE);
    GAUSS_DERIVATIVES
        .iter()
        .map(|dn| jacobian(coords, dn).determinant() / scale)
        .fold(f64::INFINITY, f64::min)
}

/// The eight Gauss points of a cell mapped to physical space.
pub fn mapped_points(coords: &[Vector3<f64>; 8]) -> Result<[MappedPoint; 8], InvertedCell> {
    let mut out = [MappedPoint {
        volume: 0.0,
        gradients: [Vector3::zeros(); 8],
    }; 8];
    for (g, dn) in GAUSS_DERIVATIVES.iter().enumerate() {
        let j = jacobian(coords, dn);
        let det = j.determinant();
        let inv_t = match j.try_inverse() {
            Some(inv) if det > 0.0 => inv.transpose(),
            _ => {
                return Err(InvertedCell {
                    relative_det: relative_min_jacobian(coords),
                })
            }
        };
        out[g].volume = det;
        for a in 0..8 {
            out[g].gradients[a] = inv_t * dn[a];
        }
    }
    Ok(out)
}

/// An element stiffness matrix as 3×3 blocks: `k[a][b][(i, j)]` = ∂f_{a,i}/∂u_{b,j}, the force on
/// node a along axis i per unit displacement of node b along axis j.
pub type ElementStiffness = [[Matrix3<f64>; 8]; 8];

/// Element stiffness K_e = ∫ Bᵀ D B dV for an isotropic material, written block-wise:
/// K_ab = ∫ (λ ∇N_a ∇N_bᵀ + μ ∇N_b ∇N_aᵀ + μ (∇N_a·∇N_b) I) dV.
/// Its assembly over elements is the stiffness K of the paper's equation (5).
pub fn element_stiffness(
    coords: &[Vector3<f64>; 8],
    material: &Material,
) -> Result<ElementStiffness, InvertedCell> {
    let points = mapped_points(coords)?;
    let (lambda, mu) = (material.lambda(), material.mu());
    let mut k = [[Matrix3::zeros(); 8]; 8];
    for p in &points {
        let (l, m) = (lambda * p.volume, mu * p.volume);
        for a in 0..8 {
            let ga = p.gradients[a];
            for b in a..8 {
                let gb = p.gradients[b];
                let dot = m * ga.dot(&gb);
                let mut block = ga * gb.transpose() * l + gb * ga.transpose() * m;
                block[(0, 0)] += dot;
                block[(1, 1)] += dot;
                block[(2, 2)] += dot;
                k[a][b] += block;
            }
        }
    }
    for a in 0..8 {
        for b in 0..a {
            k[a][b] = k[b][a].transpose();
        }
    }
    Ok(k)
}

/// Consistent nodal forces of a uniform body force density `b` (N/m³): f_a = ∫ N_a b dV
/// (the term RB of the paper's equation (4)).
pub fn element_body_force(
    coords: &[Vector3<f64>; 8],
    b: &Vector3<f64>,
) -> Result<[Vector3<f64>; 8], InvertedCell> {
    let mut f = [Vector3::zeros(); 8];
    for (g, dn) in GAUSS_DERIVATIVES.iter().enumerate() {
        let det = jacobian(coords, dn).determinant();
        if det <= 0.0 {
            return Err(InvertedCell {
                relative_det: relative_min_jacobian(coords),
            });
        }
        let n = shape(&GAUSS_POINTS[g]);
        for a in 0..8 {
            f[a] += b * (n[a] * det);
        }
    }
    Ok(f)
}

/// Volume of a cell (sum of det J over the Gauss points; exact for trilinear cells).
pub fn cell_volume(coords: &[Vector3<f64>; 8]) -> f64 {
    GAUSS_DERIVATIVES
        .iter()
        .map(|dn| jacobian(coords, dn).determinant())
        .sum()
}

/// Small-strain tensor ε = sym(∇u) at each Gauss point, from nodal displacements.
pub fn gauss_strains(
    coords: &[Vector3<f64>; 8],
    u: &[Vector3<f64>; 8],
) -> Result<[Matrix3<f64>; 8], InvertedCell> {
    let points = mapped_points(coords)?;
    Ok(points.map(|p| {
        let mut grad = Matrix3::zeros();
        for a in 0..8 {
            grad += u[a] * p.gradients[a].transpose();
        }
        (grad + grad.transpose()) * 0.5
    }))
}

/// Rotation-free (Biot) strain U − I at each Gauss point, with F = I + ∇u = R·U the polar
/// decomposition: equal to the small strain for small rotations, and unchanged by any rigid
/// rotation of the cell, so that a flexed finger's flesh shows no spurious stress.
pub fn gauss_biot_strains(
    coords: &[Vector3<f64>; 8],
    u: &[Vector3<f64>; 8],
) -> Result<[Matrix3<f64>; 8], InvertedCell> {
    let points = mapped_points(coords)?;
    Ok(points.map(|p| {
        let mut f = Matrix3::identity();
        for a in 0..8 {
            f += u[a] * p.gradients[a].transpose();
        }
        right_stretch(&f) - Matrix3::identity()
    }))
}

/// The right stretch U of F = R·U (symmetric, positive definite where det F > 0). By Newton's
/// iteration on the rotation, R ← (R + R⁻ᵀ)/2 from R = F (Higham 1986: quadratic, a few
/// iterations for the strains of a finger or a ball, a 3×3 inverse each), then U = sym(Rᵀ·F);
/// where it does not settle (det F ≤ 0, a stretch near zero) by the eigenvectors of FᵀF, as
/// √(FᵀF).
pub fn right_stretch(f: &Matrix3<f64>) -> Matrix3<f64> {
    if f.determinant() > 0.0 {
        let mut r = *f;
        for _ in 0..20 {
            let Some(inv) = r.try_inverse() else { break };
            let next = (r + inv.transpose()) * 0.5;
            let change = (next - r).norm();
            r = next;
            if change <= 1e-14 * r.norm() {
                let u = r.transpose() * f;
                return (u + u.transpose()) * 0.5;
            }
        }
    }
    let eig = (f.transpose() * f).symmetric_eigen();
    let stretch = eig.eigenvalues.map(|l| l.max(0.0).sqrt());
    eig.eigenvectors * Matrix3::from_diagonal(&stretch) * eig.eigenvectors.transpose()
}

/// The rotation R of the polar decomposition F = R·U of the deformation gradient at the cell's
/// centre, F = I + ∇u there: the rigid turn of the cell, with which a corotated element
/// (K̃ = R·K_e·Rᵀ) sees no strain. A reflection (det F ≤ 0, a cell turned inside out) is an
/// error.
pub fn centre_rotation(
    coords: &[Vector3<f64>; 8],
    u: &[Vector3<f64>; 8],
) -> Result<Matrix3<f64>, InvertedCell> {
    let dn = shape_derivatives(&Vector3::zeros());
    let j = jacobian(coords, &dn);
    let inverted = || InvertedCell {
        relative_det: relative_min_jacobian(coords),
    };
    let inv_t = j.try_inverse().ok_or_else(inverted)?.transpose();
    let mut f = Matrix3::identity();
    for a in 0..8 {
        f += u[a] * (inv_t * dn[a]).transpose();
    }
    if f.determinant() <= 0.0 || !f.iter().all(|v| v.is_finite()) {
        return Err(inverted());
    }
    let svd = f.svd(true, true);
    let (Some(w), Some(vt)) = (svd.u, svd.v_t) else {
        return Err(inverted());
    };
    Ok(w * vt)
}

/// For each corner, the three neighbouring corners along the cell's edges, in right-handed order.
const CORNER_EDGES: [[usize; 3]; 8] = [
    [1, 3, 4],
    [2, 0, 5],
    [3, 1, 6],
    [0, 2, 7],
    [7, 5, 0],
    [4, 6, 1],
    [5, 7, 2],
    [6, 4, 3],
];

/// The scaled Jacobian of a cell: the smallest, over its eight corners, of det[e1 e2 e3] /
/// (|e1| |e2| |e3|) for the three edges leaving the corner. 1 for any rectangular box, ≤ 0 for
/// an inverted corner (and 0 at the collapsed corners of prisms and tetrahedra).
pub fn scaled_jacobian(coords: &[Vector3<f64>; 8]) -> f64 {
    let mut worst = f64::INFINITY;
    for (c, [a, b, d]) in CORNER_EDGES.iter().enumerate() {
        let (e1, e2, e3) = (
            coords[*a] - coords[c],
            coords[*b] - coords[c],
            coords[*d] - coords[c],
        );
        let scale = e1.norm() * e2.norm() * e3.norm();
        let q = if scale > 0.0 {
            e1.cross(&e2).dot(&e3) / scale
        } else {
            0.0
        };
        worst = worst.min(q);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Newton's right stretch against √(FᵀF) by eigenvectors, on stretches up to 3:1 turned by
    /// up to 170° about skew axes, sheared: the same U to 1e-12 of its size, symmetric, with
    /// R = F·U⁻¹ a rotation. An inverted F takes the eigenvector route.
    #[test]
    fn the_right_stretch_by_newton_is_the_square_root_of_c() {
        let eigen = |f: &Matrix3<f64>| {
            let eig = (f.transpose() * f).symmetric_eigen();
            let s = eig.eigenvalues.map(|l| l.sqrt());
            eig.eigenvectors * Matrix3::from_diagonal(&s) * eig.eigenvectors.transpose()
        };
        let mut worst = 0.0f64;
        for k in 0..200 {
            let t = k as f64;
            let axis = nalgebra::Unit::new_normalize(Vector3::new(
                (t * 1.7).sin(),
                (t * 0.9).cos(),
                0.3 + (t * 2.3).sin(),
            ));
            let turn = nalgebra::Rotation3::from_axis_angle(&axis, (t * 0.85) % 2.97);
            let stretch = Matrix3::new(
                1.0 + 0.5 * (t * 0.37).sin(),
                0.2 * (t * 0.11).cos(),
                0.0,
                0.0,
                1.0 + 0.4 * (t * 0.53).cos(),
                0.1 * (t * 0.71).sin(),
                0.0,
                0.0,
                0.6 + 0.9 * ((t * 0.29).sin() + 1.0) / 2.0,
            );
            let f = turn.matrix() * stretch;
            let u = right_stretch(&f);
            let exact = eigen(&f);
            worst = worst.max((u - exact).norm() / exact.norm());
            assert!((u - u.transpose()).norm() < 1e-13 * u.norm());
            let r = f * u.try_inverse().unwrap();
            assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-11);
        }
        assert!(worst < 1e-12, "{worst}");
        let inverted = Matrix3::from_diagonal(&Vector3::new(-1.0, 1.2, 0.9));
        assert!((right_stretch(&inverted) - eigen(&inverted)).norm() < 1e-12);
    }

    #[test]
    fn local_coordinates_invert_the_trilinear_map_of_a_distorted_cell() {
        // A unit cube sheared and with one corner pulled out: a genuinely trilinear map.
        let mut coords = NODE_SIGNS.map(|s| Vector3::new(s[0], s[1], s[2]) * 0.5);
        for c in &mut coords {
            c.x += 0.2 * c.z;
        }
        coords[6] += Vector3::new(0.15, 0.1, 0.05);
        for xi in [
            Vector3::new(0.3, -0.4, 0.7),
            Vector3::new(-0.9, 0.95, -0.2),
            Vector3::new(1.3, 0.0, 0.0),
        ] {
            let n = shape(&xi);
            let x: Vector3<f64> = (0..8).map(|a| coords[a] * n[a]).sum();
            let back = local_coordinates(&coords, &x);
            assert!((back - xi).norm() < 1e-12, "{xi:?} -> {back:?}");
        }
    }
}
