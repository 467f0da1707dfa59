//! Points of one mesh embedded in another: to compare two solutions on different meshes, each
//! point (a node of the coarser mesh, at rest) is located in the cell of the reference mesh
//! that holds it at rest, and the reference's displacement there is the trilinear
//! interpolation of that cell's nodal displacements. A point just outside the mesh (the meshes'
//! boundaries are snapped to the skin at other places) takes the displacement of the nearest
//! point of the nearest cell within a given distance; a point farther out (bones and joint
//! spaces are holes), or only in cells of another part, is left out: there the two meshes
//! disagree on what is flesh, which is geometry, not the solver.

use crate::fem::hex8::{local_coordinates, shape};
use crate::mesh::Mesh;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::collections::HashMap;

/// How far outside the reference cube (in local coordinates) a point still counts as inside.
const SLACK: f64 = 1e-9;

/// Fixed interpolation weights of points in a mesh.
#[derive(Clone, Debug)]
pub struct Embedding {
    /// Per point: the cell's eight nodes and their weights; `None` outside the mesh.
    weights: Vec<Option<[(usize, f64); 8]>>,
}

/// Buckets of cells by their bounding boxes on a uniform grid.
struct Grid {
    min: Vector3<f64>,
    size: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl Grid {
    fn new(mesh: &Mesh) -> Grid {
        let (mut min, mut max) = (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN));
        for p in &mesh.nodes {
            min = min.inf(p);
            max = max.sup(p);
        }
        let volume = (max - min).product().max(f64::MIN_POSITIVE);
        let size = 2.0 * (volume / mesh.cell_count().max(1) as f64).cbrt();
        let mut grid = Grid {
            min,
            size,
            cells: HashMap::new(),
        };
        for c in 0..mesh.cell_count() {
            let coords = mesh.cell_coords(c);
            let (lo, hi) = coords.iter().fold(
                (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
                |(lo, hi), p| (lo.inf(p), hi.sup(p)),
            );
            let (a, b) = (grid.key(&lo), grid.key(&hi));
            for i in a[0]..=b[0] {
                for j in a[1]..=b[1] {
                    for k in a[2]..=b[2] {
                        grid.cells.entry([i, j, k]).or_default().push(c);
                    }
                }
            }
        }
        grid
    }

    fn key(&self, p: &Vector3<f64>) -> [i64; 3] {
        let q = (p - self.min) / self.size;
        [q.x.floor() as i64, q.y.floor() as i64, q.z.floor() as i64]
    }

    /// The cells whose bounding boxes meet the buckets within `reach` of the point.
    fn near(&self, p: &Vector3<f64>, reach: f64) -> Vec<usize> {
        let (a, b) = (
            self.key(&p.add_scalar(-reach)),
            self.key(&p.add_scalar(reach)),
        );
        let mut out = Vec::new();
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                for k in a[2]..=b[2] {
                    if let Some(c) = self.cells.get(&[i, j, k]) {
                        out.extend(c);
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

impl Embedding {
    /// Locates `points` in `mesh` (both at rest); a point outside every cell takes the nearest
    /// point of the nearest cell if it lies within `reach` (m) of it. Only the cells
    /// `accept(point, cell)` accepts are considered (on the hand: those of the point's own
    /// digit, since two fingers touching at rest are meshed apart along a seam whose place
    /// changes with the resolution).
    pub fn new(
        mesh: &Mesh,
        points: &[Vector3<f64>],
        reach: f64,
        accept: impl Fn(usize, usize) -> bool + Sync,
    ) -> Embedding {
        let grid = Grid::new(mesh);
        let weights = points
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let mut best: Option<(usize, Vector3<f64>, f64)> = None;
                for c in grid.near(p, reach) {
                    if !accept(i, c) {
                        continue;
                    }
                    let coords = mesh.cell_coords(c);
                    let (lo, hi) = coords.iter().fold(
                        (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
                        |(lo, hi), q| (lo.inf(q), hi.sup(q)),
                    );
                    if (0..3).any(|k| p[k] < lo[k] - reach || p[k] > hi[k] + reach) {
                        continue;
                    }
                    let xi = local_coordinates(&coords, p);
                    let (xi, d) = if xi.amax() <= 1.0 + SLACK {
                        (xi, 0.0)
                    } else {
                        let clamped = xi.map(|v| v.clamp(-1.0, 1.0));
                        let n = shape(&clamped);
                        let q: Vector3<f64> = (0..8).map(|a| coords[a] * n[a]).sum();
                        (clamped, (q - p).norm())
                    };
                    if d > reach {
                        continue;
                    }
                    if best.as_ref().is_none_or(|b| d < b.2) {
                        best = Some((c, xi, d));
                    }
                    if d == 0.0 {
                        break;
                    }
                }
                best.map(|(c, xi, _)| {
                    let n = shape(&xi);
                    let nodes = mesh.cells[c];
                    std::array::from_fn(|a| (nodes[a], n[a]))
                })
            })
            .collect();
        Embedding { weights }
    }

    /// Points inside the mesh.
    pub fn inside(&self) -> usize {
        self.weights.iter().filter(|w| w.is_some()).count()
    }

    /// A nodal vector field (displacements) interpolated at the points; `None` outside.
    pub fn interpolate(&self, field: &[Vector3<f64>]) -> Vec<Option<Vector3<f64>>> {
        self.weights
            .iter()
            .map(|w| w.map(|w| w.iter().map(|&(n, h)| field[n] * h).sum()))
            .collect()
    }
}
