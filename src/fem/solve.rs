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
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::Vector3;
use rayon::prelude::*;
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
    /// The blocks K11 was held in (src/fem/blocks.rs: one per group of nodes no cell joins;
    /// 1 without groups).
    pub blocks: usize,
    /// Of those, the blocks whose factor was kept (their values those it was made of).
    pub blocks_reused: usize,
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
    /// Whether the supernodal form was forced (blocks told apart: `symbolic_params`).
    supernodal: bool,
}

/// The group of a block holding every free dof (no groups told, or groups joined by a cell).
const ALL: u32 = u32::MAX;

/// One block of K11 (src/fem/blocks.rs; all of K11 where no groups are told): its analysis, its
/// factor, and the values it is the factor of.
#[derive(Default)]
struct Block {
    group: u32,
    analysis: Option<Analysis>,
    factor: Vec<f64>,
    /// The K11 values `factor` is the Cholesky factor of (empty when there is none): a solve
    /// with the same matrix again (a gas cavity's pressures, a contact step redone with other
    /// loads, an object that stays linear, an object factored ahead) reuses the factor instead
    /// of refactorizing.
    factored: Vec<f64>,
    scratch: Vec<MaybeUninit<u64>>,
}

/// A block taking part in the last solve: which, its partition (only its free dofs free), and
/// the equation of the whole partition each of its equations is (`None`: every one, in order).
struct Part {
    block: usize,
    partition: DofPartition,
    equations: Option<Vec<usize>>,
}

/// How the last solve's K11 is held: its pattern and partition, and its blocks.
struct Layout {
    pattern: Arc<StiffnessPattern>,
    partition: DofPartition,
    parts: Vec<Part>,
}

/// Solves equations (7) and (8), keeping the symbolic analysis between calls.
#[derive(Default)]
pub struct PartitionedSolver {
    ordering: FillOrdering,
    /// Blocks by group, each kept while other groups' change (a contact step's ball while its
    /// flesh region grows and shrinks).
    blocks: Vec<Block>,
    layout: Option<Layout>,
    /// The identity of each node of the next patterns (empty: its index).
    node_ids: Vec<usize>,
    /// The group of each node (empty: none told, K11 is one block).
    node_groups: Vec<u32>,
}

/// Whether two patterns are one (the same, or an equal one built again: a flexion increment's
/// region rebuilt over the same cells).
fn same_pattern(a: &Arc<StiffnessPattern>, b: &Arc<StiffnessPattern>) -> bool {
    Arc::ptr_eq(a, b) || (a.dofs == b.dofs && a.col_ptr == b.col_ptr && a.row_idx == b.row_idx)
}

impl Block {
    /// Bytes a factorization takes beyond the buffers held: its factor's `entries`, `values`
    /// more (K11's, gathered), and `scratch_bytes` of scratch.
    fn bytes_beyond_held(&self, entries: usize, values: usize, scratch_bytes: u64) -> u64 {
        (entries.saturating_sub(self.factor.capacity()) as u64)
            .saturating_add(values as u64)
            .saturating_mul(8)
            .saturating_add(scratch_bytes.saturating_sub(8 * self.scratch.capacity() as u64))
    }

    /// Factors `k11_values` (gathered by the analysis) in place of the last factor.
    fn factorize(&mut self, k11_values: Vec<f64>) -> Result<(), SolveError> {
        let analysis = self
            .analysis
            .as_ref()
            .expect("analysed before it is factored");
        let neq = analysis.partition.free_count();
        let k11 = SparseColMatRef::new(analysis.k11.as_ref(), &k11_values);
        let len = analysis.cholesky.len_val();
        let par = factorization_parallelism(factor_work(&analysis.cholesky));
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
                        node: analysis.partition.free[eq] / 3,
                    }
                }
            })?;
        self.factored = k11_values;
        Ok(())
    }

    /// Solves its block of K11·X = B in place for `columns` right-hand sides stored column by
    /// column in `b` (each as long as the block's equations).
    fn substitute(&mut self, b: &mut [f64], columns: usize, par: Par) {
        let analysis = self
            .analysis
            .as_ref()
            .expect("factored before it is solved");
        let neq = analysis.partition.free_count();
        if neq == 0 || columns == 0 {
            return;
        }
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
    }
}

impl PartitionedSolver {
    /// A solver using the given fill-reducing ordering.
    pub fn new(ordering: FillOrdering) -> Self {
        Self {
            ordering,
            blocks: Vec::new(),
            layout: None,
            node_ids: Vec::new(),
            node_groups: Vec::new(),
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

    /// Tells the group of each node (a contact step's bodies): where no cell joins the free
    /// dofs of two groups, K11 is block diagonal and each group's block is analysed, factored
    /// and kept on its own (src/fem/blocks.rs) — a block whose values come again keeps its
    /// factor while the others change. Without it, K11 is one block.
    pub fn set_node_groups(&mut self, groups: Vec<u32>) {
        if self.node_groups != groups {
            self.node_groups = groups;
            self.layout = None;
        }
    }

    /// The fill-reducing ordering it uses.
    pub fn ordering(&self) -> FillOrdering {
        self.ordering
    }

    /// Entries of the factors' buffers as held (acquired by the largest factorizations so far,
    /// or [`PartitionedSolver::reserve_for`]).
    pub fn factor_capacity(&self) -> usize {
        self.blocks.iter().map(|b| b.factor.capacity()).sum()
    }

    /// The kept block of `group`, made where there is none.
    fn block_of(&mut self, group: u32) -> usize {
        match self.blocks.iter().position(|b| b.group == group) {
            Some(i) => i,
            None => {
                self.blocks.push(Block {
                    group,
                    ..Default::default()
                });
                self.blocks.len() - 1
            }
        }
    }

    /// Acquires ahead the memory a factorization of `partition` on `pattern` takes (the factor
    /// and its scratch, written once so that their pages are the process's): a first
    /// factorization otherwise pays for them (the hand's 61 MB factor at resolution 1: its first
    /// factorization took 206–382 ms where the next took 83–121 ms). The analysis it needs for
    /// their sizes is not kept: the solve that follows orders its own region. For an idle solver
    /// thread (the viewer's), of a solver that holds K11 as one block. Refused as a solve would
    /// be when the factor does not fit the memory budget.
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
        let analysis = analyse(pattern, partition, positions, self.ordering, &keys, false)?;
        let entries = analysis.cholesky.len_val();
        let par = factorization_parallelism(factor_work(&analysis.cholesky));
        let scratch_bytes = analysis
            .cholesky
            .factorize_numeric_llt_scratch::<f64>(par, Default::default())
            .unaligned_bytes_required();
        let i = self.block_of(ALL);
        let block = &mut self.blocks[i];
        within_budget(
            block.bytes_beyond_held(entries, 0, scratch_bytes as u64),
            neq,
            entries,
        )?;
        if block.factor.len() < entries {
            // The factor's values are no longer those of any matrix.
            block.factored.clear();
            grow_zeroed(&mut block.factor, entries);
        }
        for word in scratch(&mut block.scratch, scratch_bytes) {
            word.write(0);
        }
        Ok(())
    }

    /// The blocks of `partition` on `pattern`, made the layout (kept where both are the last's).
    fn lay_out(&mut self, pattern: &Arc<StiffnessPattern>, partition: &DofPartition) {
        if self
            .layout
            .as_ref()
            .is_some_and(|l| same_pattern(&l.pattern, pattern) && l.partition == *partition)
        {
            return;
        }
        let neq = partition.free_count();
        let parts = match super::blocks::split(pattern, partition, &self.node_groups) {
            Some(blocks) => blocks
                .into_iter()
                .map(|b| Part {
                    block: self.block_of(b.group),
                    partition: b.partition,
                    equations: (b.equations.len() < neq).then_some(b.equations),
                })
                .collect(),
            None => vec![Part {
                block: self.block_of(ALL),
                partition: partition.clone(),
                equations: None,
            }],
        };
        self.layout = Some(Layout {
            pattern: pattern.clone(),
            partition: partition.clone(),
            parts,
        });
    }

    /// Analyses and factors the blocks of K11 for `partition` (each block's analysis and factor
    /// kept where its partition and values are those it has), filling `stats`. Where it fails,
    /// no factor is left to substitute with.
    fn factor_blocks(
        &mut self,
        k: &Stiffness,
        partition: &DofPartition,
        positions: &[Vector3<f64>],
        stats: &mut SolveStats,
    ) -> Result<(), SolveError> {
        self.lay_out(&k.pattern, partition);
        // (Held out of the solver until every block is factored: a failure leaves none.)
        let layout = self.layout.take().expect("laid out above");
        let mut keys: Option<Vec<usize>> = None;
        // Blocks told apart are factored supernodal whatever their size: the half
        // substitutions of contact rows (src/fem/forward.rs) need every block so.
        let supernodal = !self.node_groups.is_empty();
        let t = Instant::now();
        let mut reused_all = true;
        let mut carried_any = false;
        let mut analysed = Vec::with_capacity(layout.parts.len());
        for part in &layout.parts {
            let block = &mut self.blocks[part.block];
            // The analysis holds for the same pattern with the same prescribed dofs (and the
            // same form).
            let reuse = block.analysis.as_ref().is_some_and(|a| {
                same_pattern(&a.pattern, &k.pattern)
                    && a.partition == part.partition
                    && a.supernodal == supernodal
            });
            if !reuse {
                // A prescribed set a little changed on the same pattern (a flexion increment's
                // region losing a few nodes to a bone, a contact region grown by a few cells):
                // the last elimination order carried over, unless that fills more.
                let keys = keys.get_or_insert_with(|| dof_keys(&self.node_ids, k.pattern.dofs));
                let carried = block.analysis.as_ref().and_then(|a| {
                    carried_analysis(a, &k.pattern, &part.partition, keys, supernodal)
                });
                carried_any |= carried.is_some();
                // (Its factor is no longer that of any values under the new analysis.)
                block.factored.clear();
                block.analysis = Some(match carried {
                    Some(a) => a,
                    None => {
                        let entries = k11_entries(&k.pattern, &part.partition);
                        ordering_within_budget(entries, part.partition.free_count())?;
                        let ordering = self.ordering;
                        analyse(
                            &k.pattern,
                            &part.partition,
                            positions,
                            ordering,
                            keys,
                            supernodal,
                        )?
                    }
                });
            }
            reused_all &= reuse;
            analysed.push(reuse);
        }
        stats.symbolic_ms = if reused_all { 0.0 } else { ms(t) };
        stats.symbolic_reused = reused_all;
        stats.order_carried = carried_any;

        // What the factorizations will take, known from the analyses before anything is
        // allocated: the factors (beyond the buffers already held), their scratch and K11's
        // values.
        let t = Instant::now();
        let mut needed = 0u64;
        let mut todo: Vec<Option<Vec<f64>>> = vec![None; self.blocks.len()];
        let (mut entries, mut work, mut values) = (0usize, 0.0, 0usize);
        for (part, &reuse) in layout.parts.iter().zip(&analysed) {
            let block = &self.blocks[part.block];
            let analysis = block.analysis.as_ref().expect("analysed above");
            let k11_values: Vec<f64> = analysis.gather.iter().map(|&i| k.values[i]).collect();
            entries += analysis.cholesky.len_val();
            work += factor_work(&analysis.cholesky);
            values += k11_values.len();
            if reuse && block.factored == k11_values {
                continue;
            }
            let scratch_bytes = analysis
                .cholesky
                .factorize_numeric_llt_scratch::<f64>(
                    faer::get_global_parallelism(),
                    Default::default(),
                )
                .unaligned_bytes_required() as u64;
            needed = needed.saturating_add(block.bytes_beyond_held(
                analysis.cholesky.len_val(),
                k11_values.len(),
                scratch_bytes,
            ));
            todo[part.block] = Some(k11_values);
        }
        stats.factor_nnz = entries;
        stats.factor_work = work;
        stats.matrix_nnz = values;
        within_budget(needed, partition.free_count(), entries)?;
        stats.blocks = layout.parts.len();
        stats.blocks_reused = layout.parts.len() - todo.iter().filter(|v| v.is_some()).count();
        stats.factor_reused = stats.blocks_reused == stats.blocks;
        // Blocks factored side by side (the ball's and the flesh region's; each in parallel
        // itself only where it is large: `factorization_parallelism`).
        let mut jobs: Vec<(&mut Block, Vec<f64>)> = self
            .blocks
            .iter_mut()
            .zip(todo)
            .filter_map(|(b, v)| v.map(|v| (b, v)))
            .collect();
        if jobs.len() == 1 {
            let (block, values) = jobs.pop().expect("one");
            block.factorize(values)?;
        } else {
            jobs.into_par_iter()
                .map(|(block, values)| block.factorize(values))
                .collect::<Result<Vec<()>, SolveError>>()?;
        }
        stats.factorization_ms = ms(t);
        self.layout = Some(layout);
        Ok(())
    }

    /// Factors K11 of `k` for `partition` ahead of a solve, block by block: a later
    /// [`PartitionedSolver::solve`] whose blocks include one of these with the same values
    /// reuses its factor. What a contact step's objects are factored with while other work
    /// runs (src/solve/objects_factor.rs). Substitutions until the next solve
    /// ([`PartitionedSolver::solve_factored`], the half substitutions) are with these factors,
    /// on `partition`.
    pub fn factor_ahead(
        &mut self,
        k: &Stiffness,
        partition: &DofPartition,
        positions: &[Vector3<f64>],
    ) -> Result<SolveStats, SolveError> {
        if k.values.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("the stiffness matrix"));
        }
        let mut stats = SolveStats {
            free_dofs: partition.free_count(),
            prescribed_dofs: partition.prescribed_count(),
            ..Default::default()
        };
        if partition.free_count() > 0 {
            self.factor_blocks(k, partition, positions, &mut stats)?;
        }
        Ok(stats)
    }

    /// Solves K11·X = B in place with the factors of the last factorization, part by part (`b`
    /// ordered as the layout's partition's free dofs, `columns` of them).
    fn substitute(&mut self, b: &mut [f64], columns: usize, par: Par) {
        let layout = self.layout.as_ref().expect("factored before it is solved");
        let neq = layout.partition.free_count();
        for part in &layout.parts {
            let block = &mut self.blocks[part.block];
            match &part.equations {
                None => block.substitute(b, columns, par),
                Some(eqs) => {
                    let n = eqs.len();
                    let mut local = vec![0.0; n * columns];
                    for j in 0..columns {
                        for (i, &eq) in eqs.iter().enumerate() {
                            local[j * n + i] = b[j * neq + eq];
                        }
                    }
                    block.substitute(&mut local, columns, par);
                    for j in 0..columns {
                        for (i, &eq) in eqs.iter().enumerate() {
                            b[j * neq + eq] = local[j * n + i];
                        }
                    }
                }
            }
        }
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
        self.factor_blocks(k, partition, positions, &mut stats)?;

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
        let t = Instant::now();
        let ku = k.mul(&u);
        let rhs: Vec<f64> = partition.free.iter().map(|&d| loads[d] - ku[d]).collect();
        let mut x = rhs.clone();
        // One column: sequential (a task per supernode costs more than its work).
        self.substitute(&mut x, 1, Par::Seq);
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
    /// Solves K11·X = B in place with the factors of the last [`PartitionedSolver::solve`] (or
    /// [`PartitionedSolver::factor_ahead`]), for `columns` right-hand sides stored column by
    /// column in `b` (each of length NBEQ, ordered as the partition's free dofs). Costs
    /// substitutions only: this is what lets contact constraints be added through a Schur
    /// complement without refactorizing.
    pub fn solve_factored(&mut self, b: &mut [f64], columns: usize) -> Result<(), SolveError> {
        let Some(layout) = self.layout.as_ref() else {
            return Err(SolveError::Faer("no factorization to reuse".into()));
        };
        let neq = layout.partition.free_count();
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
        self.substitute(b, columns, par);
        if b.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite("a solution with the reused factor"));
        }
        Ok(())
    }
}

/// faer's symbolic parameters: the supernodal form forced (`supernodal`), or chosen by the
/// factorization's work per entry.
fn symbolic_params(supernodal: bool) -> CholeskySymbolicParams<'static> {
    CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: if supernodal {
            SupernodalThreshold::FORCE_SUPERNODAL
        } else {
            SupernodalThreshold::AUTO
        },
        ..Default::default()
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
    supernodal: bool,
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
        symbolic_params(supernodal),
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
        supernodal,
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
    supernodal: bool,
) -> Result<Analysis, SolveError> {
    let neq = partition.free_count();
    let (col_ptr, row_idx, gather) = k11_structure(pattern, partition);
    let k11 = SymbolicSparseColMat::new_checked(neq, neq, col_ptr, None, row_idx);
    let amd = || {
        factorize_symbolic_cholesky(
            k11.as_ref(),
            Side::Upper,
            SymmetricOrdering::Amd,
            symbolic_params(supernodal),
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
            symbolic_params(supernodal),
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
        supernodal,
    })
}

/// The supernodal Cholesky factor of a block of the last solve, when faer chose the supernodal
/// form: its structure, values and the forward permutation (row i of the factor is the block's
/// equation fwd[i]).
pub(crate) struct SupernodalFactor<'a> {
    pub symbolic: &'a faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>,
    pub values: &'a [f64],
    pub forward: Option<&'a [usize]>,
}

/// A block of the last solve's K11 with its supernodal factor: the equation of the whole
/// partition each of its equations is (`None`: every one, in order), and its first row in the
/// factors' rows one after the other.
pub(crate) struct SupernodalPart<'a> {
    pub factor: SupernodalFactor<'a>,
    pub equations: Option<&'a [usize]>,
    pub offset: usize,
}

impl PartitionedSolver {
    /// NBEQ and the blocks of the last solve with their factors, in order, if every one is
    /// supernodal.
    pub(crate) fn supernodal_parts(&self) -> Option<(usize, Vec<SupernodalPart<'_>>)> {
        let layout = self.layout.as_ref()?;
        let mut parts = Vec::with_capacity(layout.parts.len());
        let mut offset = 0;
        for part in &layout.parts {
            let block = &self.blocks[part.block];
            let analysis = block.analysis.as_ref()?;
            let faer::sparse::linalg::cholesky::SymbolicCholeskyRaw::Supernodal(symbolic) =
                analysis.cholesky.raw()
            else {
                return None;
            };
            if block.factored.is_empty() && analysis.partition.free_count() > 0 {
                return None;
            }
            parts.push(SupernodalPart {
                factor: SupernodalFactor {
                    symbolic,
                    values: &block.factor[..analysis.cholesky.len_val()],
                    forward: analysis.cholesky.perm().map(|p| p.arrays().0),
                },
                equations: part.equations.as_deref(),
                offset,
            });
            offset += symbolic.nrows();
        }
        Some((layout.partition.free_count(), parts))
    }
}
