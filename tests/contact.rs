//! Contact against rigid obstacles: exact uniform pressure under a block, action and reaction,
//! no penetration at convergence, and Hertz contact of an elastic ball on a rigid plane.

use nalgebra::Vector3;
use prehensile::contact::{solve_with_obstacles, ContactSettings, Obstacle};
use prehensile::fem::assembly::{assemble, StiffnessPattern};
use prehensile::fem::solve::{FillOrdering, PartitionedSolver};
use prehensile::fem::{DofPartition, Material};
use prehensile::mesh::{box_mesh, sphere_mesh, Mesh};
use std::sync::Arc;

const SETTINGS: ContactSettings = ContactSettings {
    tolerance: 1e-12,
    max_iterations: 50,
    method: prehensile::contact::ContactMethod::Lagrange,
    change_tolerance: 1e-9,
    relaxation: prehensile::contact::Relaxation::Aitken,
    search_depth: 0.01,
    pairs: prehensile::contact::PairSides::SkinNodes,
};

/// Solves `mesh` with the dofs for which `fix` returns a value prescribed, against `obstacles`.
fn solve(
    mesh: &Mesh,
    material: Material,
    fix: impl Fn(usize, &Vector3<f64>) -> Option<f64>,
    obstacles: &[Obstacle],
) -> prehensile::contact::ContactResult {
    let pattern = Arc::new(StiffnessPattern::new(mesh));
    let k = assemble(&pattern, mesh, &vec![material; mesh.cells.len()]).unwrap();
    let dofs = 3 * mesh.nodes.len();
    let mut mask = vec![false; dofs];
    let mut values = vec![0.0; dofs];
    for (n, p) in mesh.nodes.iter().enumerate() {
        for a in 0..3 {
            if let Some(v) = fix(3 * n + a, p) {
                mask[3 * n + a] = true;
                values[3 * n + a] = v;
            }
        }
    }
    let partition = DofPartition::new(mask);
    let candidates: Vec<usize> = (0..mesh.nodes.len()).collect();
    let mut solver = PartitionedSolver::new(FillOrdering::NestedDissection);
    solve_with_obstacles(
        &mut solver,
        &k,
        &partition,
        &values,
        &vec![0.0; dofs],
        &mesh.nodes,
        &candidates,
        obstacles,
        SETTINGS,
    )
    .unwrap()
}

#[test]
fn a_block_pressed_on_a_rigid_plane_carries_a_uniform_pressure() {
    let (e, h, delta, n) = (1.0e6, 1.0, 1.0e-3, 4);
    let mesh = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, h), [n, n, n]);
    let material = Material {
        young: e,
        poisson: 0.0,
        density: 0.0,
    };
    // The top face is pushed down by δ (and held sideways); the bottom rests on the table z = 0.
    let table = Obstacle::Plane {
        point: Vector3::zeros(),
        normal: Vector3::z(),
    };
    let r = solve(
        &mesh,
        material,
        |d, p| (p.z == h).then_some(if d % 3 == 2 { -delta } else { 0.0 }),
        &[table],
    );
    // σ = E·δ/H over the unit area; each bottom node carries its tributary share.
    let total: f64 = r.contacts.iter().map(|c| c.force).sum();
    assert_eq!(r.contacts.len(), (n + 1) * (n + 1));
    assert!(
        (total - e * delta / h).abs() < 1e-9 * e * delta,
        "total {total}"
    );
    let cell = 1.0 / n as f64;
    for c in &r.contacts {
        let p = mesh.nodes[c.node];
        let on_edge = |v: f64| v == 0.0 || (v - 1.0).abs() < 1e-12;
        let share = match (on_edge(p.x), on_edge(p.y)) {
            (true, true) => 0.25,
            (true, false) | (false, true) => 0.5,
            _ => 1.0,
        } * cell
            * cell;
        assert!(
            (c.force - e * delta / h * share).abs() < 1e-9,
            "node {}",
            c.node
        );
        assert!(c.gap.abs() < 1e-12);
    }
    // Action and reaction: the top supports take exactly what the table gives.
    let top: f64 = (0..mesh.nodes.len())
        .map(|n| r.solution.reaction[3 * n + 2])
        .sum();
    assert!((top + total).abs() < 1e-9 * total, "top {top} vs {total}");
    // One factorization; the contact constraints cost substitutions only.
    assert_eq!(r.factorizations, 1);
    assert!(r.max_penetration <= SETTINGS.tolerance);
}

/// An elastic ball of radius R (E, ν) pressed by δ onto the rigid plane z = 0 through its top
/// cap; returns (total force, contact radius estimate, peak pressure estimate, max penetration).
fn hertz(cells: usize) -> (f64, f64, f64, f64, usize) {
    let (r, e, nu, delta) = (0.05, 1.0e5, 0.3, 0.0015);
    let mesh = sphere_mesh(Vector3::new(0.0, 0.0, r), r, cells);
    let material = Material {
        young: e,
        poisson: nu,
        density: 0.0,
    };
    let table = Obstacle::Plane {
        point: Vector3::zeros(),
        normal: Vector3::z(),
    };
    let res = solve(
        &mesh,
        material,
        |d, p| (p.z > 1.9 * r).then_some(if d % 3 == 2 { -delta } else { 0.0 }),
        &[table],
    );
    let force: f64 = res.contacts.iter().map(|c| c.force).sum();
    // Contact radius: the Hertz pressure p0·√(1 − ρ²/a²) has mean over the disc (2/3)·p0 and
    // second moment ∫ρ² p dA / F = (2/5)·a²; the latter from the nodal forces estimates a.
    let second: f64 = res
        .contacts
        .iter()
        .map(|c| {
            let p = mesh.nodes[c.node];
            c.force * (p.x * p.x + p.y * p.y)
        })
        .sum::<f64>()
        / force;
    let a = (second * 2.5).sqrt();
    let p0 = 1.5 * force / (std::f64::consts::PI * a * a);
    (force, a, p0, res.max_penetration, res.contacts.len())
}

#[test]
fn hertz_contact_of_a_ball_on_a_rigid_plane() {
    let (r, e, nu) = (0.05f64, 1.0e5f64, 0.3f64);
    let e_star = e / (1.0 - nu * nu);
    let mut errors = Vec::new();
    let mut peaks = Vec::new();
    for cells in [12, 18, 26] {
        let (f, a, p0, pen, active) = hertz(cells);
        let a_hertz = (3.0 * f * r / (4.0 * e_star)).cbrt();
        let p0_hertz = 1.5 * f / (std::f64::consts::PI * a_hertz * a_hertz);
        let (ea, ep) = ((a / a_hertz - 1.0).abs(), (p0 / p0_hertz - 1.0).abs());
        println!(
            "{cells} cells: F = {f:.3} N, {active} nodes in contact, a = {:.3} mm (Hertz {:.3}, \
             error {:.1} %), p0 = {:.0} Pa (Hertz {:.0}, error {:.1} %), penetration {pen:.1e} m",
            a * 1e3,
            a_hertz * 1e3,
            ea * 100.0,
            p0,
            p0_hertz,
            ep * 100.0
        );
        assert!(pen <= 1e-12);
        errors.push(ea);
        peaks.push(ep);
    }
    // The contact radius approaches Hertz's as the mesh is refined (measured 23 %, 9.7 %, 4.6 %;
    // the peak pressure 34 %, 17 %, 8.5 %).
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
    assert!(errors[2] < 0.07, "{errors:?}");
    assert!(peaks[0] > peaks[2] && peaks[2] < 0.12, "{peaks:?}");
}

#[test]
fn the_ball_on_table_scene_balances_and_reports_its_tactile_map() {
    let solved =
        prehensile::headless::solve_scene_file("assets/scenes/ball-on-table.toml".as_ref())
            .unwrap();
    let f = &solved.report.frames[0];
    let c = f.contact.as_ref().expect("a contact report");
    let table = c.obstacles["table"].force;
    let finger = f.constraints["finger"].reaction;
    println!(
        "table {table:?} N on {} nodes, finger {finger:?} N, {} iterations, {} substitutions, \
         peak pressure {:.0} Pa, imbalance {:?}",
        c.obstacles["table"].nodes,
        c.iterations,
        c.substitutions,
        c.max_pressure,
        f.equilibrium.imbalance
    );
    // Action and reaction: the table pushes up exactly what the finger pushes down.
    assert!(table[2] > 10.0);
    assert!((table[2] + finger[2]).abs() < 1e-9 * table[2]);
    for i in 0..3 {
        assert!(f.equilibrium.imbalance[i].abs() < 1e-9 * table[2]);
    }
    assert!(c.max_penetration <= 1e-9 * 0.1);
    assert_eq!(c.factorizations, 1);
    // Hertz: p0 = 3F/(2πa²) with a = (3FR/4E*)^(1/3) — the nodal tactile map comes within 20 %
    // at this mesh (a pressure at nodes, averaged over their tributary areas, under-reads the peak).
    let (r, e_star) = (0.05, 1.0e6 / (1.0 - 0.45 * 0.45));
    let a = (3.0 * table[2] * r / (4.0 * e_star)).cbrt();
    let p0 = 1.5 * table[2] / (std::f64::consts::PI * a * a);
    assert!(
        (c.max_pressure / p0 - 1.0).abs() < 0.2,
        "{} vs {p0}",
        c.max_pressure
    );
}
