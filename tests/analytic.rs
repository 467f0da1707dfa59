//! Validation against closed-form elasticity: the cantilever (with its refinement study), the
//! thick-walled sphere under internal pressure (Lamé), a column under its own weight, and a
//! two-material bar (per-element materials).

use crate::common;
use common::{rel, solve_mesh};
use nalgebra::Vector3;
use prehensile::fem::loads::{add_gravity, add_shared_force};
use prehensile::fem::Material;
use prehensile::headless::solve_scene;
use prehensile::mesh::box_mesh;
use prehensile::scene::Scene;

/// Tip deflection of a cantilever L×h×h clamped at x = 0, loaded by a total transverse force P
/// shared by the nodes of the free end, meshed with (8k)×k×k hexahedra.
fn cantilever_tip(k: usize, poisson: f64) -> f64 {
    let (l, h, p) = (8.0, 1.0, -1.0);
    let mesh = box_mesh(Vector3::zeros(), Vector3::new(l, h, h), [8 * k, k, k]);
    let m = Material {
        young: 1.0e6,
        poisson,
        density: 0.0,
    };
    let end: Vec<usize> = (0..mesh.node_count())
        .filter(|&n| (mesh.nodes[n].x - l).abs() < 1e-9)
        .collect();
    let mut loads = vec![0.0; 3 * mesh.node_count()];
    add_shared_force(&mut loads, &end, &Vector3::new(0.0, 0.0, p));
    let (sol, _) = solve_mesh(
        &mesh,
        &vec![m; mesh.cell_count()],
        |_, x| {
            if x.x.abs() < 1e-9 {
                [Some(0.0); 3]
            } else {
                [None; 3]
            }
        },
        &loads,
    );
    end.iter()
        .map(|&n| sol.displacement[3 * n + 2])
        .sum::<f64>()
        / end.len() as f64
}

/// Timoshenko beam: δ = PL³/(3EI) + PL/(κGA), κ = 5/6.
fn timoshenko_tip(poisson: f64) -> f64 {
    let (l, h, p, e) = (8.0f64, 1.0f64, -1.0, 1.0e6);
    let i = h.powi(4) / 12.0;
    let g = e / (2.0 * (1.0 + poisson));
    p * l.powi(3) / (3.0 * e * i) + p * l / (5.0 / 6.0 * g * h * h)
}

#[test]
fn cantilever_converges_to_beam_theory_and_shows_shear_locking_when_coarse() {
    let exact = timoshenko_tip(0.3);
    let ratios: Vec<f64> = [1, 2, 4]
        .iter()
        .map(|&k| cantilever_tip(k, 0.3) / exact)
        .collect();
    println!("cantilever tip / Timoshenko for 8k×k×k meshes, k = 1, 2, 4: {ratios:?}");
    // Fully integrated hex8 locks in bending: one element through the thickness gives about
    // 70 % of the beam deflection (its parasitic shear stiffens it)...
    assert!(
        ratios[0] > 0.6 && ratios[0] < 0.8,
        "k=1 ratio {}",
        ratios[0]
    );
    // ...and refinement removes the locking monotonically...
    assert!(ratios[0] < ratios[1] && ratios[1] < ratios[2], "{ratios:?}");
    // ...with the error falling roughly fourfold per halving (second order in h).
    let (e1, e2, e4) = (1.0 - ratios[0], 1.0 - ratios[1], 1.0 - ratios[2]);
    assert!(
        e1 / e2 > 2.5 && e2 / e4 > 2.5,
        "error ratios {} {}",
        e1 / e2,
        e2 / e4
    );
    assert!(
        ratios[2] > 0.95 && ratios[2] < 1.02,
        "k=4 ratio {}",
        ratios[2]
    );
}

/// Lamé's thick sphere: u(r) = p a³/[E(b³−a³)]·[(1−2ν) r + (1+ν) b³/(2r²)].
fn lame(r: f64, a: f64, b: f64, p: f64, e: f64, nu: f64) -> f64 {
    p * a.powi(3) / (e * (b.powi(3) - a.powi(3)))
        * ((1.0 - 2.0 * nu) * r + (1.0 + nu) * b.powi(3) / (2.0 * r * r))
}

fn lame_scene(cells: usize, layers: usize) -> String {
    format!(
        r#"
[[material]]
name = "m"
young = 1.0e6
poisson = 0.3
[[body]]
name = "sphere"
material = "m"
shape = {{ shell = {{ center = [0, 0, 0], inner_radius = 0.05, outer_radius = 0.1, cells = {cells}, layers = {layers} }} }}
[[load]]
body = "sphere"
where = {{ surface = "inner" }}
pressure = 1.0e4
# Rigid motions held by tangential constraints at three poles, where the exact field is radial.
[[constraint]]
name = "px"
body = "sphere"
where = {{ point = [0.1, 0, 0] }}
displacement = {{ y = 0, z = 0 }}
[[constraint]]
name = "py"
body = "sphere"
where = {{ point = [0, 0.1, 0] }}
displacement = {{ x = 0, z = 0 }}
[[constraint]]
name = "pz"
body = "sphere"
where = {{ point = [0, 0, 0.1] }}
displacement = {{ x = 0, y = 0 }}
"#
    )
}

/// Largest relative error of the radial displacement over all nodes, and the largest tangential
/// displacement relative to the inner radial displacement.
fn lame_errors(cells: usize, layers: usize) -> (f64, f64) {
    let scene = Scene::parse(&lame_scene(cells, layers), "lame").unwrap();
    let solved = solve_scene(&scene, "lame").unwrap();
    let sol = &solved.frames[0].solution;
    let exact_inner = lame(0.05, 0.05, 0.1, 1.0e4, 1.0e6, 0.3);
    let mut radial_err: f64 = 0.0;
    let mut tangential: f64 = 0.0;
    for (n, x) in solved.model.mesh.nodes.iter().enumerate() {
        let r = x.norm();
        let u = sol.node_displacement(n);
        let ur = u.dot(&(x / r));
        radial_err = radial_err.max(rel(ur, lame(r, 0.05, 0.1, 1.0e4, 1.0e6, 0.3)));
        tangential = tangential.max((u - x / r * ur).norm() / exact_inner);
    }
    // The reactions at the poles vanish: the pressure on the closed cavity is self-balanced.
    for c in solved.report.frames[0].constraints.values() {
        let f: f64 = c.reaction.iter().map(|v| v.abs()).sum();
        assert!(f < 1e-9 * 1.0e4 * 0.05 * 0.05, "pole reaction {f}");
    }
    (radial_err, tangential)
}

#[test]
fn thick_sphere_under_internal_pressure_matches_lame() {
    let coarse = lame_errors(4, 2);
    let medium = lame_errors(8, 4);
    let fine = lame_errors(16, 8);
    println!(
        "Lamé radial error (max over nodes): {:.4} {:.4} {:.4}",
        coarse.0, medium.0, fine.0
    );
    println!(
        "Lamé tangential / u(a): {:.4} {:.4} {:.4}",
        coarse.1, medium.1, fine.1
    );
    // Second-order convergence: each halving of the cell size divides the error by about four.
    assert!(
        coarse.0 / medium.0 > 2.5 && medium.0 / fine.0 > 2.5,
        "{coarse:?} {medium:?} {fine:?}"
    );
    assert!(fine.0 < 0.015, "fine radial error {}", fine.0);
    assert!(fine.1 < 0.005, "fine tangential error {}", fine.1);
}

#[test]
fn column_under_its_own_weight_matches_one_dimensional_solution_at_the_nodes() {
    // ν = 0 makes the 3D problem exactly 1D: u_z(z) = −ρg/E (Lz − z²/2). Linear elements with
    // consistent loads are nodally exact in 1D.
    let (l, rho, g, e) = (1.0, 1000.0, 9.81, 1.0e5);
    let mesh = box_mesh(Vector3::zeros(), Vector3::new(0.1, 0.1, l), [2, 2, 10]);
    let m = Material {
        young: e,
        poisson: 0.0,
        density: rho,
    };
    let materials = vec![m; mesh.cell_count()];
    let mut loads = vec![0.0; 3 * mesh.node_count()];
    let weight = add_gravity(
        &mut loads,
        &mesh,
        &materials,
        0..mesh.cell_count(),
        &Vector3::new(0.0, 0.0, -g),
    )
    .unwrap();
    assert!(rel(weight.z, -rho * g * 0.01 * l) < 1e-12);
    let (sol, stress) = solve_mesh(
        &mesh,
        &materials,
        |_, x| {
            if x.z.abs() < 1e-12 {
                [Some(0.0); 3]
            } else {
                [Some(0.0), Some(0.0), None]
            }
        },
        &loads,
    );
    for (n, x) in mesh.nodes.iter().enumerate() {
        let exact = -rho * g / e * (l * x.z - x.z * x.z / 2.0);
        assert!(
            (sol.displacement[3 * n + 2] - exact).abs() < 1e-12 * (rho * g * l * l / e),
            "node {n}"
        );
    }
    // Each element carries the exact mean strain of its span, which for a linear stress is the
    // stress at its mid-height: σzz = −ρg(L − z_mid).
    for c in 0..mesh.cell_count() {
        let z_mid = mesh.cell_coords(c).iter().map(|p| p.z).sum::<f64>() / 8.0;
        let mean = stress.gauss[c].iter().map(|s| s[(2, 2)]).sum::<f64>() / 8.0;
        assert!(rel(mean, -rho * g * (l - z_mid)) < 1e-9, "cell {c}: {mean}");
    }
}

#[test]
fn bar_of_two_materials_in_series_stretches_by_the_sum_of_its_parts() {
    // Composition of sub-objects with their own properties: F·L1/(E1·A) + F·L2/(E2·A), ν = 0.
    let mesh = box_mesh(Vector3::zeros(), Vector3::new(2.0, 0.2, 0.2), [10, 2, 2]);
    let soft = Material {
        young: 1.0e5,
        poisson: 0.0,
        density: 0.0,
    };
    let hard = Material {
        young: 7.0e5,
        poisson: 0.0,
        density: 0.0,
    };
    let materials: Vec<Material> = (0..mesh.cell_count())
        .map(|c| {
            if mesh.cell_coords(c).iter().map(|p| p.x).sum::<f64>() / 8.0 < 1.2 {
                soft
            } else {
                hard
            }
        })
        .collect();
    let end: Vec<usize> = (0..mesh.node_count())
        .filter(|&n| (mesh.nodes[n].x - 2.0).abs() < 1e-12)
        .collect();
    let mut loads = vec![0.0; 3 * mesh.node_count()];
    let f = 10.0;
    // Consistent loads of a uniform traction on a 2×2 face: corner 1/16, edge 2/16, centre 4/16.
    for &n in &end {
        let p = mesh.nodes[n];
        let wy = if p.y == 0.0 || (p.y - 0.2).abs() < 1e-12 {
            1.0
        } else {
            2.0
        };
        let wz = if p.z == 0.0 || (p.z - 0.2).abs() < 1e-12 {
            1.0
        } else {
            2.0
        };
        loads[3 * n] = f * wy * wz / 16.0;
    }
    // The x = 0 face slides in its plane; three of its corners hold the lateral rigid motions.
    let (sol, _) = solve_mesh(
        &mesh,
        &materials,
        |n, x| {
            if x.x == 0.0 {
                if n == 0 {
                    [Some(0.0); 3]
                } else if x.y == 0.0 && x.z == 0.2 {
                    [Some(0.0), Some(0.0), None]
                } else if x.y == 0.2 && x.z == 0.0 {
                    [Some(0.0), None, Some(0.0)]
                } else {
                    [Some(0.0), None, None]
                }
            } else {
                [None; 3]
            }
        },
        &loads,
    );
    let a = 0.04;
    let exact = f * 1.2 / (soft.young * a) + f * 0.8 / (hard.young * a);
    for &n in &end {
        assert!(
            rel(sol.displacement[3 * n], exact) < 1e-10,
            "node {n}: {} vs {exact}",
            sol.displacement[3 * n]
        );
    }
}

#[test]
fn scene_with_a_material_region_and_an_end_traction_stretches_exactly() {
    // The same bar as above, through a scene: a [[region]] of stiffer material and a traction
    // load on the end face. Total force 250 Pa × 0.04 m² = 10 N.
    let text = r#"
[[material]]
name = "soft"
young = 1.0e5
poisson = 0.0
[[material]]
name = "hard"
young = 7.0e5
poisson = 0.0
[[body]]
name = "bar"
material = "soft"
shape = { box = { min = [0, 0, 0], max = [2.0, 0.2, 0.2], cells = [10, 2, 2] } }
[[region]]
body = "bar"
material = "hard"
where = { box = { min = [1.2, -1, -1], max = [3, 1, 1] } }
[[constraint]]
name = "slide"
body = "bar"
where = { face = "x-" }
displacement = { x = 0 }
[[constraint]]
name = "pin"
body = "bar"
where = { point = [0, 0, 0] }
displacement = [0, 0, 0]
[[constraint]]
name = "roller-y"
body = "bar"
where = { point = [0, 0.2, 0] }
displacement = { z = 0 }
[[constraint]]
name = "roller-z"
body = "bar"
where = { point = [0, 0, 0.2] }
displacement = { y = 0 }
[[load]]
name = "pull"
body = "bar"
where = { face = "x+" }
traction = [250.0, 0, 0]
[[probe]]
name = "end"
body = "bar"
point = [2.0, 0.1, 0.1]
"#;
    let solved = solve_scene(&Scene::parse(text, "bar").unwrap(), "bar").unwrap();
    let f = &solved.report.frames[0];
    assert!(
        rel(f.loads["pull"][0], 10.0) < 1e-12,
        "{:?}",
        f.loads["pull"]
    );
    assert!(rel(f.constraints["slide"].reaction[0], -10.0) < 1e-10);
    let exact = 10.0 * 1.2 / (1.0e5 * 0.04) + 10.0 * 0.8 / (7.0e5 * 0.04);
    assert!(
        rel(f.probes["end"].displacement[0], exact) < 1e-10,
        "{} vs {exact}",
        f.probes["end"].displacement[0]
    );
}
