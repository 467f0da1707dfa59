//! The FEM sub-problem of a flexion keyframe: the flesh cells the increments solve (near the
//! moving joints, or the whole hand) with their nodes renumbered, bone nodes and the region's
//! edge prescribed.

use crate::fem::assembly::StiffnessPattern;
use crate::fem::{DofPartition, Material};
use crate::hand::HandModel;
use crate::mesh::Mesh;
use nalgebra::Vector3;
use std::sync::Arc;

/// The FEM sub-problem of a keyframe: the active cells with their nodes renumbered.
#[derive(Clone)]
pub(crate) struct SubProblem {
    /// Hand node of each local node.
    pub(crate) nodes: Vec<usize>,
    /// The active cells on local nodes, at rest.
    pub(crate) mesh: Mesh,
    /// Hand cell of each local cell.
    pub(crate) cells: Vec<usize>,
    pub(crate) pattern: Arc<StiffnessPattern>,
    /// Prescribed: bone nodes and nodes shared with cells outside the region.
    pub(crate) partition: DofPartition,
    pub(crate) materials: Vec<Material>,
}

/// The FEM sub-problem of the `active` cells of `hand`, on the rest geometry: bone nodes and
/// nodes shared with inactive cells are prescribed. `None` when nothing is free.
pub(crate) fn sub_problem(
    hand: &HandModel,
    cell_materials: &[Material],
    active: &[bool],
) -> Option<SubProblem> {
    let flesh = &hand.flesh;
    let cells: Vec<usize> = (0..active.len()).filter(|&c| active[c]).collect();
    if cells.is_empty() {
        return None;
    }
    let mut local = vec![usize::MAX; flesh.mesh.nodes.len()];
    let mut nodes = Vec::new();
    let mut hexes = Vec::with_capacity(cells.len());
    for &c in &cells {
        hexes.push(flesh.mesh.cells[c].map(|n| {
            if local[n] == usize::MAX {
                local[n] = nodes.len();
                nodes.push(n);
            }
            local[n]
        }));
    }
    // Prescribed: bone nodes, and nodes shared with cells outside the region.
    let mut boundary = vec![false; flesh.mesh.nodes.len()];
    for (c, cell) in flesh.mesh.cells.iter().enumerate() {
        if !active[c] {
            for &n in cell {
                boundary[n] = true;
            }
        }
    }
    let mut mask = vec![false; nodes.len() * 3];
    for (i, &n) in nodes.iter().enumerate() {
        if flesh.node_bone[n].is_some() || boundary[n] {
            mask[3 * i..3 * i + 3].fill(true);
        }
    }
    let partition = DofPartition::new(mask);
    if partition.free_count() == 0 {
        return None;
    }
    let mesh = Mesh {
        nodes: nodes.iter().map(|&n| flesh.mesh.nodes[n]).collect(),
        cells: hexes,
    };
    let pattern = Arc::new(StiffnessPattern::new(&mesh));
    let materials = cells.iter().map(|&c| cell_materials[c]).collect();
    Some(SubProblem {
        nodes,
        mesh,
        cells,
        pattern,
        partition,
        materials,
    })
}

/// The displacements from rest of `sub`'s local nodes where the hand's nodes are at `positions`.
pub(super) fn local_displacements(sub: &SubProblem, positions: &[Vector3<f64>]) -> Vec<f64> {
    sub.nodes
        .iter()
        .enumerate()
        .flat_map(|(i, &n)| {
            let d = positions[n] - sub.mesh.nodes[i];
            [d.x, d.y, d.z]
        })
        .collect()
}
