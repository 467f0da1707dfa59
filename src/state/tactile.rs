//! The tactile map of a solved frame: the contact pressure at every node of the model, and on
//! each hand's smooth skin.

use super::Frame;
use crate::contact::{nodal_pressure, Master};
use crate::model::Model;

/// Contact pressure at every node (Pa, 0 off contact), over the boundary facets of all bodies;
/// `None` when the frame has no contact. A hand's contact is on its smooth skin: its lattice
/// nodes get the share of their cells' skin points (see [`skin_pressure`] for the map on the
/// skin itself).
pub fn contact_pressure(model: &Model, frame: &Frame) -> Option<Vec<f64>> {
    let contact = frame.contact.as_ref()?;
    let facets: Vec<crate::mesh::Facet> = model
        .bodies
        .iter()
        .flat_map(|b| b.facets.iter().copied())
        .collect();
    Some(nodal_pressure(
        &model.mesh.nodes,
        &facets,
        &contact.contacts,
    ))
}

/// Contact pressure on hand `body`'s display skin (Pa at each display vertex, 0 off contact):
/// each contact skin vertex's normal contact force over the area it stands for on the display
/// skin (its bilinear share of the display vertices' areas, deformed), carried bilinearly to
/// the display skin over the control quads both skins share — so that the map drawn and
/// exported integrates over the display skin to the contact's normal force. `None` without
/// contact on this hand's skin.
pub fn skin_pressure(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    // The contact skin is the control net itself (its quads are the control quads).
    const _: () = assert!(crate::hand::CONTACT_SKIN_LEVELS == 0);
    let hand = model.bodies[body].hand.as_deref()?;
    let force = contact_skin_forces(model, frame, body)?;
    let positions = &frame.hands.iter().find(|h| h.body == body)?.positions;
    let area = hand.skin.vertex_areas(&hand.skin.positions(positions));
    let quads = &hand.contact_skin.quads;
    let share = hand.skin.to_control(&area, quads, force.len());
    let pressure = per_area(&force, &share);
    Some(
        hand.skin
            .from_control(|q, i| pressure[quads[q][i] as usize]),
    )
}

/// Contact pressure at each vertex of hand `body`'s contact skin (Pa, 0 off contact): the
/// normal contact force there (as the slave, or its share h_i as a facet corner) over the
/// vertex's quarter of the adjacent quads on the deformed skin. `None` without contact on this
/// hand's skin.
pub fn contact_skin_pressure(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    let hand = model.bodies[body].hand.as_deref()?;
    let force = contact_skin_forces(model, frame, body)?;
    let positions = &frame.hands.iter().find(|h| h.body == body)?.positions;
    let skin = &hand.contact_skin;
    let at = skin.positions(positions);
    let mut area = vec![0.0; force.len()];
    for q in &skin.quads {
        let p = q.map(|v| at[v as usize]);
        let a = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm();
        for &v in q {
            area[v as usize] += 0.25 * a;
        }
    }
    Some(per_area(&force, &area))
}

/// The normal contact force at each vertex of hand `body`'s contact skin, N: as the slave, or
/// its share h_i as a facet's corner. `None` without contact on this hand's skin.
fn contact_skin_forces(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    let contact = frame.contact.as_ref()?;
    let &(_, first) = contact.skin_points.iter().find(|s| s.0 == body)?;
    let hand = model.bodies[body].hand.as_deref()?;
    let count = hand.contact_skin.vertex_count();
    let local = |v: usize| (v >= first && v < first + count).then(|| v - first);
    let mut force = vec![0.0; count];
    for c in &contact.contacts {
        if let Some(v) = local(c.node) {
            force[v] += c.force;
        }
        if let Master::Facet { nodes, weights, .. } = c.master {
            for (&m, h) in nodes.iter().zip(weights) {
                if let Some(v) = local(m) {
                    force[v] += h * c.force;
                }
            }
        }
    }
    Some(force)
}

/// Force over area at each vertex, 0 where the area is none.
fn per_area(force: &[f64], area: &[f64]) -> Vec<f64> {
    force
        .iter()
        .zip(area)
        .map(|(f, a)| if *a > 0.0 { f / a } else { 0.0 })
        .collect()
}
