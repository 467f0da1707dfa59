//! Half a substitution for sparse right-hand sides: y = L⁻¹·P·b with the supernodal Cholesky
//! factor P·K11·Pᵀ = L·Lᵀ of the last solve — block diagonal where K11 is held in blocks
//! (src/fem/blocks.rs): each block's factor on its rows of b, their rows numbered one block
//! after the other.
//!
//! A right-hand side with a handful of nonzeros (a contact constraint row touches at most four
//! nodes) reaches only the supernodes on the paths from its nonzeros to the root of the
//! elimination tree, and only those are visited; the result is kept as the nonzero blocks. Two
//! such vectors give b_iᵀ·K11⁻¹·b_j = y_i·y_j, the Schur complement of contact constraints,
//! without the backward half of the substitution.

use super::solve::{PartitionedSolver, SolveError, SupernodalFactor, SupernodalPart};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::{Accum, Mat, Par};
use rayon::prelude::*;

/// Y = L⁻¹·P·B for a group of k right-hand sides (the axes of one contact) as its nonzero
/// blocks: (first row in the factors' order — the blocks' factors one after the other —, the
/// block's rows of all k columns, column-major), ascending; a block is kept where any of the k
/// columns is nonzero.
#[derive(Clone, Debug, Default)]
pub struct HalfSolved {
    columns: usize,
    blocks: Vec<(usize, Vec<f64>)>,
}

impl HalfSolved {
    /// One per group of `groups[g]` columns, nothing stored yet.
    fn none_of(groups: &[usize]) -> Vec<HalfSolved> {
        groups
            .iter()
            .map(|&k| HalfSolved {
                columns: k,
                blocks: Vec::new(),
            })
            .collect()
    }

    /// Columns in the group.
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Y_aᵀ·Y_b = B_aᵀ·K11⁻¹·B_b, k_a × k_b (at most 3 × 3), row-major in `out`.
    pub fn gram(&self, other: &HalfSolved) -> [[f64; 3]; 3] {
        let mut out = [[0.0; 3]; 3];
        let (a, b) = (&self.blocks, &other.blocks);
        let (ka, kb) = (self.columns, other.columns);
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a[i].0.cmp(&b[j].0) {
                std::cmp::Ordering::Less => i += 1,
                std::cmp::Ordering::Greater => j += 1,
                std::cmp::Ordering::Equal => {
                    let size = a[i].1.len() / ka;
                    for (p, row) in out.iter_mut().enumerate().take(ka) {
                        let x = &a[i].1[p * size..(p + 1) * size];
                        for (q, v) in row.iter_mut().enumerate().take(kb) {
                            let y = &b[j].1[q * size..(q + 1) * size];
                            *v += x.iter().zip(y).map(|(x, y)| x * y).sum::<f64>();
                        }
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        out
    }

    /// Stored entries per column.
    pub fn len(&self) -> usize {
        self.blocks.iter().map(|b| b.1.len()).sum::<usize>() / self.columns.max(1)
    }

    /// No stored entry (B was zero).
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }
}

impl PartitionedSolver {
    /// L⁻¹·P·B for right-hand sides stored column by column in `b` (each NBEQ long, ordered as
    /// the partition's free dofs), in consecutive groups of `groups[g]` columns (at most 3),
    /// visiting only the supernodes each column reaches; `None` when the last factorization is
    /// not supernodal (small systems: use [`PartitionedSolver::solve_factored`]).
    ///
    /// The groups are independent: they are split into one share per thread, solved in
    /// parallel.
    pub fn forward_sparse(
        &self,
        b: &[f64],
        groups: &[usize],
    ) -> Result<Option<Vec<HalfSolved>>, SolveError> {
        let Some((n, parts)) = self.supernodal_parts() else {
            return Ok(None);
        };
        let columns: usize = groups.iter().sum();
        assert_eq!(b.len(), n * columns);
        assert!(groups.iter().all(|&k| (1..=3).contains(&k)));
        let shares = rayon::current_num_threads().clamp(1, groups.len().max(1));
        let per_share = groups.len().div_ceil(shares).max(1);
        // (groups, their columns of b) per share.
        let mut shared: Vec<(&[usize], &[f64])> = Vec::new();
        let mut at = 0;
        for chunk in groups.chunks(per_share) {
            let width: usize = chunk.iter().sum();
            shared.push((chunk, &b[at * n..(at + width) * n]));
            at += width;
        }
        let solved: Vec<Result<Vec<HalfSolved>, SolveError>> = shared
            .par_iter()
            .map(|&(chunk, b)| forward_parts(&parts, n, b, chunk))
            .collect();
        let mut out = Vec::with_capacity(groups.len());
        for s in solved {
            out.extend(s?);
        }
        Ok(Some(out))
    }

    /// K11⁻¹·Σ c·b from the half substitutions y = L⁻¹·P·b of the last factor (`terms`: the
    /// group, its column, the coefficient c): the other half only, x = Pᵀ·L⁻ᵀ·Σ c·y, reading
    /// the factor once where a whole substitution reads it twice. Ordered as the partition's
    /// free dofs; `None` when the last factorization is not supernodal.
    pub fn backward_from_halves(
        &self,
        terms: &[(&HalfSolved, usize, f64)],
    ) -> Result<Option<Vec<f64>>, SolveError> {
        let Some((n, parts)) = self.supernodal_parts() else {
            return Ok(None);
        };
        // Σ c·y in the factors' rows, block after block.
        let mut z = vec![0.0; n];
        for &(half, column, c) in terms {
            assert!(column < half.columns);
            for (start, values) in &half.blocks {
                let size = values.len() / half.columns;
                let y = &values[column * size..(column + 1) * size];
                for (z, y) in z[*start..*start + size].iter_mut().zip(y) {
                    *z += c * y;
                }
            }
        }
        let mut x = vec![0.0; n];
        for part in &parts {
            let rows = part.factor.symbolic.nrows();
            let local = backward(&part.factor, &mut z[part.offset..part.offset + rows]);
            match part.equations {
                Some(eqs) => {
                    for (&eq, v) in eqs.iter().zip(local) {
                        x[eq] = v;
                    }
                }
                None => x = local,
            }
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite(
                "a backward substitution with the reused factor",
            ));
        }
        Ok(Some(x))
    }
}

/// x = Pᵀ·L⁻ᵀ·z for one block's factor (z in its factor's rows, overwritten), in the block's
/// equations.
fn backward(factor: &SupernodalFactor<'_>, z: &mut [f64]) -> Vec<f64> {
    let n = z.len();
    // Lᵀ·x = z, supernode by supernode from the root: L_ssᵀ·x_s = z_s − L_psᵀ·x_p.
    let llt = SupernodalLltRef::new(factor.symbolic, factor.values);
    for s in (0..factor.symbolic.n_supernodes()).rev() {
        let node = llt.supernode(s);
        let start = node.start();
        let ls = node.val();
        let size = ls.ncols();
        let (top, bottom) = ls.split_at_row(size);
        let mut xs = Mat::<f64>::from_fn(size, 1, |i, _| z[start + i]);
        let pattern = node.pattern();
        if !pattern.is_empty() {
            let xp = Mat::<f64>::from_fn(pattern.len(), 1, |i, _| z[pattern[i]]);
            matmul(
                xs.as_mut(),
                Accum::Add,
                bottom.transpose(),
                xp.as_ref(),
                -1.0,
                Par::Seq,
            );
        }
        solve_upper_triangular_in_place(top.transpose(), xs.as_mut(), Par::Seq);
        for i in 0..size {
            z[start + i] = xs[(i, 0)];
        }
    }
    match factor.forward {
        Some(fwd) => {
            let mut x = vec![0.0; n];
            for (i, &f) in fwd.iter().enumerate() {
                x[f] = z[i];
            }
            x
        }
        None => z.to_vec(),
    }
}

/// [`PartitionedSolver::forward_sparse`] for one share of the groups over every block of the
/// factor (`b`: its columns, each NBEQ = `n` long): each block's rows of them solved with its
/// factor, its nonzero blocks numbered in the factors' rows one after the other.
fn forward_parts(
    parts: &[SupernodalPart<'_>],
    n: usize,
    b: &[f64],
    groups: &[usize],
) -> Result<Vec<HalfSolved>, SolveError> {
    if let [part] = parts {
        if part.equations.is_none() {
            return forward_share(&part.factor, b, groups);
        }
    }
    let columns: usize = groups.iter().sum();
    let mut out = HalfSolved::none_of(groups);
    for part in parts {
        let rows = part.factor.symbolic.nrows();
        let local: Vec<f64> = match part.equations {
            Some(eqs) => (0..columns)
                .flat_map(|j| eqs.iter().map(move |&eq| b[j * n + eq]))
                .collect(),
            None => b.to_vec(),
        };
        debug_assert_eq!(local.len(), rows * columns);
        for (o, h) in out
            .iter_mut()
            .zip(forward_share(&part.factor, &local, groups)?)
        {
            o.blocks.extend(
                h.blocks
                    .into_iter()
                    .map(|(start, values)| (part.offset + start, values)),
            );
        }
    }
    Ok(out)
}

/// [`PartitionedSolver::forward_sparse`] for one share of the groups, on this thread.
fn forward_share(
    factor: &SupernodalFactor<'_>,
    b: &[f64],
    groups: &[usize],
) -> Result<Vec<HalfSolved>, SolveError> {
    let n = factor.symbolic.nrows();
    let columns: usize = groups.iter().sum();
    if b.iter().any(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite("a constraint right-hand side"));
    }
    let mut group_of = Vec::with_capacity(columns);
    for (g, &k) in groups.iter().enumerate() {
        group_of.extend(std::iter::repeat_n(g, k));
    }
    let first: Vec<usize> = groups
        .iter()
        .scan(0, |acc, &k| {
            let f = *acc;
            *acc += k;
            Some(f)
        })
        .collect();
    // x = P·b, column by column.
    let mut x = vec![0.0; n * columns];
    for j in 0..columns {
        let (src, dst) = (&b[j * n..(j + 1) * n], &mut x[j * n..(j + 1) * n]);
        match factor.forward {
            Some(fwd) => {
                for (i, &f) in fwd.iter().enumerate() {
                    dst[i] = src[f];
                }
            }
            None => dst.copy_from_slice(src),
        }
    }
    let llt = SupernodalLltRef::new(factor.symbolic, factor.values);
    let mut out = HalfSolved::none_of(groups);
    let mut live: Vec<usize> = Vec::with_capacity(columns);
    let mut touched: Vec<usize> = Vec::new();
    for s in 0..factor.symbolic.n_supernodes() {
        let node = llt.supernode(s);
        let start = node.start();
        let ls = node.val();
        let size = ls.ncols();
        live.clear();
        live.extend((0..columns).filter(|&j| {
            x[j * n + start..j * n + start + size]
                .iter()
                .any(|&v| v != 0.0)
        }));
        if live.is_empty() {
            continue;
        }
        let (top, bottom) = ls.split_at_row(size);
        let mut xs = Mat::<f64>::from_fn(size, live.len(), |i, c| x[live[c] * n + start + i]);
        solve_lower_triangular_in_place(top, xs.as_mut(), Par::Seq);
        let pattern = node.pattern();
        if !pattern.is_empty() {
            let mut update = Mat::<f64>::zeros(pattern.len(), live.len());
            matmul(
                update.as_mut(),
                Accum::Replace,
                bottom,
                xs.as_ref(),
                1.0,
                Par::Seq,
            );
            for (c, &j) in live.iter().enumerate() {
                let col = &mut x[j * n..(j + 1) * n];
                for (idx, &i) in pattern.iter().enumerate() {
                    col[i] -= update[(idx, c)];
                }
            }
        }
        // One block per group reached, with all of the group's columns.
        touched.clear();
        touched.extend(live.iter().map(|&j| group_of[j]));
        touched.dedup();
        for &g in &touched {
            let k = groups[g];
            let mut values = vec![0.0; size * k];
            for (c, &j) in live.iter().enumerate() {
                if group_of[j] == g {
                    let a = j - first[g];
                    for i in 0..size {
                        values[a * size + i] = xs[(i, c)];
                    }
                }
            }
            out[g].blocks.push((start, values));
        }
    }
    if out
        .iter()
        .flat_map(|h| &h.blocks)
        .any(|(_, v)| v.iter().any(|x| !x.is_finite()))
    {
        return Err(SolveError::NonFinite(
            "a half substitution with the reused factor",
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::assembly::{assemble, StiffnessPattern};
    use crate::fem::solve::FillOrdering;
    use crate::fem::{DofPartition, Material};
    use crate::mesh::box_mesh;
    use nalgebra::Vector3;
    use std::sync::Arc;

    /// y_a·y_b against b_aᵀ·(K11⁻¹·b_b) from a full substitution, for sparse right-hand sides
    /// of a clamped block: the Schur complement of contact rows, both ways.
    #[test]
    fn half_substitutions_give_the_schur_complement() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [8, 8, 8]);
        let material = Material {
            young: 1.0e6,
            poisson: 0.3,
            density: 0.0,
        };
        let pattern = Arc::new(StiffnessPattern::new(&mesh));
        let k = assemble(&pattern, &mesh, &vec![material; mesh.cell_count()]).unwrap();
        let dofs = 3 * mesh.node_count();
        let mask: Vec<bool> = (0..dofs).map(|d| mesh.nodes[d / 3].z < 1e-9).collect();
        let partition = DofPartition::new(mask);
        let mut solver = PartitionedSolver::new(FillOrdering::NestedDissection);
        solver
            .solve(
                &k,
                &partition,
                &vec![0.0; dofs],
                &vec![0.0; dofs],
                &mesh.nodes,
            )
            .unwrap();
        let neq = partition.free_count();
        // Three rows like contact constraints: a node minus a facet's weighted nodes.
        let picks = [
            [17, 400, 401, 2000],
            [2300, 2301, 2302, 5],
            [900, 1500, 1501, 1502],
        ];
        let mut b = vec![0.0; 3 * neq];
        for (j, p) in picks.iter().enumerate() {
            b[j * neq + p[0]] = 1.0;
            for &e in &p[1..] {
                b[j * neq + e] = -1.0 / 3.0;
            }
        }
        // One group of two columns and one of one.
        let halves = solver
            .forward_sparse(&b, &[2, 1])
            .unwrap()
            .expect("a supernodal factor");
        let slot = |j: usize| if j < 2 { (0, j) } else { (1, 0) };
        let mut full = b.clone();
        solver.solve_factored(&mut full, 3).unwrap();
        // Only the elimination-tree paths of the nonzeros are stored.
        assert!(halves[0].len() < neq, "{} of {neq}", halves[0].len());
        assert!(halves[1].len() < neq / 2, "{} of {neq}", halves[1].len());
        for i in 0..3 {
            for j in 0..3 {
                let exact: f64 = (0..neq).map(|e| b[i * neq + e] * full[j * neq + e]).sum();
                let ((gi, ai), (gj, aj)) = (slot(i), slot(j));
                let half = halves[gi].gram(&halves[gj])[ai][aj];
                assert!(
                    (half - exact).abs() <= 1e-10 * exact.abs().max(1e-30),
                    "({i}, {j}): {half} against {exact}"
                );
            }
        }
        // The displacement of multipliers c on the three rows from their halves, the backward
        // half alone: K11⁻¹·Σ c_j·b_j of the whole substitutions.
        let c = [0.7, -1.3, 2.1];
        let from_halves = solver
            .backward_from_halves(&[
                (&halves[0], 0, c[0]),
                (&halves[0], 1, c[1]),
                (&halves[1], 0, c[2]),
            ])
            .unwrap()
            .expect("a supernodal factor");
        let scale = (0..neq)
            .map(|e| (0..3).map(|j| c[j] * full[j * neq + e]).sum::<f64>().abs())
            .fold(0.0, f64::max);
        assert!(scale > 0.0);
        for e in 0..neq {
            let exact: f64 = (0..3).map(|j| c[j] * full[j * neq + e]).sum();
            assert!(
                (from_halves[e] - exact).abs() <= 1e-10 * scale,
                "equation {e}: {} against {exact}",
                from_halves[e]
            );
        }
    }
}
