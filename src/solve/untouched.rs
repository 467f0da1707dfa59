//! A contact step that touches nothing, solved once: the step the other bodies take from their
//! static frame.
//!
//! Along a motion that has not touched yet, a contact step starts from the static frame: what it
//! carries is that frame's displacements, and detection sees the bodies there. A step in which
//! nothing touches solves the bodies alone — K̃·ΔU = R(x_s) − f(U_s) about the static frame
//! U_s, linearised as every contact step is (src/solve/corotated.rs, or Neo-Hookean,
//! src/solve/hyperelastic_objects.rs) — and the hands do not enter it: no contact couples them,
//! and the flesh carries no load of its own in a contact step (its weight is the flexion's), so
//! it stays where flexion put it. ΔU and the supports' reactions are therefore the same for every
//! such step, whatever the hands do. ΔU is not zero where the tier is not the static frame's (a
//! pressurised ball's air follows its inflated wall, its cells turn) but small against the static
//! frame's own motion from rest (the default scene's ball: 1.94 mm inflated, ΔU 0.30 mm).
//!
//! Solved once per workspace, it decides and replaces such steps (src/solve/grasp.rs): skin
//! farther than ΔU's largest nodal motion and the contact tolerance from every body, as detection
//! sees them, having crossed none, cannot touch in the step; the step's frame is the static
//! frame moved by ΔU with these reactions, the hands composed into it — what the solve would
//! give, without the factorization of the flesh and the bodies together. (Not with rigid
//! obstacles in the scene: the bodies' step would have their contact to solve; such steps are
//! judged as before, by the static frame's motion from rest.)

use super::corotated::{linearise, step_loads};
use super::error::SimError;
use super::gas::solve_with_gas;
use super::hyperelastic_objects::{linearise_neo_hookean, neo_hookean_objects};
use super::stabilize::stabilize;
use crate::fem::solve::{PartitionedSolver, Solution};
use crate::mesh::Mesh;
use crate::model::Model;
use crate::state::Frame;
use nalgebra::Vector3;

/// The step of the bodies other than the hands from their static frame, touching nothing.
pub struct UntouchedStep {
    /// ΔU over every dof (zero at the hands').
    pub displacement: Vec<f64>,
    /// The supports' reactions after the step (totals, K·U − R at their dofs; zero elsewhere
    /// and at the hands').
    pub reaction: Vec<f64>,
    /// ΔU's largest nodal motion, m.
    pub motion: f64,
}

/// The step a contact step touching nothing solves for the bodies other than the hands, from
/// the static frame `still` (the hands where they are make no difference: their dofs are held).
/// `anchor`: where the ground springs of floating bodies rest (`None`: at rest), as the contact
/// steps take it.
pub(super) fn untouched_step(
    model: &Model,
    still: &Frame,
    anchor: Option<&[f64]>,
) -> Result<UntouchedStep, SimError> {
    // With rigid obstacles the bodies' step has their contact to solve too: not this one.
    if !model.obstacles.is_empty() {
        return Err(SimError::Unsupported(
            "the step of bodies touching rigid obstacles".into(),
        ));
    }
    let hand_dof = |d: usize| model.bodies[model.body_of_node(d / 3)].hand.is_some();
    // What a step from the static frame carries: its displacements, none on the hands.
    let carried: Vec<f64> = still
        .solution
        .displacement
        .iter()
        .enumerate()
        .map(|(d, u)| if hand_dof(d) { 0.0 } else { *u })
        .collect();
    let mesh = Mesh {
        nodes: model.mesh.nodes.clone(),
        cells: model.mesh.cells.clone(),
    };
    let x_now: Vec<Vector3<f64>> = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(n, p)| p + Vector3::new(carried[3 * n], carried[3 * n + 1], carried[3 * n + 2]))
        .collect();
    let object_cell = |c: usize| model.bodies[model.cell_body[c]].hand.is_none();
    let linearised = if neo_hookean_objects(model) {
        linearise_neo_hookean(model, &mesh, Some(&carried), false, false)
    } else {
        linearise(
            model,
            &mesh,
            Some(&carried),
            false,
            (&object_cell, None, None),
        )
    }
    .map_err(|e| SimError::inverted(model, e.cell, e.inverted.relative_det))?;
    let partition = &model.partition;
    let mut k = linearised.k;
    let springs = stabilize(model, &mut k, partition);
    // The step's right-hand side from the static frame, as a contact step's.
    let rhs = step_loads(
        model,
        (&k, linearised.offset.as_deref()),
        (&springs, anchor),
        partition,
        (&carried, true),
        &x_now,
    );
    let mut solver = PartitionedSolver::new(model.ordering);
    let mut solve = |loads: &[f64]| -> Result<Solution, SimError> {
        solver
            .solve(&k, partition, &rhs.prescribed, loads, &x_now)
            .map_err(|e| SimError::solve(model, e))
    };
    let solution = match &model.gas {
        None => solve(&rhs.loads)?,
        Some(cavity) => solve_with_gas(
            cavity,
            |p| solve(&rhs.at_gauge(cavity, p)),
            |s| cavity.volume_after(&model.mesh.nodes, &carried, &s.displacement),
        )?,
    };
    let mut reaction = solution.reaction;
    for (d, r) in reaction.iter_mut().enumerate() {
        if hand_dof(d) {
            *r = 0.0;
        }
    }
    let motion = solution
        .displacement
        .chunks_exact(3)
        .map(|d| Vector3::new(d[0], d[1], d[2]).norm())
        .fold(0.0, f64::max);
    Ok(UntouchedStep {
        displacement: solution.displacement,
        reaction,
        motion,
    })
}

/// `frame` (the static frame with the hands composed into it) moved by the bodies' `step`:
/// their displacements and reactions as a step from the static frame touching nothing leaves
/// them.
pub(super) fn apply(model: &Model, step: &UntouchedStep, frame: &mut Frame) {
    for b in model.bodies.iter().filter(|b| b.hand.is_none()) {
        for d in 3 * b.nodes.start..3 * b.nodes.end {
            frame.solution.displacement[d] += step.displacement[d];
            frame.solution.reaction[d] = step.reaction[d];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::grasp::{solve_grasp, ContactCache};
    use super::super::statics::solve_static;
    use super::*;
    use crate::solve::{Posed, Workspace};

    /// The default scene's Power grasp at 17/28 of its closing (the anatomical hand; the simple
    /// hand's was 5/7): the skin near the inflated ball, nearer than the ball's 1.94 mm inflation
    /// from rest, farther than the 0.30 mm its own step from the static frame moves it (from
    /// 66/112 to 69/112 of the closing the solve takes the flesh near the ball into its region
    /// and touches nothing; at 70/112 it touches). The step composed from the static frame and the
    /// bodies' own step is the step solved (the flesh and the ball together, nothing touching) to
    /// round-off; the static frame alone would not be.
    #[test]
    fn a_step_touching_nothing_is_the_static_frame_moved_by_the_bodies_own_step() {
        let text = std::fs::read_to_string("assets/scenes/hand-power-grasp.toml").unwrap();
        let scene = crate::scene::Scene::parse(&text, "power.toml").unwrap();
        let model = Model::build(&scene, "power.toml").unwrap();
        let mut workspace = Workspace::new(&model).unwrap();
        let mut posed = Posed::rest(&model);
        let key = &model.keyframes[0];
        let from = model.bodies[key.body].initial_angles.clone();
        workspace
            .move_hands(&model, &mut posed, &[(key.body, from.clone())], None)
            .unwrap();
        let near: Vec<f64> = from
            .iter()
            .zip(&key.angles)
            .map(|(a, b)| a + 17.0 / 28.0 * (b - a))
            .collect();
        let hands = workspace
            .move_hands(&model, &mut posed, &[(key.body, near)], None)
            .unwrap()
            .hands;
        assert!(hands[0]
            .contact_displacement
            .iter()
            .all(|d| d.norm() == 0.0));
        let still = solve_static(&model, &mut PartitionedSolver::new(model.ordering)).unwrap();
        let hand_dof = |d: usize| model.bodies[model.body_of_node(d / 3)].hand.is_some();
        let carried: Vec<f64> = (still.solution.displacement.iter().enumerate())
            .map(|(d, u)| if hand_dof(d) { 0.0 } else { *u })
            .collect();
        let previous: Vec<Vec<Vector3<f64>>> = hands.iter().map(|h| h.positions.clone()).collect();
        let step = untouched_step(&model, &still, None).unwrap();
        println!("the bodies' own step: {:.4} mm", step.motion * 1e3);

        let solve = |known: Option<UntouchedStep>| {
            let mut cache = ContactCache::new(&model);
            cache.untouched = Some(known);
            let start = (Some(carried.as_slice()), Some(previous.as_slice()));
            solve_grasp(&model, &hands, start, Some(&still), &mut cache)
                .unwrap()
                .expect("the skin is within the search")
        };
        let composed = solve(Some(step));
        let solved = solve(None);
        let (c, s) = (composed.contact.unwrap(), solved.contact.unwrap());
        assert!(c.contacts.is_empty() && s.contacts.is_empty());
        // Solved: the flesh near the ball was in the step; composed: none.
        assert!(
            c.region_cells == 0 && s.region_cells > 0,
            "{} {}",
            c.region_cells,
            s.region_cells
        );
        let largest = |a: &[f64], b: &[f64], dofs: &dyn Fn(usize) -> bool| {
            (0..a.len())
                .filter(|&d| dofs(d))
                .map(|d| (a[d] - b[d]).abs())
                .fold(0.0, f64::max)
        };
        let (uc, us) = (&composed.solution, &solved.solution);
        let every = |_: usize| true;
        let objects = |d: usize| !hand_dof(d);
        let moved = largest(&us.displacement, &still.solution.displacement, &objects);
        let off = largest(&uc.displacement, &us.displacement, &every);
        println!("solved against the static frame {moved:.3e} m, against composed {off:.3e} m");
        assert!(moved > 1e-4, "the static frame alone is {moved:e} m off");
        assert!(off < 1e-9 * moved.max(1e-3), "{off:e} m");
        let force = us.reaction.iter().map(|r| r.abs()).fold(0.0, f64::max);
        let r_off = largest(&uc.reaction, &us.reaction, &every);
        assert!(r_off < 1e-8 * force, "reactions {r_off:e} N of {force:e} N");
    }
}
