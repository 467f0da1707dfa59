//! Loads: pressures (a gas cavity's too), tractions and point forces on the bodies, and
//! gravity.

use super::bodies::find_body;
use super::check::finite;
use super::gas::{GasCavity, STANDARD_AMBIENT};
use super::names::shown;
use super::select::select;
use super::{BodyModel, LoadModel};
use crate::fem::loads::{add_gravity, add_pressure, add_shared_force, add_traction};
use crate::fem::Material;
use crate::mesh::{Facet, Mesh};
use crate::scene::{LoadDef, Scene};
use nalgebra::Vector3;

/// Adds the scene's `[[load]]`s to the load vector (a gas cavity's at its rest pressure); returns
/// them and the gas cavity, if a load is one.
pub fn loads(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
    load_vector: &mut [f64],
) -> Result<(Vec<LoadModel>, Option<GasCavity>), (String, String)> {
    let mut loads = Vec::new();
    let mut cavity: Option<GasCavity> = None;
    for (i, l) in scene.load.iter().enumerate() {
        let name = l.name.clone().unwrap_or_else(|| format!("load[{i}]"));
        let field = format!("load \"{}\" (load[{i}])", shown(&name));
        if l.name.is_some() {
            super::names::named("load", &name).map_err(|m| (field.clone(), m))?;
        }
        // The report lists the loads by name (`frames[].loads`): a second of one name hid the
        // first. (An unnamed load is `load[i]` there.)
        if let Some(j) = loads.iter().position(|o: &LoadModel| o.name == name) {
            return Err((
                field,
                format!("a load of this name is defined twice (load[{j}] has it)"),
            ));
        }
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
        if l.gas || l.ambient.is_some() {
            if let Some(previous) = &cavity {
                return Err((
                    format!("{field}.gas"),
                    format!(
                        "one gas cavity per scene is supported, and load \"{}\" is one already",
                        shown(&previous.name)
                    ),
                ));
            }
            cavity = Some(gas_cavity(l, &field, &name, b, mesh, sel.facets.clone())?);
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
            pressure: l.pressure.map(|p| (p, sel.facets.clone())),
        });
    }
    Ok((loads, cavity))
}

/// The gas cavity of a load with `gas = true` (or `ambient`), checked.
fn gas_cavity(
    l: &LoadDef,
    field: &str,
    name: &str,
    body: usize,
    mesh: &Mesh,
    facets: Vec<Facet>,
) -> Result<GasCavity, (String, String)> {
    if !l.gas {
        return Err((
            format!("{field}.ambient"),
            "applies to a gas cavity only: remove `ambient`, or, where the load's surface \
             encloses a cavity (surface = \"inner\" of a shell), add `gas = true`"
                .into(),
        ));
    }
    let Some(gauge) = l.pressure else {
        return Err((
            format!("{field}.gas"),
            "a gas cavity needs `pressure` (its gauge pressure at rest, Pa), not `traction` or \
             `force`"
                .into(),
        ));
    };
    let ambient = l.ambient.unwrap_or(STANDARD_AMBIENT);
    if !(ambient.is_finite() && ambient > 0.0) {
        return Err((
            format!("{field}.ambient"),
            format!("must be a finite absolute pressure > 0 Pa (ambient = {ambient})"),
        ));
    }
    if gauge + ambient <= 0.0 {
        return Err((
            format!("{field}.pressure"),
            format!(
                "the gas's absolute pressure at rest, pressure + ambient = {gauge} + {ambient} \
                 Pa, must be > 0 (`pressure` is the gauge pressure, above ambient)"
            ),
        ));
    }
    GasCavity::new(name.to_string(), body, mesh, facets, gauge, ambient)
        .map_err(|msg| (format!("{field}.where"), msg))
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
