//! `Model::build`: from a scene to meshes, materials, prescribed dofs and the load vector, one
//! step per file in order. Everything here is fixed for a frame; the solve produces the state.

use super::bodies::{bodies, node_cells, set_masses, Bodies};
use super::cameras::cameras;
use super::constraints::{constraints, hold_hands, Prescribed};
use super::input_warnings::input_warnings;
use super::keyframes::keyframes;
use super::loads::{gravity, loads};
use super::materials::materials;
use super::obstacles::{contact_candidates, obstacles};
use super::probes::probes;
use super::regions::apply_regions;
use super::settings::{contact_settings, flexion_settings, friction_table, max_memory, ordering};
use super::supports::floating_bodies;
use super::Model;
use crate::fem::assembly::StiffnessPattern;
use crate::fem::ElementKind;
use crate::fem::{DofPartition, Material};
use crate::scene::{Scene, SceneError};
use nalgebra::Vector3;
use std::sync::Arc;

impl Model {
    /// Builds the model; `file` names the scene in errors.
    pub fn build(scene: &Scene, file: &str) -> Result<Model, SceneError> {
        let err = |(field, message): (String, String)| SceneError::invalid(file, field, message);

        let materials = materials(scene).map_err(err)?;
        let max_memory = max_memory(&scene.solver).map_err(err)?;
        let nonlinear_statics = scene.solver.tier == Some(crate::scene::TierName::Nonlinear);
        let Bodies {
            mesh,
            mut bodies,
            mut cell_material,
            cell_body,
        } = bodies(
            scene,
            (max_memory, nonlinear_statics),
            std::path::Path::new(file)
                .parent()
                .unwrap_or(std::path::Path::new("")),
        )
        .map_err(err)?;
        apply_regions(scene, &bodies, &mesh, &mut cell_material).map_err(err)?;
        let cell_materials: Vec<Material> = cell_material.iter().map(|&m| materials[m]).collect();

        let Prescribed {
            constraints,
            mut mask,
            values: prescribed,
        } = constraints(scene, &bodies, &mesh).map_err(err)?;
        hold_hands(&bodies, &mut mask);

        let mut load_vector = vec![0.0; 3 * mesh.node_count()];
        let (loads, gas) = loads(scene, &bodies, &mesh, &mut load_vector).map_err(err)?;
        let gravity_total =
            gravity(scene, &bodies, &mesh, &cell_materials, &mut load_vector).map_err(err)?;
        let probes = probes(scene, &bodies, &mesh).map_err(err)?;

        for b in floating_bodies(scene, &bodies, &mesh, &mask).map_err(err)? {
            bodies[b].floating = true;
        }
        let mut flexion = flexion_settings(&scene.solver).map_err(err)?;
        // The masses before the keyframes: a grasp holds its object's weight.
        set_masses(&mut bodies, &mesh, &cell_materials);
        let keyframes = keyframes(scene, &bodies).map_err(err)?;
        let cameras = cameras(scene).map_err(err)?;

        let obstacles = obstacles(scene).map_err(err)?;
        let contact_candidates = contact_candidates(&bodies);
        let largest = bodies.iter().map(|b| b.size).fold(0.0, f64::max);
        let smallest = (bodies.len() > 1)
            .then(|| {
                bodies
                    .iter()
                    .min_by(|a, b| a.size.total_cmp(&b.size))
                    .map(|b| (b.name.as_str(), b.size))
            })
            .flatten();
        let contact = contact_settings(&scene.solver, largest, smallest).map_err(err)?;
        // Experimental, off unless asked for (docs/hand.md, "Self-contact").
        flexion.self_contact = match scene.solver.self_contact {
            Some(true) => Some(contact),
            _ => None,
        };
        let contact_region = scene.solver.contact_region.unwrap_or(0.008);
        if !(contact_region.is_finite() && contact_region > 0.0) {
            return Err(err((
                "solver.contact_region".into(),
                format!("must be a length > 0 m, got {contact_region}"),
            )));
        }
        let friction = friction_table(scene).map_err(err)?;
        let node_cell = node_cells(&mesh);
        let ordering = ordering(&scene.solver);
        let element: ElementKind = scene.solver.element.unwrap_or_default().into();
        let input_warnings = input_warnings(
            scene,
            &bodies,
            &mesh,
            &cell_materials,
            element,
            nonlinear_statics,
        );
        let pattern = Arc::new(StiffnessPattern::new(&mesh));
        Ok(Model {
            mesh,
            bodies,
            material_names: scene.material.iter().map(|m| m.name.clone()).collect(),
            cell_material,
            cell_materials,
            cell_body,
            constraints,
            loads,
            gas,
            gravity_total,
            gravity: scene.world.gravity.map(Vector3::from),
            probes,
            partition: DofPartition::new(mask),
            prescribed,
            load_vector,
            pattern,
            ordering,
            flexion,
            keyframes,
            cameras,
            obstacles,
            contact_candidates,
            contact,
            contact_region,
            friction,
            node_cell,
            element,
            nonlinear_statics,
            max_memory,
            input_warnings,
        })
    }
}
