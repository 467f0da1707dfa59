//! Kernel: hexahedral meshes, their boundary facets and surfaces, and mesh generators.
//! May import util only.
//!
//! Meshes of 8-node hexahedra (with collapsed, degenerate forms for prisms and tetrahedra),
//! their boundary facets, generators for boxes, solid balls and hollow balls (uniform, or graded
//! toward where a ball is touched) and element shape measures.

mod generate;
mod graded;
mod grading;
mod quality;
mod surface;

pub use generate::{box_mesh, shell_mesh, sphere_mesh};
pub use graded::{graded_shell_cells, graded_shell_mesh, graded_sphere_cells, graded_sphere_mesh};
pub use grading::{Refinement, GROWTH};
pub use quality::{aspect_ratio, mesh_quality, scaled_jacobian};
pub use surface::{boundary_facets, Facet, HEX_FACES};

use nalgebra::Vector3;

/// Node indices of one hexahedron in VTK order: nodes 0–3 on the face ζ = −1 counter-clockwise
/// seen from ζ = +1, nodes 4–7 above them. A prism or tetrahedron repeats node indices.
pub type Hex = [usize; 8];

/// A volume mesh of hexahedra. Geometry and topology only: materials and bodies live in the model.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Node positions in metres.
    pub nodes: Vec<Vector3<f64>>,
    /// Cells as node indices.
    pub cells: Vec<Hex>,
}

impl Mesh {
    /// The diagonal of the nodes' bounding box, m (0 without nodes).
    pub fn bounding_size(&self) -> f64 {
        let Some(first) = self.nodes.first() else {
            return 0.0;
        };
        let (lo, hi) = self
            .nodes
            .iter()
            .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        (hi - lo).norm()
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// Appends `other`, renumbering its nodes; returns the offsets (first node, first cell) it got.
    pub fn append(&mut self, other: &Mesh) -> (usize, usize) {
        let node_offset = self.nodes.len();
        let cell_offset = self.cells.len();
        self.nodes.extend_from_slice(&other.nodes);
        self.cells
            .extend(other.cells.iter().map(|c| c.map(|n| n + node_offset)));
        (node_offset, cell_offset)
    }

    /// Positions of the eight nodes of cell `c`.
    pub fn cell_coords(&self, c: usize) -> [Vector3<f64>; 8] {
        self.cells[c].map(|n| self.nodes[n])
    }

    /// Nodes grouped into pieces connected through cells (union–find); returns the piece index of
    /// every node and the number of pieces. A node used by no cell is a piece of its own.
    pub fn connected_pieces(&self) -> (Vec<usize>, usize) {
        let n = self.nodes.len();
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        for cell in &self.cells {
            let r0 = find(&mut parent, cell[0]);
            for &node in &cell[1..] {
                let r = find(&mut parent, node);
                if r != r0 {
                    parent[r] = r0;
                }
            }
        }
        let mut piece_of_root = vec![usize::MAX; n];
        let mut piece = vec![0; n];
        let mut count = 0;
        for i in 0..n {
            let r = find(&mut parent, i);
            if piece_of_root[r] == usize::MAX {
                piece_of_root[r] = count;
                count += 1;
            }
            piece[i] = piece_of_root[r];
        }
        (piece, count)
    }
}
