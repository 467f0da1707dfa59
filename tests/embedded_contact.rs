//! Contact on points embedded in cells (issue 15, item 4: the smooth skin is the contact
//! surface). A point inside a hexahedron moves with the cell's trilinear field, Σ N_i(ξ) U_i, and
//! its contact force goes to the cell's nodes as N_i·R_C. Checked on blocks in uniform
//! compression, which hexahedra represent exactly: the force is E·A·δ/L to round-off whether the
//! points lie on the face (nine per face, more rows than the face's nodes can honour), below it
//! (extrapolated), or press a second deformable block (springs in series).

use nalgebra::Vector3;
use prehensile::contact::{
    solve_lagrange, ContactMethod, ContactProblem, ContactResult, ContactSettings, ContactSurface,
    EmbeddedPoints, Obstacle, PairSides, Relaxation, SurfacePair,
};
use prehensile::fem::assembly::{assemble, StiffnessPattern};
use prehensile::fem::hex8::{local_coordinates, shape};
use prehensile::fem::solve::{FillOrdering, PartitionedSolver};
use prehensile::fem::{DofPartition, Material};
use prehensile::mesh::{boundary_facets, box_mesh, Mesh};
use std::sync::Arc;

const E: f64 = 1.0e6;
const DELTA: f64 = 1.0e-3;

fn settings() -> ContactSettings {
    ContactSettings {
        tolerance: 1e-12,
        max_iterations: 200,
        method: ContactMethod::Lagrange,
        change_tolerance: 1e-12,
        relaxation: Relaxation::Aitken,
        search_depth: 0.2,
        pairs: PairSides::SkinNodes,
    }
}

/// Points at local (ξ, η) ∈ {1/6, 1/2, 5/6}² of the bottom face of every bottom cell of `mesh`
/// (cells whose lowest corner is at `z0`), moved down by `below`, embedded in their cell.
fn bottom_points(mesh: &Mesh, z0: f64, below: f64) -> EmbeddedPoints {
    let mut points = EmbeddedPoints::none(mesh.nodes.len());
    for cell in &mesh.cells {
        let coords = cell.map(|n| mesh.nodes[n]);
        let lo = coords
            .iter()
            .fold(Vector3::repeat(f64::INFINITY), |m, p| m.inf(p));
        let hi = coords
            .iter()
            .fold(Vector3::repeat(f64::NEG_INFINITY), |m, p| m.sup(p));
        if (lo.z - z0).abs() > 1e-12 {
            continue;
        }
        for a in [1.0 / 6.0, 0.5, 5.0 / 6.0] {
            for b in [1.0 / 6.0, 0.5, 5.0 / 6.0] {
                let p = Vector3::new(
                    lo.x + a * (hi.x - lo.x),
                    lo.y + b * (hi.y - lo.y),
                    z0 - below,
                );
                let n = shape(&local_coordinates(&coords, &p));
                points.push((0..8).map(|i| (cell[i], n[i])));
            }
        }
    }
    points
}

fn stiffness(mesh: &Mesh, young: impl Fn(usize) -> f64) -> prehensile::fem::assembly::Stiffness {
    let materials: Vec<Material> = (0..mesh.cells.len())
        .map(|c| Material {
            young: young(c),
            poisson: 0.0,
            density: 0.0,
        })
        .collect();
    let pattern = Arc::new(StiffnessPattern::new(mesh));
    assemble(&pattern, mesh, &materials).unwrap()
}

/// The block z ∈ [z0, z0 + 1] (unit section, 2×2×2 cells, ν = 0) with its top held laterally
/// and pushed down by δ onto the plane z = 0 through its embedded bottom points (`below` under
/// its bottom face); its bottom nodes are not candidates. Returns the result, the top's
/// reaction and the positions of the points at the solution.
fn block_on_plane(z0: f64, below: f64) -> (ContactResult, f64, Vec<Vector3<f64>>) {
    let mesh = box_mesh(
        Vector3::new(0.0, 0.0, z0),
        Vector3::new(1.0, 1.0, z0 + 1.0),
        [2, 2, 2],
    );
    let k = stiffness(&mesh, |_| E);
    let dofs = 3 * mesh.nodes.len();
    let mut mask = vec![false; dofs];
    let mut values = vec![0.0; dofs];
    for (n, p) in mesh.nodes.iter().enumerate() {
        if (p.z - (z0 + 1.0)).abs() < 1e-12 {
            mask[3 * n..3 * n + 3].fill(true);
            values[3 * n + 2] = -DELTA;
        }
    }
    let partition = DofPartition::new(mask);
    let points = bottom_points(&mesh, z0, below);
    let positions = points.extend(&mesh.nodes);
    let candidates: Vec<usize> = (mesh.nodes.len()..positions.len()).collect();
    let problem = ContactProblem {
        k: &k,
        partition: &partition,
        prescribed: &values,
        loads: &vec![0.0; dofs],
        positions: &positions,
        embedded: &points,
        obstacles: &[Obstacle::Plane {
            point: Vector3::zeros(),
            normal: Vector3::z(),
        }],
        obstacle_candidates: &candidates,
        surfaces: &[],
        pairs: &[],
        friction: &|_, _| 0.0,
        stop: None,
        crossings: &[],
        held_before: &[],
        forces_before: &[],
    };
    let mut solver = PartitionedSolver::new(FillOrdering::NestedDissection);
    let r = solve_lagrange(&mut solver, &problem, &settings()).expect("contact solves");
    let top: f64 = (0..mesh.nodes.len())
        .filter(|&n| partition.prescribed[3 * n + 2])
        .map(|n| r.solution.reaction[3 * n + 2])
        .sum();
    let at: Vec<Vector3<f64>> = candidates
        .iter()
        .map(|&v| problem.position(&r.solution.displacement, v))
        .collect();
    (r, top, at)
}

#[test]
fn nine_points_per_face_carry_the_exact_force_of_a_block_on_a_plane() {
    let (r, top, at) = block_on_plane(0.0, 0.0);
    let exact = E * DELTA; // E·A·δ/L, A = L = 1
    let total: f64 = r.contacts.iter().map(|c| c.force).sum();
    assert!(
        (total - exact).abs() < 1e-6 * exact,
        "contact {total} N, exact {exact} N"
    );
    // Action and reaction: the top pushes down what the plane pushes up.
    assert!((top + total).abs() < 1e-6 * exact, "top {top} N");
    // The forces reach the nodes by the points' weights, which sum to one.
    let nodal: f64 = r
        .contacts
        .iter()
        .flat_map(|c| c.nodal_forces())
        .map(|(_, f)| f.z)
        .sum();
    assert!((nodal - total).abs() < 1e-9 * exact);
    // No point below the plane: 36 rows on 9 bottom nodes, released one at a time.
    let lowest = at.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    assert!(lowest > -1e-9, "a point is {lowest} m below the plane");
}

#[test]
fn points_below_their_cells_follow_the_extrapolated_field() {
    // The block floats 0.1 m above the plane; its points are 0.1 m under its bottom face,
    // extrapolated from the bottom cells (height h = 0.5 m, so s = 0.1 / h = 0.2: weights 1 + s
    // on the bottom face, −s on the face above). A point's force R goes to the nodes as N_i·R
    // (virtual work): the bottom cell carries (1 + s)·R, the cell above R, and the point stays
    // on the plane: u_p = −δ + h·R/E + h(1 + s)·R/E + s·h(1 + s)·R/E = 0, so
    // R = E·δ / (h + h(1 + s)²) = E·δ / 1.22 (not E·δ / 1.1: the field below a cell is that
    // cell's, not the block's).
    let (r, top, at) = block_on_plane(0.1, 0.1);
    let (h, s) = (0.5, 0.2);
    let exact = E * DELTA / (h + h * (1.0 + s) * (1.0 + s));
    let total: f64 = r.contacts.iter().map(|c| c.force).sum();
    assert!(
        (total - exact).abs() < 1e-6 * exact,
        "contact {total} N, exact {exact} N"
    );
    assert!((top + total).abs() < 1e-6 * exact);
    assert!(
        at.iter().all(|p| p.z.abs() < 1e-9),
        "the points rest on the plane"
    );
}

#[test]
fn embedded_points_pressing_a_second_block_give_springs_in_series() {
    // Block A (z 1..2, E_a) with its points on its bottom face, pushed down by δ onto block B
    // (z 0..1, E_b, base fixed) whose top facets are the master surface.
    let (ea, eb) = (4.0 * E, E);
    let a = box_mesh(
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(1.0, 1.0, 2.0),
        [2, 2, 2],
    );
    let b = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [3, 3, 3]);
    let mut mesh = Mesh {
        nodes: Vec::new(),
        cells: Vec::new(),
    };
    let (a0, _) = mesh.append(&a);
    let (b0, _) = mesh.append(&b);
    let k = stiffness(&mesh, |c| if c < a.cells.len() { ea } else { eb });
    let dofs = 3 * mesh.nodes.len();
    let mut mask = vec![false; dofs];
    let mut values = vec![0.0; dofs];
    for (n, p) in mesh.nodes.iter().enumerate() {
        let top = n < a.nodes.len() && p.z == 2.0;
        let base = n >= a.nodes.len() && p.z == 0.0;
        if top || base {
            mask[3 * n..3 * n + 3].fill(true);
            if top {
                values[3 * n + 2] = -DELTA;
            }
        }
    }
    let partition = DofPartition::new(mask);
    // A's cells are the first in the mesh: its bottom points, embedded in them.
    let a_only = Mesh {
        nodes: mesh.nodes.clone(),
        cells: mesh.cells[..a.cells.len()].to_vec(),
    };
    let points = bottom_points(&a_only, 1.0, 0.0);
    let positions = points.extend(&mesh.nodes);
    let b_quads: Vec<[usize; 4]> = boundary_facets(&b)
        .iter()
        .map(|f| f.nodes.map(|n| n + b0))
        .collect();
    let surfaces = vec![ContactSurface::from_quads(1, &b_quads, &positions)];
    let pairs = vec![SurfacePair {
        slaves: (mesh.nodes.len()..positions.len()).collect(),
        surface: 0,
        primary: false,
        slave_surface: None,
        own: None,
    }];
    let problem = ContactProblem {
        k: &k,
        partition: &partition,
        prescribed: &values,
        loads: &vec![0.0; dofs],
        positions: &positions,
        embedded: &points,
        obstacles: &[],
        obstacle_candidates: &[],
        surfaces: &surfaces,
        pairs: &pairs,
        friction: &|_, _| 0.0,
        stop: None,
        crossings: &[],
        held_before: &[],
        forces_before: &[],
    };
    let mut solver = PartitionedSolver::new(FillOrdering::NestedDissection);
    let r = solve_lagrange(&mut solver, &problem, &settings()).expect("contact solves");
    // Springs in series. The points (6 × 6) and B's facets (3 × 3) do not match: node-to-facet
    // contact then passes the patch test only approximately (B's top gets the points' loads
    // shared by h_i, not a uniform pressure): within 0.1 %.
    let exact = DELTA / (1.0 / ea + 1.0 / eb);
    let total: f64 = r.contacts.iter().map(|c| c.force).sum();
    assert!(
        (total - exact).abs() < 1e-3 * exact,
        "contact {total} N, exact {exact} N"
    );
    // Action and reaction to round-off, whatever the discretisation.
    let reaction = |range: std::ops::Range<usize>| -> f64 {
        range.map(|n| r.solution.reaction[3 * n + 2]).sum()
    };
    let top = reaction(a0..a0 + a.nodes.len());
    let base = reaction(b0..b0 + b.nodes.len());
    assert!((top + total).abs() < 1e-9 * exact, "A's top {top} N");
    assert!((base - total).abs() < 1e-9 * exact, "B's base {base} N");
}
