//! What a hand's grip does to an object in a solved frame: its contacts on the object as a rigid
//! body sees them, the sum of their normal forces, and the friction margin with which they hold
//! it against a load (`contact::hold_margin`); and the outcome of a grasp keyframe.

use super::Frame;
use crate::contact::{hold_margin, GripContact, Master};
use crate::model::Model;
use nalgebra::Vector3;
use std::collections::BTreeMap;

/// The outcome of a grasp keyframe (`hands.<hand>.grasp` in report.json).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GraspOutcome {
    /// The body grasped.
    pub object: String,
    /// The preshape the digits closed from.
    pub preshape: String,
    /// Whether the grip found holds the object as asked.
    pub held: bool,
    /// The joint angles found, degrees (save them as an ordinary keyframe's `pose`).
    pub pose: BTreeMap<String, f64>,
    /// The joint angles of the preshape the closing started from, degrees: with `pose`, the
    /// closing as two ordinary keyframes (the viewer adds them to its timeline).
    pub preshape_pose: BTreeMap<String, f64>,
    /// The friction margin achieved: the friction the contacts have over what holding the
    /// object against its weight needs (0: no friction holds it; capped at 1e6: the normal
    /// forces alone hold it).
    pub margin: f64,
    /// The margin asked for (a gravity hold).
    pub margin_target: Option<f64>,
    /// The sum of the hand's normal contact forces on the object, N.
    pub grip: f64,
    /// The grip force asked for, N (a force hold).
    pub force_target: Option<f64>,
    /// How far the touching digits closed past their first contact, degrees of each synergy's
    /// largest joint (negative: short of it, back towards the preshape).
    pub closing_deg: f64,
    /// The hand's normal force on the object in the preshape, before any closing, N: more than
    /// zero where the preshape is posed into the object.
    pub preshape_grip: f64,
    /// A gravity hold: how far the object's centre moved when let go of (its supports freed,
    /// held by the hand alone), m; `None` when that solve found nothing holding it, and for a
    /// force hold.
    pub drift: Option<f64>,
    /// The digits that touch the object in the pose found.
    pub digits_touching: Vec<String>,
    /// Poses solved by FEM in the search.
    pub trials: usize,
    /// Each pose solved, in the order of the search: its closing past first contact
    /// (degrees), grip (N) and margin.
    pub search: Vec<GripTrial>,
    /// Why the grip does not hold (when `held` is false).
    pub reason: Option<String>,
    /// The digits closed along their synergies to the grip (`false`: the pose was judged as
    /// posed, `close = false`).
    pub closed: bool,
}

/// One pose of a grasp's search.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct GripTrial {
    /// Closing past first contact, degrees.
    pub closing_deg: f64,
    /// The sum of the normal forces on the object, N.
    pub grip: f64,
    /// The friction margin against its weight (0 for a force hold).
    pub margin: f64,
    /// Every bone's reaction within its threshold (`bone_thresholds`): a pose the search may
    /// show.
    pub within_thresholds: bool,
}

/// A hand's grip on an object in a frame.
#[derive(Clone, Debug)]
pub struct Grip {
    /// Its contacts, as the object feels them.
    pub contacts: Vec<GripContact>,
    /// The sum of their normal forces, N.
    pub normal_force: f64,
    /// The object's centre of mass where the frame leaves it, m.
    pub centre: Vector3<f64>,
}

impl Grip {
    /// The friction margin with which the grip holds the object against `load` (N).
    pub fn margin(&self, load: &Vector3<f64>, size: f64) -> f64 {
        hold_margin(&self.contacts, &self.centre, load, size).margin
    }
}

/// Hand body `hand`'s grip on body `object` in `frame`, with the Coulomb friction of `model`
/// between their materials.
pub fn grip(model: &Model, frame: &Frame, hand: usize, object: usize) -> Grip {
    let u = &frame.solution.displacement;
    let at = |n: usize| model.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
    let (hands, objects) = (&model.bodies[hand].nodes, &model.bodies[object].nodes);
    // μ of a contact between the materials of its nodes' cells, as the contact solve takes it.
    let material = |n: usize| model.material_name(model.cell_material[model.node_cell[n]]);
    let mut contacts = Vec::new();
    if let Some(result) = &frame.contact {
        for c in &result.contacts {
            let on_object = |n: &usize| objects.contains(n);
            let slave_is_object = c.terms[..c.slave_terms].iter().any(|t| on_object(&t.0));
            let master_is_object = matches!(c.master, Master::Facet { body, .. } if body == object);
            let touches_hand = c.terms.iter().any(|t| hands.contains(&t.0));
            if !(touches_hand && (slave_is_object || master_is_object)) {
                continue;
            }
            // The force on the slave is along the master's outward normal: on the object as
            // the slave that pushes it in; on the object as the master, it feels the reverse.
            let inward = if slave_is_object { c.normal } else { -c.normal };
            let (mut point, mut weight) = (Vector3::zeros(), 0.0);
            for &(n, w) in &c.terms {
                if on_object(&n) {
                    point += at(n) * w.abs();
                    weight += w.abs();
                }
            }
            let node_of = |on: &dyn Fn(usize) -> bool| c.terms.iter().map(|t| t.0).find(|&n| on(n));
            let (ours, theirs) = (
                node_of(&|n| hands.contains(&n)),
                node_of(&|n| objects.contains(&n)),
            );
            if let (true, true, Some(a), Some(b)) = (weight > 0.0, c.force > 0.0, ours, theirs) {
                contacts.push(GripContact {
                    point: point / weight,
                    inward,
                    normal_force: c.force,
                    friction: model.friction_between(material(a), material(b)),
                });
            }
        }
    }
    // (+ 0: an empty sum is −0.)
    let normal_force = contacts.iter().map(|c| c.normal_force).sum::<f64>() + 0.0;
    Grip {
        contacts,
        normal_force,
        centre: mass_centre(model, frame, object),
    }
}

/// The centre of mass of body `b` where `frame` leaves it, m: its cells' centres where they are
/// now, weighted by their mass at rest.
pub fn mass_centre(model: &Model, frame: &Frame, b: usize) -> Vector3<f64> {
    let u = &frame.solution.displacement;
    let (mut sum, mut mass) = (Vector3::zeros(), 0.0);
    for c in model.bodies[b].cells.clone() {
        let nodes = &model.mesh.cells[c];
        let m = model.cell_materials[c].density
            * crate::fem::hex8::cell_volume(&model.mesh.cell_coords(c)).abs();
        let now = nodes
            .iter()
            .map(|&n| model.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
            .sum::<Vector3<f64>>()
            / 8.0;
        sum += now * m;
        mass += m;
    }
    if mass > 0.0 {
        sum / mass
    } else {
        model.bodies[b]
            .nodes
            .clone()
            .map(|n| model.mesh.nodes[n])
            .sum::<Vector3<f64>>()
            / model.bodies[b].nodes.len().max(1) as f64
    }
}
