//! Element shape measures: the scaled Jacobian and the aspect ratio of a hexahedron.

use super::Mesh;
use nalgebra::Vector3;

/// The three edges leaving each corner of a hexahedron (VTK order), right-handed.
const CORNER_EDGES: [[usize; 4]; 8] = [
    [0, 1, 3, 4],
    [1, 2, 0, 5],
    [2, 3, 1, 6],
    [3, 0, 2, 7],
    [4, 7, 5, 0],
    [5, 4, 6, 1],
    [6, 5, 7, 2],
    [7, 6, 4, 3],
];

/// The smallest scaled Jacobian of a hexahedron: over its eight corners, the triple product of the
/// three edges leaving the corner over the product of their lengths (1 for a box, ≤ 0 inverted).
pub fn scaled_jacobian(corners: &[Vector3<f64>; 8]) -> f64 {
    CORNER_EDGES
        .iter()
        .map(|&[c, a, b, d]| {
            let (e1, e2, e3) = (
                corners[a] - corners[c],
                corners[b] - corners[c],
                corners[d] - corners[c],
            );
            let lengths = e1.norm() * e2.norm() * e3.norm();
            if lengths > 0.0 {
                e1.dot(&e2.cross(&e3)) / lengths
            } else {
                0.0
            }
        })
        .fold(f64::INFINITY, f64::min)
}

/// An edge shorter than this share of an element's longest is collapsed (its two corners one).
pub const COLLAPSED: f64 = 1e-9;

/// The longest edge of a hexahedron over its shortest, the edges a degenerate element (a prism
/// or a tetrahedron written as a hexahedron) collapses to a point left out — those shorter than
/// [`COLLAPSED`] of the longest: a corner merged by arithmetic is seldom exactly the same point
/// (infinite where every edge is collapsed).
pub fn aspect_ratio(corners: &[Vector3<f64>; 8]) -> f64 {
    const EDGES: [[usize; 2]; 12] = [
        [0, 1],
        [1, 2],
        [2, 3],
        [3, 0],
        [4, 5],
        [5, 6],
        [6, 7],
        [7, 4],
        [0, 4],
        [1, 5],
        [2, 6],
        [3, 7],
    ];
    let lengths = EDGES.map(|[a, b]| (corners[a] - corners[b]).norm());
    let longest = lengths.iter().copied().fold(0.0, f64::max);
    let shortest = lengths
        .iter()
        .copied()
        .filter(|&l| l > COLLAPSED * longest)
        .fold(f64::INFINITY, f64::min);
    if shortest.is_finite() {
        longest / shortest
    } else {
        f64::INFINITY
    }
}

/// The smallest scaled Jacobian and the largest aspect ratio over the cells of a mesh.
pub fn mesh_quality(mesh: &Mesh) -> (f64, f64) {
    (0..mesh.cells.len()).map(|c| mesh.cell_coords(c)).fold(
        (f64::INFINITY, 0.0f64),
        |(jac, aspect), corners| {
            (
                jac.min(scaled_jacobian(&corners)),
                aspect.max(aspect_ratio(&corners)),
            )
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::box_mesh;

    #[test]
    fn a_box_is_perfect_and_a_sheared_box_is_not() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(2.0, 1.0, 1.0), [1, 1, 1]);
        let (jac, aspect) = mesh_quality(&mesh);
        assert!((jac - 1.0).abs() < 1e-12);
        assert!((aspect - 2.0).abs() < 1e-12);
        let mut sheared = mesh.clone();
        for p in &mut sheared.nodes {
            p.x += p.z;
        }
        let (jac, _) = mesh_quality(&sheared);
        assert!((jac - 0.5f64.sqrt()).abs() < 1e-12, "{jac}");
    }

    /// A prism written as a hexahedron (its top face's back edge collapsed): the collapsed edge
    /// is no edge, so the aspect is that of the edges it has; a flat box's is its flatness.
    #[test]
    fn a_collapsed_edge_is_no_edge_of_the_aspect() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [1, 1, 1]);
        let mut corners = mesh.cell_coords(0);
        // VTK order: 4–7 the top face; collapse 6 onto 7 (the edge 6–7 vanishes).
        corners[6] = corners[7];
        let aspect = aspect_ratio(&corners);
        // Longest edge left: the top's diagonal 5–6 (√2), shortest 1.
        assert!((aspect - 2f64.sqrt()).abs() < 1e-12, "{aspect}");
        let flat = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1e-7), [1, 1, 1]);
        assert!((aspect_ratio(&flat.cell_coords(0)) - 1e7).abs() < 1e-3);
    }
}
