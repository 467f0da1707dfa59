//! Boundary facets of a hexahedral mesh: the cell faces that belong to exactly one cell.

use super::Mesh;
use std::collections::HashMap;

/// Local node indices of the six faces of a hexahedron in VTK order, each ordered so that
/// (n1 − n0) × (n3 − n0) points out of the cell.
pub const HEX_FACES: [[usize; 4]; 6] = [
    [0, 4, 7, 3], // ξ = −1
    [1, 2, 6, 5], // ξ = +1
    [0, 1, 5, 4], // η = −1
    [2, 3, 7, 6], // η = +1
    [0, 3, 2, 1], // ζ = −1
    [4, 5, 6, 7], // ζ = +1
];

/// A boundary facet: a quadrilateral (or, on a collapsed cell, a triangle with a repeated node),
/// its nodes ordered so that its normal points out of the body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Facet {
    /// Global node indices.
    pub nodes: [usize; 4],
    /// The cell it bounds.
    pub cell: usize,
}

/// All boundary facets of the mesh. Faces that collapse to fewer than three distinct nodes (on
/// degenerate cells) are not facets.
pub fn boundary_facets(mesh: &Mesh) -> Vec<Facet> {
    let mut seen: HashMap<[usize; 4], (usize, Facet)> = HashMap::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for face in HEX_FACES {
            let nodes = face.map(|i| cell[i]);
            let mut key = nodes;
            key.sort_unstable();
            let mut distinct = 1;
            for i in 1..4 {
                if key[i] != key[i - 1] {
                    distinct += 1;
                }
            }
            if distinct < 3 {
                continue;
            }
            // Canonical key: sorted distinct nodes, padded by repeating the largest.
            let mut canon = [0usize; 4];
            let mut len = 0;
            for &k in &key {
                if len == 0 || canon[len - 1] != k {
                    canon[len] = k;
                    len += 1;
                }
            }
            for i in len..4 {
                canon[i] = canon[len - 1];
            }
            seen.entry(canon)
                .and_modify(|e| e.0 += 1)
                .or_insert((1, Facet { nodes, cell: c }));
        }
    }
    let mut facets: Vec<Facet> = seen
        .into_values()
        .filter(|(count, _)| *count == 1)
        .map(|(_, f)| f)
        .collect();
    facets.sort_unstable_by_key(|f| (f.cell, f.nodes));
    facets
}
