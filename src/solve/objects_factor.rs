//! A contact step's other bodies — their stiffness and its factor — made beside its detection.
//!
//! No cell joins an object to a hand, so K11 of a contact step is block diagonal: the objects'
//! free dofs, the flesh region's (src/fem/blocks.rs). The objects' block depends on what the
//! step carries, not on what the detection finds (the flesh region near the contact does), so
//! it is assembled about the carried state, given its floating springs and factored while the
//! detection runs on the other core; the step's solve then finds those values again and keeps
//! that factor, and factors only the flesh region's block. K is that of one assembly of the
//! whole, bit for bit (`Linearised::joined`: each entry is one part's plus the other's zero);
//! the blocks' factors give the whole's solution to round-off (each block ordered on its own:
//! src/fem/blocks.rs's tests). A drag's first step makes this part beside its knot's flexion
//! instead (`ContactCache::prepare_objects`).

use super::corotated::{linearise, Linearised};
use super::stabilize::stabilize;
use crate::fem::assembly::AssemblyError;
use crate::fem::kept_elements::KeptElements;
use crate::fem::solve::PartitionedSolver;
use crate::model::Model;
use crate::util::timing::ms;
use nalgebra::Vector3;
use std::time::Instant;

/// The objects' part of a contact step's K, with their floating springs.
pub(super) struct ObjectsStiffness {
    pub linearised: Linearised,
    /// (body, spring stiffness) of each floating body (`stabilize`).
    pub springs: Vec<(usize, f64)>,
    /// Their assembly and factorization, ms.
    pub ms: f64,
    /// Whether their factor was kept from an earlier step (the same values).
    pub kept: bool,
}

/// The objects' part made ahead of a step (`ContactCache::prepare_objects`): from which
/// carried state, with which tangent.
pub(super) struct PreparedObjects {
    pub carried: Option<Vec<f64>>,
    pub geometric: bool,
    pub objects: Result<ObjectsStiffness, AssemblyError>,
}

/// The node groups of a contact step's blocks: each node's body.
pub(super) fn body_groups(model: &Model) -> Vec<u32> {
    let mut groups = vec![0u32; model.mesh.node_count()];
    for (b, body) in model.bodies.iter().enumerate() {
        groups[body.nodes.clone()].fill(b as u32);
    }
    groups
}

/// The objects' cells linearised about `carried` (`geometric`: with their turn's and the
/// pressures' stiffness), their floating springs added, and their block of K11 factored into
/// `solver` (its node groups the bodies); their element stiffnesses at rest taken from `kept`
/// (made there at the first call). A factorization that fails is left to the step's solve,
/// which makes it again and says why.
pub(super) fn objects_stiffness(
    model: &Model,
    carried: Option<&[f64]>,
    geometric: bool,
    (solver, kept): (&mut PartitionedSolver, &mut Option<KeptElements>),
) -> Result<ObjectsStiffness, AssemblyError> {
    let t = Instant::now();
    let object = |c: usize| model.bodies[model.cell_body[c]].hand.is_none();
    // (The hands' cells are the step's other assembly's, which checks them.)
    let hand = |c: usize| !object(c);
    // (The objects' nodes are at rest in the model's mesh, as in the step's: their K_e is the
    // same at every step.)
    if kept.is_none() {
        *kept = Some(
            KeptElements::of(&model.mesh, &model.cell_materials, &object)
                .map_err(|(cell, inverted)| AssemblyError { cell, inverted })?,
        );
    }
    let mut linearised = linearise(
        model,
        &model.mesh,
        carried,
        geometric,
        (&object, Some(&hand), kept.as_ref()),
    )?;
    // The objects' free dofs are the model's (every hand node is held there), as in the step.
    let springs = stabilize(model, &mut linearised.k, &model.partition);
    let positions: Vec<Vector3<f64>> = match carried {
        Some(u) => model
            .mesh
            .nodes
            .iter()
            .enumerate()
            .map(|(n, p)| p + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
            .collect(),
        None => model.mesh.nodes.clone(),
    };
    let kept_factor = solver
        .factor_ahead(&linearised.k, &model.partition, &positions)
        .is_ok_and(|s| s.blocks > 0 && s.blocks_reused == s.blocks);
    Ok(ObjectsStiffness {
        linearised,
        springs,
        ms: ms(t),
        kept: kept_factor,
    })
}
