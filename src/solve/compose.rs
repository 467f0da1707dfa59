//! A frame composed of the static frame of the bodies and the hands' states: their displacements
//! and reactions; its stresses (rotation-free for the flesh; Neo-Hookean with the nonlinear tier)
//! are computed if it is the frame kept (src/solve/frame_stress.rs).

use super::error::SimError;
use crate::fem::stress::StressField;
use crate::model::Model;
use crate::state::{Frame, HandFrame, PendingStress};

/// The static frame with the hands' displacements and reactions, its stresses pending.
pub fn compose(model: &Model, still: &Frame, hands: Vec<HandFrame>) -> Result<Frame, SimError> {
    let mut frame = Frame {
        solution: still.solution.clone(),
        stress: StressField::default(),
        stress_pending: Some(PendingStress::Composed),
        assembly_ms: still.assembly_ms,
        stress_ms: 0.0,
        hands: Vec::new(),
        contact: still.contact.clone(),
    };
    for h in &hands {
        let body = &model.bodies[h.body];
        for (i, p) in h.positions.iter().enumerate() {
            let n = body.nodes.start + i;
            let u = p - model.mesh.nodes[n];
            frame.solution.displacement[3 * n..3 * n + 3].copy_from_slice(u.as_slice());
            frame.solution.reaction[3 * n..3 * n + 3].copy_from_slice(h.reaction[i].as_slice());
        }
    }
    frame.hands = hands;
    Ok(frame)
}
