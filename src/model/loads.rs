//! Loads: pressures, tractions and point forces on the bodies, and gravity.

use super::bodies::find_body;
use super::check::finite;
use super::select::select;
use super::{BodyModel, LoadModel};
use crate::fem::loads::{add_gravity, add_pressure, add_shared_force, add_traction};
use crate::fem::Material;
use crate::mesh::Mesh;
use crate::scene::Scene;
use nalgebra::Vector3;

/// Adds the scene's `[[load]]`s to the load vector.
pub fn loads(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
    load_vector: &mut [f64],
) -> Result<Vec<LoadModel>, (String, String)> {
    let mut loads = Vec::new();
    for (i, l) in scene.load.iter().enumerate() {
        let name = l.name.clone().unwrap_or_else(|| format!("load[{i}]"));
        let field = format!("load \"{name}\" (load[{i}])");
        let b = find_body(bodies, &l.body, format!("{field}.body"))?;
        if bodies[b].hand.is_some() {
            return Err((
                format!("{field}.body"),
                "loads on a hand are not supported: the hand is driven by its skeleton".into(),
            ));
        }
        let sel = select(&bodies[b], mesh, &l.selection)
            .map_err(|msg| (format!("{field}.where"), msg))?;
        let kinds = [
            l.pressure.is_some(),
            l.traction.is_some(),
            l.force.is_some(),
        ];
        if kinds.iter().filter(|&&k| k).count() != 1 {
            return Err((
                field,
                "give exactly one of `pressure` (Pa), `traction` ([tx, ty, tz] Pa) and \
                 `force` ([fx, fy, fz] N)"
                    .into(),
            ));
        }
        let values: Vec<f64> = l
            .pressure
            .into_iter()
            .chain(l.traction.into_iter().flatten())
            .chain(l.force.into_iter().flatten())
            .collect();
        if !finite(&values) {
            return Err((field, "holds a value that is not a finite number".into()));
        }
        if l.force.is_none() && sel.facets.is_empty() {
            return Err((
                format!("{field}.where"),
                "selects no boundary facet, and a pressure or traction acts on facets (use \
                 a face, a surface or a box)"
                    .into(),
            ));
        }
        let total = if let Some(p) = l.pressure {
            add_pressure(load_vector, mesh, &sel.facets, p)
        } else if let Some(t) = l.traction {
            add_traction(load_vector, mesh, &sel.facets, &Vector3::from(t))
        } else {
            let f = Vector3::from(l.force.unwrap());
            add_shared_force(load_vector, &sel.nodes, &f);
            f
        };
        loads.push(LoadModel {
            name,
            body: b,
            total,
        });
    }
    Ok(loads)
}

/// Adds the weight of the bodies other than hands (`[world] gravity`) to the load vector;
/// returns the total gravity force.
pub fn gravity(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
    cell_materials: &[Material],
    load_vector: &mut [f64],
) -> Result<Vector3<f64>, (String, String)> {
    let mut gravity_total = Vector3::zeros();
    if let Some(g) = scene.world.gravity {
        if !finite(&g) {
            return Err(("world.gravity".into(), "is not a finite vector".into()));
        }
        // The weight of a hand's flesh (a few newtons at most, held by its bones) is not
        // modelled: the hand moves by its skeleton.
        for body in bodies.iter().filter(|b| b.hand.is_none()) {
            gravity_total += add_gravity(
                load_vector,
                mesh,
                cell_materials,
                body.cells.clone(),
                &Vector3::from(g),
            )
            .map_err(|e| {
                (
                    "world.gravity".into(),
                    format!("element {} is inverted", e.cell),
                )
            })?;
        }
    }
    Ok(gravity_total)
}
