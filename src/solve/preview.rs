//! A pose shown before it is solved: the hands of a solved frame moved to the pose by skinning
//! (each flesh node, the contact's displacement included, following the blended rigid motions
//! of its bones from the frame's joint angles to the pose's), every other body where the frame
//! has it. What the viewer draws at once while the flexion and the contact are solved; nothing
//! in it is a result (the stresses, reactions and contact forces are the frame's).

use crate::model::Model;
use crate::state::Frame;
use nalgebra::Vector3;

/// `frame` with each hand of `targets` (hand body, joint angles in degrees) moved to its angles
/// by skinning; hands not in `targets` and the other bodies stay as they are. `None` when no
/// hand of `targets` moves (the frame already shows the pose) or a target names no hand of the
/// frame.
pub fn skinned_preview(
    model: &Model,
    frame: &Frame,
    targets: &[(usize, Vec<f64>)],
) -> Option<Frame> {
    let mut preview = frame.clone();
    let mut moved_any = false;
    for (body, angles) in targets {
        let hand_model = model.bodies.get(*body)?.hand.as_deref()?;
        let shown = preview.hands.iter_mut().find(|h| h.body == *body)?;
        if shown.angles.len() != angles.len()
            || shown.positions.len() != hand_model.weights.weights.len()
        {
            return None;
        }
        if shown.angles == *angles {
            continue;
        }
        // Moved from the frame's pose: no longer the frame's grasp, whatever it found.
        shown.grasp = None;
        let motion = hand_model.skeleton.motion(&shown.angles, angles);
        let mut moved = vec![Vector3::zeros(); shown.positions.len()];
        hand_model.weights.apply(
            model.flexion.blend,
            &motion,
            &shown.positions,
            0..shown.positions.len(),
            &mut moved,
        );
        let start = model.bodies[*body].nodes.start;
        for (i, p) in moved.iter().enumerate() {
            let n = start + i;
            let u = p - model.mesh.nodes[n];
            preview.solution.displacement[3 * n..3 * n + 3].copy_from_slice(u.as_slice());
        }
        shown.positions = moved;
        shown.angles = angles.clone();
        moved_any = true;
    }
    moved_any.then_some(preview)
}
