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

/// The longest edge of a hexahedron over its shortest.
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
    let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    longest / shortest
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
}
