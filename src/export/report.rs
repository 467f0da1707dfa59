//! `report.json`: per frame, the reaction of every constraint (the sum of the reactions Ru of
//! equation (8) over its prescribed dofs), the displacement of every probe, the balance of
//! applied loads against reactions, and what the solver cost.

use crate::fem::stress::von_mises;
use crate::model::Model;
use crate::state::Frame;
use nalgebra::Vector3;
use serde::Serialize;
use std::collections::BTreeMap;

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// The scene file.
    pub scene: String,
    /// Sizes of the model.
    pub model: ModelSummary,
    /// Warnings about the settings (e.g. flexion increments above 10°); empty when none.
    pub warnings: Vec<String>,
    /// One entry per solved frame.
    pub frames: Vec<FrameReport>,
}

/// Sizes of the model.
#[derive(Clone, Debug, Serialize)]
pub struct ModelSummary {
    /// Nodes.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Degrees of freedom (3 per node).
    pub dofs: usize,
    /// Per body.
    pub bodies: Vec<BodySummary>,
}

/// One body.
#[derive(Clone, Debug, Serialize)]
pub struct BodySummary {
    /// Name.
    pub name: String,
    /// Nodes.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Volume, m³.
    pub volume: f64,
    /// Mass, kg.
    pub mass: f64,
}

/// A constraint's resultant.
#[derive(Clone, Debug, Serialize)]
pub struct ConstraintReport {
    /// Sum of the support reactions over its prescribed dofs, N.
    pub reaction: [f64; 3],
    /// How many dofs it prescribes.
    pub dofs: usize,
}

/// A probe's reading.
#[derive(Clone, Debug, Serialize)]
pub struct ProbeReport {
    /// The node read (global index).
    pub node: usize,
    /// Its position before deformation, m.
    pub position: [f64; 3],
    /// Its displacement, m.
    pub displacement: [f64; 3],
}

/// Applied loads against reactions: their sum is the out-of-balance force.
#[derive(Clone, Debug, Serialize)]
pub struct Equilibrium {
    /// Total applied load (gravity, pressure, forces), N.
    pub applied: [f64; 3],
    /// Total support reaction, N.
    pub reactions: [f64; 3],
    /// applied + reactions, N (zero to round-off at equilibrium).
    pub imbalance: [f64; 3],
}

/// Solver costs, ms.
#[derive(Clone, Debug, Serialize)]
pub struct Timings {
    /// Assembly of K.
    pub assembly: f64,
    /// Ordering and symbolic analysis (0 when reused).
    pub symbolic: f64,
    /// Numeric Cholesky factorization.
    pub factorization: f64,
    /// Substitution and reactions.
    pub solve: f64,
    /// Stress recovery.
    pub stress: f64,
}

/// Solver figures.
#[derive(Clone, Debug, Serialize)]
pub struct SolverReport {
    /// Relative residual of equation (7).
    pub residual: f64,
    /// Whether the symbolic factorization was reused.
    pub symbolic_reused: bool,
    /// Unknown dofs (NBEQ).
    pub free_dofs: usize,
    /// Prescribed dofs (NP).
    pub prescribed_dofs: usize,
    /// Stored entries of K11.
    pub matrix_nnz: usize,
    /// Entries of the Cholesky factor.
    pub factor_nnz: usize,
    /// Timings.
    pub timings_ms: Timings,
}

/// One frame.
#[derive(Clone, Debug, Serialize)]
pub struct FrameReport {
    /// Frame number.
    pub frame: usize,
    /// Time, s (pseudo-time of the paper's t_i).
    pub time: f64,
    /// Per constraint.
    pub constraints: BTreeMap<String, ConstraintReport>,
    /// Per probe.
    pub probes: BTreeMap<String, ProbeReport>,
    /// Per load, the total force applied, N.
    pub loads: BTreeMap<String, [f64; 3]>,
    /// Total gravity force, N.
    pub gravity: [f64; 3],
    /// Balance.
    pub equilibrium: Equilibrium,
    /// Largest displacement magnitude, m.
    pub max_displacement: f64,
    /// Largest nodal von Mises stress, Pa.
    pub max_von_mises: f64,
    /// Solver figures.
    pub solver: SolverReport,
    /// Per hand body: pose, bone reactions, flesh volume, flexion cost.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub hands: BTreeMap<String, HandReport>,
    /// Contact against the obstacles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactReport>,
    /// The gas cavity (a load with `gas = true`): its gauge pressure and volume in this frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cavity: Option<crate::state::CavityState>,
}

/// Contact in a frame.
#[derive(Clone, Debug, Serialize)]
pub struct ContactReport {
    /// Method (`lagrange` or `paper`).
    pub method: crate::contact::ContactMethod,
    /// Per obstacle: the total force it exerts on the bodies (N) and the nodes touching it.
    pub obstacles: BTreeMap<String, ObstacleReport>,
    /// Per pair of bodies in contact (`"hand/ball"`): the force the first exerts on the second,
    /// N (the second exerts the opposite: action equals reaction), and the contacts.
    pub bodies: BTreeMap<String, ObstacleReport>,
    /// Contacts sticking and slipping (Coulomb friction).
    pub sticking: usize,
    /// Contacts slipping.
    pub slipping: usize,
    /// The paper's iteration stopped because a bone's reaction overran its threshold.
    pub stopped_by_threshold: bool,
    /// Largest displacement change in the last iteration of the paper's method, m.
    pub last_change: f64,
    /// Hand cells solved with the contact.
    pub region_cells: usize,
    /// Active-set iterations.
    pub iterations: usize,
    /// The active set still changed at the iteration cap and its last settled set was kept
    /// (every contact pushing, the penetration within the limit, not within the tolerance).
    pub at_iteration_cap: bool,
    /// Factorizations (one: constraints are added through the Schur complement).
    pub factorizations: usize,
    /// Substitutions with the reused factor.
    pub substitutions: usize,
    /// Largest penetration at convergence, m.
    pub max_penetration: f64,
    /// Largest contact pressure, Pa: on the bodies' surface nodes and on the hands' skin.
    pub max_pressure: f64,
    /// Largest contact pressure on the hands' skin read over a patch 3.2 mm in radius
    /// (`state::TACTILE_PATCH_RADIUS`: the press of the skin within that distance facing the
    /// same way, over its area), Pa: the peak that converges under refinement, where
    /// `max_pressure` is one vertex's force over its own area. 0 without a hand.
    pub max_patch_pressure: f64,
    /// Time of the contact iterations, ms.
    pub contact_ms: f64,
    /// Where the time of the contact frame went, ms.
    pub times: crate::contact::ContactTimes,
}

/// One obstacle's contact.
#[derive(Clone, Debug, Serialize)]
pub struct ObstacleReport {
    /// Total force on the bodies, N.
    pub force: [f64; 3],
    /// Nodes in contact.
    pub nodes: usize,
}

fn contact_report(model: &Model, frame: &Frame) -> Option<ContactReport> {
    let c = frame.contact.as_ref()?;
    let mut obstacles: BTreeMap<String, ObstacleReport> = model
        .obstacles
        .iter()
        .map(|(name, _)| {
            (
                name.clone(),
                ObstacleReport {
                    force: [0.0; 3],
                    nodes: 0,
                },
            )
        })
        .collect();
    let mut bodies: BTreeMap<String, ObstacleReport> = BTreeMap::new();
    for p in &c.contacts {
        if let crate::contact::Master::Facet { body, .. } = p.master {
            // The force on the node's body from the facet's body.
            let a = model.body_of_node(p.slave_node());
            let key = format!("{}/{}", model.bodies[body].name, model.bodies[a].name);
            let entry = bodies.entry(key).or_insert(ObstacleReport {
                force: [0.0; 3],
                nodes: 0,
            });
            let f = p.force_vector();
            for i in 0..3 {
                entry.force[i] += f[i];
            }
            entry.nodes += 1;
        }
    }
    for p in &c.contacts {
        let Some(index) = p.obstacle() else { continue };
        let o = obstacles
            .get_mut(&model.obstacles[index].0)
            .expect("obstacle");
        let f = p.force_vector();
        for i in 0..3 {
            o.force[i] += f[i];
        }
        o.nodes += 1;
    }
    let pressure = crate::state::contact_pressure(model, frame).unwrap_or_default();
    let count = |a: crate::contact::Adhesion| c.contacts.iter().filter(|p| p.adhesion == a).count();
    Some(ContactReport {
        method: c.method,
        obstacles,
        bodies,
        sticking: count(crate::contact::Adhesion::Stick),
        slipping: count(crate::contact::Adhesion::Slip),
        stopped_by_threshold: c.stopped_by_threshold,
        last_change: c.last_change,
        region_cells: c.region_cells,
        iterations: c.iterations,
        at_iteration_cap: c.at_iteration_cap,
        factorizations: c.factorizations,
        substitutions: c.substitutions,
        max_penetration: c.max_penetration,
        max_pressure: pressure
            .iter()
            .copied()
            .chain(frame.hands.iter().flat_map(|h| {
                crate::state::skin_pressure(model, frame, h.body).unwrap_or_default()
            }))
            .fold(0.0, f64::max),
        max_patch_pressure: crate::state::tactile_peaks(model, frame).map_or(0.0, |p| p.patch),
        contact_ms: c.contact_ms,
        times: c.times.clone(),
    })
}

/// A bone's reaction.
#[derive(Clone, Debug, Serialize)]
pub struct BoneReport {
    /// Sum of R_u over the bone's nodes (equation (8)): the force the bone exerts on the flesh, N.
    pub reaction: [f64; 3],
    /// Its magnitude, N.
    pub magnitude: f64,
    /// Flesh nodes attached to the bone.
    pub nodes: usize,
}

/// A hand in a frame.
#[derive(Clone, Debug, Serialize)]
pub struct HandReport {
    /// Joint angles, degrees.
    pub pose: BTreeMap<String, f64>,
    /// Per bone.
    pub bones: BTreeMap<String, BoneReport>,
    /// Sum of all bone reactions, N (zero to round-off: the flesh is in equilibrium).
    pub bone_reaction_sum: [f64; 3],
    /// Per part (palm: the carpus; a digit: its metacarpal and phalanges), the sum of its
    /// bones' reactions, N: what the part's skeleton bears as a whole. It converges under
    /// refinement where its split among a digit's bones, across the joints' flesh, does not
    /// (the five-digit grasp: within 0.3–5 % between hand resolutions 1.5 and 2, each bone's
    /// own reaction up to 3× apart; docs/validation.md).
    pub part_reactions: BTreeMap<String, PartContact>,
    /// Flesh volume, m³.
    pub flesh_volume: f64,
    /// Relative change of the flesh volume from rest.
    pub volume_change: f64,
    /// Increments, factorizations and timings of the motion into this frame.
    pub motion: crate::state::KeyframeStats,
    /// Total contact force on each part of the hand (palm, thumb … little), N, and its
    /// magnitude: the tactile summary.
    pub contact: BTreeMap<String, PartContact>,
    /// Can the muscles hold this grasp? False when a bone's reaction overruns its threshold.
    pub realisable: bool,
    /// The bones over their thresholds, worst first, with what the animator should change.
    pub overloads: Vec<crate::state::outcome::Overload>,
    /// What a grasp keyframe found (the gentlest grip): whether it holds, the pose, the margin
    /// achieved, why not (docs/contact.md, "The gentlest grip").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grasp: Option<crate::state::GraspOutcome>,
    /// Where the skin has gone into the hand's own flesh (beyond where it already is at rest).
    pub skin_overlap: SkinOverlap,
    /// The skin pressed on itself (`[solver] self_contact`: a fold, a fingertip on the palm,
    /// fingers side by side); absent where it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub self_contact: Option<SelfContactReport>,
    /// Where the flesh has lost more than half its volume (`state::crushed_flesh`): squeezed
    /// between bones past what flesh, nearly incompressible, bears; the reactions of the bones
    /// around it depend on the mesh there.
    pub crushed_flesh: crate::state::CrushedFlesh,
    /// Flesh the frame's contact pressed inside out (`state::pressed_inside_out`); absent where
    /// none is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pressed_inside_out: Option<crate::state::InsideOut>,
}

/// The press of a hand's skin on itself in a frame: part of the tactile map.
#[derive(Clone, Debug, Serialize)]
pub struct SelfContactReport {
    /// The normal forces of the press, each counted once (half of what both sides feel), N.
    pub force: f64,
    /// What each part's skin feels (palm, thumb … little: the part of the bone leading each
    /// vertex's heaviest node), N; parts with none left out. Each press is felt on both sides:
    /// these sum to twice `force`.
    pub parts: BTreeMap<String, f64>,
    /// Largest pressure of the press on the display skin, Pa: a vertex's force over its own
    /// area (node-to-facet forces are spiky where the skins first meet: it reads where, not how
    /// much; it does not converge under refinement).
    pub max_pressure: f64,
    /// Largest pressure of the press read over a patch 3.2 mm in radius
    /// (`state::TACTILE_PATCH_RADIUS`), on the contact skin, Pa: the peak to read as how much.
    pub max_patch_pressure: f64,
}

/// The self-contact entry of hand frame `h` (`None` when its skin presses nowhere on itself).
fn self_contact_report(model: &Model, h: &crate::state::HandFrame) -> Option<SelfContactReport> {
    if !h.presses_itself() {
        return None;
    }
    let hand = model.bodies[h.body].hand.as_deref()?;
    let total: f64 = h.self_contact.iter().sum();
    let mut parts = vec![0.0; crate::state::outcome::PARTS.len()];
    for (v, f) in h.self_contact.iter().enumerate() {
        parts[crate::state::outcome::part_of_skin_vertex(hand, v)] += f;
    }
    let max_pressure = crate::state::self_contact_skin_pressure(model, h)
        .unwrap_or_default()
        .into_iter()
        .fold(0.0, f64::max);
    Some(SelfContactReport {
        force: 0.5 * total,
        parts: crate::state::outcome::PARTS
            .iter()
            .zip(parts)
            .filter(|(_, f)| *f > 0.0)
            .map(|(name, f)| (name.to_string(), f))
            .collect(),
        max_pressure,
        max_patch_pressure: crate::state::self_contact_patch_pressure(model, h)
            .unwrap_or_default()
            .into_iter()
            .fold(0.0, f64::max),
    })
}

/// The contact skin's vertices inside the hand's own flesh in a frame, away from where the skins
/// of neighbouring digits meet at rest (the webs; `model::SkinOverlapCheck`): skin that passed
/// through skin — a crease's two sides, a finger into its neighbour or the palm — where nothing
/// kept it out (`[solver] self_contact` off, or the linear tier, which does not carry it).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SkinOverlap {
    /// How many vertices.
    pub vertices: usize,
    /// How many per part of the hand (the part of the bone leading the vertex's heaviest
    /// node); parts with none left out.
    pub parts: BTreeMap<String, usize>,
    /// The contact skin's vertices inside another hand's flesh, by that hand's name (hands
    /// with none left out): the solver's contact is between a hand and the other bodies, not
    /// between two hands, so nothing keeps two hands out of each other.
    pub other_hands: BTreeMap<String, usize>,
}

/// For each hand of `frame` (by body), how many of its contact skin's vertices lie inside each
/// other hand's closed contact skin (by winding number; name → count, none left out).
fn inside_other_hands(model: &Model, frame: &Frame) -> Vec<BTreeMap<String, usize>> {
    use crate::contact::WindingTree;
    let mut out = vec![BTreeMap::new(); frame.hands.len()];
    if frame.hands.len() < 2 {
        return out;
    }
    // Each hand's contact skin where the frame has it, and its triangles.
    type Skin<'a> = Option<(Vec<Vector3<f64>>, &'a [[usize; 3]])>;
    let skins: Vec<Skin> = frame
        .hands
        .iter()
        .map(|h| {
            let body = &model.bodies[h.body];
            let (hand, check) = (body.hand.as_deref()?, body.skin_overlap.as_ref()?);
            Some((hand.contact_skin.positions(&h.positions), check.triangles()))
        })
        .collect();
    for (b, skin) in skins.iter().enumerate() {
        let Some((positions, triangles)) = skin else {
            continue;
        };
        let tree = WindingTree::new(triangles, positions);
        let name = &model.bodies[frame.hands[b].body].name;
        for (a, other) in skins.iter().enumerate() {
            let Some((points, _)) = other.as_ref().filter(|_| a != b) else {
                continue;
            };
            let inside = points.iter().filter(|x| tree.inside(x)).count();
            if inside > 0 {
                out[a].insert(name.clone(), inside);
            }
        }
    }
    out
}

/// The skin overlap of `hand` with its flesh's nodes at `nodes`, by `check`, counted per part.
pub fn skin_overlap(
    hand: &crate::hand::HandModel,
    nodes: &[Vector3<f64>],
    check: &crate::model::SkinOverlapCheck,
) -> SkinOverlap {
    use crate::state::outcome::{part_of_skin_vertex, PARTS};
    let inside = check.overlap(hand, nodes);
    let mut parts = BTreeMap::new();
    for &v in &inside {
        *parts
            .entry(PARTS[part_of_skin_vertex(hand, v)].to_string())
            .or_default() += 1;
    }
    SkinOverlap {
        vertices: inside.len(),
        parts,
        other_hands: BTreeMap::new(),
    }
}

/// A force on one part of a hand (its contact, or its bones' reactions).
#[derive(Clone, Debug, Serialize)]
pub struct PartContact {
    /// Force, N.
    pub force: [f64; 3],
    /// Its magnitude, N.
    pub magnitude: f64,
}

/// `by_bone` summed over each part of the hand (palm, thumb … little), named; parts with no
/// force left out unless `all`.
fn per_part(
    hand: &crate::hand::HandModel,
    by_bone: &[Vector3<f64>],
    all: bool,
) -> BTreeMap<String, PartContact> {
    let mut parts = vec![Vector3::zeros(); crate::state::outcome::PARTS.len()];
    for (b, f) in by_bone.iter().enumerate() {
        parts[crate::state::outcome::part_of_bone(hand, b)] += f;
    }
    crate::state::outcome::PARTS
        .iter()
        .zip(parts)
        .filter(|(_, f)| all || f.norm() > 0.0)
        .map(|(name, f)| {
            (
                name.to_string(),
                PartContact {
                    force: arr(f),
                    magnitude: f.norm(),
                },
            )
        })
        .collect()
}

/// The report entries of the hands of a frame.
pub fn hand_reports(model: &Model, frame: &Frame) -> BTreeMap<String, HandReport> {
    let mut other_hands = inside_other_hands(model, frame).into_iter();
    frame
        .hands
        .iter()
        .map(|h| {
            let other_hands = other_hands.next().unwrap_or_default();
            let body = &model.bodies[h.body];
            let hand = body
                .hand
                .as_deref()
                .expect("a hand frame belongs to a hand");
            let skeleton = &hand.skeleton;
            let mut counts = vec![0; skeleton.bones.len()];
            for b in hand.flesh.node_bone.iter().flatten() {
                counts[*b] += 1;
            }
            let bones = skeleton
                .bones
                .iter()
                .enumerate()
                .map(|(b, bone)| {
                    let r = h.bone_reactions[b];
                    (
                        bone.name.clone(),
                        BoneReport {
                            reaction: arr(r),
                            magnitude: r.norm(),
                            nodes: counts[b],
                        },
                    )
                })
                .collect();
            (
                body.name.clone(),
                HandReport {
                    pose: skeleton.pose_of(&h.angles),
                    bones,
                    bone_reaction_sum: arr(h.bone_reactions.iter().sum()),
                    part_reactions: per_part(hand, &h.bone_reactions, true),
                    flesh_volume: h.volume,
                    volume_change: h.volume / body.volume - 1.0,
                    motion: h.stats.clone(),
                    contact: per_part(hand, &h.contact_force, false),
                    realisable: h.overloads.is_empty(),
                    overloads: h.overloads.clone(),
                    grasp: h.grasp.clone(),
                    skin_overlap: SkinOverlap {
                        other_hands,
                        ..body
                            .skin_overlap
                            .as_ref()
                            .map(|c| skin_overlap(hand, &h.positions, c))
                            .unwrap_or_default()
                    },
                    self_contact: self_contact_report(model, h),
                    crushed_flesh: crate::state::crushed_flesh(hand, &h.positions),
                    pressed_inside_out: crate::state::pressed_inside_out(
                        hand,
                        &h.positions,
                        &h.contact_displacement,
                    ),
                },
            )
        })
        .collect()
}

fn arr(v: Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Builds the report entry of a solved frame.
pub fn frame_report(model: &Model, frame: &Frame, index: usize, time: f64) -> FrameReport {
    let sol = &frame.solution;
    let dof_vec = |dofs: &[usize], values: &[f64]| {
        let mut v = Vector3::zeros();
        for &d in dofs {
            v[d % 3] += values[d];
        }
        v
    };
    let constraints = model
        .constraints
        .iter()
        .map(|c| {
            (
                c.name.clone(),
                ConstraintReport {
                    reaction: arr(dof_vec(&c.dofs, &sol.reaction)),
                    dofs: c.dofs.len(),
                },
            )
        })
        .collect();
    let probes = model
        .probes
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                ProbeReport {
                    node: p.node,
                    position: arr(model.mesh.nodes[p.node]),
                    displacement: arr(sol.node_displacement(p.node)),
                },
            )
        })
        .collect();
    let applied: Vector3<f64> =
        model.loads.iter().map(|l| l.total).sum::<Vector3<f64>>() + model.gravity_total;
    let all: Vec<usize> = (0..sol.reaction.len()).collect();
    let mut reactions = dof_vec(&all, &sol.reaction);
    if let Some(c) = &frame.contact {
        // The obstacles' contact forces act like supports.
        for p in c.contacts.iter().filter(|p| p.obstacle().is_some()) {
            reactions += p.force_vector();
        }
    }
    let max_displacement = (0..model.mesh.node_count())
        .map(|n| sol.node_displacement(n).norm())
        .fold(0.0, f64::max);
    let max_von_mises = frame.stress.nodal.iter().map(von_mises).fold(0.0, f64::max);
    FrameReport {
        frame: index,
        time,
        constraints,
        probes,
        loads: model
            .loads
            .iter()
            .map(|l| (l.name.clone(), arr(l.total)))
            .collect(),
        gravity: arr(model.gravity_total),
        equilibrium: Equilibrium {
            applied: arr(applied),
            reactions: arr(reactions),
            imbalance: arr(applied + reactions),
        },
        max_displacement,
        max_von_mises,
        solver: SolverReport {
            residual: sol.stats.relative_residual,
            symbolic_reused: sol.stats.symbolic_reused,
            free_dofs: sol.stats.free_dofs,
            prescribed_dofs: sol.stats.prescribed_dofs,
            matrix_nnz: sol.stats.matrix_nnz,
            factor_nnz: sol.stats.factor_nnz,
            timings_ms: Timings {
                assembly: frame.assembly_ms,
                symbolic: sol.stats.symbolic_ms,
                factorization: sol.stats.factorization_ms,
                solve: sol.stats.solve_ms,
                stress: frame.stress_ms,
            },
        },
        hands: hand_reports(model, frame),
        contact: contact_report(model, frame),
        cavity: crate::state::cavity_state(model, frame),
    }
}

/// Summary of the model.
pub fn model_summary(model: &Model) -> ModelSummary {
    ModelSummary {
        nodes: model.mesh.node_count(),
        elements: model.mesh.cell_count(),
        dofs: 3 * model.mesh.node_count(),
        bodies: model
            .bodies
            .iter()
            .map(|b| BodySummary {
                name: b.name.clone(),
                nodes: b.nodes.len(),
                elements: b.cells.len(),
                volume: b.volume,
                mass: b.mass,
            })
            .collect(),
    }
}
