//! Probes: the node of a body nearest to each probed point.

use super::bodies::find_body;
use super::check::finite;
use super::names::shown;
use super::select::select;
use super::{BodyModel, ProbeModel};
use crate::mesh::Mesh;
use crate::scene::{Scene, Selection};
use nalgebra::Vector3;

/// The scene's `[[probe]]`s.
pub fn probes(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
) -> Result<Vec<ProbeModel>, (String, String)> {
    let mut probes = Vec::new();
    for (i, p) in scene.probe.iter().enumerate() {
        let field = format!("probe \"{}\" (probe[{i}])", shown(&p.name));
        super::names::named("probe", &p.name).map_err(|m| (field.clone(), m))?;
        if probes.iter().any(|o: &ProbeModel| o.name == p.name) {
            return Err((field, "a probe of this name is defined twice".into()));
        }
        if !finite(&p.point) {
            return Err((format!("{field}.point"), "is not a finite point".into()));
        }
        let b = find_body(bodies, &p.body, format!("{field}.body"))?;
        let sel = select(&bodies[b], mesh, &Selection::Point(p.point))
            .map_err(|msg| (format!("{field}.point"), msg))?;
        probes.push(ProbeModel {
            name: p.name.clone(),
            body: b,
            point: Vector3::from(p.point),
            node: sel.nodes[0],
        });
    }
    Ok(probes)
}
