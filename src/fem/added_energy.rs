//! An energy Newton lowers beside a body's elastic energy (`fem::newton`): a barrier that keeps
//! surfaces apart (the hand's skin touching itself, `contact::self_barrier`). Its Hessian couples
//! nodes that share no cell, so the tangent it joins is held on the body's pattern grown by
//! those couplings ([`with_blocks`]).

use super::assembly::{Stiffness, StiffnessPattern};
use nalgebra::DMatrix;
use std::sync::Arc;

/// A dense block of a Hessian over some nodes: `matrix` is 3·nodes × 3·nodes, its rows and
/// columns node by node in the order of `nodes` (x, y, z each), symmetric.
#[derive(Clone, Debug)]
pub struct NodeBlock {
    /// The nodes, distinct.
    pub nodes: Vec<usize>,
    /// The block, J/m².
    pub matrix: DMatrix<f64>,
}

/// An energy of the displacements u (over a body's dofs, m) added to the body's.
pub trait AddedEnergy: Sync {
    /// The energy at `u` (J), its gradient added into `gradient` (N, over every dof); `None`
    /// where `u` is not admissible (surfaces through or onto each other), `gradient` then
    /// untouched.
    fn energy(&self, u: &[f64], gradient: &mut [f64]) -> Option<f64>;

    /// Its Hessian at `u` as blocks (their sum); `projected`: each block's positive
    /// semi-definite part (a tangent that stays definite where the exact one is not, at the
    /// cost of Newton's quadratic convergence).
    fn hessian(&self, u: &[f64], projected: bool) -> Vec<NodeBlock>;

    /// The largest share α ∈ (0, 1] of the step `du` from `u` that keeps `u + α·du` admissible
    /// all the way (continuous collision), with a margin.
    fn largest_step(&self, u: &[f64], du: &[f64]) -> f64;
}

/// Several energies added together: admissible where each is, the step as short as the
/// shortest any allows.
pub struct AddedSum<'a>(pub Vec<&'a dyn AddedEnergy>);

impl AddedEnergy for AddedSum<'_> {
    fn energy(&self, u: &[f64], gradient: &mut [f64]) -> Option<f64> {
        let mut sum = vec![0.0; gradient.len()];
        let mut total = 0.0;
        for e in &self.0 {
            total += e.energy(u, &mut sum)?;
        }
        for (g, s) in gradient.iter_mut().zip(sum) {
            *g += s;
        }
        Some(total)
    }

    fn hessian(&self, u: &[f64], projected: bool) -> Vec<NodeBlock> {
        self.0
            .iter()
            .flat_map(|e| e.hessian(u, projected))
            .collect()
    }

    fn largest_step(&self, u: &[f64], du: &[f64]) -> f64 {
        self.0
            .iter()
            .map(|e| e.largest_step(u, du))
            .fold(1.0, f64::min)
    }
}

/// `k` plus the blocks, on `k`'s pattern grown by every coupling of two nodes of one block
/// (values of `k` kept where they were). Without blocks, `k` itself.
pub fn with_blocks(k: &Stiffness, blocks: &[NodeBlock]) -> Stiffness {
    if blocks.is_empty() {
        return k.clone();
    }
    let old = &k.pattern;
    let mut neighbours = old.node_neighbours.clone();
    let mut grown = false;
    for b in blocks {
        for &a in &b.nodes {
            for &c in &b.nodes {
                if a != c && neighbours[a].binary_search(&c).is_err() {
                    let at = neighbours[a].partition_point(|&x| x < c);
                    neighbours[a].insert(at, c);
                    grown = true;
                }
            }
        }
    }
    let mut out = if grown {
        let pattern = Arc::new(StiffnessPattern::from_neighbours(neighbours));
        let mut values = vec![0.0; pattern.nnz()];
        for col in 0..old.dofs {
            let (from, to) = (
                old.col_ptr[col]..old.col_ptr[col + 1],
                pattern.col_ptr[col]..pattern.col_ptr[col + 1],
            );
            let rows = &pattern.row_idx[to.clone()];
            for k_old in from {
                let at = rows
                    .binary_search(&old.row_idx[k_old])
                    .expect("a grown pattern holds the old one");
                values[to.start + at] = k.values[k_old];
            }
        }
        Stiffness { pattern, values }
    } else {
        k.clone()
    };
    for b in blocks {
        for (i, &a) in b.nodes.iter().enumerate() {
            for (j, &c) in b.nodes.iter().enumerate() {
                // The stored upper triangle: node a's rows against node c's columns, a ≤ c.
                if a > c {
                    continue;
                }
                let block = b.matrix.fixed_view::<3, 3>(3 * i, 3 * j).into_owned();
                out.add_block(a, c, &block);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_mesh;
    use nalgebra::Vector3;

    /// The grown matrix times a vector is the old one's plus the blocks' (a coupling of two
    /// corners of a bar that share no cell, and one inside a cell).
    #[test]
    fn blocks_add_to_the_product_on_a_grown_pattern() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(3.0, 1.0, 1.0), [3, 1, 1]);
        let pattern = Arc::new(StiffnessPattern::new(&mesh));
        let dofs = pattern.dofs;
        let k = Stiffness {
            values: (0..pattern.nnz()).map(|i| 1.0 + (i % 7) as f64).collect(),
            pattern,
        };
        let far = (0, mesh.node_count() - 1);
        assert!(k.pattern.node_neighbours[far.0]
            .binary_search(&far.1)
            .is_err());
        let m = |n: usize, seed: f64| {
            let a = DMatrix::from_fn(3 * n, 3 * n, |i, j| seed + ((i * 5 + j * 3) % 11) as f64);
            &a + a.transpose()
        };
        let blocks = vec![
            NodeBlock {
                nodes: vec![far.1, far.0],
                matrix: m(2, 0.5),
            },
            NodeBlock {
                nodes: vec![1, 0, 4],
                matrix: m(3, -0.25),
            },
        ];
        let grown = with_blocks(&k, &blocks);
        assert!(grown.pattern.nnz() > k.pattern.nnz());
        let x: Vec<f64> = (0..dofs).map(|i| ((i * 13) % 17) as f64 - 8.0).collect();
        let mut expected = k.mul(&x);
        for b in &blocks {
            let xs = DMatrix::from_fn(3 * b.nodes.len(), 1, |r, _| x[3 * b.nodes[r / 3] + r % 3]);
            let y = &b.matrix * xs;
            for (r, v) in y.iter().enumerate() {
                expected[3 * b.nodes[r / 3] + r % 3] += v;
            }
        }
        let got = grown.mul(&x);
        for (a, b) in got.iter().zip(&expected) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} against {b}");
        }
    }
}
