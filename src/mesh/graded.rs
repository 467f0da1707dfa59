//! Balls meshed finer where they are touched: cubed spheres whose lattice lines are graded
//! toward one point of the surface (sizes growing by `GROWTH` from the refinement's size there to
//! the base size), built around the pole −z and turned onto it.

use super::generate::{cubed_shell, lattice};
use super::grading::{
    graded_positions, polar_face_coordinates, pole_rotation, side_face_coordinates, Refinement,
};
use super::Mesh;
use nalgebra::Vector3;
use std::collections::HashMap;
use std::f64::consts::FRAC_PI_2;

/// Half the edge of a graded solid ball's core cube, over the radius: the wall between the cube
/// and the sphere is 0.55 R thick on the axes and 0.22 R at the cube's corners.
pub const CORE: f64 = 0.45;

/// A solid ball whose base size is that of `cells` cells across, refined toward
/// `refine.direction`: a core cube (half-edge `CORE`·R) wrapped in a cubed sphere (no cell with
/// three faces on the sphere, as the mapped cube of `sphere_mesh` has at its corners). On the
/// surface, arcs of `refine.size` at the touched point; through the wall, layers of
/// `refine.size` at the surface. Surface nodes lie on the sphere.
pub fn graded_sphere_mesh(
    center: Vector3<f64>,
    radius: f64,
    cells: usize,
    refine: &Refinement,
) -> Mesh {
    let largest = FRAC_PI_2 * radius / cells as f64;
    let across = polar_face_coordinates(radius, refine.size, largest);
    let along = side_face_coordinates(radius, refine.size, largest);
    let lines = [&across[..], &across[..], &along[..]];
    let wall = (1.0 - CORE) * radius;
    // Fractions of the way from the core's surface (0) to the sphere (1).
    let fractions: Vec<f64> = graded_positions(0.0, wall, refine.size, 2.0 * radius / cells as f64)
        .iter()
        .rev()
        .map(|d| 1.0 - d / wall)
        .collect();
    let turn = pole_rotation(&refine.direction);
    let core_point = |q: Vector3<f64>| q * (CORE * radius);
    let mut core = lattice(&lines);
    for p in &mut core.nodes {
        *p = core_point(*p);
    }
    let wall_mesh = cubed_shell(&lines, fractions.len() - 1, |q, l| {
        let s = fractions[l];
        if s == 0.0 {
            core_point(q)
        } else {
            core_point(q) * (1.0 - s) + q.normalize() * (radius * s)
        }
    });
    let mut ball = welded(core, &wall_mesh);
    for p in &mut ball.nodes {
        *p = center + turn * *p;
    }
    ball
}

/// About how many cells [`graded_sphere_mesh`] makes (from its coordinate lines, without
/// meshing: the core lattice and the wall's layers of the cube's surface quads); `None` beyond
/// `usize`.
pub fn graded_sphere_cells(radius: f64, cells: usize, refine: &Refinement) -> Option<usize> {
    let largest = FRAC_PI_2 * radius / cells as f64;
    let a = polar_face_coordinates(radius, refine.size, largest).len() - 1;
    let b = side_face_coordinates(radius, refine.size, largest).len() - 1;
    let wall = (1.0 - CORE) * radius;
    let layers = graded_positions(0.0, wall, refine.size, 2.0 * radius / cells as f64).len() - 1;
    let core = a.checked_mul(a)?.checked_mul(b)?;
    core.checked_add(surface_quads(a, b)?.checked_mul(layers)?)
}

/// About how many cells [`graded_shell_mesh`] makes; `None` beyond `usize`.
pub fn graded_shell_cells(
    inner_radius: f64,
    outer_radius: f64,
    (cells, layers): (usize, usize),
    refine: &Refinement,
    outer: bool,
) -> Option<usize> {
    let touched = if outer { outer_radius } else { inner_radius };
    let largest = FRAC_PI_2 * touched / cells as f64;
    let a = polar_face_coordinates(touched, refine.size, largest).len() - 1;
    let b = side_face_coordinates(touched, refine.size, largest).len() - 1;
    let wall = outer_radius - inner_radius;
    let depth = graded_positions(0.0, wall, refine.size, wall / layers as f64).len() - 1;
    surface_quads(a, b)?.checked_mul(depth)
}

/// Quads on the surface of a lattice box of a × a × b segments.
fn surface_quads(a: usize, b: usize) -> Option<usize> {
    a.checked_mul(a)?
        .checked_add(a.checked_mul(b)?.checked_mul(2)?)?
        .checked_mul(2)
}

/// A hollow ball (the cubed sphere of `shell_mesh`) with the base sizes of `cells` quads per cube
/// face and `layers` cells through the wall, refined toward `refine.direction` on the outer
/// surface (`outer`) or on the inner one: arcs of `refine.size` at the touched point of that
/// surface, and layers of `refine.size` next to it.
pub fn graded_shell_mesh(
    center: Vector3<f64>,
    inner_radius: f64,
    outer_radius: f64,
    (cells, layers): (usize, usize),
    refine: &Refinement,
    outer: bool,
) -> Mesh {
    let touched = if outer { outer_radius } else { inner_radius };
    let largest = FRAC_PI_2 * touched / cells as f64;
    let across = polar_face_coordinates(touched, refine.size, largest);
    let along = side_face_coordinates(touched, refine.size, largest);
    let wall = outer_radius - inner_radius;
    let depth = graded_positions(0.0, wall, refine.size, wall / layers as f64);
    let radii: Vec<f64> = if outer {
        depth.iter().rev().map(|d| outer_radius - d).collect()
    } else {
        depth.iter().map(|d| inner_radius + d).collect()
    };
    let turn = pole_rotation(&refine.direction);
    cubed_shell(&[&across, &across, &along], radii.len() - 1, |q, l| {
        center + turn * (q.normalize() * radii[l])
    })
}

/// `base` with `other` appended, the nodes of `other` at exactly the position of a node of `base`
/// merged into it.
fn welded(mut base: Mesh, other: &Mesh) -> Mesh {
    let key = |p: &Vector3<f64>| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let existing: HashMap<[u64; 3], usize> = base
        .nodes
        .iter()
        .enumerate()
        .map(|(i, p)| (key(p), i))
        .collect();
    let renumber: Vec<usize> = other
        .nodes
        .iter()
        .map(|p| {
            existing.get(&key(p)).copied().unwrap_or_else(|| {
                base.nodes.push(*p);
                base.nodes.len() - 1
            })
        })
        .collect();
    base.cells
        .extend(other.cells.iter().map(|c| c.map(|n| renumber[n])));
    base
}
