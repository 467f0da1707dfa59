//! The tactile map of a solved frame: the contact pressure at every node of the model.

use super::Frame;
use crate::contact::nodal_pressure;
use crate::model::Model;

/// Contact pressure at every node (Pa, 0 off contact), over the boundary facets of all bodies;
/// `None` when the frame has no contact.
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
