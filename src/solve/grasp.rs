//! A frame in which hands touch other bodies: the paper's ball grasping. The hands have been
//! posed by flexion (their skin displacements known); the other bodies and the flesh near the
//! contact are then solved together, linearised about that state:
//!
//! - the other bodies on their rest geometry, with their loads and supports, as in the static
//!   solve;
//! - the hand flesh within `contact_region` of the contact, with its stiffness assembled on the
//!   posed geometry (one more updated-Lagrangian increment), bone nodes prescribed (U_k: the
//!   bones do not move further) and the rest of the flesh held where flexion left it;
//!
//! with node-to-facet contact both ways between skin and object (object nodes against skin
//! triangles, skin points against object triangles) and against the rigid obstacles, resolved by
//! the scene's contact method. The skin is the hand's smooth skin (`HandModel::contact_skin`),
//! its points embedded in the flesh cells (`contact::EmbeddedPoints`). The bone reactions of
//! equation (8) then include the grasp.

use super::compose::compose;
use super::corotated::{linearise, step_loads, Linearised};
pub use super::detection::StepStart;
use super::detection::{detect, Detected, Detection};
use super::error::SimError;
use super::frame_stress::contact_stress;
use super::hyperelastic_objects::{linearise_neo_hookean, neo_hookean_objects};
use super::insides::deepest_inside;
use super::objects_factor::{body_groups, objects_stiffness, PreparedObjects};
use super::stabilize::{check_held, stabilize};
use super::statics::solve_static;
use super::untouched::UntouchedStep;
use crate::contact::{
    solve_lagrange, solve_paper, ContactError, ContactMethod, ContactProblem, ContactResult,
    ContactSurface, EmbeddedPoints, Master,
};
use crate::fem::assembly::AssemblyError;
use crate::fem::kept_elements::KeptElements;
use crate::fem::solve::{PartitionedSolver, SolveError};
use crate::fem::stress::StressField;
use crate::mesh::Mesh;
use crate::model::Model;
use crate::state::outcome::{node_bone, overloads};
use crate::state::HandState;
use crate::state::{Frame, HandFrame, PendingStress};
use crate::util::timing::ms;
use nalgebra::Vector3;
use std::time::Instant;

/// What the contact steps of a model keep from one to the next: the partitioned solver (its
/// symbolic analysis, carried over while the region changes by a few dofs), and the contact
/// nodes the last step held (the next one's warm start).
pub struct ContactCache {
    solver: PartitionedSolver,
    pub(super) held: Vec<usize>,
    /// The contact forces those nodes transferred (over every dof; the paper's iteration's
    /// warm start; empty after the exact method).
    pub(super) transferred: Vec<f64>,
    /// Where the ground springs of floating bodies rest, over every dof (`None`: at rest): an
    /// object let go of (`let_go`) is anchored where the last solve left it.
    pub(super) anchor: Option<Vec<f64>>,
    /// An object's springs that carried more than they may are kept here instead of failing
    /// the step (`Some(None)`: nothing to tell; `None`: such a step fails).
    pub(super) unheld: Option<Option<ContactError>>,
    /// The step of the other bodies from the static frame touching nothing
    /// (src/solve/untouched.rs): `None` before it is asked, `Some(None)` where it could not be
    /// solved (such steps are then solved).
    pub(super) untouched: Option<Option<UntouchedStep>>,
    /// The objects' element stiffnesses at rest (src/solve/objects_factor.rs), made at the
    /// first step that assembles them.
    kept: Option<KeptElements>,
    /// The objects' stiffness and factor made ahead of the next step, while its knot flexed
    /// ([`ContactCache::prepare_objects`]).
    prepared: Option<PreparedObjects>,
}

/// What a keyframe's contact steps hand to the next keyframe's besides the hands' states (the
/// nodes held, the forces transferred, where a let-go object is anchored): what a keyframe
/// solved ahead starts from and leaves ([`super::anticipate`]). Not the solver's caches.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Carried {
    held: Vec<usize>,
    transferred: Vec<f64>,
    anchor: Option<Vec<f64>>,
}

impl ContactCache {
    /// What the next keyframe's contact steps would start from; `None` where an object's
    /// springs keep what they carried beyond their share (`unheld`: letting go of an object).
    pub(super) fn carried(&self) -> Option<Carried> {
        self.unheld.is_none().then(|| Carried {
            held: self.held.clone(),
            transferred: self.transferred.clone(),
            anchor: self.anchor.clone(),
        })
    }

    /// Goes on from `carried` (a [`Self::carried`]).
    pub(super) fn restore(&mut self, carried: Carried) {
        self.held = carried.held;
        self.transferred = carried.transferred;
        self.anchor = carried.anchor;
    }

    /// Nothing kept yet for the contact steps of `model`: factorizations ordered by its
    /// ordering, K11 held in blocks by its bodies (src/solve/objects_factor.rs).
    pub fn new(model: &Model) -> ContactCache {
        let mut solver = PartitionedSolver::new(model.ordering);
        solver.set_node_groups(body_groups(model));
        ContactCache {
            solver,
            held: Vec::new(),
            transferred: Vec::new(),
            anchor: None,
            unheld: None,
            untouched: None,
            kept: None,
            prepared: None,
        }
    }
}

impl ContactCache {
    /// Makes the objects' part of the next contact step's K and its factor now, from `carried`
    /// (the step's start), the complete tangent where the step has no motion to follow
    /// (`without_motion`, as [`solve_grasp`] decides): for a thread that would otherwise wait
    /// (a drag's first step waits for its knot's flexion). The step takes it where it starts
    /// from the same state with the same tangent, else makes its own.
    pub(super) fn prepare_objects(
        &mut self,
        model: &Model,
        carried: Option<&[f64]>,
        without_motion: bool,
    ) {
        if neo_hookean_objects(model) || model.bodies.iter().all(|b| b.hand.is_some()) {
            return;
        }
        let geometric = complete_tangent(model, without_motion && carried.is_some());
        self.prepared = Some(PreparedObjects {
            carried: carried.map(<[f64]>::to_vec),
            geometric,
            objects: objects_stiffness(
                model,
                carried,
                geometric,
                (&mut self.solver, &mut self.kept),
            ),
        });
    }
}

/// The frame with the hands at `hands`: solved with contact when a hand touches (or nearly
/// touches) another body, otherwise the static frame `still` (solved now if `None`) with the
/// hands composed into it.
pub fn frame_with_hands(
    model: &Model,
    still: Option<&Frame>,
    hands: Vec<HandFrame>,
    (carried, previous): StepStart<'_>,
    cache: &mut ContactCache,
) -> Result<Frame, SimError> {
    // Along a motion that has not touched yet (nothing carried but the static frame), skin
    // that has come within the search of a body without touching it leaves the bodies in
    // their static frame: the step is not solved.
    let untouched = match (still, previous) {
        (Some(s), Some(_)) if carried.is_none_or(|c| is_static(model, s, c)) => Some(s),
        _ => None,
    };
    if let Some(frame) = solve_grasp(model, &hands, (carried, previous), untouched, cache)? {
        return Ok(frame);
    }
    match still {
        Some(s) => compose(model, s, hands),
        None => {
            let s = solve_static(model, &mut PartitionedSolver::new(model.ordering))?;
            compose(model, &s, hands)
        }
    }
}

/// The contact solve of a frame, or `None` when no hand is near another body.
///
/// `carried`: the displacements the previous contact step of the motion left, over every dof
/// (the other bodies' from rest, the flesh's over its flexed pose), from which this step goes on.
/// The problem stays linear in the total displacements U (K of the bodies at rest, of the flesh
/// on its flexed pose), but the contact is detected and linearised about the carried
/// configuration: K·ΔU = R − K·U_prev + Cᵀλ with ΔU = U − U_prev, so that a step only has to
/// resolve the penetration its own motion made.
///
/// `previous`: each hand's flexed skin before this step's flexion (in the order of `hands`):
/// a skin node whose path from there went into a body is held against the facet it crossed
/// (src/solve/crossing.rs).
///
/// `cache`: kept from step to step, so that a region solved again (a correction at the pose)
/// or a little changed reuses or carries over its symbolic analysis, and the contact nodes the
/// last step held start this one's active set (a step with nothing carried starts cold).
pub fn solve_grasp(
    model: &Model,
    hands: &[HandFrame],
    start: StepStart<'_>,
    untouched: Option<&Frame>,
    cache: &mut ContactCache,
) -> Result<Option<Frame>, SimError> {
    match solve_grasp_with(model, hands, start, untouched, cache, false) {
        // Neo-Hookean bodies squeezed where their exact tangent is indefinite (compressive
        // stress outweighing the material's stiffness in some mode, which the contact itself
        // restrains), or corotated ones whose complete tangent is: the step again with each
        // element's tangent made definite (the corotated ones' K̃ alone); the exact internal
        // forces stay, so the corrections at the pose still converge to equilibrium.
        Err(SimError::Contact(ContactError::Unstable { .. })) => {
            solve_grasp_with(model, hands, start, untouched, cache, true)
        }
        other => other,
    }
}

/// [`solve_grasp`] with the Neo-Hookean bodies' element tangents made positive definite and
/// the corotated ones' without their turn's and pressures' stiffness (`definite`), or exact.
fn solve_grasp_with(
    model: &Model,
    hands: &[HandFrame],
    (carried, previous): StepStart<'_>,
    untouched: Option<&Frame>,
    cache: &mut ContactCache,
    definite: bool,
) -> Result<Option<Frame>, SimError> {
    let settings = &model.contact;
    if model.bodies.iter().all(|b| b.hand.is_some()) || hands.is_empty() {
        return Ok(None);
    }
    let t_all = Instant::now();
    let carried_given = carried;
    let zero;
    let carried = match carried {
        Some(c) => c,
        None => {
            zero = vec![0.0; 3 * model.mesh.node_count()];
            &zero
        }
    };
    // (The other bodies corotated about what the motion carries, src/solve/corotated.rs, or
    // Neo-Hookean about it, src/solve/hyperelastic_objects.rs.)
    // The complete tangent where the step has no motion to follow — a correction at a pose,
    // a keyframe in one step from a frame in contact (a slider nudged) — where it settles the
    // pose in fewer corrections. Along a motion the step starts away from the pose's
    // equilibrium, where a soft ball's complete tangent may be nearly singular (a 10 kPa ball
    // under its air was thrown off the fingers), so K̃ alone.
    let without_motion = !definite && previous.is_none() && carried_given.is_some();
    let neo_hookean = neo_hookean_objects(model);
    let geometric = complete_tangent(model, without_motion);
    // The detection, and beside it (on the other core) the corotated or linear objects'
    // stiffness and its factor (src/solve/objects_factor.rs).
    let step = match &cache.untouched {
        Some(Some(step)) => Some(step),
        _ => None,
    };
    // (Then, on its side, the hands' part of K, assembled on the flesh region it found.)
    let detect = || {
        let found = detect(
            model,
            hands,
            (carried_given, previous),
            (untouched, step),
            t_all,
        );
        let detection_ms = ms(t_all);
        let t = Instant::now();
        let hands_part = match &found {
            Ok(Detection::Near(d)) if !neo_hookean => {
                Some(hands_stiffness(model, d, carried_given))
            }
            _ => None,
        };
        (found, detection_ms, hands_part, ms(t))
    };
    let ((found, detection_ms, hands_part, hands_ms), objects) = if neo_hookean {
        (detect(), None)
    } else {
        // (Made ahead, while the step's knot flexed, from the same state with this tangent: taken.)
        let prepared = cache
            .prepared
            .take()
            .filter(|p| p.geometric == geometric && p.carried.as_deref() == carried_given)
            .map(|p| p.objects);
        match prepared {
            Some(objects) => (detect(), Some(objects)),
            // A step that may be left unsolved (along a motion from the static frame, where
            // the skin often comes near nothing): its detection first, the objects' part only
            // where it found skin near them.
            None if untouched.is_some() => {
                let found = detect();
                let near = matches!(found.0, Ok(Detection::Near(_)));
                let (solver, kept) = (&mut cache.solver, &mut cache.kept);
                let objects = near
                    .then(|| objects_stiffness(model, carried_given, geometric, (solver, kept)));
                (found, objects)
            }
            None => {
                let (solver, kept) = (&mut cache.solver, &mut cache.kept);
                let (found, objects) = rayon::join(detect, || {
                    objects_stiffness(model, carried_given, geometric, (solver, kept))
                });
                (found, Some(objects))
            }
        }
    };
    let Detected {
        x,
        x_now_nodes,
        x_now,
        embedded,
        skin_points,
        surfaces,
        pairs,
        near_skin,
        crossed,
        partition,
        region_cells,
    } = match found? {
        Detection::Apart => return Ok(None),
        Detection::Untouched(frame) => return Ok(Some(frame)),
        Detection::Near(d) => d,
    };
    let mut times = crate::contact::ContactTimes {
        detection: detection_ms,
        ..Default::default()
    };
    // K: the objects at rest, the hands on their posed geometry.
    let t = Instant::now();
    let inverted = |e: AssemblyError| {
        let b = model.cell_body[e.cell];
        let body = &model.bodies[b];
        let element = e.cell - body.cells.start;
        let skinned = body.hand.as_deref().is_some_and(|hand| {
            let part = hand.flesh.cell_digit[element].map_or(0, |d| d + 1);
            model.flexion.methods[part] == crate::model::FleshMethod::Skinning
        });
        if skinned {
            SimError::Unsupported(format!(
                "body \"{}\": skinning folded flesh element {element} over (smallest det J / \
                 size³ = {:.3e}) and the hand is near another body: the contact step needs the \
                 flesh solved, not skinned — use an FEM tier (\"corotational\", \
                 \"incremental\" or \"nonlinear\") for a scene with contact",
                body.name, e.inverted.relative_det
            ))
        } else {
            SimError::InvertedElement {
                body: body.name.clone(),
                element,
                relative_det: e.inverted.relative_det,
            }
        }
    };
    let mut objects_kept = None;
    let (linearised, springs) = if neo_hookean {
        let mesh = Mesh {
            nodes: x.clone(),
            cells: model.mesh.cells.clone(),
        };
        let mut linearised =
            linearise_neo_hookean(model, &mesh, carried_given, definite, without_motion)
                .map_err(inverted)?;
        let springs = stabilize(model, &mut linearised.k, &partition);
        (linearised, springs)
    } else {
        // (Both parts are made for a step that found skin near the objects.)
        let objects = objects.expect("the objects' part").map_err(inverted)?;
        let hands_part = hands_part.expect("the hands' part").map_err(inverted)?;
        times.beside = objects.ms;
        objects_kept = Some(objects.kept);
        (hands_part.joined(objects.linearised), objects.springs)
    };
    let k = linearised.k;
    // (The hands' part assembled after the detection, on its side of the join.)
    let assembly_ms = ms(t) + hands_ms;

    let node_material = |n: usize| -> usize {
        model
            .node_cell(n)
            .map_or(usize::MAX, |c| model.cell_material[c])
    };
    let friction = |node: usize, master: &Master| -> f64 {
        let a = model.material_name(node_material(embedded.main_node(node)));
        let b = match master {
            Master::Obstacle(o) => model.obstacles[*o].0.as_str(),
            Master::Facet { nodes, .. } => {
                model.material_name(node_material(embedded.main_node(nodes[0])))
            }
        };
        model.friction_between(a, b)
    };
    // The paper's threshold check: any bone's total reaction beyond its threshold.
    let stop = |reaction: &[f64]| -> bool {
        hands.iter().any(|h| {
            let body = &model.bodies[h.body];
            let hand = body.hand.as_deref().expect("a hand body");
            let mut bones = vec![Vector3::zeros(); hand.skeleton.bones.len()];
            for (i, r) in h.reaction.iter().enumerate() {
                let n = body.nodes.start + i;
                let extra = Vector3::new(reaction[3 * n], reaction[3 * n + 1], reaction[3 * n + 2]);
                bones[node_bone(hand, i)] += r + extra;
            }
            bones
                .iter()
                .zip(&body.thresholds)
                .any(|(r, &limit)| r.norm() > limit)
        })
    };
    // The step from the carried displacements: loads less the forces they already hold,
    // supports' values less what they already moved; the flesh outside the region stays put.
    // f(U_c): K·U_c, plus what the carried rotation of the other bodies adds; the loads with
    // the pressures on the surface where it is now.
    let rhs = step_loads(
        model,
        (&k, linearised.offset.as_deref()),
        (&springs, cache.anchor.as_deref()),
        &partition,
        (carried, carried_given.is_some()),
        &x_now_nodes,
    );
    let problem = ContactProblem {
        k: &k,
        partition: &partition,
        prescribed: &rhs.prescribed,
        loads: &rhs.loads,
        positions: &x_now,
        embedded: &embedded,
        obstacles: &model
            .obstacles
            .iter()
            .map(|o| o.1.clone())
            .collect::<Vec<_>>(),
        obstacle_candidates: &model.contact_candidates,
        surfaces: &surfaces,
        pairs: &pairs,
        friction: &friction,
        stop: Some(&stop),
        crossings: &crossed,
        held_before: if carried_given.is_some() {
            &cache.held
        } else {
            &[]
        },
        forces_before: if carried_given.is_some() {
            &cache.transferred
        } else {
            &[]
        },
    };
    let solver = &mut cache.solver;
    let held = match settings.method {
        ContactMethod::Paper => {
            let bodies: Vec<usize> = hands.iter().map(|h| h.body).collect();
            super::paper_roles::held_in_step3(model, &bodies)
        }
        ContactMethod::Lagrange => Vec::new(),
    };
    let mut contact_solve = |problem: &ContactProblem| {
        match settings.method {
            ContactMethod::Lagrange => solve_lagrange(solver, problem, settings),
            ContactMethod::Paper => solve_paper(solver, problem, settings, &held),
        }
        .map_err(|e| contact_error(model, e, geometric))
    };
    let result = match &model.gas {
        None => contact_solve(&problem)?,
        // A gas cavity: one contact solve per pressure tried (src/solve/gas.rs); its volume is
        // that of the carried displacements plus the step's.
        Some(cavity) => super::gas::solve_with_gas(
            cavity,
            |p| {
                contact_solve(&ContactProblem {
                    loads: &rhs.at_gauge(cavity, p),
                    ..problem
                })
            },
            |r| cavity.volume_after(&model.mesh.nodes, carried, &r.solution.displacement),
        )?,
    };
    // Displacements from the reference again: the carried ones plus the step's. (The reactions
    // are already the totals: K·ΔU − (R − K·U_prev) = K·U − R.)
    let mut result = result;
    for (u, c) in result.solution.displacement.iter_mut().zip(carried) {
        *u += c;
    }
    // The nodes held: the next step's warm start (also a step that fails from here on: it is
    // redone from the same state, where the same nodes will be held).
    cache.held = crate::contact::held_nodes(&result.summary.contacts);
    cache.transferred = match settings.method {
        ContactMethod::Paper => crate::contact::transferred_forces(
            &result.summary.contacts,
            result.solution.displacement.len(),
        ),
        ContactMethod::Lagrange => Vec::new(),
    };
    match (
        check_held(model, &springs, &result, cache.anchor.as_deref()),
        &mut cache.unheld,
    ) {
        (Ok(()), unheld) => {
            if let Some(u) = unheld {
                *u = None;
            }
        }
        (Err(e), Some(u)) => *u = Some(e),
        (Err(e), None) => return Err(SimError::Contact(e)),
    }
    too_deep(
        model,
        (&surfaces, hands.len()),
        &near_skin,
        &x,
        (&embedded, &skin_points),
        &result,
    )?;

    // The frame: objects' displacements from rest, hands' from rest through their pose.
    let u = &result.solution.displacement;
    let mut frame_u = u.clone();
    let mut frame_r = result.solution.reaction.clone();
    let mut hand_frames = Vec::new();
    for h in hands {
        let body = &model.bodies[h.body];
        let hand = body.hand.as_deref().expect("a hand body");
        let mut hf = h.clone();
        let mut contact_force = vec![Vector3::zeros(); hand.skeleton.bones.len()];
        hf.contact_displacement = vec![Vector3::zeros(); hf.positions.len()];
        hf.contact_reaction = vec![Vector3::zeros(); hf.positions.len()];
        for (i, p) in hf.positions.iter_mut().enumerate() {
            let n = body.nodes.start + i;
            let du = Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
            *p += du;
            hf.contact_displacement[i] = du;
            let dr = result.solution.reaction_at(n);
            hf.reaction[i] += dr;
            hf.contact_reaction[i] = dr;
            let total = *p - model.mesh.nodes[n];
            frame_u[3 * n..3 * n + 3].copy_from_slice(total.as_slice());
            frame_r[3 * n..3 * n + 3].copy_from_slice(hf.reaction[i].as_slice());
        }
        for c in &result.contacts {
            for (n, f) in c.nodal_forces() {
                if body.nodes.contains(&n) {
                    contact_force[node_bone(hand, n - body.nodes.start)] += f;
                }
            }
        }
        let state = HandState {
            angles: hf.angles.clone(),
            transforms: hand.skeleton.transforms(&hf.angles),
            positions: hf.positions.clone(),
            reaction: hf.reaction.clone(),
            self_contact: Vec::new(),
            far_strained: Vec::new(),
        };
        hf.bone_reactions = state.bone_reactions(hand);
        hf.volume = state.flesh_volume(hand);
        hf.overloads = overloads(
            hand,
            &state.transforms,
            &hf.bone_reactions,
            &body.thresholds,
        );
        hf.contact_force = contact_force;
        hand_frames.push(hf);
    }
    // Rotation-free strain in the flesh, and in the other bodies where they were corotated
    // (their Cauchy stress where they are Neo-Hookean): once this is the frame kept.
    let objects_turned = carried_given.is_some() && model.corotates_objects();
    let rule = PendingStress::Contact { objects_turned };
    // Neo-Hookean bodies' stresses at once: an object cell turned inside out (det F ≤ 0) is
    // found there and told as a contact error, so that the motion halves its step.
    let t = Instant::now();
    let (stress, stress_pending) = if neo_hookean_objects(model) {
        (contact_stress(model, &frame_u, objects_turned)?, None)
    } else {
        (StressField::default(), Some(rule))
    };
    let stress_ms = ms(t);
    // The frame keeps the displacements once: the whole model's, in its own solution.
    let ContactResult {
        mut solution,
        mut summary,
    } = result;
    solution.displacement = frame_u;
    solution.reaction = frame_r;
    summary.contact_ms = ms(t_all);
    summary.region_cells = region_cells;
    summary.times.detection = times.detection;
    summary.times.assembly = assembly_ms;
    summary.times.stress = stress_ms;
    summary.times.beside = times.beside;
    summary.objects_kept = objects_kept;
    summary.skin_points = hands
        .iter()
        .zip(&skin_points)
        .map(|(h, r)| (h.body, r.start))
        .collect();
    Ok(Some(Frame {
        solution,
        stress,
        stress_pending,
        assembly_ms,
        stress_ms,
        hands: hand_frames,
        contact: Some(summary),
    }))
}

/// Whether a contact step's corotated objects take their turn's and their pressures' stiffness
/// into the tangent: where the step has no motion to follow (`without_motion`, from a carried
/// state; see [`solve_grasp_with`]) and the objects are corotated, not Neo-Hookean.
fn complete_tangent(model: &Model, without_motion: bool) -> bool {
    without_motion && !neo_hookean_objects(model) && model.corotates_objects()
}

/// The hands' part of a contact step's K (the objects' is made beside, src/solve/objects_factor.rs):
/// a hand's cell with no free node and nothing `carried` on its nodes adds nothing, and the
/// assembly leaves it out, only checking it is not folded (skinning, or flexion's incremental
/// skinning outside its region, may have folded it: reported by the step).
fn hands_stiffness(
    model: &Model,
    detected: &Detected,
    carried_given: Option<&[f64]>,
) -> Result<Linearised, AssemblyError> {
    let partition = &detected.partition;
    let mesh = Mesh {
        nodes: detected.x.clone(),
        cells: model.mesh.cells.clone(),
    };
    let object = |c: usize| model.bodies[model.cell_body[c]].hand.is_none();
    let needed = |c: usize| {
        !object(c)
            && model.mesh.cells[c].iter().any(|&n| {
                (0..3).any(|a| {
                    !partition.prescribed[3 * n + a]
                        || carried_given.is_some_and(|u| u[3 * n + a] != 0.0)
                })
            })
    };
    // (The objects' cells are assembled and checked by the other part.)
    linearise(
        model,
        &mesh,
        carried_given,
        false,
        (&needed, Some(&object), None),
    )
}

/// Whether `carried` is what a frame composed of the static frame `still` carries: the other
/// bodies' static displacements, nothing on the hands.
fn is_static(model: &Model, still: &Frame, carried: &[f64]) -> bool {
    let u = &still.solution.displacement;
    u.len() == carried.len()
        && model.bodies.iter().all(|b| {
            let dofs = 3 * b.nodes.start..3 * b.nodes.end;
            if b.hand.is_some() {
                carried[dofs].iter().all(|v| *v == 0.0)
            } else {
                carried[dofs.clone()] == u[dofs]
            }
        })
}

/// `geometric`: the corotated bodies' tangent had their turn's and pressures' stiffness.
fn contact_error(model: &Model, e: ContactError, geometric: bool) -> SimError {
    match e {
        // A Neo-Hookean body whose tangent about the step's start is indefinite, or a
        // corotated one's complete tangent: this step's failure (a smaller one may stay on the
        // stable side, or the step again with a definite tangent), not a support missing.
        ContactError::Solve(SolveError::NotPositiveDefinite { node, .. })
            if (neo_hookean_objects(model) || geometric)
                && model.bodies[model.body_of_node(node)].hand.is_none() =>
        {
            let body = &model.bodies[model.body_of_node(node)];
            SimError::Contact(ContactError::Unstable {
                body: body.name.clone(),
                node: node - body.nodes.start,
                rest: model.mesh.nodes[node].into(),
            })
        }
        ContactError::Solve(source) => SimError::solve(model, source),
        // A runaway of a node whose body is held (supports, bones) is no missing support: the
        // contact's reach is too short for the motion.
        ContactError::Runaway { node, distance, .. } => {
            match model.bodies.iter().find(|b| b.nodes.contains(&node)) {
                // Further than the body's own size: the step diverges (a longer search lets
                // it run further: 0.10 m became 6.8 m with the search at 0.25 m).
                Some(body) if !body.floating && distance > body.size => {
                    let turned = model.corotates_objects()
                        && !neo_hookean_objects(model)
                        && body.hand.is_none();
                    let advice = if turned {
                        " — its small-strain law turned with its elements does not settle under \
                         this press: solve the scene with [solver] tier = \"nonlinear\" \
                         (Neo-Hookean bodies, their exact tangent)"
                    } else {
                        ""
                    };
                    SimError::Contact(ContactError::Diverges {
                        node: node - body.nodes.start,
                        body: body.name.clone(),
                        distance,
                        size: body.size,
                        advice: advice.into(),
                    })
                }
                Some(body) if !body.floating => SimError::Contact(ContactError::BeyondSearch {
                    node: node - body.nodes.start,
                    body: body.name.clone(),
                    distance,
                    factor: crate::contact::RUNAWAY,
                    search: model.contact.search_depth,
                    default: crate::contact::ContactSettings::default().search_depth,
                }),
                _ => SimError::Contact(e),
            }
        }
        other => SimError::Contact(other),
    }
}

/// A skin point left inside an object (beyond the search depth, contact never found it).
/// `surfaces`: the hands' contact skins, then the objects' surfaces (from the `hands`-th).
fn too_deep(
    model: &Model,
    (surfaces, hands): (&[ContactSurface], usize),
    near_skin: &[usize],
    x: &[Vector3<f64>],
    (embedded, skin): (&EmbeddedPoints, &[std::ops::Range<usize>]),
    result: &crate::contact::ContactResult,
) -> Result<(), SimError> {
    let u = &result.solution.displacement;
    let current: Vec<Vector3<f64>> = x
        .iter()
        .enumerate()
        .map(|(n, p)| p + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
        .collect();
    let current = embedded.extend(&current);
    // Deeper than the contact's limit inside a closed piece of a body's outer surface (by
    // winding numbers; a shell's cavity is inside it): a node the contact never held, or held
    // against the wrong facet. A node the contact holds is within the limit of the outer
    // surface.
    let resolved = model.contact.penetration_limit();
    match deepest_inside(&surfaces[hands..], near_skin, &current, resolved) {
        Some((n, body, depth)) => Err(SimError::Contact(ContactError::TooDeep {
            place: place_of(model, (embedded, skin), n, &current[n]),
            other: model.bodies[body].name.clone(),
            depth_mm: depth * 1e3,
            search_mm: model.contact.search_depth * 1e3,
            advice: too_deep_advice(model, body, depth),
        })),
        None => Ok(()),
    }
}

/// What to change where a point was left `depth` (m) inside `body`, which the contact does
/// not hold. Deeper than the contact searches: raise the search depth past it. Within it: the
/// diagnosis only — the body's facets fold around the point further than one linearised
/// contact step follows. (A shell's wall "giving way" was told here with a stiffer material or
/// a thicker wall as advice; it was the cavity's wall met by the skin, now left out, and the
/// advice did not work: on the finger press at MCP 30° with the hand at resolution 0.5 the
/// stiffer ball stopped earlier, at 25 % of its keyframe, and the thicker wall failed alike.)
fn too_deep_advice(model: &Model, body: usize, depth: f64) -> String {
    let search = model.contact.search_depth;
    if depth >= search {
        // No deeper than the smallest body: a deeper search is refused (docs/scene-format.md).
        let smallest = if model.bodies.len() > 1 {
            model
                .bodies
                .iter()
                .map(|b| b.size)
                .fold(f64::INFINITY, f64::min)
        } else {
            f64::INFINITY
        };
        return format!(
            "it went deeper than the contact searches ({:.1} mm): raise solver.contact_search \
             to {:.1} mm or more",
            search * 1e3,
            (2.0 * depth).min(smallest).max(depth) * 1e3
        );
    }
    let b = &model.bodies[body];
    let wall = b
        .shell_radii()
        .map(|(inner, outer)| format!(" (its wall is {:.1} mm thick)", (outer - inner) * 1e3))
        .unwrap_or_default();
    // (No advice here: the motion stops at the last step kept, or the correction at the pose
    // keeps the last settled frame, and those say what to do.)
    format!(
        "the facets of \"{}\"{wall} around it fold further than one linearised contact step \
         follows (within the contact's search depth, {:.1} mm)",
        b.name,
        search * 1e3
    )
}

/// Where contact point `n` (a mesh node, or a skin point embedded past them; `skin`: each
/// hand's range of them) at `position` is, for an error: "\"hand\" (skin point 812, over bone
/// index.distal, at (x, y, z) mm)", or "\"ball\" (node 40, at …)" (numbered within its body,
/// or its hand's skin as in `skin_NNNN.vtu`).
fn place_of(
    model: &Model,
    (embedded, skin): (&EmbeddedPoints, &[std::ops::Range<usize>]),
    n: usize,
    position: &Vector3<f64>,
) -> String {
    let node = embedded.main_node(n);
    let b = model.body_of_node(node);
    let body = &model.bodies[b];
    let at = format!(
        ", at ({:.1}, {:.1}, {:.1}) mm",
        position.x * 1e3,
        position.y * 1e3,
        position.z * 1e3
    );
    let local = node - body.nodes.start;
    let bone = body.hand.as_deref().map(|hand| {
        let bone = crate::state::outcome::node_bone(hand, local);
        format!(", over bone {}", hand.skeleton.bones[bone].name)
    });
    let bone = bone.unwrap_or_default();
    match skin.iter().find(|r| r.contains(&n)) {
        Some(r) => format!("\"{}\" (skin point {}{bone}{at})", body.name, n - r.start),
        None => format!("\"{}\" (node {local}{bone}{at})", body.name),
    }
}
