//! Which side the paper's step 3 holds (`contact::solve_paper`): its iteration computes the
//! reactions of the side it solves against the other held where the last iterate left it, and
//! converges by itself only when the side solved is the softer (the rate of this
//! Dirichlet–Neumann iteration is the ratio of the solved side's stiffness to the held side's).
//! The paper holds the skin and solves the object: right for its soft rubber ball, wrong for a
//! ball stiffer than the flesh, where the roles are exchanged.

use crate::model::Model;
use std::ops::Range;

/// The node ranges step 3 holds: the hands' (the paper's order) when their flesh is at least as
/// stiff as every other deformable body's softest material, else the other bodies'.
pub(super) fn held_in_step3(model: &Model, hands: &[usize]) -> Vec<Range<usize>> {
    let softest = |b: usize| {
        model.bodies[b]
            .cells
            .clone()
            .map(|c| model.cell_materials[c].young)
            .fold(f64::INFINITY, f64::min)
    };
    let flesh = hands
        .iter()
        .map(|&h| softest(h))
        .fold(f64::INFINITY, f64::min);
    let others: Vec<usize> = (0..model.bodies.len())
        .filter(|b| !hands.contains(b) && !model.bodies[*b].cells.is_empty())
        .collect();
    let objects = others.iter().map(|&b| softest(b)).fold(0.0f64, f64::max);
    let held: Vec<usize> = if objects > flesh {
        others
    } else {
        hands.to_vec()
    };
    held.into_iter()
        .map(|b| model.bodies[b].nodes.clone())
        .collect()
}
