//! `prehensile bench solver`: assembly, factorization and solve times and peak memory on the unit
//! cube with n×n×n cells, bottom clamped and top pressed (the scene of `docs/scene-format.md`).

use crate::fem::assembly::{assemble, StiffnessPattern};
use crate::fem::solve::{FillOrdering, PartitionedSolver};
use crate::model::Model;
use crate::scene::Scene;
use crate::util::timing::ms;
use anyhow::Context;
use std::sync::Arc;
use std::time::Instant;

/// One row of the solver benchmark.
#[derive(Clone, Debug)]
pub struct SolverRow {
    /// Cells per edge.
    pub n: usize,
    /// Elements.
    pub elements: usize,
    /// Free dofs.
    pub free_dofs: usize,
    /// Building the sparsity pattern (once per mesh), ms.
    pub pattern_ms: f64,
    /// Assembly, ms (best of the repetitions).
    pub assembly_ms: f64,
    /// Ordering and symbolic analysis, ms.
    pub symbolic_ms: f64,
    /// Numeric factorization, ms.
    pub factorization_ms: f64,
    /// Substitution and reactions, ms.
    pub solve_ms: f64,
    /// Second solve with new prescribed values (symbolic reused): factorization + solve, ms.
    pub resolve_ms: f64,
    /// Whether the second solve reused the symbolic analysis.
    pub reused: bool,
    /// Entries of L.
    pub factor_nnz: usize,
    /// Peak resident memory of the process during this size, MiB.
    pub peak_mib: f64,
}

/// The benchmark scene for n cells per edge.
pub fn cube_scene(n: usize, ordering: &str) -> String {
    format!(
        r#"
[solver]
ordering = "{ordering}"
[[material]]
name = "rubber"
young = 1.0e6
poisson = 0.3
density = 1100.0
[[body]]
name = "block"
material = "rubber"
shape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], cells = [{n}, {n}, {n}] }} }}
[[constraint]]
name = "base"
body = "block"
where = {{ face = "z-" }}
displacement = [0.0, 0.0, 0.0]
[[constraint]]
name = "press"
body = "block"
where = {{ face = "z+" }}
displacement = {{ z = -0.01 }}
"#
    )
}

/// Runs the solver benchmark for each size; a size whose model cannot be built or solved (too
/// many elements, not enough memory) is the error, naming it.
pub fn solver_rows(
    sizes: &[usize],
    ordering: FillOrdering,
    repeats: usize,
) -> anyhow::Result<Vec<SolverRow>> {
    let name = match ordering {
        FillOrdering::Auto => "auto",
        FillOrdering::NestedDissection => "nested_dissection",
        FillOrdering::Amd => "amd",
    };
    let mut rows = Vec::new();
    for &n in sizes {
        let row = solver_row(n, name, ordering, repeats)
            .with_context(|| format!("--sizes {n}: the cube of {n}×{n}×{n} cells"))?;
        rows.push(row);
    }
    Ok(rows)
}

/// One size of [`solver_rows`].
fn solver_row(
    n: usize,
    name: &str,
    ordering: FillOrdering,
    repeats: usize,
) -> anyhow::Result<SolverRow> {
    reset_peak_memory();
    let scene = Scene::parse(&cube_scene(n, name), "bench")?;
    let model = Model::build(&scene, "bench")?;
    // The pattern again, timed (the model built its own).
    let t = Instant::now();
    let pattern = Arc::new(StiffnessPattern::new(&model.mesh));
    let pattern_ms = ms(t);
    let mut assembly_ms = f64::INFINITY;
    let mut k = None;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        k = Some(
            assemble(&pattern, &model.mesh, &model.cell_materials)
                .map_err(|e| anyhow::anyhow!("element {} is inverted or flat", e.cell))?,
        );
        assembly_ms = assembly_ms.min(ms(t));
    }
    let k = k.expect("one assembly at least");
    let mut solver = PartitionedSolver::new(ordering);
    let first = solver.solve(
        &k,
        &model.partition,
        &model.prescribed,
        &model.load_vector,
        &model.mesh.nodes,
    )?;
    let doubled: Vec<f64> = model.prescribed.iter().map(|v| 2.0 * v).collect();
    let t = Instant::now();
    let second = solver.solve(
        &k,
        &model.partition,
        &doubled,
        &model.load_vector,
        &model.mesh.nodes,
    )?;
    let resolve_ms = ms(t);
    Ok(SolverRow {
        n,
        elements: model.mesh.cell_count(),
        free_dofs: first.stats.free_dofs,
        pattern_ms,
        assembly_ms,
        symbolic_ms: first.stats.symbolic_ms,
        factorization_ms: first.stats.factorization_ms,
        solve_ms: first.stats.solve_ms,
        resolve_ms,
        reused: second.stats.symbolic_reused,
        factor_nnz: first.stats.factor_nnz,
        peak_mib: peak_memory_mib(),
    })
}

/// Formats rows as a Markdown table.
pub fn solver_table(rows: &[SolverRow]) -> String {
    let mut s = String::from(
        "| n | elements | free dofs | pattern ms | assembly ms | symbolic ms | factorization ms | solve ms | re-solve ms (symbolic reused) | nnz(L) | peak MiB |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} ({}) | {:.2e} | {:.0} |\n",
            r.n,
            r.elements,
            r.free_dofs,
            r.pattern_ms,
            r.assembly_ms,
            r.symbolic_ms,
            r.factorization_ms,
            r.solve_ms,
            r.resolve_ms,
            if r.reused { "yes" } else { "no" },
            r.factor_nnz as f64,
            r.peak_mib
        );
    }
    s
}

/// Resets the kernel's record of peak resident memory (Linux; elsewhere a no-op).
fn reset_peak_memory() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident memory since the last reset, MiB (Linux `VmHWM`; NaN elsewhere).
fn peak_memory_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}
