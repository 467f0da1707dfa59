//! The memory a model will take, estimated from its size before it is built, and refused when
//! it exceeds what a solve may take (`[solver] max_memory`, the machine's free memory, the
//! address space left): an error naming what is needed and what is available, never an abort
//! of the allocator.

use crate::fem::assembly::StiffnessPattern;
use crate::fem::hex8_hyperelastic::ElementState;
use crate::fem::memory::{budget_with, fewer_share, human};

/// Bytes a cell takes while the model is built, beyond the stiffness pattern: its nodes and
/// per-cell data (~200 B) and the map of its six faces that finds the boundary (~150 B a face,
/// twice over while that map grows).
const BUILD_BYTES_PER_CELL: u64 = 2000;

/// Refuses a model of `nodes` nodes and `cells` cells (all bodies so far, the last of which is
/// named by `field`, with `body_cells` cells) whose stiffness pattern and build would not fit;
/// `nonlinear`: the nonlinear tier, which keeps every element's state (forces and tangent) at
/// once (collected in parallel into a vector that may double while it grows: twice its size).
pub fn fits_in_memory(
    nodes: usize,
    cells: usize,
    body_cells: usize,
    (max_memory, nonlinear): (Option<u64>, bool),
    field: &str,
) -> Result<(), (String, String)> {
    let Some((available, limit)) = budget_with(max_memory) else {
        return Ok(());
    };
    let pattern = StiffnessPattern::bytes_for(nodes);
    let per_cell = BUILD_BYTES_PER_CELL
        + if nonlinear {
            2 * std::mem::size_of::<ElementState>() as u64
        } else {
            0
        };
    let needed = pattern.saturating_add((cells as u64).saturating_mul(per_cell));
    if needed <= available {
        return Ok(());
    }
    Err((
        field.to_string(),
        format!(
            "the model's {nodes} nodes and {cells} elements ({body_cells} of them this body's) \
             need about {} to build ({} for the stiffness matrix alone, the factor more), but \
             {} is free ({limit}): use fewer cells (or a lower hand resolution) — at most \
             {:.0} % as many for the build; the factor, checked next, needs several times the \
             stiffness matrix — or {}",
            human(needed),
            human(pattern),
            human(available),
            100.0 * fewer_share(available, needed, 1.0),
            limit.remedy()
        ),
    ))
}
