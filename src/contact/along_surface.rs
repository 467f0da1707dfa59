//! Distances along a surface, over its edges (Dijkstra), with the vertices that coincide joined
//! at no length: where the hand's lattice splits a node between two digits, its skin's vertices
//! are split too, and across such a seam the skin is one. The self-contact's neighbourhoods
//! (`self_contact::OwnNeighbourhood`) and where a hand's digit skins meet at rest
//! (`model::SkinOverlapCheck`) are measured with it.

use nalgebra::Vector3;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// Vertices nearer than this are one point of the surface, m.
const SAME: f64 = 1e-6;

/// A surface's edges with their lengths, and its coinciding vertices joined.
#[derive(Clone, Debug)]
pub struct SurfaceEdges {
    /// Each vertex's neighbours over an edge (at no length across a seam), and the length.
    edges: Vec<Vec<(usize, f64)>>,
    /// Each vertex's representative: the first (in order along x) it coincides with, itself if
    /// none.
    joined: Vec<usize>,
}

impl SurfaceEdges {
    /// The edges of `triangles` (indices into `positions`).
    pub fn new(positions: &[Vector3<f64>], triangles: &[[usize; 3]]) -> SurfaceEdges {
        let mut edges: Vec<Vec<(usize, f64)>> = vec![Vec::new(); positions.len()];
        for t in triangles {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let length = (positions[a] - positions[b]).norm();
                if !edges[a].iter().any(|e| e.0 == b) {
                    edges[a].push((b, length));
                    edges[b].push((a, length));
                }
            }
        }
        let mut on: Vec<usize> = (0..positions.len())
            .filter(|&n| !edges[n].is_empty())
            .collect();
        on.sort_by(|&a, &b| positions[a].x.total_cmp(&positions[b].x));
        let mut joined: Vec<usize> = (0..positions.len()).collect();
        for (i, &a) in on.iter().enumerate() {
            for &b in &on[i + 1..] {
                if positions[b].x - positions[a].x > SAME {
                    break;
                }
                if (positions[a] - positions[b]).norm() < SAME {
                    edges[a].push((b, 0.0));
                    edges[b].push((a, 0.0));
                    if joined[b] == b {
                        joined[b] = joined[a];
                    }
                }
            }
        }
        SurfaceEdges { edges, joined }
    }

    /// Whether vertex `v` lies on the surface (on some triangle).
    pub fn on_surface(&self, v: usize) -> bool {
        !self.edges[v].is_empty()
    }

    /// Each vertex's representative among those it coincides with.
    pub fn joined(&self) -> &[usize] {
        &self.joined
    }

    /// The vertices nearer than `radius` along the surface to one of `sources`, with that
    /// distance, m.
    pub fn within(&self, sources: &[usize], radius: f64) -> HashMap<usize, f64> {
        // Lengths as integer nanometres, for the heap's order.
        let key = |d: f64| Reverse((d * 1e9) as u64);
        let mut best: HashMap<usize, f64> = sources.iter().map(|&s| (s, 0.0)).collect();
        let mut heap: BinaryHeap<_> = sources.iter().map(|&s| (key(0.0), s)).collect();
        while let Some((Reverse(d), n)) = heap.pop() {
            let d = d as f64 * 1e-9;
            if d > best[&n] + 1e-12 {
                continue;
            }
            for &(m, length) in &self.edges[n] {
                let e = d + length;
                if e < radius && best.get(&m).is_none_or(|&b| e < b) {
                    best.insert(m, e);
                    heap.push((key(e), m));
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of two unit squares along x, split along x = 1 into two pieces whose vertices
    /// coincide there: joined, the far corner at (2, 0) is 2 along the surface from (0, 0), the
    /// one at (2, 1) 1 + √2.
    #[test]
    fn a_seam_of_coinciding_vertices_is_crossed_at_no_length() {
        let p = |x: f64, y: f64| Vector3::new(x, y, 0.0);
        let positions = vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0),
            p(0.0, 1.0),
            p(1.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 1.0),
            p(1.0, 1.0),
        ];
        let triangles = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
        let edges = SurfaceEdges::new(&positions, &triangles);
        assert_eq!(edges.joined(), [0, 1, 2, 3, 1, 5, 6, 2]);
        let near = edges.within(&[0], 2.5);
        assert!((near[&5] - 2.0).abs() < 1e-9, "{near:?}");
        assert!((near[&6] - (1.0 + 2f64.sqrt())).abs() < 1e-9, "{near:?}");
        assert!(!edges.within(&[0], 2.2).contains_key(&6));
        assert!(edges.within(&[0], 1.5).keys().all(|&v| v != 5));
    }
}
