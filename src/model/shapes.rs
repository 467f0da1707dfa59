//! The mesh of a body's shape (box, sphere, shell or given mesh), after checking its parameters.

use super::check::finite;
use crate::mesh::{box_mesh, shell_mesh, sphere_mesh, Mesh};
use crate::scene::Shape;
use nalgebra::Vector3;

/// Generates the mesh of a shape after checking its parameters.
pub fn build_shape(shape: &Shape) -> Result<Mesh, String> {
    const MAX_CELLS: usize = 5_000_000;
    match shape {
        Shape::Hand { .. } => Err("a hand is built by the hand module".into()),
        Shape::Mesh { nodes, cells } => {
            if nodes.is_empty() || cells.is_empty() {
                return Err("mesh needs at least one node and one cell".into());
            }
            if let Some(i) = nodes.iter().position(|p| !finite(p)) {
                return Err(format!("mesh node {i} is not a finite point"));
            }
            for (c, cell) in cells.iter().enumerate() {
                if let Some(&n) = cell.iter().find(|&&n| n >= nodes.len()) {
                    return Err(format!(
                        "mesh element {c} names node {n}, but there are {} nodes",
                        nodes.len()
                    ));
                }
            }
            Ok(Mesh {
                nodes: nodes.iter().map(|p| Vector3::from(*p)).collect(),
                cells: cells.clone(),
            })
        }
        Shape::Box { min, max, cells } => {
            if !finite(min) || !finite(max) {
                return Err("box min and max must be finite".into());
            }
            if (0..3).any(|i| max[i] <= min[i]) {
                return Err(format!(
                    "box max {max:?} must exceed min {min:?} on every axis"
                ));
            }
            if cells.contains(&0) {
                return Err(format!("box cells {cells:?} must all be at least 1"));
            }
            if cells.iter().product::<usize>() > MAX_CELLS {
                return Err(format!(
                    "box cells {cells:?} make more than {MAX_CELLS} elements"
                ));
            }
            Ok(box_mesh(Vector3::from(*min), Vector3::from(*max), *cells))
        }
        Shape::Sphere {
            center,
            radius,
            cells,
        } => {
            if !(finite(center) && radius.is_finite() && *radius > 0.0) {
                return Err(format!(
                    "sphere needs a finite center and a radius > 0 (radius = {radius})"
                ));
            }
            if *cells == 0 || cells.pow(3) > MAX_CELLS {
                return Err(format!(
                    "sphere cells = {cells} must be at least 1 and at most 170"
                ));
            }
            Ok(sphere_mesh(Vector3::from(*center), *radius, *cells))
        }
        Shape::Shell {
            center,
            inner_radius,
            outer_radius,
            cells,
            layers,
        } => {
            if !(finite(center) && inner_radius.is_finite() && *inner_radius > 0.0) {
                return Err(format!(
                    "shell needs a finite center and inner_radius > 0 (inner_radius = {inner_radius})"
                ));
            }
            if !(outer_radius.is_finite() && outer_radius > inner_radius) {
                return Err(format!(
                    "shell outer_radius = {outer_radius} must exceed inner_radius = {inner_radius}"
                ));
            }
            if *cells == 0 || *layers == 0 || 6 * cells * cells * layers > MAX_CELLS {
                return Err(format!(
                    "shell cells = {cells} and layers = {layers} must be at least 1 (and make at \
                     most {MAX_CELLS} elements)"
                ));
            }
            Ok(shell_mesh(
                Vector3::from(*center),
                *inner_radius,
                *outer_radius,
                *cells,
                *layers,
            ))
        }
    }
}
