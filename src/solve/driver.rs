//! The timeline of a scene: the static frame of the other bodies, and every hand carried from
//! rest to its initial pose and then through its keyframes by incremental flexion. One frame
//! per distinct time (time 0 first).

use super::error::SimError;
use super::flexion::Flexion;
use super::grasp::frame_with_hands;
use super::statics::solve_static;
use crate::fem::hyperelastic_body::HyperelasticBody;
use crate::fem::solve::{PartitionedSolver, Solution, SolveStats};
use crate::fem::stress::{from_gauss, stress_field_except, StressField};
use crate::model::Model;
use crate::state::HandState;
use crate::state::{Frame, HandFrame};
use nalgebra::Matrix3;

/// Solves every frame of the model.
pub fn solve_frames(model: &Model) -> Result<(Vec<f64>, Vec<Frame>), SimError> {
    let hands: Vec<usize> = (0..model.bodies.len())
        .filter(|&b| model.bodies[b].hand.is_some())
        .collect();
    // The static frame of the other bodies, unless one of them can only be held by a hand.
    let floating = model.bodies.iter().any(|b| b.floating);
    let still = if model.partition.free_count() == 0 {
        Some(still_frame(model))
    } else if floating && !hands.is_empty() {
        None
    } else {
        Some(solve_static(
            model,
            &mut PartitionedSolver::new(model.ordering),
        )?)
    };
    if hands.is_empty() {
        return Ok((vec![0.0], vec![still.expect("solved")]));
    }
    let mut steppers = Vec::new();
    let mut states = Vec::new();
    let mut frames = Vec::new();
    let mut hand_frames = Vec::new();
    for &b in &hands {
        let body = &model.bodies[b];
        let hand = body.hand.as_deref().unwrap();
        let materials = model.cell_materials[body.cells.clone()].to_vec();
        let mut stepper = Flexion::new(
            hand,
            &body.name,
            materials,
            model.flexion.clone(),
            model.ordering,
        );
        let mut state = HandState::rest(hand);
        set_far_parts(model, b, &mut stepper, &state, &body.initial_angles);
        let stats = stepper.move_to(&mut state, &body.initial_angles)?;
        hand_frames.push(hand_frame(model, b, &state, stats));
        steppers.push(stepper);
        states.push(state);
    }
    let mut times = vec![0.0];
    frames.push(frame_with_hands(
        model,
        still.as_ref(),
        hand_frames.clone(),
    )?);
    let mut k = 0;
    while k < model.keyframes.len() {
        let time = model.keyframes[k].time;
        let mut current = hand_frames.clone();
        while k < model.keyframes.len() && model.keyframes[k].time == time {
            let key = &model.keyframes[k];
            let h = hands.iter().position(|&b| b == key.body).unwrap();
            set_far_parts(model, key.body, &mut steppers[h], &states[h], &key.angles);
            let stats = steppers[h].move_to(&mut states[h], &key.angles)?;
            current[h] = hand_frame(model, key.body, &states[h], stats);
            k += 1;
        }
        if time == 0.0 {
            frames[0] = frame_with_hands(model, still.as_ref(), current.clone())?;
        } else {
            times.push(time);
            frames.push(frame_with_hands(model, still.as_ref(), current.clone())?);
        }
        hand_frames = current;
    }
    Ok((times, frames))
}

/// Tells `stepper` which parts of hand `body` stay far from contact on the way from `state`
/// to `target` (none when `[solver] far_from_contact = "solve"`).
pub fn set_far_parts(
    model: &Model,
    body: usize,
    stepper: &mut Flexion,
    state: &HandState,
    target: &[f64],
) {
    let far = match model.flexion.near_contact {
        Some(distance) => super::proximity::far_parts(model, body, state, target, distance),
        None => [false; super::proximity::PARTS],
    };
    stepper.set_far_parts(far);
}

/// The frame of a model with nothing free (only hands): every displacement and reaction zero.
pub fn still_frame(model: &Model) -> Frame {
    let dofs = 3 * model.mesh.node_count();
    Frame {
        solution: Solution {
            displacement: vec![0.0; dofs],
            reaction: vec![0.0; dofs],
            stats: SolveStats {
                prescribed_dofs: model.partition.prescribed_count(),
                ..Default::default()
            },
        },
        stress: StressField {
            gauss: vec![[Matrix3::zeros(); 8]; model.mesh.cell_count()],
            nodal: vec![Matrix3::zeros(); model.mesh.node_count()],
            cell_von_mises: vec![0.0; model.mesh.cell_count()],
        },
        assembly_ms: 0.0,
        stress_ms: 0.0,
        hands: Vec::new(),
        contact: None,
    }
}

/// The frame of hand body `body` in `state`, with what reaching it cost.
pub fn hand_frame(
    model: &Model,
    body: usize,
    state: &HandState,
    stats: crate::state::KeyframeStats,
) -> HandFrame {
    let hand = model.bodies[body].hand.as_deref().unwrap();
    let bone_reactions = state.bone_reactions(hand);
    HandFrame {
        body,
        angles: state.angles.clone(),
        positions: state.positions.clone(),
        bone_reactions: bone_reactions.clone(),
        reaction: state.reaction.clone(),
        volume: state.flesh_volume(hand),
        stats,
        contact_force: vec![nalgebra::Vector3::zeros(); hand.skeleton.bones.len()],
        overloads: crate::state::outcome::overloads(
            hand,
            &state.transforms,
            &bone_reactions,
            &model.bodies[body].thresholds,
        ),
    }
}

/// The static frame with the hands' displacements, reactions and (rotation-free) stresses.
pub fn compose(model: &Model, still: &Frame, hands: Vec<HandFrame>) -> Result<Frame, SimError> {
    let mut frame = still.clone();
    for h in &hands {
        let body = &model.bodies[h.body];
        for (i, p) in h.positions.iter().enumerate() {
            let n = body.nodes.start + i;
            let u = p - model.mesh.nodes[n];
            frame.solution.displacement[3 * n..3 * n + 3].copy_from_slice(u.as_slice());
            frame.solution.reaction[3 * n..3 * n + 3].copy_from_slice(h.reaction[i].as_slice());
        }
    }
    let inverted = |c: usize, relative_det: f64| {
        let b = model.cell_body[c];
        SimError::InvertedElement {
            body: model.bodies[b].name.clone(),
            element: c - model.bodies[b].cells.start,
            relative_det,
        }
    };
    frame.stress = if model.nonlinear_statics {
        // The Cauchy stress of the Neo-Hookean law the nonlinear tier solved with, for the
        // hands' flesh and the other bodies alike.
        nonlinear_stress(model, &frame.solution.displacement)
            .map_err(|(c, det_f)| inverted(c, det_f))?
    } else {
        let hand_cell = |c: usize| model.bodies[model.cell_body[c]].hand.is_some();
        // Flesh moved by skinning only (`flesh = "skinning"`, per part or the tier) has no
        // stress.
        let skinned = |c: usize| {
            let body = &model.bodies[model.cell_body[c]];
            body.hand.as_deref().is_some_and(|hand| {
                let part = hand.flesh.cell_digit[c - body.cells.start].map_or(0, |d| d + 1);
                model.flexion.methods[part] == crate::model::FleshMethod::Skinning
            })
        };
        stress_field_except(
            &model.mesh,
            &model.cell_materials,
            &frame.solution.displacement,
            &hand_cell,
            &skinned,
        )
        .map_err(|(c, e)| inverted(c, e.relative_det))?
    };
    frame.hands = hands;
    Ok(frame)
}

/// Cauchy stress of the Neo-Hookean law (`[solver] volumetric`) at the Gauss points of every cell of
/// the model displaced by `u` from rest; an inverted cell gives (cell, det F).
fn nonlinear_stress(model: &Model, u: &[f64]) -> Result<StressField, (usize, f64)> {
    let body = HyperelasticBody::with_pattern(
        &model.mesh,
        &model.cell_materials,
        model.flexion.volumetric,
        model.pattern.clone(),
    )
    .map_err(|e| (e.cell, e.relative_det))?;
    let gauss = body.cauchy_stress(u).map_err(|e| (e.cell, e.det_f))?;
    Ok(from_gauss(&model.mesh, gauss))
}
