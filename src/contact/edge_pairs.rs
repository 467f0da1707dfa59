//! A surface's edges, for the barrier that keeps it out of itself (`self_barrier.rs`): two
//! closed surfaces that did not cross come to cross only where a point passes through a facet
//! or an edge through an edge, so the barrier holds point–facet pairs and edge–edge pairs
//! apart. Here: the surface's edges (each once, the facets' diagonals too), each edge's share
//! of the surface's area (a third of the facets on either side: the shares sum to the
//! surface's area), the pairs of edges within reach of each other, and the first time an edge
//! passes through another over a step (`swept::edges_cross`).
//!
//! Two edges with a common end, or with an end within the radius of an end of the other along
//! the surface and every end of each within 1.5 radii of an end of the other
//! (`OwnNeighbourhood`), are the same flesh: flesh, not contact, keeps them apart.

use super::bounds::Bounds;
use super::edge_edge::edge_edge_distance2;
use super::self_contact::OwnNeighbourhood;
use super::surface::SurfaceBvh;
use super::swept::edges_cross;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};

/// In a facet's edges: one left out (too short).
const NONE: usize = usize::MAX;

/// A surface's edges (see the module's text).
pub(super) struct SurfaceEdgeSet {
    /// Each edge's ends (contact indices, the smaller first).
    pub edges: Vec<[usize; 2]>,
    /// Each edge's share of the surface's area, m².
    pub area: Vec<f64>,
    /// Each edge at rest, from its first end to its second, m (the mollifier of nearly
    /// parallel edges).
    pub rest: Vec<Vector3<f64>>,
    /// Each facet's three edges ([`NONE`] where left out).
    by_facet: Vec<[usize; 3]>,
}

impl SurfaceEdgeSet {
    /// The edges of the facets `triangles` (contact indices) over the positions `rest`, but
    /// those shorter than `shortest` (m; a split seam's slivers, two corners equal to
    /// round-off: an edge passing through one is a point passing through an edge, which the
    /// points against the facets see, and the mollifier of so short an edge would be
    /// round-off).
    pub fn new(triangles: &[[usize; 3]], rest: &[Vector3<f64>], shortest: f64) -> SurfaceEdgeSet {
        let mut index: HashMap<[usize; 2], usize> = HashMap::new();
        let (mut edges, mut area, mut by_facet) = (Vec::new(), Vec::new(), Vec::new());
        for t in triangles {
            let [a, b, c] = t.map(|n| rest[n]);
            let third = (b - a).cross(&(c - a)).norm() / 6.0;
            let mut mine = [NONE; 3];
            for (k, (i, j)) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
                .into_iter()
                .enumerate()
            {
                if (rest[j] - rest[i]).norm() < shortest {
                    continue;
                }
                let key = [i.min(j), i.max(j)];
                let e = *index.entry(key).or_insert_with(|| {
                    edges.push(key);
                    area.push(0.0);
                    edges.len() - 1
                });
                area[e] += third;
                mine[k] = e;
            }
            by_facet.push(mine);
        }
        let rest = edges
            .iter()
            .map(|&[i, j]: &[usize; 2]| rest[j] - rest[i])
            .collect();
        SurfaceEdgeSet {
            edges,
            area,
            rest,
            by_facet,
        }
    }

    /// The edges of the facets whose boxes `bvh` finds meeting `query`, each once, into
    /// `found` (emptied first: a worker's buffer, used again edge after edge).
    fn candidates(&self, bvh: &SurfaceBvh, query: &Bounds, found: &mut Vec<usize>) {
        found.clear();
        found.extend(
            bvh.facets_meeting_iter(query)
                .flat_map(|t| self.by_facet[t])
                .filter(|&e| e != NONE),
        );
        found.sort_unstable();
        found.dedup();
    }

    /// Every pair of edges (e, f), e < f, nearer than `reach` at `positions` and not the same
    /// flesh by `own`, with its squared distance; `bvh` holds the surface's facets at
    /// `positions` grown by `reach`.
    pub fn near_pairs(
        &self,
        bvh: &SurfaceBvh,
        positions: &[Vector3<f64>],
        reach: f64,
        own: &OwnNeighbourhood,
    ) -> Vec<(usize, usize, f64)> {
        let reach2 = reach * reach;
        // (Each worker's candidates in one buffer; the pairs in the order of e, then f.)
        (0..self.edges.len())
            .into_par_iter()
            .fold(
                || (Vec::new(), Vec::new()),
                |(mut out, mut found): (Vec<(usize, usize, f64)>, Vec<usize>), e| {
                    let [a0, a1] = self.edges[e].map(|n| positions[n]);
                    self.candidates(bvh, &Bounds::of([&a0, &a1]), &mut found);
                    for &f in &found {
                        if f <= e || own.excludes_edge(&self.edges[e], &self.edges[f]) {
                            continue;
                        }
                        let [b0, b1] = self.edges[f].map(|n| positions[n]);
                        let d2 = edge_edge_distance2(&a0, &a1, &b0, &b1);
                        if d2 < reach2 {
                            out.push((e, f, d2));
                        }
                    }
                    (out, found)
                },
            )
            .map(|(out, _)| out)
            .reduce(Vec::new, |mut a, mut b| {
                a.append(&mut b);
                a
            })
    }

    /// The first share t ∈ [0, 1] of the step from `start` to `end` at which an edge passes
    /// through another (1 if none does), but pairs that are the same flesh by `own` and the
    /// pairs `left_out`; `bvh` holds the facets' boxes swept over the step.
    pub fn first_crossing(
        &self,
        bvh: &SurfaceBvh,
        (start, end): (&[Vector3<f64>], &[Vector3<f64>]),
        own: &OwnNeighbourhood,
        left_out: &HashSet<(usize, usize)>,
    ) -> f64 {
        (0..self.edges.len())
            .into_par_iter()
            .map_init(Vec::new, |found, e| {
                let [i, j] = self.edges[e];
                let path = Bounds::of([&start[i], &start[j], &end[i], &end[j]]);
                let mut first = 1.0f64;
                self.candidates(bvh, &path, found);
                for &f in found.iter() {
                    if f <= e
                        || own.excludes_edge(&self.edges[e], &self.edges[f])
                        || left_out.contains(&(e, f))
                    {
                        continue;
                    }
                    let [k, l] = self.edges[f];
                    let corners = |x: &[Vector3<f64>]| [x[i], x[j], x[k], x[l]];
                    if let Some(t) = edges_cross(&corners(start), &corners(end)) {
                        first = first.min(t);
                    }
                }
                first
            })
            .reduce(|| 1.0, f64::min)
    }
}
