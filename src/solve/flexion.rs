//! Finger flexion by increments: the paper's procedure (Figure 2 and Figure 6) in an updated
//! Lagrangian, small-strain form.
//!
//! A keyframe's joint motion is split into increments of at most `max_step_deg`. For each
//! increment the bones are moved; the displacement of every bone node from the previous increment
//! is prescribed (U_k); the stiffness is assembled on the current geometry; equation (7),
//! K11·U_u = R_k − K12·U_k with R_k = 0, gives the free flesh displacement; equation (8) the bone
//! reactions; the flesh positions are updated.
//!
//! Only what the motion requires is solved: with a local region, the cells within `radius` of a
//! moving joint are solved by FEM and every other node follows its bones by incremental skinning
//! (exactly rigid away from joints, where the FEM solution is rigid too); digits set to skinning
//! follow their bones geometrically (the fast path).

use super::error::SimError;
use super::linear_factor::LinearFactor;
use super::region::{local_displacements, sub_problem, SubProblem};
use super::self_contact::{barrier_kappa, OwnSkin};
use super::step_control::StepControl;
use crate::contact::SelfBarrier;
use crate::fem::assembly::{assemble, assemble_warped};
use crate::fem::hex8::relative_min_jacobian;
use crate::fem::solve::{FillOrdering, PartitionedSolver};
use crate::fem::Material;
use crate::hand::HandModel;
use crate::mesh::Mesh;
use crate::model::{FleshMethod, FleshRegion, FlexionScheme, FlexionSettings};
use crate::state::{HandState, KeyframeStats};
use crate::util::near::NearPoints;
use crate::util::timing::ms;
use nalgebra::{Isometry3, Matrix3, Point3, Quaternion, UnitQuaternion, Vector3};
use std::sync::Arc;
use std::time::Instant;

/// The bones at an increment's end and where the flesh would be if it only followed them
/// ([`Flexion::predict`]).
pub(super) struct Predicted {
    /// Rigid motion of every bone, rest → the increment's end.
    pub(super) transforms: Vec<Isometry3<f64>>,
    /// Each bone's motion over the increment.
    pub(super) delta: Vec<Isometry3<f64>>,
    /// Every node's predicted position, m.
    pub(super) next: Vec<Vector3<f64>>,
}

/// What the increments of one keyframe share ([`Flexion::plan`]).
pub(super) struct Plan {
    /// Joint angles at the start of the keyframe, degrees.
    pub(super) start: Vec<f64>,
    /// Joint angles at its end, degrees.
    pub(super) target: Vec<f64>,
    /// Increments planned (the largest joint motion over `max_step_deg`).
    pub(super) steps: usize,
    /// The FEM region, `None` when nothing is free.
    pub(super) sub: Option<SubProblem>,
    /// Free nodes of skinned digits: they follow skinning from rest.
    pub(super) direct: Vec<usize>,
    /// Every other free node: it follows incremental skinning unless the FEM solves it.
    pub(super) incremental: Vec<usize>,
}

impl Plan {
    /// The joint angles at fraction `f` of the keyframe (linear in each angle).
    pub(super) fn angles_at(&self, f: f64) -> Vec<f64> {
        self.start
            .iter()
            .zip(&self.target)
            .map(|(a, b)| a + (b - a) * f)
            .collect()
    }
}

/// Asked once per increment; `true` stops [`Flexion::move_to`] with [`SimError::Cancelled`].
pub type CancelCheck = Arc<dyn Fn() -> bool + Send + Sync>;

/// What a hand's flexion keyframes reuse from one to the next: part of the driver's workspace
/// ([`super::Workspace`]).
pub struct FlexionCaches {
    /// The partitioned solver: its symbolic analysis is kept while the prescribed set is unchanged.
    pub(super) solver: PartitionedSolver,
    /// The linear tier's factored rest stiffness, built by its first keyframe.
    pub(super) linear: Option<LinearFactor>,
    /// The last FEM region (its cells, and its sub-problem): the knots of a keyframe, and
    /// keyframes moving the same joints, solve the same (building the full hand's took 19–36 ms
    /// a knot).
    region: Option<(Vec<bool>, SubProblem)>,
    /// Knots flexed ahead while the solver was idle, for a keyframe that may come next.
    pub(super) knots: super::knot_memo::KnotMemo,
}

impl FlexionCaches {
    /// Empty caches for the fill-reducing `ordering`.
    pub fn new(ordering: FillOrdering) -> Self {
        FlexionCaches {
            solver: PartitionedSolver::new(ordering),
            linear: None,
            region: None,
            knots: Default::default(),
        }
    }
}

/// Moves a hand through keyframes.
pub struct Flexion<'a> {
    pub(super) hand: &'a HandModel,
    pub(super) body: String,
    pub(super) materials: Vec<Material>,
    pub(super) settings: FlexionSettings,
    pub(super) ordering: FillOrdering,
    cancel: Option<CancelCheck>,
    /// What the keyframes of this hand reuse: the solver's symbolic analysis, the linear tier's
    /// factor.
    pub(super) caches: FlexionCaches,
    /// Parts of the hand (0 palm, 1 thumb … 5 little) whose flesh follows skinning in the next
    /// keyframe because they stay far from contact.
    far: [bool; 6],
    /// The flesh positions the next keyframe's FEM region is chosen on (`None`: where the
    /// keyframe starts).
    region_at: Option<Vec<Vector3<f64>>>,
}

impl<'a> Flexion<'a> {
    /// A stepper for `hand` (called `body` in errors) with the material of each flesh cell.
    pub fn new(
        hand: &'a HandModel,
        body: &str,
        materials: Vec<Material>,
        settings: FlexionSettings,
        ordering: FillOrdering,
    ) -> Self {
        Flexion {
            hand,
            body: body.to_string(),
            materials,
            settings,
            ordering,
            cancel: None,
            caches: FlexionCaches::new(ordering),
            far: [false; 6],
            region_at: None,
        }
    }

    /// Leaves the FEM cells of the parts marked `far` (0 palm, 1 thumb … 5 little) to
    /// skinning in the keyframes that follow, until set again: the parts that stay far from
    /// every other body (`super::proximity::far_parts`). The linear tier, whose factored
    /// stiffness is the cheap path already, ignores it.
    pub fn set_far_parts(&mut self, far: [bool; 6]) {
        self.far = far;
    }

    /// Chooses the next keyframe's FEM region on the flesh at `positions` instead of where the
    /// keyframe starts: a motion flexed one knot at a time (`solve::path`) chooses it where
    /// the motion starts, so that every knot solves the same cells (the flesh moving by a few
    /// millimetres moved two cells of the full hand's 7 813 in or out of the 12 mm around the
    /// joints, and each knot's symbolic analysis was made again).
    pub fn set_region_geometry(&mut self, positions: Option<Vec<Vector3<f64>>>) {
        self.region_at = positions;
    }

    /// Checks `cancel` before every increment: when it answers `true`, [`Flexion::move_to`]
    /// returns [`SimError::Cancelled`], the state left at the last completed increment (a
    /// consistent pose from which a later `move_to` can go on).
    pub fn with_cancel(mut self, cancel: CancelCheck) -> Self {
        self.cancel = Some(cancel);
        self
    }

    /// Reuses the caches of an earlier stepper of the same hand, flesh materials and settings
    /// (see [`Flexion::into_caches`]).
    pub fn with_caches(mut self, caches: FlexionCaches) -> Self {
        self.caches = caches;
        self
    }

    /// Hands over the caches (the symbolic analysis, the linear tier's factor if a linear
    /// keyframe built it), so that a later stepper skips that work.
    pub fn into_caches(self) -> FlexionCaches {
        self.caches
    }

    pub(super) fn cell_method(&self, c: usize) -> FleshMethod {
        self.settings.methods[self.hand.flesh.cell_digit[c].map_or(0, |d| d + 1)]
    }

    /// The parts left to skinning because they stay far from contact (`set_far_parts`).
    pub(super) fn far_parts(&self) -> [bool; 6] {
        self.far
    }

    /// Moves `state` to the joint angles `target` (degrees).
    pub fn move_to(
        &mut self,
        state: &mut HandState,
        target: &[f64],
    ) -> Result<KeyframeStats, SimError> {
        match self.settings.scheme {
            FlexionScheme::Linear => {
                if self.cancel.as_ref().is_some_and(|c| c()) {
                    return Err(SimError::Cancelled);
                }
                let tier = match self.caches.linear.take() {
                    Some(tier) => tier,
                    None => LinearFactor::new(
                        self.hand,
                        &self.body,
                        &self.materials,
                        &self.settings,
                        self.ordering,
                    )?,
                };
                self.caches
                    .linear
                    .insert(tier)
                    .move_to(self.hand, state, target)
            }
            FlexionScheme::Nonlinear => self.move_to_nonlinear(state, target),
            FlexionScheme::UpdatedLagrangian | FlexionScheme::Corotational => {
                self.move_to_linear_increments(state, target)
            }
        }
    }

    /// Acquires ahead, for the schemes of linear increments (the corotated and the paper's),
    /// the memory of the largest factorization a keyframe of the hand at `state` makes: that of
    /// the FEM region of every FEM cell ([`PartitionedSolver::reserve_for`]). The region the
    /// caches keep is left as it is (the one the hand last moved: the next keyframe's
    /// likeliest).
    pub fn prepare(&mut self, state: &HandState) -> Result<(), SimError> {
        if !matches!(
            self.settings.scheme,
            FlexionScheme::UpdatedLagrangian | FlexionScheme::Corotational
        ) {
            return Ok(());
        }
        let active: Vec<bool> = (0..self.hand.flesh.mesh.cells.len())
            .map(|c| self.cell_method(c) == FleshMethod::Fem)
            .collect();
        let Some(sub) = sub_problem(self.hand, &self.materials, &active) else {
            return Ok(());
        };
        let positions: Vec<Vector3<f64>> = sub.nodes.iter().map(|&n| state.positions[n]).collect();
        self.caches
            .solver
            .reserve_for(&sub.pattern, &sub.partition, &positions)
            .map_err(|source| SimError::Solve {
                body: self.body.clone(),
                source,
            })
    }

    /// Whether the caller asked to stop.
    pub(super) fn cancelled(&self) -> bool {
        self.cancel.as_ref().is_some_and(|c| c())
    }

    /// The increments of the paper (updated Lagrangian) or corotated ones: one linear solve
    /// each.
    fn move_to_linear_increments(
        &mut self,
        state: &mut HandState,
        target: &[f64],
    ) -> Result<KeyframeStats, SimError> {
        let t_all = Instant::now();
        let mut stats = KeyframeStats::default();
        let Some(plan) = self.plan(state, target, &mut stats) else {
            return Ok(stats);
        };
        const MAX_HALVINGS: usize = 4;
        // The region's skin, kept out of itself by a barrier (src/solve/flexion_barrier.rs).
        let own_skin = match (&self.settings.self_contact, &plan.sub) {
            (Some(contact), Some(sub)) => OwnSkin::new(self.hand, sub, contact).map(|skin| {
                let young = sub.materials.iter().map(|m| m.young).fold(0.0, f64::max);
                let start = local_displacements(sub, &state.positions);
                let barrier = skin.barrier(&sub.mesh.nodes, barrier_kappa(young), &start);
                (skin, barrier)
            }),
            _ => None,
        };

        // March from 0 to 1 in fractions of the keyframe; an increment that would turn a cell
        // inside out is retried with half the step, up to MAX_HALVINGS times.
        let mut control = StepControl::new(plan.steps, MAX_HALVINGS, false);
        while !control.finished() {
            if self.cancelled() {
                return Err(SimError::Cancelled);
            }
            let f = control.target();
            let angles = plan.angles_at(f);
            let t_update = Instant::now();
            let Predicted {
                transforms,
                delta,
                mut next,
            } = self.predict(&plan, state, &angles);
            stats.update_ms += ms(t_update);

            if let Some(sub) = &plan.sub {
                let rotations = match self.settings.scheme {
                    FlexionScheme::Corotational => Some(cell_rotations(self.hand, sub, &delta)),
                    _ => None,
                };
                let own = own_skin.as_ref().map(|(skin, barrier)| (skin, barrier));
                match self.solve_increment(sub, own, state, &mut next, rotations, &mut stats) {
                    Ok(None) => {}
                    // A crushed cell, or a self-contact that did not settle: half the step.
                    Ok(Some(_)) | Err(SimError::SelfContactUnsettled { .. }) if control.halve() => {
                        stats.halvings += 1;
                        continue;
                    }
                    Err(SimError::SelfContactUnsettled { reason, .. }) => {
                        let (joint, angle) = self.moving_most(&plan, &angles);
                        return Err(SimError::SelfContactUnsettled {
                            body: self.body.clone(),
                            joint,
                            angle,
                            reason,
                            share: None,
                        });
                    }
                    Err(e) => return Err(e),
                    Ok(Some((cell, _))) => {
                        let (joint, angle) = self.nearest_moving_joint(&plan, state, &angles, cell);
                        return Err(SimError::FleshCrushed {
                            body: self.body.clone(),
                            element: cell,
                            rest_position_mm: self.rest_centre_mm(cell),
                            joint,
                            angle,
                            self_contact: own_skin.is_some(),
                            share: None,
                        });
                    }
                }
            }
            stats.increments_taken += 1;
            state.positions = next;
            state.transforms = transforms;
            state.angles = angles;
            control.accept(f, true);
        }
        state.angles = target.to_vec();
        stats.total_ms = ms(t_all);
        Ok(stats)
    }

    /// What the increments of a keyframe from `state` to `target` share: the number of
    /// increments, the FEM region and who follows skinning (filling the region's counts in
    /// `stats`); `None` when no joint moves.
    pub(super) fn plan(
        &mut self,
        state: &HandState,
        target: &[f64],
        stats: &mut KeyframeStats,
    ) -> Option<Plan> {
        let hand = self.hand;
        let skeleton = &hand.skeleton;
        let flesh = &hand.flesh;
        let start = state.angles.clone();
        let largest = start
            .iter()
            .zip(target)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if largest == 0.0 {
            return None;
        }
        let steps = (largest / self.settings.max_step_deg - 1e-9)
            .ceil()
            .max(1.0) as usize;
        stats.increments = steps;

        // Cells solved by FEM, chosen at the start of the keyframe: those within `radius` of a
        // cell whose nodes do not all move by one and the same bone motion over the keyframe
        // (a joint's blend zone, or the seam between flesh following different bones, like
        // the thumb's web). Everywhere else skinning moves the flesh rigidly, as FEM would.
        let at = self.region_at.as_deref().unwrap_or(&state.positions);
        let centre = |c: usize| {
            flesh.mesh.cells[c]
                .iter()
                .map(|&n| at[n])
                .sum::<Vector3<f64>>()
                / 8.0
        };
        // Parts far from contact (`set_far_parts`) are left to skinning: in the whole region
        // their cells, in the local one the regions of the joints whose blend zone is theirs.
        let part = |c: usize| flesh.cell_digit[c].map_or(0, |d| d + 1);
        let active: Vec<bool> = match self.settings.region {
            FleshRegion::Whole => (0..flesh.mesh.cells.len())
                .map(|c| {
                    let fem = self.cell_method(c) == FleshMethod::Fem;
                    if fem && self.far[part(c)] {
                        stats.far_cells += 1;
                    }
                    fem && !self.far[part(c)]
                })
                .collect(),
            FleshRegion::Local { radius } => {
                let motion = state.motion_to(&skeleton.transforms(target));
                // Bones grouped by their motion over the keyframe.
                let class = super::self_contact::motion_classes(&motion);
                // Cells where bones moving apart meet (a joint's blend zone), counting only
                // the bones of parts not in `far`: a node that follows far bones only sides
                // with any neighbour, so a far finger's joints and their blend into the palm
                // are left to skinning.
                let seams_with = |far: &[bool; 6]| -> Vec<Vector3<f64>> {
                    let far_bone = |b: usize| far[skeleton.bones[b].digit.map_or(0, |d| d + 1)];
                    // `None`: the node's bones move apart; `Some(None)`: far bones only.
                    let node_class = |n: usize| -> Option<Option<usize>> {
                        let mut out: Option<usize> = None;
                        for &(b, _) in &hand.weights.weights[n] {
                            if far_bone(b) {
                                continue;
                            }
                            match out {
                                None => out = Some(class[b]),
                                Some(k) if k != class[b] => return None,
                                Some(_) => {}
                            }
                        }
                        Some(out)
                    };
                    (0..flesh.mesh.cells.len())
                        .filter(|&c| {
                            let mut seen: Option<usize> = None;
                            for &n in &flesh.mesh.cells[c] {
                                match node_class(n) {
                                    None => return true,
                                    Some(None) => {}
                                    Some(Some(k)) => match seen {
                                        None => seen = Some(k),
                                        Some(s) if s != k => return true,
                                        Some(_) => {}
                                    },
                                }
                            }
                            false
                        })
                        .map(centre)
                        .collect()
                };
                let region = |seams: &[Vector3<f64>]| -> Vec<bool> {
                    let seams = NearPoints::new(seams, radius);
                    (0..flesh.mesh.cells.len())
                        .map(|c| {
                            self.cell_method(c) == FleshMethod::Fem && seams.any_within(&centre(c))
                        })
                        .collect()
                };
                let mut active = region(&seams_with(&self.far));
                // Self-contact: the region grows around where the skin will meet itself.
                if let Some(contact) = &self.settings.self_contact {
                    let meeting = super::self_contact::near_itself(
                        hand,
                        self.settings.blend,
                        (&skeleton.transforms(target), &motion),
                        &state.positions,
                        contact,
                    );
                    let meeting = NearPoints::new(&meeting, radius);
                    for (c, a) in active.iter_mut().enumerate() {
                        if !*a && self.cell_method(c) == FleshMethod::Fem && !self.far[part(c)] {
                            *a = meeting.any_within(&centre(c));
                        }
                    }
                }
                if self.far.iter().any(|&f| f) {
                    let all = region(&seams_with(&[false; 6]));
                    stats.far_cells = all.iter().zip(&active).filter(|(a, b)| **a && !**b).count();
                }
                active
            }
        };
        if stats.far_cells > 0 {
            const NAMES: [&str; 6] = ["palm", "thumb", "index", "middle", "ring", "little"];
            stats.far_digits = (0..6)
                .filter(|&p| self.far[p])
                .map(|p| NAMES[p].to_string())
                .collect();
        }
        let sub = self.sub_problem(&active);
        if let Some(sub) = &sub {
            stats.fem_cells = sub.cells.len();
            stats.free_dofs = sub.partition.free_count();
            stats.prescribed_dofs = sub.partition.prescribed_count();
        }
        // Nodes owned by skinned digits follow skinning from rest; every other free node not
        // solved by FEM follows incremental skinning.
        let mut owned_by_skinning = vec![true; flesh.mesh.nodes.len()];
        for (c, cell) in flesh.mesh.cells.iter().enumerate() {
            if self.cell_method(c) == FleshMethod::Fem {
                for &n in cell {
                    owned_by_skinning[n] = false;
                }
            }
        }
        let direct: Vec<usize> = (0..owned_by_skinning.len())
            .filter(|&n| owned_by_skinning[n] && flesh.node_bone[n].is_none())
            .collect();
        let incremental: Vec<usize> = (0..owned_by_skinning.len())
            .filter(|&n| !owned_by_skinning[n] && flesh.node_bone[n].is_none())
            .collect();
        Some(Plan {
            start,
            target: target.to_vec(),
            steps,
            sub,
            direct,
            incremental,
        })
    }

    /// The bones at `angles` and where the flesh would be if it only followed them: the bone
    /// transforms, their motion since `state`, and the positions of every node (bone nodes
    /// rigidly, skinned digits by skinning from rest, every other node by incremental
    /// skinning from `state`).
    pub(super) fn predict(&self, plan: &Plan, state: &HandState, angles: &[f64]) -> Predicted {
        let hand = self.hand;
        let flesh = &hand.flesh;
        let transforms = hand.skeleton.transforms(angles);
        let delta = state.motion_to(&transforms);
        let mut next = state.positions.clone();
        hand.weights.apply(
            self.settings.blend,
            &delta,
            &state.positions,
            plan.incremental.iter().copied(),
            &mut next,
        );
        hand.weights.apply(
            self.settings.blend,
            &transforms,
            &flesh.mesh.nodes,
            plan.direct.iter().copied(),
            &mut next,
        );
        for (n, b) in flesh.node_bone.iter().enumerate() {
            if let Some(b) = b {
                next[n] = (transforms[*b] * Point3::from(flesh.mesh.nodes[n])).coords;
            }
        }
        Predicted {
            transforms,
            delta,
            next,
        }
    }

    /// The moving joint nearest to flesh cell `cell` in `state`, and its angle in `angles`.
    pub(super) fn nearest_moving_joint(
        &self,
        plan: &Plan,
        state: &HandState,
        angles: &[f64],
        cell: usize,
    ) -> (String, f64) {
        let c = self.hand.flesh.mesh.cells[cell];
        let now = c.iter().map(|&n| state.positions[n]).sum::<Vector3<f64>>() / 8.0;
        self.hand
            .skeleton
            .dofs
            .iter()
            .enumerate()
            .filter(|(i, _)| plan.target[*i] != plan.start[*i])
            .min_by(|a, b| {
                let d = |d: &crate::hand::JointDof| {
                    let p = state.transforms[d.bone] * Point3::from(d.center);
                    (p.coords - now).norm()
                };
                d(a.1).total_cmp(&d(b.1))
            })
            .map(|(i, d)| (d.name.clone(), angles[i]))
            .unwrap_or_default()
    }

    /// The joint moving most over the keyframe `plan`, and its angle in `angles`.
    fn moving_most(&self, plan: &Plan, angles: &[f64]) -> (String, f64) {
        let motion = |i: usize| (plan.target[i] - plan.start[i]).abs();
        (0..plan.target.len())
            .max_by(|&a, &b| motion(a).total_cmp(&motion(b)))
            .map(|i| (self.hand.skeleton.dofs[i].name.clone(), angles[i]))
            .unwrap_or_default()
    }

    /// Centre of flesh cell `cell` in the rest pose, mm.
    pub(super) fn rest_centre_mm(&self, cell: usize) -> [f64; 3] {
        let flesh = &self.hand.flesh;
        let at = flesh.mesh.cells[cell]
            .iter()
            .map(|&n| flesh.mesh.nodes[n])
            .sum::<Vector3<f64>>()
            / 8.0;
        [at.x * 1e3, at.y * 1e3, at.z * 1e3]
    }

    fn sub_problem(&mut self, active: &[bool]) -> Option<SubProblem> {
        if let Some((cells, sub)) = &self.caches.region {
            if cells.as_slice() == active {
                return Some(sub.clone());
            }
        }
        let sub = sub_problem(self.hand, &self.materials, active)?;
        self.caches.region = Some((active.to_vec(), sub.clone()));
        Some(sub)
    }
}

impl Flexion<'_> {
    /// One increment on the FEM region: equations (7)–(8) on the current geometry.
    fn solve_increment(
        &mut self,
        sub: &SubProblem,
        own_skin: Option<(&OwnSkin, &SelfBarrier)>,
        state: &mut HandState,
        next: &mut [Vector3<f64>],
        rotations: Option<Vec<Matrix3<f64>>>,
        stats: &mut KeyframeStats,
    ) -> Result<Option<(usize, f64)>, SimError> {
        let inverted = |cell: usize, relative_det: f64| SimError::InvertedElement {
            body: self.body.clone(),
            element: cell,
            relative_det,
        };
        let mut mesh = Mesh {
            nodes: sub.nodes.iter().map(|&n| state.positions[n]).collect(),
            cells: sub.mesh.cells.clone(),
        };
        let t = Instant::now();
        let dofs = sub.nodes.len() * 3;
        // Unknowns: the displacement increment (paper), or the new positions (corotational).
        let absolute = rotations.is_some();
        let (k, loads) = match &rotations {
            None => (
                assemble(&sub.pattern, &mesh, &sub.materials)
                    .map_err(|e| inverted(sub.cells[e.cell], e.inverted.relative_det))?,
                vec![0.0; dofs],
            ),
            Some(r) => assemble_warped(&sub.pattern, &mesh, &sub.materials, r)
                .map_err(|e| inverted(sub.cells[e.cell], e.inverted.relative_det))?,
        };
        stats.assembly_ms += ms(t);
        // Regions of successive increments number the hand's nodes each their own way.
        self.caches.solver.set_node_ids(sub.nodes.clone());
        // The self-contact's press at the skin's vertices (the state's), set once the increment
        // is taken.
        let mut pressed = None;
        let solution = match own_skin {
            Some((skin, barrier)) => {
                let stiffness = (&k, loads.as_slice(), absolute);
                let at = (&mesh, &*next);
                match self.barrier_increment(sub, barrier, stiffness, at, stats)? {
                    Err((cell, q)) => return Ok(Some((cell, q))),
                    Ok((solution, u)) => {
                        pressed = Some((skin, barrier, u));
                        solution
                    }
                }
            }
            None => {
                let mut prescribed = vec![0.0; dofs];
                for (i, &n) in sub.nodes.iter().enumerate() {
                    if sub.partition.prescribed[3 * i] {
                        let value = if absolute {
                            next[n]
                        } else {
                            next[n] - state.positions[n]
                        };
                        prescribed[3 * i..3 * i + 3].copy_from_slice(value.as_slice());
                    }
                }
                let solution = self
                    .caches
                    .solver
                    .solve(&k, &sub.partition, &prescribed, &loads, &mesh.nodes)
                    .map_err(|source| SimError::Solve {
                        body: self.body.clone(),
                        source,
                    })?;
                stats.factorizations += 1;
                solution
            }
        };
        let s = &solution.stats;
        stats.symbolic_ms += s.symbolic_ms;
        stats.factorization_ms += s.factorization_ms;
        stats.solve_ms += s.solve_ms;
        stats.relative_residual = stats.relative_residual.max(s.relative_residual);
        for (i, &n) in sub.nodes.iter().enumerate() {
            if !sub.partition.prescribed[3 * i] {
                let u = solution.node_displacement(i);
                mesh.nodes[i] = if absolute { u } else { state.positions[n] + u };
            } else {
                mesh.nodes[i] = next[n];
            }
        }
        // No cell may turn inside out: report it, and leave the state untouched.
        for (local, cell) in mesh.cells.iter().enumerate() {
            let q = relative_min_jacobian(&cell.map(|n| mesh.nodes[n]));
            if q <= 0.0 {
                return Ok(Some((sub.cells[local], q)));
            }
        }
        if let Some((skin, barrier, u)) = pressed {
            let vertices = self.hand.contact_skin.vertex_count();
            let press = (&mut state.self_contact, vertices);
            (stats.self_contacts, stats.self_contact_force) = skin.set_press(barrier, &u, press);
        }
        for (i, &n) in sub.nodes.iter().enumerate() {
            if sub.partition.prescribed[3 * i] {
                state.reaction[n] += Vector3::new(
                    solution.reaction[3 * i],
                    solution.reaction[3 * i + 1],
                    solution.reaction[3 * i + 2],
                );
            } else {
                next[n] = mesh.nodes[i];
            }
        }
        Ok(None)
    }
}

/// The rotation each cell of the sub-problem follows in an increment: the skinning blend of its
/// nodes' bones' incremental rotations (quaternions on one hemisphere, averaged, normalised).
fn cell_rotations(
    hand: &HandModel,
    sub: &SubProblem,
    delta: &[Isometry3<f64>],
) -> Vec<Matrix3<f64>> {
    // Once per node of the region (a node is shared by up to eight cells).
    let node: Vec<Quaternion<f64>> = sub
        .nodes
        .iter()
        .map(|&n| hand.weights.blended_rotation(n, delta).into_inner())
        .collect();
    sub.mesh
        .cells
        .iter()
        .map(|cell| {
            let first = node[cell[0]];
            let mut sum = Quaternion::new(0.0, 0.0, 0.0, 0.0);
            for &n in cell {
                let q = node[n];
                sum += if q.dot(&first) < 0.0 { -q } else { q };
            }
            UnitQuaternion::new_normalize(sum)
                .to_rotation_matrix()
                .into_inner()
        })
        .collect()
}
