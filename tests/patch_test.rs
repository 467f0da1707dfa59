//! Patch tests: a linear displacement field imposed on the boundary of an irregular mesh must be
//! reproduced exactly inside, with constant stress — for distorted hexahedra (MacNeal & Harder
//! 1985) and for the degenerate prism and tetrahedron forms.

use crate::common;
use common::solve_mesh;
use nalgebra::{Matrix3, Vector3};
use prehensile::fem::Material;
use prehensile::mesh::{box_mesh, Hex, Mesh};

/// MacNeal & Harder's linear field: u = 1e-3(2x+y+z)/2, v = 1e-3(x+2y+z)/2, w = 1e-3(x+y+2z)/2.
fn linear_field(p: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(
        1e-3 * (2.0 * p.x + p.y + p.z) / 2.0,
        1e-3 * (p.x + 2.0 * p.y + p.z) / 2.0,
        1e-3 * (p.x + p.y + 2.0 * p.z) / 2.0,
    )
}

const STEEL_LIKE: Material = Material {
    young: 1.0e6,
    poisson: 0.25,
    density: 0.0,
};

/// The seven-element distorted unit cube of MacNeal & Harder (1985).
fn macneal_harder_cube() -> Mesh {
    let mut nodes: Vec<Vector3<f64>> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ]
    .into_iter()
    .map(Vector3::from)
    .collect();
    nodes.extend(
        [
            [0.249, 0.342, 0.192],
            [0.826, 0.288, 0.288],
            [0.850, 0.649, 0.263],
            [0.273, 0.750, 0.230],
            [0.320, 0.186, 0.643],
            [0.677, 0.305, 0.683],
            [0.788, 0.693, 0.644],
            [0.165, 0.745, 0.702],
        ]
        .into_iter()
        .map(Vector3::from),
    );
    let cells: Vec<Hex> = vec![
        [8, 9, 10, 11, 12, 13, 14, 15], // inner
        [0, 1, 2, 3, 8, 9, 10, 11],     // bottom
        [12, 13, 14, 15, 4, 5, 6, 7],   // top
        [0, 1, 9, 8, 4, 5, 13, 12],     // front (y = 0)
        [11, 10, 2, 3, 15, 14, 6, 7],   // back (y = 1)
        [0, 8, 11, 3, 4, 12, 15, 7],    // left (x = 0)
        [9, 1, 2, 10, 13, 5, 6, 14],    // right (x = 1)
    ];
    Mesh { nodes, cells }
}

/// Imposes the linear field on the nodes `on_boundary` selects, solves, and returns the largest
/// error of interior displacement and of Gauss-point stress against the exact constant stress.
fn patch_errors(mesh: &Mesh, on_boundary: impl Fn(&Vector3<f64>) -> bool) -> (f64, f64, usize) {
    let materials = vec![STEEL_LIKE; mesh.cell_count()];
    let loads = vec![0.0; 3 * mesh.node_count()];
    let (sol, stress) = solve_mesh(
        mesh,
        &materials,
        |_, p| {
            if on_boundary(p) {
                linear_field(p).map(Some).into()
            } else {
                [None; 3]
            }
        },
        &loads,
    );
    let interior = mesh.nodes.iter().filter(|p| !on_boundary(p)).count();
    let report = |u: f64, s: f64| {
        println!(
            "patch: {} cells, displacement error {u:.2e} m, stress error {s:.2e} Pa",
            mesh.cell_count()
        )
    };
    let u_err = (0..mesh.node_count())
        .map(|n| (sol.node_displacement(n) - linear_field(&mesh.nodes[n])).norm())
        .fold(0.0, f64::max);
    let exact = Matrix3::new(
        2000.0, 400.0, 400.0, 400.0, 2000.0, 400.0, 400.0, 400.0, 2000.0,
    );
    let s_err = stress
        .gauss
        .iter()
        .flatten()
        .chain(stress.nodal.iter())
        .map(|s| (s - exact).amax())
        .fold(0.0, f64::max);
    report(u_err, s_err);
    (u_err, s_err, interior)
}

fn on_unit_cube_boundary(p: &Vector3<f64>) -> bool {
    p.iter()
        .any(|&c| c.abs() < 1e-12 || (c - 1.0).abs() < 1e-12)
}

#[test]
fn macneal_harder_distorted_hexahedra_reproduce_constant_stress() {
    let mesh = macneal_harder_cube();
    let (u_err, s_err, interior) = patch_errors(&mesh, on_unit_cube_boundary);
    assert_eq!(interior, 8);
    // σx = σy = σz = 2000, τ = 400 everywhere, to round-off.
    assert!(u_err < 1e-15, "displacement error {u_err:e}");
    assert!(s_err < 1e-8, "stress error {s_err:e} Pa (of 2000)");
}

/// A 3×3×3 box with its interior nodes moved off the lattice.
fn perturbed_box() -> Mesh {
    let mut mesh = box_mesh(Vector3::zeros(), Vector3::from_element(1.0), [3, 3, 3]);
    for (n, p) in mesh.nodes.iter_mut().enumerate() {
        if !on_unit_cube_boundary(p) {
            let k = n as f64;
            *p += Vector3::new((k * 1.3).sin(), (k * 2.1).cos(), (k * 0.7).sin()) * 0.06;
        }
    }
    mesh
}

/// Splits every hexahedron into two prisms, written as hexahedra with a collapsed edge.
fn prisms(mesh: &Mesh) -> Mesh {
    let cells = mesh
        .cells
        .iter()
        .flat_map(|h| {
            [
                [h[0], h[1], h[2], h[2], h[4], h[5], h[6], h[6]],
                [h[0], h[2], h[3], h[3], h[4], h[6], h[7], h[7]],
            ]
        })
        .collect();
    Mesh {
        nodes: mesh.nodes.clone(),
        cells,
    }
}

/// Splits every hexahedron into six tetrahedra around its 0–6 diagonal, each written as a
/// hexahedron with nodes repeated (a, b, c, c, d, d, d, d).
fn tetrahedra(mesh: &Mesh) -> Mesh {
    const TETS: [[usize; 4]; 6] = [
        [0, 1, 2, 6],
        [0, 2, 3, 6],
        [0, 3, 7, 6],
        [0, 7, 4, 6],
        [0, 4, 5, 6],
        [0, 5, 1, 6],
    ];
    let cells = mesh
        .cells
        .iter()
        .flat_map(|h| {
            TETS.map(|t| {
                let [a, b, c, d] = t.map(|i| h[i]);
                [a, b, c, c, d, d, d, d]
            })
        })
        .collect();
    Mesh {
        nodes: mesh.nodes.clone(),
        cells,
    }
}

#[test]
fn degenerate_prisms_pass_the_patch_test() {
    let mesh = prisms(&perturbed_box());
    let (u_err, s_err, interior) = patch_errors(&mesh, on_unit_cube_boundary);
    assert_eq!(interior, 8);
    assert!(u_err < 1e-14, "displacement error {u_err:e}");
    assert!(s_err < 1e-7, "stress error {s_err:e} Pa");
}

#[test]
fn degenerate_tetrahedra_pass_the_patch_test() {
    let mesh = tetrahedra(&perturbed_box());
    let (u_err, s_err, interior) = patch_errors(&mesh, on_unit_cube_boundary);
    assert_eq!(interior, 8);
    assert!(u_err < 1e-14, "displacement error {u_err:e}");
    assert!(s_err < 1e-7, "stress error {s_err:e} Pa");
}

#[test]
fn tetrahedron_split_covers_the_volume_with_positive_jacobians() {
    use prehensile::fem::hex8::{cell_volume, relative_min_jacobian};
    let mesh = tetrahedra(&perturbed_box());
    let total: f64 = (0..mesh.cell_count())
        .map(|c| cell_volume(&mesh.cell_coords(c)))
        .sum();
    assert!((total - 1.0).abs() < 1e-12, "volume {total}");
    for c in 0..mesh.cell_count() {
        assert!(
            relative_min_jacobian(&mesh.cell_coords(c)) > 0.0,
            "cell {c}"
        );
    }
}
