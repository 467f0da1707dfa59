//! The pose-dependent state of a hand (angles, bone motions, flesh positions, accumulated
//! reactions) and what reaching a keyframe cost.

use crate::fem::hex8::cell_volume;
use crate::hand::HandModel;
use nalgebra::{Isometry3, Vector3};

/// The pose-dependent state of a hand.
#[derive(Clone, Debug)]
pub struct HandState {
    /// Joint angles, degrees.
    pub angles: Vec<f64>,
    /// Rigid motion of every bone (rest → now).
    pub transforms: Vec<Isometry3<f64>>,
    /// Flesh node positions, m.
    pub positions: Vec<Vector3<f64>>,
    /// Reaction at every node (non-zero at prescribed nodes), N: the sum of the increments'
    /// reactions, as the updated Lagrangian scheme sums their stresses (each increment's
    /// reactions balance, so the total does).
    pub reaction: Vec<Vector3<f64>>,
    /// Normal force of the skin's contact with itself at each vertex of the contact skin, N: the
    /// barrier's force on the vertex, as a point pressed and as a corner of the facets and edges
    /// pressed (each press is felt on both sides), at the state — a total, where the reactions
    /// are the increments' sums. A keyframe sets it over its FEM region's skin and leaves the
    /// rest as the keyframes before left it. Empty until the skin meets itself.
    pub self_contact: Vec<f64>,
    /// The flesh cells (by index) whose positions a part's skinning far from contact has
    /// strained since they were last solved: no equilibrium, so the nonlinear tier, which reads
    /// the reactions as the flesh's internal force at the state, leaves them out
    /// (`solve::far_strain`). Empty: none (and for a state rebuilt from a frame).
    pub far_strained: Vec<bool>,
}

/// `a` and `b` (forces at the same points; an empty one is zero everywhere) added with the
/// factors `fa` and `fb`.
pub fn blend_forces(a: &[f64], fa: f64, b: &[f64], fb: f64) -> Vec<f64> {
    let n = a.len().max(b.len());
    (0..n)
        .map(|i| fa * a.get(i).copied().unwrap_or(0.0) + fb * b.get(i).copied().unwrap_or(0.0))
        .collect()
}

impl HandState {
    /// The motion of every bone from this state to the bone transforms `then`
    /// (then · now⁻¹, what incremental skinning applies).
    pub fn motion_to(&self, then: &[Isometry3<f64>]) -> Vec<Isometry3<f64>> {
        crate::hand::relative_motion(&self.transforms, then)
    }

    /// The rest pose.
    pub fn rest(hand: &HandModel) -> HandState {
        let angles = hand.skeleton.rest_angles();
        HandState {
            transforms: hand.skeleton.transforms(&angles),
            angles,
            positions: hand.flesh.mesh.nodes.clone(),
            reaction: vec![Vector3::zeros(); hand.flesh.mesh.nodes.len()],
            self_contact: Vec::new(),
            far_strained: Vec::new(),
        }
    }

    /// Sum of the reactions on each bone's nodes (equation (8)), N. With a local FEM region,
    /// the reactions at the region's edge (nodes moved by skinning) count for the bone they
    /// follow most, so that the bones' reactions still balance.
    pub fn bone_reactions(&self, hand: &HandModel) -> Vec<Vector3<f64>> {
        let mut out = vec![Vector3::zeros(); hand.skeleton.bones.len()];
        for (n, r) in self.reaction.iter().enumerate() {
            let b = hand.flesh.node_bone[n].unwrap_or(hand.weights.weights[n][0].0);
            out[b] += r;
        }
        out
    }

    /// Volume of the flesh, m³.
    pub fn flesh_volume(&self, hand: &HandModel) -> f64 {
        hand.flesh
            .mesh
            .cells
            .iter()
            .map(|c| cell_volume(&c.map(|n| self.positions[n])))
            .sum()
    }
}

/// Where the last of a keyframe's corrections at the pose moved the bodies most, when they
/// ended unsettled: the cause the warning gives.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct UnsettledMotion {
    /// The body.
    pub body: String,
    /// The node within the body.
    pub node: usize,
    /// How far the last correction moved it, m.
    pub moved: f64,
    /// Whether the last three corrections moved the bodies ever more, the second more than the
    /// first and the third more than the second (they drift away rather than swing).
    pub growing: bool,
}

/// What one keyframe cost.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct KeyframeStats {
    /// Increments planned (the joint motion over `max_step_deg`).
    pub increments: usize,
    /// Increments taken (more when steps were halved).
    pub increments_taken: usize,
    /// Times a step was halved because a cell would have turned inside out.
    pub halvings: usize,
    /// Cells solved by FEM (over several steps, in the step that solved the most).
    pub fem_cells: usize,
    /// Free dofs of the FEM problem.
    pub free_dofs: usize,
    /// Prescribed dofs of the FEM problem (bones and region boundary).
    pub prescribed_dofs: usize,
    /// Factorizations.
    pub factorizations: usize,
    /// Time in assembly, ms.
    pub assembly_ms: f64,
    /// Time in symbolic analysis, ms.
    pub symbolic_ms: f64,
    /// Time in numeric factorization, ms.
    pub factorization_ms: f64,
    /// Time in substitution and reactions, ms.
    pub solve_ms: f64,
    /// Time in skinning and updates, ms.
    pub update_ms: f64,
    /// Wall time of the keyframe, ms.
    pub total_ms: f64,
    /// Largest relative residual of the linear solves (of the Newton iterations that
    /// converged, where an increment is solved by Newton).
    pub relative_residual: f64,
    /// Cells of the FEM region left to skinning because their part of the hand stayed far
    /// from every other body ([`Flexion::set_far_parts`]); over several steps, in the step
    /// whose `fem_cells` is given.
    pub far_cells: usize,
    /// The digits left to skinning in this keyframe because they stayed far from every other
    /// body: their bones bear no new flexion reaction.
    pub far_digits: Vec<String>,
    /// Contact solves kept on the way: the contact steps along the motion (1 for a keyframe
    /// solved in one step with its contact, 0 without contact) and the corrections at the pose.
    pub contact_steps: usize,
    /// Of `contact_steps`, the corrections at the pose (contact steps without motion until the
    /// hands' contact force settles).
    pub pose_corrections: usize,
    /// The relative change of the hands' contact force in the last correction, when the
    /// corrections ended without settling to `solve::CONTACT_CORRECTION` (the forces shown are
    /// that uncertain); not written when they settled.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsettled_at_pose: Option<f64>,
    /// Where the last of unsettled corrections moved the bodies most (with
    /// `unsettled_at_pose`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsettled_motion: Option<UnsettledMotion>,
    /// A correction at the pose whose contact solve failed, and why: the frame is the last
    /// correction kept (or the motion's last step), its forces uncertain by
    /// `unsettled_at_pose` where a correction was kept; not written when none failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub correction_failed: Option<String>,
    /// Contact solves that did not settle and were redone smaller (the one-step attempt of a
    /// keyframe then solved in steps, halved steps).
    pub contact_retries: usize,
    /// The pairs of the hand's skin its barrier holds apart at the end of the flexion (the fold
    /// of a crease, a fingertip on the palm, fingers side by side; issue 16): a point off a
    /// facet, or an edge off an edge.
    pub self_contacts: usize,
    /// The sum of their normal forces (of a pair's one side: its point, or its first edge), N.
    pub self_contact_force: f64,
    /// The keyframe's motion went in two stages, the fingers first and the thumb after them:
    /// with the skin kept out of itself, the motion of both at once did not settle (the thumb
    /// folding over fingers still closing; issue 16). Written only when true.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub thumb_after_fingers: bool,
    /// The keyframe ended short of its pose: how far it went and why (`None`: it reached it;
    /// not written then).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_short: Option<StoppedShort>,
    /// Knots of the flexion taken from the work the solver did ahead while it was idle (the
    /// viewer's pose presets, flexed from the pose shown): their times and factorizations were
    /// spent then and are not counted here. Written only when some were.
    #[serde(skip_serializing_if = "is_zero")]
    pub knots_flexed_ahead: usize,
    /// The whole keyframe was solved ahead, while the solver was idle (the viewer's pose
    /// presets), and taken when asked: its times were spent then. Written only when true.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub solved_ahead: bool,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// A keyframe whose motion ended before its pose: the frame is the last state the solve could
/// reach, and the grasp is not realisable beyond it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StoppedShort {
    /// The fraction of the keyframe's joint motion reached, 0–1.
    pub reached: f64,
    /// Why the motion could not go on.
    pub reason: String,
    /// The contact solve could not follow the motion further: a limit of the solver, not of
    /// the grasp (the command exits non-zero). False where a bone's reaction overran its muscle
    /// threshold: the paper's limit of a realisable grasp, a result.
    pub solver_limit: bool,
}

impl KeyframeStats {
    /// The change of the hands' contact force in the last correction at the pose above which a
    /// frame is said to be unsettled (the report's warning, the viewer's status): 1 %. Below it
    /// the corrections' jitter (contact points moving between facets) is recorded in
    /// `unsettled_at_pose` only.
    pub const UNSETTLED_WARNING: f64 = 0.01;

    /// Adds the cost of `step`, a later part of the same keyframe: counts and times add up, the
    /// sizes and the residual are the largest; skinned far from contact are the digits (and
    /// cells) skinned in every part.
    pub fn absorb(&mut self, step: &KeyframeStats) {
        self.increments += step.increments;
        self.increments_taken += step.increments_taken;
        self.halvings += step.halvings;
        // The cell counts of one step, the largest FEM sub-problem (the FEM region follows
        // the flesh, step by step): its FEM and skinned cells are those of one region.
        if step.fem_cells > self.fem_cells {
            self.fem_cells = step.fem_cells;
            self.far_cells = step.far_cells;
            self.far_digits = step.far_digits.clone();
        }
        self.free_dofs = self.free_dofs.max(step.free_dofs);
        self.prescribed_dofs = self.prescribed_dofs.max(step.prescribed_dofs);
        self.factorizations += step.factorizations;
        self.assembly_ms += step.assembly_ms;
        self.symbolic_ms += step.symbolic_ms;
        self.factorization_ms += step.factorization_ms;
        self.solve_ms += step.solve_ms;
        self.update_ms += step.update_ms;
        self.total_ms += step.total_ms;
        self.relative_residual = self.relative_residual.max(step.relative_residual);
        self.contact_steps += step.contact_steps;
        self.pose_corrections += step.pose_corrections;
        self.thumb_after_fingers |= step.thumb_after_fingers;
        if step.correction_failed.is_some() {
            self.correction_failed = step.correction_failed.clone();
        }
        if step.unsettled_at_pose.is_some() {
            self.unsettled_at_pose = step.unsettled_at_pose;
            self.unsettled_motion = step.unsettled_motion.clone();
        }
        self.contact_retries += step.contact_retries;
        self.knots_flexed_ahead += step.knots_flexed_ahead;
        // The flexion's end is the later step's.
        if step.increments_taken > 0 {
            self.self_contacts = step.self_contacts;
            self.self_contact_force = step.self_contact_force;
        }
        if step.stopped_short.is_some() {
            self.stopped_short = step.stopped_short.clone();
        }
    }
}
