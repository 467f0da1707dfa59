//! The mesh of a body's shape (box, sphere, shell or given mesh), after checking its parameters.

use super::check::finite;
use super::refinement::refinement;
use crate::mesh::{
    box_mesh, graded_shell_cells, graded_shell_mesh, graded_sphere_cells, graded_sphere_mesh,
    shell_mesh, sphere_mesh, Mesh, Refinement,
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
            // The same cell twice (its nodes in any order) would count its material twice.
            let mut seen: std::collections::HashMap<[usize; 8], usize> =
                std::collections::HashMap::with_capacity(cells.len());
            for (c, cell) in cells.iter().enumerate() {
                let mut key = *cell;
                key.sort_unstable();
                if let Some(first) = seen.insert(key, c) {
                    return Err(whole(format!(
                        "mesh elements {first} and {c} are the same element (the same eight \
                         nodes): each piece of material is one element"
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
                        let count_at = |size: f64, cells: usize| {
                            let refine = Refinement { size, ..refine };
                            graded_sphere_cells(*radius, cells, &refine)
                        };
                        return Err((
                            ".sphere.refine.size".into(),
                            format!(
                                "cells = {cells} refined to size = {} m make more than \
                                 {MAX_CELLS} elements (about {}): {}",
                                crate::util::readable(refine.size),
                                count.map_or("more than 2^64".into(), |n| n.to_string()),
                                within_cap(count_at, (refine.size, *radius), *cells, MAX_CELLS)
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
                // The field at fault: the one that is zero, else the larger share of the count.
                let field = if *layers == 0 || (*cells != 0 && *layers > 6 * *cells) {
                    ".shell.layers"
                } else {
                    ".shell.cells"
                };
                return Err((
                    field.into(),
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
                        let count_at = |size: f64, cells: usize| {
                            let refine = Refinement { size, ..refine };
                            graded_shell_cells(
                                *inner_radius,
                                *outer_radius,
                                (cells, *layers),
                                &refine,
                                outer,
                            )
                        };
                        return Err((
                            ".shell.refine.size".into(),
                            format!(
                                "cells = {cells} and layers = {layers} refined to size = {} m \
                                 make more than {MAX_CELLS} elements (about {}): {}",
                                crate::util::readable(refine.size),
                                count.map_or("more than 2^64".into(), |n| n.to_string()),
                                within_cap(
                                    count_at,
                                    (refine.size, *outer_radius),
                                    *cells,
                                    MAX_CELLS
                                )
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

/// What brings a refined ball within `cap` elements, `count_at(size, cells)` counting them: a
/// larger `size` (the smallest that does, at most `largest`) at these `cells`, or fewer cells
/// (the most that do) at this size — each alone, where it can. Either is a mesh at the cap, which
/// the memory check that follows may still refuse (with its own share of the elements).
fn within_cap(
    count_at: impl Fn(f64, usize) -> Option<usize>,
    (size, largest): (f64, f64),
    cells: usize,
    cap: usize,
) -> String {
    let fits = |size: f64, cells: usize| count_at(size, cells).is_some_and(|n| n <= cap);
    let mut options = Vec::new();
    if fits(largest, cells) {
        // Geometric bisection: the smallest size that fits, rounded up to 3 digits.
        let (mut lo, mut hi) = (size, largest);
        for _ in 0..60 {
            let mid = (lo * hi).sqrt();
            if fits(mid, cells) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let digits = 10f64.powf(hi.log10().floor() - 2.0);
        let rounded = (hi / digits).ceil() * digits;
        let rounded = if fits(rounded, cells) { rounded } else { hi };
        options.push(format!(
            "size = {rounded:.3e} m or more (at cells = {cells})"
        ));
    }
    if fits(size, 1) {
        let (mut lo, mut hi) = (1, cells);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if fits(size, mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        options.push(format!(
            "cells = {lo} or fewer (at size = {} m)",
            crate::util::readable(size)
        ));
    }
    match options.len() {
        0 => "no size or cell count brings it under the cap alone: both, or a smaller body".into(),
        _ => format!("{} — either alone", options.join(", or ")),
    }
}

#[cfg(test)]
mod tests {
    use super::build_shape;
    use crate::mesh::{graded_sphere_cells, Refinement};
    use crate::scene::{Refine, Shape};
    use nalgebra::Vector3;

    /// The number after `key` in `text`.
    fn after(text: &str, key: &str) -> f64 {
        let rest = text
            .split(key)
            .nth(1)
            .unwrap_or_else(|| panic!("{key}: {text}"));
        let number: String = rest
            .chars()
            .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | '-'))
            .collect();
        number.parse().unwrap_or_else(|_| panic!("{key}: {text}"))
    }

    /// A sphere refined past the element cap is told the size, and the cell count, that each
    /// alone bring it under the cap — and no less: 3 % finer, or one cell more, is over it.
    #[test]
    fn a_refined_sphere_over_the_cap_is_told_what_brings_it_under() {
        let (radius, cells, size) = (0.05, 100, 5e-6);
        let shape = Shape::Sphere {
            center: [0.0, 0.0, radius],
            radius,
            cells,
            refine: Some(Refine {
                toward: [0.0, 0.0, 0.0],
                size: Some(size),
            }),
        };
        let (field, message) = build_shape(&shape).expect_err("over the cap");
        assert_eq!(field, ".sphere.refine.size");
        let count = |size: f64, cells: usize| {
            let refine = Refinement {
                direction: -Vector3::z(),
                size,
            };
            graded_sphere_cells(radius, cells, &refine).unwrap()
        };
        let cap = 5_000_000;
        let larger = after(&message, "): size = ");
        let fewer = after(&message, "or cells = ") as usize;
        println!("{message}");
        assert!(count(larger, cells) <= cap && count(0.97 * larger, cells) > cap);
        assert!(count(size, fewer) <= cap && count(size, fewer + 1) > cap);
    }
}
