//! The finite-value gate: every number of a solved frame that reaches a file or the screen is
//! checked finite first. A value that overflowed (a load of 1e160 N, a Young's modulus of
//! 1e-300 Pa) stops the solve with the quantity, the body and the node, element or bone named.

use super::Frame;
use crate::model::Model;
use nalgebra::{Matrix3, Vector3};

/// The first non-finite value of a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct NonFinite {
    /// What it is, e.g. `displacement`, `von Mises stress`, `bone reaction`.
    pub quantity: &'static str,
    /// The body it belongs to.
    pub body: String,
    /// Where in the body: `node 12`, `element 4`, `bone "index.distal"` (numbered within the
    /// body).
    pub at: String,
    /// The value (inf, -inf or NaN).
    pub value: f64,
}

/// The first value of `frame` that is not finite, if any.
pub fn first_non_finite(model: &Model, frame: &Frame) -> Option<NonFinite> {
    let node_owner = |global: usize| {
        model
            .bodies
            .iter()
            .find(|b| b.nodes.contains(&global))
            .map_or((String::new(), global), |b| {
                (b.name.clone(), global - b.nodes.start)
            })
    };
    let at_node = |quantity: &'static str, global: usize, value: f64| {
        let (body, n) = node_owner(global);
        NonFinite {
            quantity,
            body,
            at: format!("node {n}"),
            value,
        }
    };
    let bad_vec = |v: &Vector3<f64>| v.iter().copied().find(|x| !x.is_finite());
    let bad_mat = |m: &Matrix3<f64>| m.iter().copied().find(|x| !x.is_finite());

    let u = &frame.solution.displacement;
    if let Some(i) = u.iter().position(|x| !x.is_finite()) {
        return Some(at_node("displacement", i / 3, u[i]));
    }
    let r = &frame.solution.reaction;
    if let Some(i) = r.iter().position(|x| !x.is_finite()) {
        return Some(at_node("support reaction", i / 3, r[i]));
    }
    let s = &frame.stress;
    if let Some(c) = s.cell_von_mises.iter().position(|x| !x.is_finite()) {
        let b = &model.bodies[model.cell_body[c]];
        return Some(NonFinite {
            quantity: "von Mises stress",
            body: b.name.clone(),
            at: format!("element {}", c - b.cells.start),
            value: s.cell_von_mises[c],
        });
    }
    for (n, m) in s.nodal.iter().enumerate() {
        if let Some(x) = bad_mat(m) {
            return Some(at_node("stress", n, x));
        }
    }
    for hand in &frame.hands {
        let body = &model.bodies[hand.body];
        let local = |quantity: &'static str, n: usize, value: f64| NonFinite {
            quantity,
            body: body.name.clone(),
            at: format!("node {n}"),
            value,
        };
        for (quantity, field) in [
            ("flesh position", &hand.positions),
            ("flesh reaction", &hand.reaction),
            ("contact displacement", &hand.contact_displacement),
            ("contact reaction", &hand.contact_reaction),
        ] {
            for (n, v) in field.iter().enumerate() {
                if let Some(x) = bad_vec(v) {
                    return Some(local(quantity, n, x));
                }
            }
        }
        let bone_name = |i: usize| {
            body.hand
                .as_ref()
                .and_then(|h| h.skeleton.bones.get(i))
                .map_or(format!("bone {i}"), |b| format!("bone \"{}\"", b.name))
        };
        for (quantity, field) in [
            ("bone reaction", &hand.bone_reactions),
            ("contact force on a bone", &hand.contact_force),
        ] {
            for (i, v) in field.iter().enumerate() {
                if let Some(x) = bad_vec(v) {
                    return Some(NonFinite {
                        quantity,
                        body: body.name.clone(),
                        at: bone_name(i),
                        value: x,
                    });
                }
            }
        }
        if let Some(x) = hand.angles.iter().copied().find(|x| !x.is_finite()) {
            return Some(NonFinite {
                quantity: "joint angle",
                body: body.name.clone(),
                at: "its skeleton".into(),
                value: x,
            });
        }
        if !hand.volume.is_finite() {
            return Some(NonFinite {
                quantity: "flesh volume",
                body: body.name.clone(),
                at: "the whole hand".into(),
                value: hand.volume,
            });
        }
    }
    if let Some(contact) = &frame.contact {
        for p in &contact.contacts {
            let values = [p.force, p.gap]
                .into_iter()
                .chain(p.normal.iter().copied())
                .chain(p.tangential.iter().copied());
            for x in values {
                if !x.is_finite() {
                    return Some(at_node("contact force", p.node, x));
                }
            }
        }
    }
    None
}
