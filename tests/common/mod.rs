//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod flexion;
pub mod gltf_validator;
pub mod held;
pub mod limited;
pub mod viewer;
pub mod vtu;

use nalgebra::Vector3;
use prehensile::fem::assembly::{assemble, StiffnessPattern};
use prehensile::fem::solve::{FillOrdering, PartitionedSolver, Solution};
use prehensile::fem::stress::{stress_field, StressField};
use prehensile::fem::{DofPartition, Material};
use prehensile::mesh::Mesh;
use std::sync::Arc;

/// Solves a mesh with one material everywhere, `prescribed(node) -> [Option<f64>; 3]` and a load
/// vector, returning the solution and the stresses.
pub fn solve_mesh(
    mesh: &Mesh,
    materials: &[Material],
    prescribed: impl Fn(usize, &Vector3<f64>) -> [Option<f64>; 3],
    loads: &[f64],
) -> (Solution, StressField) {
    let dofs = 3 * mesh.node_count();
    let mut mask = vec![false; dofs];
    let mut values = vec![0.0; dofs];
    for (n, p) in mesh.nodes.iter().enumerate() {
        for (i, v) in prescribed(n, p).iter().enumerate() {
            if let Some(v) = v {
                mask[3 * n + i] = true;
                values[3 * n + i] = *v;
            }
        }
    }
    let pattern = Arc::new(StiffnessPattern::new(mesh));
    let k = assemble(&pattern, mesh, materials).expect("assembly");
    let mut solver = PartitionedSolver::new(FillOrdering::NestedDissection);
    let sol = solver
        .solve(&k, &DofPartition::new(mask), &values, loads, &mesh.nodes)
        .expect("solve");
    let stress = stress_field(mesh, materials, &sol.displacement).expect("stress");
    (sol, stress)
}

/// Relative difference |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// How deep the display skin of hand body `hand` lies inside the outer surface of body `object`
/// in `frame` (m; 0 when it is all outside), and the depth of the hand's flesh lattice nodes
/// there, by winding numbers on the deformed geometry.
pub fn skin_depth_inside(
    model: &prehensile::model::Model,
    frame: &prehensile::state::Frame,
    hand: usize,
    object: usize,
) -> (f64, f64) {
    let (display, lattice, _) = skins_depth_inside(model, frame, hand, object);
    (display, lattice)
}

/// [`skin_depth_inside`]'s display skin and lattice, and the contact skin's points (the skin the
/// contact holds, at the lattice's resolution).
pub fn skins_depth_inside(
    model: &prehensile::model::Model,
    frame: &prehensile::state::Frame,
    hand: usize,
    object: usize,
) -> (f64, f64, f64) {
    use prehensile::contact::{
        connected_pieces, project_on_triangle, winding_number_of, ContactSurface,
    };
    let body = &model.bodies[hand];
    let h = frame
        .hands
        .iter()
        .find(|h| h.body == hand)
        .expect("a hand frame");
    let deformed: Vec<Vector3<f64>> = (0..model.mesh.node_count())
        .map(|n| model.mesh.nodes[n] + frame.solution.node_displacement(n))
        .collect();
    let quads: Vec<[usize; 4]> = model.bodies[object]
        .facets
        .iter()
        .map(|f| f.nodes)
        .collect();
    // Split as the solver splits them: along the diagonals at rest.
    let surface = ContactSurface::from_quads_split_at(object, &quads, &model.mesh.nodes, &deformed);
    // The outer surface: the piece with the largest extent.
    let extent = |piece: &Vec<[usize; 3]>| {
        let xs = piece.iter().flatten().map(|&n| deformed[n].x);
        xs.clone().fold(f64::NEG_INFINITY, f64::max) - xs.fold(f64::INFINITY, f64::min)
    };
    let outer = connected_pieces(&surface.triangles)
        .into_iter()
        .max_by(|a, b| extent(a).total_cmp(&extent(b)))
        .expect("a surface");
    let depth = |p: &Vector3<f64>| -> f64 {
        if winding_number_of(p, &outer, &deformed).abs() < 0.5 {
            return 0.0;
        }
        outer
            .iter()
            .filter_map(|t| project_on_triangle(p, &t.map(|m| deformed[m])))
            .map(|q| q.distance)
            .fold(f64::INFINITY, f64::min)
    };
    let hand_model = body.hand.as_deref().expect("a hand body");
    let skin = hand_model
        .skin
        .positions(&h.positions)
        .iter()
        .map(depth)
        .fold(0.0, f64::max);
    let lattice = h.positions.iter().map(depth).fold(0.0, f64::max);
    let contact = hand_model
        .contact_skin
        .positions(&h.positions)
        .iter()
        .map(depth)
        .fold(0.0, f64::max);
    (skin, lattice, contact)
}

/// How deep (m) any boundary node of body `object`, deformed, lies inside hand `hand`'s display
/// skin (the skin the user sees), by winding numbers: the reverse of [`skin_depth_inside`],
/// independent of the contact's own detection. The skin is open at the wrist, far from any
/// object.
pub fn object_depth_inside_skin(
    model: &prehensile::model::Model,
    frame: &prehensile::state::Frame,
    hand: usize,
    object: usize,
) -> f64 {
    use prehensile::contact::{project_on_triangle, winding_number_of};
    let h = frame
        .hands
        .iter()
        .find(|h| h.body == hand)
        .expect("a hand frame");
    let hand_model = model.bodies[hand].hand.as_deref().expect("a hand body");
    let skin = hand_model.skin.positions(&h.positions);
    let triangles = hand_model.skin.triangle_indices();
    let mut nodes: Vec<usize> = model.bodies[object]
        .facets
        .iter()
        .flat_map(|f| f.nodes)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    use rayon::prelude::*;
    nodes
        .par_iter()
        .map(|&n| {
            let p = model.mesh.nodes[n] + frame.solution.node_displacement(n);
            if winding_number_of(&p, &triangles, &skin).abs() < 0.5 {
                return 0.0;
            }
            triangles
                .iter()
                .filter_map(|t| project_on_triangle(&p, &t.map(|m| skin[m])))
                .map(|q| q.distance)
                .fold(f64::INFINITY, f64::min)
        })
        .reduce(|| 0.0, f64::max)
}

/// `prehensile solve <scene> --out <out>`, run as a user runs it.
pub fn solve_cli(scene: &std::path::Path, out: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .arg("solve")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .expect("the prehensile binary runs")
}

/// `assets/scenes/hand-power-grasp.toml` solved (the default scene closed into the Power grasp),
/// and the index of the thumb's IP among its hand's joint angles (the thumb touches the ball).
pub fn power_grasp_and_thumb_ip() -> (prehensile::headless::Solved, usize) {
    let text = std::fs::read_to_string("assets/scenes/hand-power-grasp.toml").unwrap();
    let scene = prehensile::scene::Scene::parse(&text, "power.toml").unwrap();
    let solved = prehensile::headless::solve_scene(&scene, "power.toml").unwrap();
    let h = &solved.frames.last().unwrap().hands[0];
    let hand = solved.model.bodies[h.body].hand.as_deref().unwrap();
    let ip = hand
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == "thumb.ip")
        .unwrap();
    (solved, ip)
}

/// A scene's text with its right hand's `form` named (`"simple"` or `"anatomical"`): the
/// shipped scenes leave it to the default. Panics when the text has no right hand.
pub fn with_hand_form(text: &str, form: &str) -> String {
    let named = text.replacen(
        "side = \"right\"",
        &format!("side = \"right\", form = \"{form}\""),
        1,
    );
    assert!(
        named != text,
        "no right hand to give the form \"{form}\" in:\n{text}"
    );
    named
}
