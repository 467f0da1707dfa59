//! K11 split into blocks that share no stiffness: the free dofs of each group of nodes (a body
//! of a contact step: the ball, the hand's flesh near it), where no cell joins two groups.
//!
//! K11 is then block diagonal, K11 = diag(K_a, K_b, …), and so is its Cholesky factor: each
//! block is ordered, analysed and factored on its own, and a block whose values are those it
//! was last factored with keeps its factor (an object that stays linear for the whole session;
//! a corotated ball factored ahead, beside other work, about the state the step starts from).

use super::assembly::StiffnessPattern;
use super::partition::DofPartition;

/// One block of a partition split by groups: its group, the partition with only its free dofs
/// free, and the equation of the whole partition each of its equations is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SplitBlock {
    pub group: u32,
    pub partition: DofPartition,
    pub equations: Vec<usize>,
}

/// The blocks of `partition` by the nodes' `groups` (node n in group `groups[n]`; nodes beyond
/// it in group 0), in the order of their first free dof (one where a single group has free
/// dofs); `None` where no block is told apart — no groups, no free dof, or a cell (a stiffness
/// entry) joining two groups' free dofs, which would make the blocks' factors those of another
/// matrix.
pub(crate) fn split(
    pattern: &StiffnessPattern,
    partition: &DofPartition,
    groups: &[u32],
) -> Option<Vec<SplitBlock>> {
    if groups.is_empty() {
        return None;
    }
    let group = |n: usize| groups.get(n).copied().unwrap_or(0);
    // The groups with free dofs, in order of their first.
    let mut order: Vec<u32> = Vec::new();
    for &d in &partition.free {
        let g = group(d / 3);
        if !order.contains(&g) {
            order.push(g);
        }
    }
    if order.is_empty() {
        return None;
    }
    // A free node next to a free node of another group (they share a cell): one block.
    let free_node = |n: usize| (0..3).any(|a| !partition.prescribed[3 * n + a]);
    let mut last = usize::MAX;
    for &d in partition.free.iter().filter(|_| order.len() > 1) {
        let n = d / 3;
        if n == last {
            continue;
        }
        last = n;
        let g = group(n);
        if pattern.node_neighbours[n]
            .iter()
            .any(|&m| group(m) != g && free_node(m))
        {
            return None;
        }
    }
    let dofs = partition.prescribed.len();
    Some(
        order
            .into_iter()
            .map(|g| {
                let mut prescribed = vec![true; dofs];
                let mut equations = Vec::new();
                for (eq, &d) in partition.free.iter().enumerate() {
                    if group(d / 3) == g {
                        prescribed[d] = false;
                        equations.push(eq);
                    }
                }
                SplitBlock {
                    group: g,
                    partition: DofPartition::new(prescribed),
                    equations,
                }
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{box_mesh, Mesh};
    use nalgebra::Vector3;

    /// Two boxes side by side, apart: nodes 0..n of the first, n..2n of the second.
    fn two_boxes(gap: f64) -> (Mesh, usize) {
        let a = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [2, 2, 2]);
        let b = box_mesh(
            Vector3::new(1.0 + gap, 0.0, 0.0),
            Vector3::new(2.0 + gap, 1.0, 1.0),
            [2, 2, 2],
        );
        let n = a.node_count();
        let mut nodes = a.nodes.clone();
        nodes.extend(&b.nodes);
        let mut cells = a.cells.clone();
        cells.extend(b.cells.iter().map(|c| c.map(|m| m + n)));
        (Mesh { nodes, cells }, n)
    }

    #[test]
    fn bodies_that_share_no_cell_split_and_their_equations_cover_the_partition_once() {
        let (mesh, n) = two_boxes(0.5);
        let pattern = StiffnessPattern::new(&mesh);
        let dofs = 3 * mesh.node_count();
        // The first box clamped at x = 0, a few dofs of the second prescribed too.
        let mask: Vec<bool> = (0..dofs)
            .map(|d| mesh.nodes[d / 3].x < 1e-9 || d == 3 * n + 1 || d == 3 * n + 5)
            .collect();
        let partition = DofPartition::new(mask);
        let groups: Vec<u32> = (0..mesh.node_count()).map(|m| u32::from(m >= n)).collect();
        let blocks = split(&pattern, &partition, &groups).expect("two blocks");
        assert_eq!(blocks.len(), 2);
        assert_eq!(blocks[0].group, 0);
        let mut seen = vec![0; partition.free_count()];
        for b in &blocks {
            assert_eq!(b.equations.len(), b.partition.free_count());
            for (local, &eq) in b.equations.iter().enumerate() {
                seen[eq] += 1;
                // The same dof, and of this block's group.
                let d = partition.free[eq];
                assert_eq!(b.partition.free[local], d);
                assert_eq!(groups[d / 3], b.group);
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        // One group: one block of its own, every equation. No groups: none told apart.
        let one = split(&pattern, &partition, &vec![7; mesh.node_count()]).expect("one block");
        assert_eq!(one.len(), 1);
        assert_eq!((one[0].group, &one[0].partition), (7, &partition));
        assert_eq!(
            one[0].equations,
            (0..partition.free_count()).collect::<Vec<_>>()
        );
        assert!(split(&pattern, &partition, &[]).is_none());
    }

    #[test]
    fn groups_joined_by_a_cell_are_one_block() {
        // The second box's first cell made to share nodes with the first box: a cell joins them.
        let (mut mesh, n) = two_boxes(0.5);
        let c = mesh.cells.len() - 8;
        mesh.cells[c][0] = 4;
        let pattern = StiffnessPattern::new(&mesh);
        let dofs = 3 * mesh.node_count();
        let partition = DofPartition::new(vec![false; dofs]);
        let groups: Vec<u32> = (0..mesh.node_count()).map(|m| u32::from(m >= n)).collect();
        assert!(split(&pattern, &partition, &groups).is_none());
        // With the shared node's group prescribed, nothing joins the free dofs.
        let mut mask = vec![false; dofs];
        for node in mesh.cells[c] {
            if node < n {
                for a in 0..3 {
                    mask[3 * node + a] = true;
                }
            }
        }
        let partition = DofPartition::new(mask);
        assert!(split(&pattern, &partition, &groups).is_some());
    }

    /// A solve held in blocks gives the solve held whole: displacements, reactions, whole and
    /// half substitutions of rows spanning both bodies (a contact's), the backward half; and a
    /// block factored ahead with the same values is kept.
    #[test]
    fn a_solve_in_blocks_is_the_solve_held_whole_and_a_block_factored_ahead_is_kept() {
        use crate::fem::assembly::assemble;
        use crate::fem::solve::{FillOrdering, PartitionedSolver};
        use crate::fem::Material;
        use std::sync::Arc;
        let a = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [7, 7, 7]);
        let b = box_mesh(
            Vector3::new(1.5, 0.0, 0.0),
            Vector3::new(2.5, 1.0, 1.0),
            [6, 6, 6],
        );
        let n = a.node_count();
        let mut nodes = a.nodes.clone();
        nodes.extend(&b.nodes);
        let mut cells = a.cells.clone();
        cells.extend(b.cells.iter().map(|c| c.map(|m| m + n)));
        let mesh = Mesh { nodes, cells };
        let material = |young: f64| Material {
            young,
            poisson: 0.3,
            density: 0.0,
        };
        let materials: Vec<Material> = (0..mesh.cell_count())
            .map(|c| material(if c < a.cell_count() { 1.0e6 } else { 3.0e5 }))
            .collect();
        let pattern = Arc::new(StiffnessPattern::new(&mesh));
        let k = assemble(&pattern, &mesh, &materials).unwrap();
        let dofs = 3 * mesh.node_count();
        // Each box clamped on its face x = its least; one pulled, the other pushed.
        let mask: Vec<bool> = (0..dofs)
            .map(|d| {
                let p = mesh.nodes[d / 3];
                p.x < 1e-9 || (p.x - 1.5).abs() < 1e-9
            })
            .collect();
        let partition = DofPartition::new(mask);
        let prescribed: Vec<f64> = (0..dofs)
            .map(|d| {
                if d % 3 == 2 {
                    1e-3 * (d as f64).sin()
                } else {
                    0.0
                }
            })
            .collect();
        let loads: Vec<f64> = (0..dofs)
            .map(|d| {
                if d % 3 == 0 {
                    (d as f64 * 0.37).cos()
                } else {
                    0.0
                }
            })
            .collect();
        let whole = {
            let mut solver = PartitionedSolver::new(FillOrdering::Auto);
            let s = solver
                .solve(&k, &partition, &prescribed, &loads, &mesh.nodes)
                .unwrap();
            assert_eq!(s.stats.blocks, 1);
            (solver, s)
        };
        let groups: Vec<u32> = (0..mesh.node_count()).map(|m| u32::from(m >= n)).collect();
        let mut blocks = PartitionedSolver::new(FillOrdering::Auto);
        blocks.set_node_groups(groups.clone());
        let split = blocks
            .solve(&k, &partition, &prescribed, &loads, &mesh.nodes)
            .unwrap();
        assert_eq!((split.stats.blocks, split.stats.blocks_reused), (2, 0));
        let scale = whole
            .1
            .displacement
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let force = whole.1.reaction.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0 && force > 0.0);
        for d in 0..dofs {
            assert!((split.displacement[d] - whole.1.displacement[d]).abs() <= 1e-10 * scale);
            assert!((split.reaction[d] - whole.1.reaction[d]).abs() <= 1e-9 * force);
        }
        // Rows like contact constraints between the boxes: a node of one minus a facet's
        // weighted nodes of the other.
        let neq = partition.free_count();
        let eq = |node: usize, axis: usize| partition.equation[3 * node + axis];
        let free_a: Vec<usize> = (0..n).filter(|&m| eq(m, 0) != usize::MAX).collect();
        let free_b: Vec<usize> = (n..mesh.node_count())
            .filter(|&m| eq(m, 0) != usize::MAX)
            .collect();
        let (fa, fb) = (
            |i: usize| free_a[i % free_a.len()],
            |i: usize| free_b[i % free_b.len()],
        );
        let picks = [
            (fa(300), [fb(40), fb(41), fb(90)]),
            (fb(200), [fa(30), fa(31), fa(350)]),
            (fa(77), [fb(7), fb(8), fb(60)]),
        ];
        let mut rows = vec![0.0; 3 * neq];
        for (j, (p, facet)) in picks.iter().enumerate() {
            let e = eq(*p, 0);
            assert_ne!(e, usize::MAX);
            rows[j * neq + e] = 1.0;
            for &f in facet {
                let e = eq(f, 0);
                assert_ne!(e, usize::MAX);
                rows[j * neq + e] = -1.0 / 3.0;
            }
        }
        let mut exact = rows.clone();
        let (mut whole_solver, _) = whole;
        whole_solver.solve_factored(&mut exact, 3).unwrap();
        let mut full = rows.clone();
        blocks.solve_factored(&mut full, 3).unwrap();
        let big = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (x, y) in full.iter().zip(&exact) {
            assert!((x - y).abs() <= 1e-10 * big);
        }
        let halves = blocks
            .forward_sparse(&rows, &[2, 1])
            .unwrap()
            .expect("supernodal factors");
        let slot = |j: usize| if j < 2 { (0, j) } else { (1, 0) };
        for i in 0..3 {
            for j in 0..3 {
                let w: f64 = (0..neq)
                    .map(|e| rows[i * neq + e] * exact[j * neq + e])
                    .sum();
                let ((gi, ai), (gj, aj)) = (slot(i), slot(j));
                let half = halves[gi].gram(&halves[gj])[ai][aj];
                assert!(
                    (half - w).abs() <= 1e-9 * w.abs().max(1e-30),
                    "({i}, {j}): {half} against {w}"
                );
            }
        }
        let c = [0.7, -1.3, 2.1];
        let back = blocks
            .backward_from_halves(&[
                (&halves[0], 0, c[0]),
                (&halves[0], 1, c[1]),
                (&halves[1], 0, c[2]),
            ])
            .unwrap()
            .expect("supernodal factors");
        for e in 0..neq {
            let x: f64 = (0..3).map(|j| c[j] * exact[j * neq + e]).sum();
            assert!((back[e] - x).abs() <= 1e-10 * big, "equation {e}");
        }
        // The second box factored ahead with the first prescribed, then the whole solved: the
        // second's factor is kept, the first's made; the same answer.
        let mut ahead = PartitionedSolver::new(FillOrdering::Auto);
        ahead.set_node_groups(groups);
        let only_b: Vec<bool> = (0..dofs)
            .map(|d| partition.prescribed[d] || d < 3 * n)
            .collect();
        let pre = ahead
            .factor_ahead(&k, &DofPartition::new(only_b), &mesh.nodes)
            .unwrap();
        assert_eq!((pre.blocks, pre.blocks_reused), (1, 0));
        let after = ahead
            .solve(&k, &partition, &prescribed, &loads, &mesh.nodes)
            .unwrap();
        assert_eq!((after.stats.blocks, after.stats.blocks_reused), (2, 1));
        for d in 0..dofs {
            assert!((after.displacement[d] - split.displacement[d]).abs() <= 1e-12 * scale);
        }
        // Other values for the second box: made again.
        let mut stiffer = k.clone();
        for v in &mut stiffer.values {
            *v *= 2.0;
        }
        let again = ahead
            .solve(&stiffer, &partition, &prescribed, &loads, &mesh.nodes)
            .unwrap();
        assert_eq!(again.stats.blocks_reused, 0);
        let stiffer_whole = PartitionedSolver::new(FillOrdering::Auto)
            .solve(&stiffer, &partition, &prescribed, &loads, &mesh.nodes)
            .unwrap();
        let moved = (0..dofs)
            .map(|d| (again.displacement[d] - split.displacement[d]).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1e-3 * scale);
        for d in 0..dofs {
            let x = stiffer_whole.displacement[d];
            assert!((again.displacement[d] - x).abs() <= 1e-10 * scale);
        }
    }
}
