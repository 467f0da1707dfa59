//! The partitioned solver: reuse of the symbolic factorization, linearity in the prescribed
//! values, fill of nested dissection against minimum degree, and a clear failure on a mechanism.

use nalgebra::Vector3;
use prehensile::fem::assembly::{assemble, StiffnessPattern};
use prehensile::fem::solve::{FillOrdering, PartitionedSolver, SolveError};
use prehensile::fem::{DofPartition, Material};
use prehensile::mesh::{box_mesh, Mesh};
use std::sync::Arc;

const RUBBER: Material = Material {
    young: 1.0e6,
    poisson: 0.3,
    density: 1100.0,
};

/// Bottom clamped, top pressed along z: the benchmark problem.
fn cube(n: usize) -> (Mesh, DofPartition, Vec<f64>) {
    let mesh = box_mesh(Vector3::zeros(), Vector3::from_element(1.0), [n, n, n]);
    let mut mask = vec![false; 3 * mesh.node_count()];
    let mut values = vec![0.0; 3 * mesh.node_count()];
    for (k, p) in mesh.nodes.iter().enumerate() {
        if p.z == 0.0 {
            mask[3 * k..3 * k + 3].fill(true);
        } else if p.z == 1.0 {
            mask[3 * k + 2] = true;
            values[3 * k + 2] = -0.01;
        }
    }
    (mesh, DofPartition::new(mask), values)
}

#[test]
fn a_second_solve_with_new_prescribed_values_reuses_the_symbolic_analysis_and_is_linear() {
    let (mesh, partition, values) = cube(6);
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let k = assemble(&pattern, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let loads = vec![0.0; 3 * mesh.node_count()];
    let mut solver = PartitionedSolver::new(FillOrdering::NestedDissection);
    let first = solver
        .solve(&k, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(!first.stats.symbolic_reused);
    let doubled: Vec<f64> = values.iter().map(|v| 2.5 * v).collect();
    let second = solver
        .solve(&k, &partition, &doubled, &loads, &mesh.nodes)
        .unwrap();
    assert!(second.stats.symbolic_reused);
    assert_eq!(second.stats.symbolic_ms, 0.0);
    // The same K11 again: its numeric factor is reused too.
    assert!(!first.stats.factor_reused && second.stats.factor_reused);
    let scale = first.reaction.iter().map(|r| r.abs()).fold(0.0, f64::max);
    for d in 0..values.len() {
        assert!((second.reaction[d] - 2.5 * first.reaction[d]).abs() < 1e-10 * scale);
        assert!((second.displacement[d] - 2.5 * first.displacement[d]).abs() < 1e-13);
    }
    // A stiffer material (K doubled) is factored anew: the same prescribed displacements,
    // twice the reactions.
    let mut stiffer = k.clone();
    stiffer.values.iter_mut().for_each(|v| *v *= 2.0);
    let doubled_k = solver
        .solve(&stiffer, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(doubled_k.stats.symbolic_reused && !doubled_k.stats.factor_reused);
    for d in 0..values.len() {
        assert!((doubled_k.reaction[d] - 2.0 * first.reaction[d]).abs() < 1e-10 * scale);
        assert!((doubled_k.displacement[d] - first.displacement[d]).abs() < 1e-13);
    }
    // A new prescribed set is a new pattern for K11: analysed again.
    let mut mask = partition.prescribed.clone();
    mask[3 * (mesh.node_count() - 1)] = true;
    let third = solver
        .solve(&k, &DofPartition::new(mask), &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(!third.stats.symbolic_reused);
    // The same mesh's pattern built again (a flexion increment rebuilds its region's): equal,
    // so the analysis of the first partition holds again, and the solve gives the first's
    // displacements on K assembled on it (the factor was made for the third partition).
    let rebuilt = Arc::new(StiffnessPattern::new(&mesh));
    assert!(!Arc::ptr_eq(&rebuilt, &pattern));
    let k_again = assemble(&rebuilt, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let _ = solver
        .solve(&k, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    let fourth = solver
        .solve(&k_again, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(fourth.stats.symbolic_reused);
    for d in 0..values.len() {
        assert!((fourth.displacement[d] - first.displacement[d]).abs() < 1e-13);
    }
}

#[test]
fn nested_dissection_fills_less_than_minimum_degree_and_gives_the_same_answer() {
    let (mesh, partition, values) = cube(12);
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let k = assemble(&pattern, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let loads = vec![0.0; 3 * mesh.node_count()];
    let nd = PartitionedSolver::new(FillOrdering::NestedDissection)
        .solve(&k, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    let amd = PartitionedSolver::new(FillOrdering::Amd)
        .solve(&k, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    println!(
        "nnz(L): nested dissection {} vs AMD {}",
        nd.stats.factor_nnz, amd.stats.factor_nnz
    );
    assert!(nd.stats.factor_nnz < amd.stats.factor_nnz);
    for d in 0..values.len() {
        assert!((nd.displacement[d] - amd.displacement[d]).abs() < 1e-12);
    }
    assert!(nd.stats.relative_residual < 1e-12 && amd.stats.relative_residual < 1e-12);
}

/// A slender bar, one end clamped, the other pulled along its axis: thin as a finger.
fn bar(cells: usize) -> (Mesh, DofPartition, Vec<f64>) {
    let length = 0.01 * cells as f64;
    let mesh = box_mesh(
        Vector3::zeros(),
        Vector3::new(length, 0.02, 0.02),
        [cells, 2, 2],
    );
    let mut mask = vec![false; 3 * mesh.node_count()];
    let mut values = vec![0.0; 3 * mesh.node_count()];
    for (k, p) in mesh.nodes.iter().enumerate() {
        if p.x == 0.0 {
            mask[3 * k..3 * k + 3].fill(true);
        } else if (p.x - length).abs() < 1e-12 {
            mask[3 * k] = true;
            values[3 * k] = 1e-3;
        }
    }
    (mesh, DofPartition::new(mask), values)
}

#[test]
fn the_default_ordering_keeps_the_lesser_work_of_dissection_and_minimum_degree() {
    // Dissection wins on the compact cube, minimum degree on the slender bar (the hand's
    // fingers: 7.6 M entries against 12.8 M at resolution 1); the default keeps whichever the
    // symbolic analysis plans less work for, and solves alike.
    for (name, (mesh, partition, values)) in [("cube", cube(10)), ("bar", bar(300))] {
        let pattern = Arc::new(StiffnessPattern::new(&mesh));
        let k = assemble(&pattern, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
        let loads = vec![0.0; 3 * mesh.node_count()];
        let solve = |ordering| {
            PartitionedSolver::new(ordering)
                .solve(&k, &partition, &values, &loads, &mesh.nodes)
                .unwrap()
        };
        let (nd, amd, auto) = (
            solve(FillOrdering::NestedDissection),
            solve(FillOrdering::Amd),
            solve(FillOrdering::default()),
        );
        let (nd_nnz, amd_nnz) = (nd.stats.factor_nnz, amd.stats.factor_nnz);
        let (nd_work, amd_work) = (nd.stats.factor_work, amd.stats.factor_work);
        println!(
            "{name}: nnz(L) nested dissection {nd_nnz}, AMD {amd_nnz}, default {}; work \
             {nd_work:.3e} / {amd_work:.3e} / {:.3e}",
            auto.stats.factor_nnz, auto.stats.factor_work
        );
        assert_eq!(auto.stats.factor_work, nd_work.min(amd_work), "{name}");
        // On these two the lesser work is also the lesser fill.
        assert_eq!(nd_work < amd_work, nd_nnz < amd_nnz, "{name}");
        let scale = auto
            .displacement
            .iter()
            .map(|u| u.abs())
            .fold(0.0, f64::max);
        let apart = (0..values.len())
            .map(|d| (auto.displacement[d] - nd.displacement[d]).abs())
            .fold(0.0, f64::max);
        assert!(apart < 1e-8 * scale, "{name}: {apart:e} of {scale:e}");
        assert!(auto.stats.relative_residual < 1e-10, "{name}");
        match name {
            "cube" => assert!(nd_nnz < amd_nnz),
            _ => assert!(amd_nnz < nd_nnz),
        }
    }
}

#[test]
fn an_order_is_carried_over_to_a_prescribed_set_changed_by_a_few_dofs() {
    let (mesh, partition, values) = cube(8);
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let k = assemble(&pattern, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let loads = vec![0.0; 3 * mesh.node_count()];
    let mut solver = PartitionedSolver::new(FillOrdering::default());
    let first = solver
        .solve(&k, &partition, &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(!first.stats.order_carried);
    // Two interior nodes held where they are: the last order less their dofs.
    let mut mask = partition.prescribed.clone();
    for n in [200, 300] {
        mask[3 * n..3 * n + 3].fill(true);
    }
    let fewer = DofPartition::new(mask);
    let carried = solver
        .solve(&k, &fewer, &values, &loads, &mesh.nodes)
        .unwrap();
    let fresh = PartitionedSolver::new(FillOrdering::default())
        .solve(&k, &fewer, &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(carried.stats.order_carried && !carried.stats.symbolic_reused);
    assert!(carried.stats.factor_work <= 1.05 * fresh.stats.factor_work);
    let scale = fresh
        .displacement
        .iter()
        .map(|u| u.abs())
        .fold(0.0, f64::max);
    for d in 0..values.len() {
        assert!((carried.displacement[d] - fresh.displacement[d]).abs() < 1e-12 * scale);
        assert!((carried.reaction[d] - fresh.reaction[d]).abs() < 1e-9);
    }
    // The same nodes numbered otherwise (a region rebuilt), named by their identities: the
    // order follows the nodes.
    let n = mesh.node_count();
    let perm: Vec<usize> = (0..n).rev().collect();
    let renumbered = Mesh {
        nodes: perm.iter().map(|&i| mesh.nodes[i]).collect(),
        cells: mesh.cells.iter().map(|c| c.map(|i| n - 1 - i)).collect(),
    };
    let moved = |v: &[f64]| -> Vec<f64> {
        perm.iter()
            .flat_map(|&i| v[3 * i..3 * i + 3].to_vec())
            .collect()
    };
    let pattern2 = Arc::new(StiffnessPattern::new(&renumbered));
    let k2 = assemble(&pattern2, &renumbered, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let mask2: Vec<bool> = perm
        .iter()
        .flat_map(|&i| partition.prescribed[3 * i..3 * i + 3].to_vec())
        .collect();
    solver.set_node_ids(perm.clone());
    let again = solver
        .solve(
            &k2,
            &DofPartition::new(mask2),
            &moved(&values),
            &loads,
            &renumbered.nodes,
        )
        .unwrap();
    // (Carried from the second order: the two nodes free again come last.)
    assert!(again.stats.order_carried);
    assert!(again.stats.factor_work <= 1.05 * first.stats.factor_work);
    let expected = moved(&first.displacement);
    for d in 0..values.len() {
        assert!((again.displacement[d] - expected[d]).abs() < 1e-12 * scale);
    }
    // Many dofs new to the prescribed set (the pressed face let go): ordered afresh.
    solver.set_node_ids(Vec::new());
    let mut freed = partition.prescribed.clone();
    for (n, p) in mesh.nodes.iter().enumerate() {
        if p.z == 1.0 {
            freed[3 * n + 2] = false;
        }
    }
    let afresh = solver
        .solve(&k, &DofPartition::new(freed), &values, &loads, &mesh.nodes)
        .unwrap();
    assert!(!afresh.stats.order_carried && !afresh.stats.symbolic_reused);
}

#[test]
fn an_unheld_mechanism_fails_with_a_diagnosis_not_a_nan() {
    // Two cubes side by side that share no node: the second is held by nothing.
    let mut mesh = box_mesh(Vector3::zeros(), Vector3::from_element(1.0), [2, 2, 2]);
    mesh.append(&box_mesh(
        Vector3::new(2.0, 0.0, 0.0),
        Vector3::new(3.0, 1.0, 1.0),
        [2, 2, 2],
    ));
    let mut mask = vec![false; 3 * mesh.node_count()];
    for (k, p) in mesh.nodes.iter().enumerate() {
        if p.x == 0.0 {
            mask[3 * k..3 * k + 3].fill(true);
        }
    }
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let k = assemble(&pattern, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let mut loads = vec![0.0; 3 * mesh.node_count()];
    loads[3 * (mesh.node_count() - 1)] = 1.0;
    let values = vec![0.0; 3 * mesh.node_count()];
    let err = PartitionedSolver::new(FillOrdering::NestedDissection)
        .solve(&k, &DofPartition::new(mask), &values, &loads, &mesh.nodes)
        .unwrap_err();
    match err {
        SolveError::NotPositiveDefinite { node, .. } => {
            assert!(node >= 27, "node {node} is in the held cube")
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn non_finite_input_is_refused_before_solving() {
    let (mesh, partition, values) = cube(2);
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let k = assemble(&pattern, &mesh, &vec![RUBBER; mesh.cell_count()]).unwrap();
    let mut loads = vec![0.0; 3 * mesh.node_count()];
    loads[4] = f64::NAN;
    let err = PartitionedSolver::default()
        .solve(&k, &partition, &values, &loads, &mesh.nodes)
        .unwrap_err();
    assert!(err.to_string().contains("load vector"), "{err}");
}
