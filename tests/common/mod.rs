//! Helpers shared by the integration tests.
#![allow(dead_code)]

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
