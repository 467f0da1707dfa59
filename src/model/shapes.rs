//! The mesh of a body's shape (box, sphere, shell or given mesh), after checking its parameters.

use super::check::finite;
use super::refinement::refinement;
use crate::mesh::{
    box_mesh, graded_shell_cells, graded_shell_mesh, graded_sphere_cells, graded_sphere_mesh,
    shell_mesh, sphere_mesh, Mesh,
};
use crate::scene::Shape;
use nalgebra::Vector3;

/// Generates the mesh of a shape after checking its parameters; the error is (the field under
/// the shape, empty for the shape itself, e.g. `.sphere.refine.size`; the message).
pub fn build_shape(shape: &Shape) -> Result<Mesh, (String, String)> {
    const MAX_CELLS: usize = 5_000_000;
    let whole = |m: String| (String::new(), m);
    match shape {
        Shape::Hand { .. } => Err(whole("a hand is built by the hand module".into())),
        Shape::Mesh { nodes, cells } => {
            if nodes.is_empty() || cells.is_empty() {
                return Err(whole("mesh needs at least one node and one cell".into()));
            }
            if let Some(i) = nodes.iter().position(|p| !finite(p)) {
                return Err(whole(format!("mesh node {i} is not a finite point")));
            }
            for (c, cell) in cells.iter().enumerate() {
                if let Some(&n) = cell.iter().find(|&&n| n >= nodes.len()) {
                    return Err(whole(format!(
                        "mesh element {c} names node {n}, but there are {} nodes",
                        nodes.len()
                    )));
                }
            }
            Ok(Mesh {
                nodes: nodes.iter().map(|p| Vector3::from(*p)).collect(),
                cells: cells.clone(),
            })
        }
        Shape::Box { min, max, cells } => {
            if !finite(min) || !finite(max) {
                return Err(whole("box min and max must be finite".into()));
            }
            if (0..3).any(|i| max[i] <= min[i]) {
                return Err(whole(format!(
                    "box max {max:?} must exceed min {min:?} on every axis"
                )));
            }
            if cells.contains(&0) {
                return Err(whole(format!("box cells {cells:?} must all be at least 1")));
            }
            let count = cells.iter().try_fold(1usize, |n, &c| n.checked_mul(c));
            if count.is_none_or(|n| n > MAX_CELLS) {
                return Err((
                    ".box.cells".into(),
                    format!("box cells {cells:?} make more than {MAX_CELLS} elements"),
                ));
            }
            Ok(box_mesh(Vector3::from(*min), Vector3::from(*max), *cells))
        }
        Shape::Sphere {
            center,
            radius,
            cells,
            refine,
        } => {
            if !(finite(center) && radius.is_finite() && *radius > 0.0) {
                return Err(whole(format!(
                    "sphere needs a finite center and a radius > 0 (radius = {radius})"
                )));
            }
            if *cells == 0 || cells.checked_pow(3).is_none_or(|n| n > MAX_CELLS) {
                return Err((
                    ".sphere.cells".into(),
                    format!("sphere cells = {cells} must be at least 1 and at most 170"),
                ));
            }
            match refine {
                None => Ok(sphere_mesh(Vector3::from(*center), *radius, *cells)),
                Some(refine) => {
                    let (refine, _) = refinement(refine, center, (0.0, *radius))
                        .map_err(|(f, m)| (format!(".sphere.refine.{f}"), m))?;
                    let count = graded_sphere_cells(*radius, *cells, &refine);
                    if count.is_none_or(|n| n > MAX_CELLS) {
                        return Err((
                            ".sphere.refine.size".into(),
                            format!(
                                "cells = {cells} refined to size = {} m make more than \
                                 {MAX_CELLS} elements (about {}): a larger size or fewer cells",
                                refine.size,
                                count.map_or("more than 2^64".into(), |n| n.to_string())
                            ),
                        ));
                    }
                    Ok(graded_sphere_mesh(
                        Vector3::from(*center),
                        *radius,
                        *cells,
                        &refine,
                    ))
                }
            }
        }
        Shape::Shell {
            center,
            inner_radius,
            outer_radius,
            cells,
            layers,
            refine,
        } => {
            if !(finite(center) && inner_radius.is_finite() && *inner_radius > 0.0) {
                return Err(whole(format!(
                    "shell needs a finite center and inner_radius > 0 (inner_radius = {inner_radius})"
                )));
            }
            if !(outer_radius.is_finite() && outer_radius > inner_radius) {
                return Err(whole(format!(
                    "shell outer_radius = {outer_radius} must exceed inner_radius = {inner_radius}"
                )));
            }
            let count = cells
                .checked_mul(*cells)
                .and_then(|n| n.checked_mul(*layers))
                .and_then(|n| n.checked_mul(6));
            if *cells == 0 || *layers == 0 || count.is_none_or(|n| n > MAX_CELLS) {
                return Err((
                    ".shell.cells".into(),
                    format!(
                        "shell cells = {cells} and layers = {layers} must be at least 1 (and make \
                         at most {MAX_CELLS} elements)"
                    ),
                ));
            }
            let center = Vector3::from(*center);
            match refine {
                None => Ok(shell_mesh(
                    center,
                    *inner_radius,
                    *outer_radius,
                    *cells,
                    *layers,
                )),
                Some(refine) => {
                    let (refine, outer) =
                        refinement(refine, &center.into(), (*inner_radius, *outer_radius))
                            .map_err(|(f, m)| (format!(".shell.refine.{f}"), m))?;
                    let count = graded_shell_cells(
                        *inner_radius,
                        *outer_radius,
                        (*cells, *layers),
                        &refine,
                        outer,
                    );
                    if count.is_none_or(|n| n > MAX_CELLS) {
                        return Err((
                            ".shell.refine.size".into(),
                            format!(
                                "cells = {cells} and layers = {layers} refined to size = {} m \
                                 make more than {MAX_CELLS} elements (about {}): a larger size \
                                 or fewer cells",
                                refine.size,
                                count.map_or("more than 2^64".into(), |n| n.to_string())
                            ),
                        ));
                    }
                    Ok(graded_shell_mesh(
                        center,
                        *inner_radius,
                        *outer_radius,
                        (*cells, *layers),
                        &refine,
                        outer,
                    ))
                }
            }
        }
    }
}
