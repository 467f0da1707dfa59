//! The sparse pipeline against an independent, deliberately plain implementation written here:
//! an explicit 6×24 strain-displacement matrix B, the 6×6 Voigt matrix D, a dense global K, and a
//! dense LU solve of the partitioned system (6)–(8). Nothing is shared with `fem` but the mesh.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, Vector3};
use prehensile::fem::assembly::{assemble, StiffnessPattern};
use prehensile::fem::loads::add_gravity;
use prehensile::fem::solve::{FillOrdering, PartitionedSolver};
use prehensile::fem::{DofPartition, Material};
use prehensile::mesh::{box_mesh, Mesh};
use std::sync::Arc;

fn d_matrix(m: &Material) -> SMatrix<f64, 6, 6> {
    let (e, nu) = (m.young, m.poisson);
    let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mut d = SMatrix::<f64, 6, 6>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            d[(i, j)] = if i == j { c * (1.0 - nu) } else { c * nu };
        }
        d[(3 + i, 3 + i)] = c * (1.0 - 2.0 * nu) / 2.0;
    }
    d
}

/// Reference element: K = Σ_g Bᵀ D B det J, f = Σ_g Nᵀ ρ g det J.
fn reference_element(
    x: &[Vector3<f64>; 8],
    m: &Material,
    g: &Vector3<f64>,
) -> (SMatrix<f64, 24, 24>, [f64; 24]) {
    let corners = [
        (-1., -1., -1.),
        (1., -1., -1.),
        (1., 1., -1.),
        (-1., 1., -1.),
        (-1., -1., 1.),
        (1., -1., 1.),
        (1., 1., 1.),
        (-1., 1., 1.),
    ];
    let q = 1.0 / 3f64.sqrt();
    let d = d_matrix(m);
    let mut k = SMatrix::<f64, 24, 24>::zeros();
    let mut f = [0.0; 24];
    for &(s, t, u) in &[
        (-q, -q, -q),
        (q, -q, -q),
        (q, q, -q),
        (-q, q, -q),
        (-q, -q, q),
        (q, -q, q),
        (q, q, q),
        (-q, q, q),
    ] {
        let mut dn = [[0.0; 3]; 8];
        let mut n = [0.0; 8];
        for (a, &(xa, ya, za)) in corners.iter().enumerate() {
            n[a] = 0.125 * (1.0 + xa * s) * (1.0 + ya * t) * (1.0 + za * u);
            dn[a] = [
                0.125 * xa * (1.0 + ya * t) * (1.0 + za * u),
                0.125 * ya * (1.0 + xa * s) * (1.0 + za * u),
                0.125 * za * (1.0 + xa * s) * (1.0 + ya * t),
            ];
        }
        let mut jac = Matrix3::<f64>::zeros();
        for a in 0..8 {
            for i in 0..3 {
                for j in 0..3 {
                    jac[(i, j)] += x[a][i] * dn[a][j];
                }
            }
        }
        let det = jac.determinant();
        let jinv = jac.try_inverse().unwrap();
        let mut b = SMatrix::<f64, 6, 24>::zeros();
        for a in 0..8 {
            let mut gx = [0.0; 3];
            for i in 0..3 {
                for j in 0..3 {
                    gx[i] += jinv[(j, i)] * dn[a][j];
                }
            }
            b[(0, 3 * a)] = gx[0];
            b[(1, 3 * a + 1)] = gx[1];
            b[(2, 3 * a + 2)] = gx[2];
            b[(3, 3 * a)] = gx[1];
            b[(3, 3 * a + 1)] = gx[0];
            b[(4, 3 * a + 1)] = gx[2];
            b[(4, 3 * a + 2)] = gx[1];
            b[(5, 3 * a)] = gx[2];
            b[(5, 3 * a + 2)] = gx[0];
        }
        k += b.transpose() * d * b * det;
        for a in 0..8 {
            for i in 0..3 {
                f[3 * a + i] += n[a] * m.density * g[i] * det;
            }
        }
    }
    (k, f)
}

fn distorted_mesh() -> Mesh {
    let mut mesh = box_mesh(Vector3::zeros(), Vector3::new(0.3, 0.2, 0.2), [3, 2, 2]);
    for (n, p) in mesh.nodes.iter_mut().enumerate() {
        let k = n as f64;
        *p += Vector3::new((k * 1.7).sin(), (k * 0.9).cos(), (k * 2.3).sin()) * 0.012;
    }
    // Collapse one cell into a prism to include the degenerate form.
    let c = mesh.cells[5];
    mesh.cells[5] = [c[0], c[1], c[2], c[2], c[4], c[5], c[6], c[6]];
    mesh
}

#[test]
fn sparse_partitioned_solve_matches_a_dense_reference_implementation() {
    let mesh = distorted_mesh();
    let rubber = Material {
        young: 1.0e6,
        poisson: 0.3,
        density: 1100.0,
    };
    let bone = Material {
        young: 1.5e10,
        poisson: 0.22,
        density: 1900.0,
    };
    let materials: Vec<Material> = (0..mesh.cell_count())
        .map(|c| if c % 3 == 0 { bone } else { rubber })
        .collect();
    let g = Vector3::new(0.0, 0.0, -9.81);
    let ndof = 3 * mesh.node_count();

    // Boundary conditions: x = 0 face clamped; the far face pushed along z by 1 mm in z only;
    // a point force on one free node.
    let mut mask = vec![false; ndof];
    let mut values = vec![0.0; ndof];
    for (n, p) in mesh.nodes.iter().enumerate() {
        if p.x < 0.02 {
            for i in 0..3 {
                mask[3 * n + i] = true;
            }
        } else if p.x > 0.28 {
            mask[3 * n + 2] = true;
            values[3 * n + 2] = -1e-3;
        }
    }
    let mut loads = vec![0.0; ndof];
    add_gravity(&mut loads, &mesh, &materials, 0..mesh.cell_count(), &g).unwrap();
    let free_node = (0..mesh.node_count())
        .find(|&n| !mask[3 * n] && !mask[3 * n + 2])
        .unwrap();
    loads[3 * free_node + 1] += 3.5;

    // The pipeline under test.
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let k = assemble(&pattern, &mesh, &materials).unwrap();
    let sol = PartitionedSolver::new(FillOrdering::NestedDissection)
        .solve(
            &k,
            &DofPartition::new(mask.clone()),
            &values,
            &loads,
            &mesh.nodes,
        )
        .unwrap();

    // The reference: dense K and dense LU on K11.
    let mut kd = DMatrix::<f64>::zeros(ndof, ndof);
    let mut fd = DVector::<f64>::zeros(ndof);
    for (c, cell) in mesh.cells.iter().enumerate() {
        let (ke, fe) = reference_element(&mesh.cell_coords(c), &materials[c], &g);
        for a in 0..24 {
            fd[3 * cell[a / 3] + a % 3] += fe[a];
            for b in 0..24 {
                kd[(3 * cell[a / 3] + a % 3, 3 * cell[b / 3] + b % 3)] += ke[(a, b)];
            }
        }
    }
    fd[3 * free_node + 1] += 3.5;
    let free: Vec<usize> = (0..ndof).filter(|&d| !mask[d]).collect();
    let fixed: Vec<usize> = (0..ndof).filter(|&d| mask[d]).collect();
    let k11 = kd.select_rows(&free).select_columns(&free);
    let k12 = kd.select_rows(&free).select_columns(&fixed);
    let uk = DVector::from_iterator(fixed.len(), fixed.iter().map(|&d| values[d]));
    let rk = DVector::from_iterator(free.len(), free.iter().map(|&d| fd[d]));
    let uu = k11.lu().solve(&(rk - k12 * &uk)).unwrap();
    let mut u = DVector::<f64>::zeros(ndof);
    for (i, &d) in free.iter().enumerate() {
        u[d] = uu[i];
    }
    for (i, &d) in fixed.iter().enumerate() {
        u[d] = uk[i];
    }
    let ru = &kd * &u - &fd;

    let umax = u.amax();
    let rmax = fixed.iter().map(|&d| ru[d].abs()).fold(0.0, f64::max);
    for d in 0..ndof {
        assert!(
            (sol.displacement[d] - u[d]).abs() < 1e-10 * umax,
            "dof {d}: {} vs {}",
            sol.displacement[d],
            u[d]
        );
    }
    for &d in &fixed {
        assert!(
            (sol.reaction[d] - ru[d]).abs() < 1e-9 * rmax,
            "reaction {d}: {} vs {}",
            sol.reaction[d],
            ru[d]
        );
    }
    // Applied loads plus reactions balance (equilibrium of the whole body).
    for i in 0..3 {
        let applied: f64 = (0..mesh.node_count()).map(|n| loads[3 * n + i]).sum();
        let reactions: f64 = (0..mesh.node_count())
            .map(|n| sol.reaction[3 * n + i])
            .sum();
        assert!(
            (applied + reactions).abs() < 1e-9 * rmax,
            "axis {i}: {applied} + {reactions}"
        );
    }
}
