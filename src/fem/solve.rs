//! The partitioned solve of the paper's equations (6)–(8) with faer's sparse Cholesky.
//!
//! K11·Uu = Rk − K12·Uk (7) is solved for the unknown displacements, then the nodal forces at
//! the prescribed dofs follow from Ru = K21·Uu + K22·Uk (8). The symbolic analysis of K11
//! (fill-reducing ordering, elimination tree, supernodes) depends only on which dofs are
//! prescribed and on the mesh, so it is computed once and reused while both stay the same.

use super::assembly::{Stiffness, StiffnessPattern};
use super::memory::{grow_zeroed, scratch};
use super::ordering::nested_dissection;
use super::partition::DofPartition;
use crate::util::timing::ms;
use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::perm::Perm;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::Vector3;
use serde::Serialize;
use std::mem::MaybeUninit;
use std::sync::Arc;
use std::time::Instant;
use thiserror::Error;

/// Fill-reducing ordering used for K11.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FillOrdering {
    /// Both below analysed, the one whose numeric factorization is less work kept (the
    /// default): nested dissection wins on compact 3D meshes (a 30³ cube: 0.61× AMD's fill),
    /// AMD on thin and branched ones (the hand's flesh at resolution 1: 7.6 M entries against
    /// 12.8 M; a slab of one cell's section).
    #[default]
    Auto,
    /// Geometric nested dissection on node coordinates.
    NestedDissection,
    /// faer's approximate minimum degree.
    Amd,
}

/// Why a solve failed.
#[derive(Debug, Error)]
pub enum SolveError {
    /// K11 is not positive definite: some part of the model can move without deforming.
    #[error(
        "the stiffness of the unknown degrees of freedom is not positive definite (pivot {pivot} \
         of {equations}, node {node}): some part of the model can still move without deforming"
    )]
    NotPositiveDefinite {
        /// Elimination step that failed.
        pivot: usize,
        /// NBEQ.
        equations: usize,
        /// A node whose dof sits at that pivot.
        node: usize,
    },
    /// An input was NaN or infinite.
    #[error("{0} holds a value that is not a finite number")]
    NonFinite(&'static str),
    /// The factorization ran out of memory.
    #[error("sparse Cholesky failed: {0}")]
    Faer(String),
    /// Ordering the factor would not fit in the memory the solve may take: refused before
    /// it runs.
    #[error(
        "ordering the sparse Cholesky factor of {equations} equations takes about {} while it \
         runs (its factor several times more), but {} is free ({limit}): use fewer elements — \
         at most {:.0} % as many: a coarser mesh, fewer `cells`, a lower hand `resolution` — \
         or {}",
        super::memory::human(*needed),
        super::memory::human(*available),
        100.0 * super::memory::fewer_share(*available, *needed, 1.0),
        .limit.remedy()
    )]
    OrderingTooBig {
        /// Bytes the ordering would take.
        needed: u64,
        /// Bytes the solve may take.
        available: u64,
        /// What limits it.
        limit: super::memory::BudgetSource,
        /// NBEQ.
        equations: usize,
    },
    /// The factor would not fit in the memory the solve may take: refused before allocating.
    #[error(
        "the sparse Cholesky factor of {equations} equations needs about {} ({entries} \
         entries), but {} is free ({limit}): use fewer elements — at most {:.0} % as many, \
         since a 3D mesh's factor grows as its size to the power 4/3: a coarser mesh, fewer \
         `cells`, a lower hand `resolution` — or {}",
        super::memory::human(*needed),
        super::memory::human(*available),
        100.0 * super::memory::fewer_share(*available, *needed, 4.0 / 3.0),
        .limit.remedy()
    )]
    TooBig {
        /// Bytes the factorization would take.
        needed: u64,
        /// Bytes the solve may take.
        available: u64,
        /// What limits it.
        limit: super::memory::BudgetSource,
        /// NBEQ.
        equations: usize,
        /// Entries of the factor.
        entries: usize,
    },
}

/// What a solve cost and how well it did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SolveStats {
    /// Time to order K11 and analyse it symbolically (0 when reused).
    pub symbolic_ms: f64,
    /// Whether the symbolic analysis of an earlier solve was reused.
    pub symbolic_reused: bool,
    /// Whether, not reused, it was made with the elimination order of the earlier one carried
    /// over (a prescribed set changed by a few dofs) instead of ordered afresh.
    pub order_carried: bool,
    /// Whether the numeric factor of the last solve was reused (the same K11 again).
    pub factor_reused: bool,
    /// Numeric Cholesky factorization time.
    pub factorization_ms: f64,
    /// Forward/back substitution plus reactions.
    pub solve_ms: f64,
    /// NBEQ, the unknown displacements.
    pub free_dofs: usize,
    /// NP, the prescribed displacements.
    pub prescribed_dofs: usize,
    /// Stored entries of K11 (upper triangle).
    pub matrix_nnz: usize,
    /// Entries of the Cholesky factor L.
    pub factor_nnz: usize,
    /// Multiply-adds of its numeric factorization, as the symbolic analysis plans it.
    pub factor_work: f64,
    /// ‖K11·Uu − (Rk − K12·Uk)‖ / ‖Rk − K12·Uk‖.
    pub relative_residual: f64,
}

/// The result of one partitioned solve.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Displacement of every dof: Uu where free, Uk where prescribed.
    pub displacement: Vec<f64>,
    /// At prescribed dofs the force the support exerts, Ru − R (equation (8) less the external
    /// load applied at that dof); zero at free dofs.
    pub reaction: Vec<f64>,
    /// Cost and quality.
    pub stats: SolveStats,
}

impl Solution {
    /// Displacement of node `n`.
    pub fn node_displacement(&self, n: usize) -> Vector3<f64> {
        Vector3::new(
            self.displacement[3 * n],
            self.displacement[3 * n + 1],
            self.displacement[3 * n + 2],
        )
    }

    /// Reaction at node `n` (zero at its free dofs).
    pub fn reaction_at(&self, n: usize) -> Vector3<f64> {
        Vector3::new(
            self.reaction[3 * n],
            self.reaction[3 * n + 1],
            self.reaction[3 * n + 2],
        )
    }
}

/// Symbolic analysis of K11 for one partition of one pattern.
struct Analysis {
    pattern: Arc<StiffnessPattern>,
    partition: DofPartition,
    /// Index into the full upper values of each stored K11 entry.
    gather: Vec<usize>,
    k11: SymbolicSparseColMat<usize>,
    cholesky: SymbolicCholesky<usize>,
    /// The numeric factorization's work per free dof of the last analysis that ordered afresh
    /// (this one, or the one whose order this carries over).
    work_per_dof: f64,
    /// The free dofs in elimination order, each as 3 × its node's identity + its axis (see
    /// [`PartitionedSolver::set_node_ids`]).
    order_keys: Vec<usize>,
}

/// Solves equations (7) and (8), keeping the symbolic analysis between calls.
#[derive(Default)]
pub struct PartitionedSolver {
    ordering: FillOrdering,
    analysis: Option<Analysis>,
    factor: Vec<f64>,
    /// The K11 values `factor` is the Cholesky factor of (empty when there is none): a solve
    /// with the same matrix again (a gas cavity's pressures, a contact step redone with other
    /// loads) reuses the factor instead of refactorizing.
    factored: Vec<f64>,
    scratch: Vec<MaybeUninit<u64>>,
    /// The identity of each node of the next patterns (empty: its index).
    node_ids: Vec<usize>,
}

impl PartitionedSolver {
    /// A solver using the given fill-reducing ordering.
    pub fn new(ordering: FillOrdering) -> Self {
        Self {
            ordering,
            analysis: None,
            factor: Vec::new(),
            factored: Vec::new(),
            scratch: Vec::new(),
            node_ids: Vec::new(),
        }
    }

    /// Names the nodes of the patterns solved next by their identity in a larger mesh (a
    /// flexion region's nodes by their hand node): where a later pattern numbers the same
    /// nodes otherwise (the region grew or shrank by a few cells), the elimination order is
    /// carried over through these identities instead of ordered afresh. Without it a node's
    /// identity is its index.
    pub fn set_node_ids(&mut self, ids: Vec<usize>) {
        self.node_ids = ids;
    }

    /// The fill-reducing ordering it uses.
    pub fn ordering(&self) -> FillOrdering {
        self.ordering
    }

    /// Entries of the factor's buffer as held (acquired by the largest factorization so far, or
    /// [`PartitionedSolver::reserve_for`]).
    pub fn factor_capacity(&self) -> usize {
        self.factor.capacity()
    }

    /// Acquires ahead the memory a factorization of `partition` on `pattern` takes (the factor
    /// and its scratch, written once so that their pages are the process's): a first
    /// factorization otherwise pays for them (the hand's 61 MB factor at resolution 1: its first
    /// factorization took 206–382 ms where the next took 83–121 ms). The analysis it needs for
    /// their sizes is not kept: the solve that follows orders its own region. For an idle solver
    /// thread (the viewer's). Refused as a solve would be when the factor does not fit the
    /// memory budget.
    pub fn reserve_for(
        &mut self,
        pattern: &Arc<StiffnessPattern>,
        partition: &DofPartition,
        positions: &[Vector3<f64>],
    ) -> Result<(), SolveError> {
        let neq = partition.free_count();
        if neq == 0 {
            return Ok(());
        }
        let keys = dof_keys(&self.node_ids, pattern.dofs);
        let analysis = analyse(pattern, partition, positions, self.ordering, &keys)?;
        let entries = analysis.cholesky.len_val();
        let par = factorization_parallelism(factor_work(&analysis.cholesky));
        let scratch_bytes = analysis
            .cholesky
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .unaligned_bytes_required();
        within_budget(
            self.bytes_beyond_held(entries, 0, scratch_bytes as u64),
            neq,
            entries,
        )?;
        if self.factor.len() < entries {
            // The factor's values are no longer those of any matrix.
            self.factored.clear();
            grow_zeroed(&mut self.factor, entries);
        }
        for word in scratch(&mut self.scratch, scratch_bytes) {
            word.write(0);
        }
        Ok(())
    }

    /// Bytes a factorization takes beyond the buffers held: its factor's `entries`, `values`
    /// more (K11's, gathered), and `scratch_bytes` of scratch.
    fn bytes_beyond_held(&self, entries: usize, values: usize, scratch_bytes: u64) -> u64 {
        (entries.saturating_sub(self.factor.capacity()) as u64)
            .saturating_add(values as u64)
            .saturating_mul(8)
            .saturating_add(scratch_bytes.saturating_sub(8 * self.scratch.capacity() as u64))
    }

    /// Solves K·U = R with the dofs marked in `partition` held at `prescribed_values`
    /// (read only at prescribed dofs). `positions` are the node positions the ordering works on.
    pub fn solve(
        &mut self,
        k: &Stiffness,
        partition: &DofPartition,
        prescribed_values: &[f64],
        loads: &[f64],
        positions: &[Vector3<f64>],
    ) -> Result<Solution, SolveError> {
        let dofs = k.pattern.dofs;
        assert_eq!(partition.prescribed.len(), dofs);
        assert_eq!(prescribed_values.len(), dofs);
        assert_eq!(loads.len(), dofs);
        if k.values.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("the stiffness matrix"));
        }
        if loads.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("the load vector"));
        }
        if (0..dofs).any(|d| partition.prescribed[d] && !prescribed_values[d].is_finite()) {
            return Err(SolveError::NonFinite("the prescribed displacements"));
        }
        let mut stats = SolveStats {
            free_dofs: partition.free_count(),
            prescribed_dofs: partition.prescribed_count(),
            ..Default::default()
        };

        // The analysis holds for the same pattern, or an equal one built again (a flexion
        // increment's region rebuilt over the same cells), with the same prescribed dofs.
        let reuse = self.analysis.as_ref().is_some_and(|a| {
            let same_pattern = Arc::ptr_eq(&a.pattern, &k.pattern)
                || (a.pattern.dofs == k.pattern.dofs
                    && a.pattern.col_ptr == k.pattern.col_ptr
                    && a.pattern.row_idx == k.pattern.row_idx);
            same_pattern && a.partition == *partition
        });
        if !reuse {
            let t = Instant::now();
            // A prescribed set a little changed on the same pattern (a flexion increment's
            // region losing a few nodes to a bone, a contact region grown by a few cells):
            // the last elimination order carried over, unless that fills more.
            let keys = dof_keys(&self.node_ids, k.pattern.dofs);
            let carried = self
                .analysis
                .as_ref()
                .and_then(|a| carried_analysis(a, &k.pattern, partition, &keys));
            stats.order_carried = carried.is_some();
            self.analysis = Some(match carried {
                Some(a) => a,
                None => {
                    let entries = k11_entries(&k.pattern, partition);
                    ordering_within_budget(entries, partition.free_count())?;
                    analyse(&k.pattern, partition, positions, self.ordering, &keys)?
                }
            });
            stats.symbolic_ms = ms(t);
        }
        stats.symbolic_reused = reuse;
        let analysis = self.analysis.as_ref().unwrap();
        let neq = partition.free_count();

        // Uk embedded in a full vector; K·[0; Uk] gives K12·Uk on the free rows (eq. 7)
        // and K22·Uk on the prescribed rows (eq. 8).
        let mut u: Vec<f64> = (0..dofs)
            .map(|d| {
                if partition.prescribed[d] {
                    prescribed_values[d]
                } else {
                    0.0
                }
            })
            .collect();

        // What the factorization will take, known from the analysis before anything is
        // allocated: the factor (beyond the buffer already held), its scratch and K11's values.
        let entries = analysis.cholesky.len_val();
        let scratch_bytes = analysis
            .cholesky
            .factorize_numeric_llt_scratch::<f64>(
                faer::get_global_parallelism(),
                Default::default(),
            )
            .unaligned_bytes_required() as u64;
        let needed = self.bytes_beyond_held(entries, analysis.gather.len(), scratch_bytes);
        within_budget(needed, neq, entries)?;

        let t = Instant::now();
        let k11_values: Vec<f64> = analysis.gather.iter().map(|&i| k.values[i]).collect();
        let k11 = SparseColMatRef::new(analysis.k11.as_ref(), &k11_values);
        let len = analysis.cholesky.len_val();
        stats.factor_nnz = len;
        stats.factor_work = factor_work(&analysis.cholesky);
        let par = factorization_parallelism(stats.factor_work);
        stats.matrix_nnz = k11_values.len();
        let factored = reuse && self.factored == k11_values;
        stats.factor_reused = factored;
        if !factored {
            self.factored.clear();
            grow_zeroed(&mut self.factor, len);
            let req = analysis
                .cholesky
                .factorize_numeric_llt_scratch::<f64>(par, Default::default());
            let mem = scratch(&mut self.scratch, req.unaligned_bytes_required());
            analysis
                .cholesky
                .factorize_numeric_llt(
                    &mut self.factor,
                    k11,
                    Side::Upper,
                    LltRegularization::default(),
                    par,
                    MemStack::new_any(mem),
                    Default::default(),
                )
                .map_err(|e| match e {
                    LltError::NonPositivePivot { index } => {
                        // faer counts the pivot from 1 in its simplicial factorization (and
                        // may from 0 in its supernodal one): the step, within 0..neq.
                        let step = index.saturating_sub(1).min(neq.saturating_sub(1));
                        let perm = analysis.cholesky.perm();
                        let eq = perm.map_or(step, |p| p.arrays().0[step]);
                        SolveError::NotPositiveDefinite {
                            pivot: index,
                            equations: neq,
                            node: partition.free[eq] / 3,
                        }
                    }
                })?;
            self.factored = k11_values;
        }
        stats.factorization_ms = ms(t);

        let t = Instant::now();
        let ku = k.mul(&u);
        let rhs: Vec<f64> = partition.free.iter().map(|&d| loads[d] - ku[d]).collect();
        let mut x = rhs.clone();
        {
            // One column: sequential (a task per supernode costs more than its work).
            let llt = LltRef::new(&analysis.cholesky, &self.factor);
            let req = analysis.cholesky.solve_in_place_scratch::<f64>(1, Par::Seq);
            let mem = scratch(&mut self.scratch, req.unaligned_bytes_required());
            llt.solve_in_place_with_conj(
                Conj::No,
                MatMut::from_column_major_slice_mut(&mut x, neq, 1),
                Par::Seq,
                MemStack::new_any(mem),
            );
        }
        for (e, &d) in partition.free.iter().enumerate() {
            u[d] = x[e];
        }
        // Equation (8): Ru = K21·Uu + K22·Uk; the support's share is Ru less the applied load.
        let ku = k.mul(&u);
        let mut reaction = vec![0.0; dofs];
        let mut residual = 0.0;
        let mut reference = 0.0;
        for d in 0..dofs {
            let r = ku[d] - loads[d];
            if partition.prescribed[d] {
                reaction[d] = r;
            } else {
                residual += r * r;
            }
        }
        for v in &rhs {
            reference += v * v;
        }
        stats.relative_residual = if reference > 0.0 {
            (residual / reference).sqrt()
        } else {
            residual.sqrt()
        };
        stats.solve_ms = ms(t);
        if u.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("the computed displacement"));
        }
        Ok(Solution {
            displacement: u,
            reaction,
            stats,
        })
    }
}

/// A factorization of `equations` equations and `entries` factor entries that needs `needed`
/// more bytes, refused where the memory budget does not leave them.
fn within_budget(needed: u64, equations: usize, entries: usize) -> Result<(), SolveError> {
    if let Some((available, limit)) = super::memory::budget() {
        if needed > available {
            return Err(SolveError::TooBig {
                needed,
                available,
                limit,
                equations,
                entries,
            });
        }
    }
    Ok(())
}

/// Bytes the ordering and the symbolic analysis of K11 take while they run, a stored entry of
/// its upper triangle: its structure and where each value is (8 B each), faer's minimum-degree
/// workspace (about 2.2 words an entry), and the two symbolic factorizations that run side by
/// side (`analyse`: minimum degree and nested dissection, each on a permuted copy, 2 words an
/// entry). Measured: a cube of 100³ cells (3.0 M equations, 123 M entries) peaked at 10.1 GB,
/// its model ≈ 3.5 GB of it.
const ORDERING_BYTES_PER_ENTRY: u64 = 56;

/// And an equation (permutations, elimination tree, counts, supernodes: 16 words).
const ORDERING_BYTES_PER_EQUATION: u64 = 128;

/// The stored entries of K11's upper triangle (the free rows and columns of `pattern`),
/// counted without building it.
fn k11_entries(pattern: &StiffnessPattern, partition: &DofPartition) -> u64 {
    partition
        .free
        .iter()
        .map(|&d| {
            pattern.row_idx[pattern.col_ptr[d]..pattern.col_ptr[d + 1]]
                .iter()
                .filter(|&&r| partition.equation[r] != usize::MAX)
                .count() as u64
        })
        .sum()
}

/// The ordering of `equations` equations with `entries` stored entries, refused before it runs
/// where the memory budget does not leave what it takes (a cube of 150³ cells, 10 M equations,
/// was killed by the kernel at 24 GB while it ordered, before its factor could be refused).
fn ordering_within_budget(entries: u64, equations: usize) -> Result<(), SolveError> {
    let needed = entries
        .saturating_mul(ORDERING_BYTES_PER_ENTRY)
        .saturating_add((equations as u64).saturating_mul(ORDERING_BYTES_PER_EQUATION));
    if let Some((available, limit)) = super::memory::budget() {
        if needed > available {
            return Err(SolveError::OrderingTooBig {
                needed,
                available,
                limit,
                equations,
            });
        }
    }
    Ok(())
}

/// Right-hand sides from which a substitution with the factor runs in parallel.
const SOLVE_PARALLEL_COLUMNS: usize = 8;

/// The numeric factorization's multiply-adds ([`factor_work`]) from which it runs in parallel
/// (faer's global parallelism). Below, sequential: on the 2-core machine of
/// docs/performance.md a contact step's factorization (9 300 equations) took 36 ms alone
/// against 45–62 ms on both cores, and the 20³ cube of `bench solver` (26 019 equations)
/// 361–371 ms against 532 ms.
const PARALLEL_FACTOR_WORK: f64 = 2.0e10;

/// The parallelism of a numeric factorization of `work` multiply-adds.
fn factorization_parallelism(work: f64) -> Par {
    if work < PARALLEL_FACTOR_WORK {
        Par::Seq
    } else {
        faer::get_global_parallelism()
    }
}

impl PartitionedSolver {
    /// Solves K11·X = B in place with the factor of the last [`PartitionedSolver::solve`], for
    /// `columns` right-hand sides stored column by column in `b` (each of length NBEQ, ordered as
    /// the partition's free dofs). Costs substitutions only: this is what lets contact
    /// constraints be added through a Schur complement without refactorizing.
    pub fn solve_factored(&mut self, b: &mut [f64], columns: usize) -> Result<(), SolveError> {
        let Some(analysis) = self.analysis.as_ref() else {
            return Err(SolveError::Faer("no factorization to reuse".into()));
        };
        let neq = analysis.partition.free_count();
        assert_eq!(b.len(), neq * columns);
        if columns == 0 || neq == 0 {
            return Ok(());
        }
        // A few columns: sequential (a task per supernode costs more than its work).
        let par = if columns < SOLVE_PARALLEL_COLUMNS {
            Par::Seq
        } else {
            faer::get_global_parallelism()
        };
        let llt = LltRef::new(&analysis.cholesky, &self.factor);
        let req = analysis
            .cholesky
            .solve_in_place_scratch::<f64>(columns, par);
        let mem = scratch(&mut self.scratch, req.unaligned_bytes_required());
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, neq, columns),
            par,
            MemStack::new_any(mem),
        );
        if b.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("a solution with the reused factor"));
        }
        Ok(())
    }
}

/// Extracts the pattern of K11 from the full upper pattern, orders it and analyses it.
/// Free dofs new to a prescribed set, as a share of its free dofs, up to which the last
/// elimination order is carried over (they are eliminated last).
const CARRIED_NEW: f64 = 0.01;

/// The numeric factorization's work per free dof, relative to that of the last order made
/// afresh, up to which a carried-over order is kept.
const CARRIED_FILL: f64 = 1.05;

/// Floating-point multiply-adds of the numeric factorization the symbolic analysis `cholesky`
/// plans: Σ c_j² over the factor's columns (c_j its entries below the diagonal); for a
/// supernode of w columns and r rows below them, w³/3 + r·w² + r²·w (its diagonal block, the
/// panel below it, and its update of the rest).
pub(crate) fn factor_work(cholesky: &SymbolicCholesky<usize>) -> f64 {
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
    match cholesky.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => s
            .col_ptr()
            .windows(2)
            .map(|w| {
                let c = w[1].saturating_sub(w[0]).saturating_sub(1) as f64;
                c * c
            })
            .sum(),
        SymbolicCholeskyRaw::Supernodal(s) => {
            let rows = s.col_ptr_for_row_idx();
            (0..s.n_supernodes())
                .map(|k| {
                    let w = (s.supernode_end()[k] - s.supernode_begin()[k]) as f64;
                    let r = (rows[k + 1] - rows[k]) as f64;
                    w * w * w / 3.0 + r * w * w + r * r * w
                })
                .sum()
        }
    }
}

/// Each dof's key: 3 × its node's identity (`ids`, or its index where empty) + its axis.
fn dof_keys(ids: &[usize], dofs: usize) -> Vec<usize> {
    (0..dofs)
        .map(|d| 3 * ids.get(d / 3).copied().unwrap_or(d / 3) + d % 3)
        .collect()
}

/// The analysis of `partition` on `pattern` (its dofs' `keys`) with the elimination order of
/// `last` (an analysis of the same nodes, maybe numbered otherwise, with other dofs free): the
/// free dofs in their last order, the new ones after them. `None` where too many are new, the
/// symbolic analysis fails, or the factorization would cost more than [`CARRIED_FILL`] times
/// the order made afresh (per free dof).
fn carried_analysis(
    last: &Analysis,
    pattern: &Arc<StiffnessPattern>,
    partition: &DofPartition,
    keys: &[usize],
) -> Option<Analysis> {
    let neq = partition.free_count();
    if neq == 0 {
        return None;
    }
    let mut rank = std::collections::HashMap::with_capacity(last.order_keys.len());
    for (i, &key) in last.order_keys.iter().enumerate() {
        rank.insert(key, i);
    }
    let (mut kept, mut new): (Vec<(usize, usize)>, Vec<usize>) = (Vec::new(), Vec::new());
    for (eq, &d) in partition.free.iter().enumerate() {
        match rank.get(&keys[d]) {
            Some(&r) => kept.push((r, eq)),
            None => new.push(eq),
        }
    }
    if new.len() as f64 > CARRIED_NEW * neq as f64 {
        return None;
    }
    kept.sort_unstable();
    let forward: Vec<usize> = kept.into_iter().map(|(_, eq)| eq).chain(new).collect();
    let (col_ptr, row_idx, gather) = k11_structure(pattern, partition);
    let k11 = SymbolicSparseColMat::new_checked(neq, neq, col_ptr, None, row_idx);
    let order_keys = forward.iter().map(|&eq| keys[partition.free[eq]]).collect();
    let mut inverse = vec![0usize; neq];
    for (i, &eq) in forward.iter().enumerate() {
        inverse[eq] = i;
    }
    let perm = Perm::new_checked(forward.into_boxed_slice(), inverse.into_boxed_slice(), neq);
    let cholesky = factorize_symbolic_cholesky(
        k11.as_ref(),
        Side::Upper,
        SymmetricOrdering::Custom(perm.as_ref()),
        Default::default(),
    )
    .ok()?;
    if factor_work(&cholesky) > CARRIED_FILL * last.work_per_dof * neq as f64 {
        return None;
    }
    Some(Analysis {
        pattern: pattern.clone(),
        partition: partition.clone(),
        gather,
        k11,
        cholesky,
        work_per_dof: last.work_per_dof,
        order_keys,
    })
}

/// The upper triangle of K11 (the free rows and columns of `pattern`): column pointers, row
/// indices, and where each entry's value is in the pattern's.
fn k11_structure(
    pattern: &StiffnessPattern,
    partition: &DofPartition,
) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
    let neq = partition.free_count();
    let mut col_ptr = Vec::with_capacity(neq + 1);
    let mut row_idx = Vec::new();
    let mut gather = Vec::new();
    col_ptr.push(0);
    for &d in &partition.free {
        for k in pattern.col_ptr[d]..pattern.col_ptr[d + 1] {
            let eq = partition.equation[pattern.row_idx[k]];
            if eq != usize::MAX {
                row_idx.push(eq);
                gather.push(k);
            }
        }
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx, gather)
}

fn analyse(
    pattern: &Arc<StiffnessPattern>,
    partition: &DofPartition,
    positions: &[Vector3<f64>],
    ordering: FillOrdering,
    keys: &[usize],
) -> Result<Analysis, SolveError> {
    let neq = partition.free_count();
    let (col_ptr, row_idx, gather) = k11_structure(pattern, partition);
    let k11 = SymbolicSparseColMat::new_checked(neq, neq, col_ptr, None, row_idx);
    let amd = || {
        factorize_symbolic_cholesky(
            k11.as_ref(),
            Side::Upper,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| SolveError::Faer(format!("{e:?}")))
    };
    let dissection = || {
        let free_nodes: Vec<usize> = (0..positions.len())
            .filter(|&n| (0..3).any(|i| !partition.prescribed[3 * n + i]))
            .collect();
        let node_order = nested_dissection(&free_nodes, positions, &pattern.node_neighbours);
        let forward: Vec<usize> = node_order
            .iter()
            .flat_map(|&n| (0..3).map(move |i| 3 * n + i))
            .filter(|&d| !partition.prescribed[d])
            .map(|d| partition.equation[d])
            .collect();
        let mut inverse = vec![0usize; neq];
        for (new, &old) in forward.iter().enumerate() {
            inverse[old] = new;
        }
        let perm = Perm::new_checked(forward.into_boxed_slice(), inverse.into_boxed_slice(), neq);
        factorize_symbolic_cholesky(
            k11.as_ref(),
            Side::Upper,
            SymmetricOrdering::Custom(perm.as_ref()),
            Default::default(),
        )
        .map_err(|e| SolveError::Faer(format!("{e:?}")))
    };
    let cholesky = match ordering {
        FillOrdering::Amd => amd()?,
        FillOrdering::NestedDissection => dissection()?,
        // The symbolic analysis tells the numeric factorization's work before any is done.
        // Both at once (on two cores the full hand's at resolution 1 took 80 ms one after the
        // other).
        FillOrdering::Auto => {
            let (a, d) = rayon::join(amd, dissection);
            let (a, d) = (a?, d?);
            if factor_work(&a) < factor_work(&d) {
                a
            } else {
                d
            }
        }
    };
    let work_per_dof = factor_work(&cholesky) / neq.max(1) as f64;
    let order_keys = match cholesky.perm() {
        Some(p) => p
            .arrays()
            .0
            .iter()
            .map(|&eq| keys[partition.free[eq]])
            .collect(),
        None => partition.free.iter().map(|&d| keys[d]).collect(),
    };
    Ok(Analysis {
        pattern: pattern.clone(),
        partition: partition.clone(),
        gather,
        k11,
        cholesky,
        work_per_dof,
        order_keys,
    })
}

/// The supernodal Cholesky factor of the last solve, when faer chose the supernodal form: its
/// structure, values and the forward permutation (row i of the factor is equation fwd[i]).
pub(crate) struct SupernodalFactor<'a> {
    pub symbolic: &'a faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    pub values: &'a [f64],
    pub forward: Option<&'a [usize]>,
}

impl PartitionedSolver {
    /// The factor of the last solve, if it is supernodal.
    pub(crate) fn supernodal_factor(&self) -> Option<SupernodalFactor<'_>> {
        let analysis = self.analysis.as_ref()?;
        match analysis.cholesky.raw() {
            faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(symbolic) => {
                Some(SupernodalFactor {
                    symbolic,
                    values: &self.factor[..analysis.cholesky.len_val()],
                    forward: analysis.cholesky.perm().map(|p| p.arrays().0),
                })
            }
            _ => None,
        }
    }
}
