//! Embedding a point of the skin in the flesh: the cell, and the natural coordinates in it, whose
//! trilinear map reproduces the point. A skin point belongs to a control quad tied to a boundary
//! cell, but the smooth skin may pass a cell or more beyond that cell (where its skin nodes stay
//! inside the skin, attached to a bone flush with it); there the cell's natural coordinates leave
//! the range Newton's iteration keeps them in (±2) and the point would be pulled in: a dent of
//! the skin up to 4 mm deep on the backs of the fingers. The cells around it (sharing a node) are
//! then tried: one holding the point interpolates it; where none does, the nearest extrapolates it
//! along its tangent map.

use crate::fem::hex8::{jacobian, local_coordinates, shape, shape_derivatives};
use crate::mesh::Mesh;
use nalgebra::Vector3;

/// A point is reproduced when its embedded position lies within this of it, m.
const REPRODUCED: f64 = 1e-9;

/// The largest weight an extrapolation may put on a node (measured on the hands at most 4.6).
const WEIGHT_BOUND: f64 = 8.0;

/// Where a skin point may be embedded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reach {
    /// In the cell of its control quad only, its natural coordinates kept within ±2: a point
    /// beyond is pulled in (the contact skin, whose dents the contact solver is tuned with:
    /// docs/hand.md).
    OwnCell,
    /// In its own cell, a neighbour or extrapolated from the nearest ([`embed`]): exactly on
    /// the skin's shape (the display skin).
    Nearest,
}

/// The cells of every node (compressed rows).
pub struct NodeCells {
    offsets: Vec<u32>,
    cells: Vec<u32>,
}

impl NodeCells {
    pub fn new(mesh: &Mesh) -> NodeCells {
        let mut count = vec![0u32; mesh.node_count() + 1];
        for cell in &mesh.cells {
            for &n in cell {
                count[n + 1] += 1;
            }
        }
        for i in 1..count.len() {
            count[i] += count[i - 1];
        }
        let mut fill = count.clone();
        let mut cells = vec![0u32; count[mesh.node_count()] as usize];
        for (c, cell) in mesh.cells.iter().enumerate() {
            for &n in cell {
                cells[fill[n] as usize] = c as u32;
                fill[n] += 1;
            }
        }
        NodeCells {
            offsets: count,
            cells,
        }
    }

    /// The cells sharing a node with `cell` (itself included), each once.
    fn around(&self, mesh: &Mesh, cell: usize) -> Vec<usize> {
        let mut out: Vec<usize> = mesh.cells[cell]
            .iter()
            .flat_map(|&n| {
                let (a, b) = (self.offsets[n] as usize, self.offsets[n + 1] as usize);
                self.cells[a..b].iter().map(|&c| c as usize)
            })
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// How far natural coordinates are from the reference cube (0 on its faces, negative inside).
fn beyond(xi: &Vector3<f64>) -> f64 {
    xi.amax() - 1.0
}

/// Shape-function values at `xi` of cell `c`, and the position they give.
fn at(mesh: &Mesh, c: usize, xi: &Vector3<f64>) -> ([f64; 8], Vector3<f64>) {
    let n = shape(xi);
    let x = (0..8).map(|a| mesh.nodes[mesh.cells[c][a]] * n[a]).sum();
    (n, x)
}

/// The weights embedding `p`, over the nodes of the cell returned (`reach` [`Reach::OwnCell`]:
/// the first case only, whatever the result):
/// - `cell` itself when its trilinear map reproduces `p` within ±2 natural coordinates (as
///   before: interpolation inside the cell, mild extrapolation up to half a cell beyond it);
/// - otherwise a cell around it that holds `p` (interpolation);
/// - otherwise the cell around it nearest `p`, extrapolated along its tangent map from ξ₀ (the
///   point's natural coordinates clamped to the cell): x = x(ξ₀) + J(ξ₀)·δ, weights
///   N_a(ξ₀) + ∇N_a(ξ₀)·δ, bounded by [`WEIGHT_BOUND`] (the next nearest cell otherwise). They sum to
///   one and reproduce every affine motion of the cell, like the trilinear map, but grow linearly
///   with the distance, not as its cube (a trilinear map extrapolated three cells out puts
///   weights of 30 on nodes and turns a cell's slight distortion into spikes of the skin);
/// - otherwise the same among the cells around those, up to [`RINGS`] rings out (a point beyond
///   thin cells, whose tangent maps reach it only with weights beyond the bound);
/// - otherwise `cell` as in the first case (the point pulled in).
pub fn embed(
    mesh: &Mesh,
    around: &NodeCells,
    cell: usize,
    p: &Vector3<f64>,
    reach: Reach,
) -> (usize, [f64; 8]) {
    let fit = |c: usize| {
        let coords = mesh.cells[c].map(|n| mesh.nodes[n]);
        let xi = local_coordinates(&coords, p);
        let (n, x) = at(mesh, c, &xi);
        (xi, n, (x - p).norm())
    };
    let (_, n, miss) = fit(cell);
    if miss <= REPRODUCED || reach == Reach::OwnCell {
        return (cell, n);
    }
    // The cells around it first; where none holds the point nor extrapolates it within the
    // bound, the cells around those (a display skin vertex may lie a few cells from its
    // control quad's cell where the lattice's boundary cells are small, as at resolution 1.5).
    let mut cells = vec![cell];
    for _ in 0..RINGS {
        cells = cells.iter().flat_map(|&c| around.around(mesh, c)).collect();
        cells.sort_unstable();
        cells.dedup();
        if let Some(found) = in_cells(mesh, &cells, p, &fit) {
            return found;
        }
    }
    (cell, n)
}

/// [`embed`] in a mesh whose cells are a lattice's split into `n` × `n` × `n` each
/// (`super::subdivide`: the children of parent cell P are cells P·n³ … P·n³ + n³ − 1, child
/// (i, j, k) at P·n³ + i + n·(j + n·k)): the point embedded first in `cell`'s parent, by the
/// parent's map, then in the child holding its natural coordinates (the nearest one beyond
/// the parent), at the same point. The children's maps are the parent's, piece by piece, so the
/// point and its reach are those of the unsplit mesh at every `n` — a skin point pulled in by
/// [`Reach::OwnCell`] at ±2 of its cell is pulled in alike, where embedded in a child directly
/// it would be pulled in at ±2 of a cell n times smaller.
pub fn embed_split(
    mesh: &Mesh,
    around: &NodeCells,
    cell: usize,
    p: &Vector3<f64>,
    reach: Reach,
    n: usize,
) -> (usize, [f64; 8]) {
    if n <= 1 {
        return embed(mesh, around, cell, p, reach);
    }
    let per = n * n * n;
    let first = (cell / per) * per;
    let child_of = |[i, j, k]: [usize; 3]| first + i + n * (j + n * k);
    let parent: [Vector3<f64>; 8] = std::array::from_fn(|a| {
        let [x, y, z] = super::lattice::CORNERS[a];
        mesh.nodes[mesh.cells[child_of([x * (n - 1), y * (n - 1), z * (n - 1)])][a]]
    });
    let xi = local_coordinates(&parent, p);
    if !xi.iter().all(|v| v.is_finite()) {
        return embed(mesh, around, cell, p, reach);
    }
    let m = n as f64;
    let index = |t: f64| (((t + 1.0) * 0.5 * m).floor().clamp(0.0, m - 1.0)) as usize;
    let at = [index(xi.x), index(xi.y), index(xi.z)];
    let child = child_of(at);
    let local = Vector3::from_fn(|d, _| m * (xi[d] + 1.0) - 2.0 * at[d] as f64 - 1.0);
    let (weights, x) = self::at(mesh, child, &local);
    if (x - p).norm() <= REPRODUCED || reach == Reach::OwnCell {
        return (child, weights);
    }
    embed(mesh, around, child, p, reach)
}

/// How many rings of cells around a point's own cell [`embed`] looks in.
const RINGS: usize = 3;

/// A cell of `cells` holding `p` (interpolated), else the nearest extrapolating it within
/// [`WEIGHT_BOUND`]; `fit` gives a cell's natural coordinates of `p`, their shape functions and
/// how far they miss it.
fn in_cells(
    mesh: &Mesh,
    cells: &[usize],
    p: &Vector3<f64>,
    fit: &dyn Fn(usize) -> (Vector3<f64>, [f64; 8], f64),
) -> Option<(usize, [f64; 8])> {
    let fits: Vec<(usize, Vector3<f64>, [f64; 8], f64)> = cells
        .iter()
        .map(|&c| {
            let (xi, n, miss) = fit(c);
            (c, xi, n, miss)
        })
        .collect();
    if let Some(&(c, _, n, _)) = fits
        .iter()
        .filter(|f| f.3 <= REPRODUCED && beyond(&f.1) <= 1e-9)
        .min_by(|a, b| beyond(&a.1).total_cmp(&beyond(&b.1)))
    {
        return Some((c, n));
    }
    // Extrapolated along a cell's tangent map from ξ₀, Newton's estimate of the point clamped
    // to the reference cube (the cell's point nearest it for a cell not too distorted), the
    // cells tried nearest first; a cell whose Jacobian there is (nearly) singular gives
    // weights beyond the bound and the next is tried.
    // (cell, ξ₀, N(ξ₀), the point's offset from x(ξ₀))
    let mut tangents: Vec<_> = fits
        .iter()
        .map(|&(c, xi, _, _)| {
            let xi0 = xi.map(|v| v.clamp(-1.0, 1.0));
            let (n0, x0) = at(mesh, c, &xi0);
            (c, xi0, n0, p - x0)
        })
        .collect();
    tangents.sort_by(|a, b| a.3.norm().total_cmp(&b.3.norm()));
    for (c, xi0, n0, d) in tangents {
        let dn = shape_derivatives(&xi0);
        let coords = mesh.cells[c].map(|n| mesh.nodes[n]);
        let Some(inv) = jacobian(&coords, &dn).try_inverse() else {
            continue;
        };
        let delta = inv * d;
        let w: [f64; 8] = std::array::from_fn(|a| n0[a] + dn[a].dot(&delta));
        if w.iter().all(|w| w.is_finite() && w.abs() <= WEIGHT_BOUND) {
            return Some((c, w));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit cubes side by side along x, the second sheared so that its map is not affine.
    fn two_cells() -> Mesh {
        let mut mesh = row(&[0.0, 1.0, 2.0]);
        // The node at x = 2, y = 1, z = 1.
        mesh.nodes[2 + 3 + 6].x += 0.3;
        mesh
    }

    fn place(mesh: &Mesh, cell: usize, n: &[f64; 8]) -> Vector3<f64> {
        (0..8).map(|a| mesh.nodes[mesh.cells[cell][a]] * n[a]).sum()
    }

    #[test]
    fn a_point_its_cell_reproduces_stays_in_that_cell() {
        let mesh = two_cells();
        let around = NodeCells::new(&mesh);
        // Just beyond the first cell, inside the second: the first cell's (affine) map
        // reproduces it, so it is kept.
        let p = Vector3::new(1.4, 0.5, 0.5);
        let (c, n) = embed(&mesh, &around, 0, &p, Reach::Nearest);
        assert_eq!(c, 0);
        assert!((place(&mesh, c, &n) - p).norm() < 1e-12);
    }

    #[test]
    fn a_point_beyond_its_cells_reach_goes_to_the_neighbour_holding_it() {
        let mesh = two_cells();
        let around = NodeCells::new(&mesh);
        // 1.6 cell widths from the first cell's centre: its natural coordinate would be 3.2,
        // beyond the ±2 Newton keeps, so the first cell cannot reproduce it; the second holds
        // it.
        let p = Vector3::new(2.1, 0.9, 0.9);
        let coords = mesh.cells[0].map(|n| mesh.nodes[n]);
        let own: Vector3<f64> = {
            let n = shape(&local_coordinates(&coords, &p));
            (0..8).map(|a| coords[a] * n[a]).sum()
        };
        assert!((own - p).norm() > 0.1, "the first cell alone misplaces it");
        let (c, n) = embed(&mesh, &around, 0, &p, Reach::Nearest);
        assert_eq!(c, 1);
        assert!((place(&mesh, c, &n) - p).norm() < 1e-9);
        assert!(
            n.iter().all(|&w| w > -1e-12),
            "interpolated, not extrapolated"
        );
    }

    #[test]
    fn a_point_beyond_every_cell_is_extrapolated_along_the_nearest_cells_tangent_map() {
        // The two cells turned, stretched and sheared by an affine map (so that J is neither
        // diagonal nor symmetric), the second cell also distorted.
        let a = nalgebra::Matrix3::new(1.1, 0.4, 0.0, -0.3, 0.9, 0.3, 0.05, 0.2, 1.2);
        let b = Vector3::new(0.3, -0.2, 0.1);
        let plain = two_cells();
        let mesh = Mesh {
            nodes: plain.nodes.iter().map(|x| a * x + b).collect(),
            cells: plain.cells.clone(),
        };
        let around = NodeCells::new(&mesh);
        // Beyond both cells diagonally, about three cells from the first: neither cell holds
        // it and neither's trilinear map reaches it within ±2 (the first's would need
        // ξ = (4, 5, 7), weighing a node by 5·6·8/8 = 30).
        let p = a * Vector3::new(2.5, 3.0, 4.0) + b;
        let (c, n) = embed(&mesh, &around, 0, &p, Reach::Nearest);
        assert!((place(&mesh, c, &n) - p).norm() < 1e-12, "reproduced");
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let largest = n.iter().map(|w| w.abs()).fold(0.0, f64::max);
        assert!(largest <= WEIGHT_BOUND, "{n:?}");
        // Measured 7.5: a quarter of the trilinear map's 30 (linear growth, not cubic).
        assert!(largest < 10.0, "{n:?}");
    }

    /// A row of cells along x between the given planes, each 1 × 1 across.
    fn row(planes: &[f64]) -> Mesh {
        let mut nodes = Vec::new();
        for k in 0..2 {
            for j in 0..2 {
                for &x in planes {
                    nodes.push(Vector3::new(x, j as f64, k as f64));
                }
            }
        }
        let m = planes.len();
        let id = |i: usize, j: usize, k: usize| i + m * j + 2 * m * k;
        let cells = (0..m - 1)
            .map(|i| {
                [
                    id(i, 0, 0),
                    id(i + 1, 0, 0),
                    id(i + 1, 1, 0),
                    id(i, 1, 0),
                    id(i, 0, 1),
                    id(i + 1, 0, 1),
                    id(i + 1, 1, 1),
                    id(i, 1, 1),
                ]
            })
            .collect();
        Mesh { nodes, cells }
    }

    /// Beyond two thin cells (0.01 across): the cells sharing a node with the first reach the
    /// point only with weights of ≈ 20 (beyond the bound); the next ring's cell holds it and
    /// interpolates it exactly (the first cell alone pulled it 0.77 in).
    #[test]
    fn a_point_beyond_thin_cells_is_found_in_the_next_ring() {
        let mesh = row(&[0.0, 0.01, 0.02, 1.02]);
        let around = NodeCells::new(&mesh);
        let p = Vector3::new(0.8, 0.5, 0.5);
        let (c, n) = embed(&mesh, &around, 0, &p, Reach::Nearest);
        assert_eq!(c, 2);
        assert!((place(&mesh, c, &n) - p).norm() < 1e-12, "reproduced");
        assert!(n.iter().all(|w| (0.0..=1.0).contains(w)), "{n:?}");
        // Its own cell alone does not reproduce it.
        let (c, n) = embed(&mesh, &around, 0, &p, Reach::OwnCell);
        assert_eq!(c, 0);
        assert!((place(&mesh, c, &n) - p).norm() > 0.5);
    }
}
