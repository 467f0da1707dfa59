//! A surface kept out of itself by an energy (issue 16, the nonlinear tier): the barrier of
//! incremental potential contact (Li et al. 2020, `barrier.rs`) summed over every pair of a
//! surface point and a facet of the same surface nearer than the barrier's reach d̂, beyond the
//! point's own neighbourhood (`OwnNeighbourhood`: flesh, not contact, keeps those apart):
//!
//!   B(u) = κ Σ A_p b(d²(p, t), d̂²),
//!
//! (A_p the surface's area around the point: the barrier is a pressure's, and refining the
//! surface does not add points' barriers to it; but a point within reach of several facets —
//! near their shared edge or corner — counts each, as in incremental potential contact's first
//! form, and more of them as the facets shrink below the reach) which grows without bound as a point comes onto a facet. Newton lowers the flesh's energy plus
//! B (`fem::newton::solve_increment_with`), so the press of skin on skin is part of the energy
//! it minimises — its line search, its escape from saddles and its regularised tangents work as
//! they do without contact — and each step is cut short before a point would pass through a
//! facet (continuous collision, `swept.rs`), so that from a state with no point through the
//! surface, no point goes through. The points and facets are the hand's smooth skin, embedded in
//! the flesh cells (`EmbeddedPoints`): a pair's gradient and Hessian reach the nodes through the
//! points' weights. Edges passing through edges are not seen (as in the increments' active set).
//!
//! Pairs already nearer than d̂ where the barrier is built (at rest: skin that meets skin at the
//! webs) are left out for good: skin that merely touches at rest does not lock.

use super::barrier::{barrier, pair_barrier, point_triangle_derivatives, point_triangle_distance2};
use super::bounds::Bounds;
use super::embedded::EmbeddedPoints;
use super::self_contact::OwnNeighbourhood;
use super::surface::ContactSurface;
use super::swept::passes_through;
use crate::fem::added_energy::{AddedEnergy, NodeBlock};
use nalgebra::{DMatrix, SMatrix, Vector3};
use rayon::prelude::*;
use std::collections::HashSet;
use std::sync::Arc;

/// Share of the way to a first crossing a step may go (continuous collision's margin).
const TO_CROSSING: f64 = 0.8;

/// The barrier over one surface's points and facets (see the module's text).
pub struct SelfBarrier {
    /// The points, embedded in the body's nodes (contact indices after the nodes).
    embedded: EmbeddedPoints,
    /// The nodes' positions the displacements are measured from, m.
    reference: Vec<Vector3<f64>>,
    /// The surface's facets (contact indices).
    surface: ContactSurface,
    /// The points that may press on facets (contact indices).
    points: Vec<usize>,
    /// The surface's area around each contact index (m²; 0 but at the points).
    area: Vec<f64>,
    /// Which facets each point may not meet.
    own: Arc<OwnNeighbourhood>,
    /// (point, facet) pairs within reach where the barrier was built: never held apart.
    at_start: HashSet<(usize, usize)>,
    /// The barrier's reach d̂, m.
    reach: f64,
    /// Its stiffness κ, N/m⁵ (b on squared distances, m⁴, times an area and κ: J).
    kappa: f64,
}

/// One pair within reach: its point and facet, and the 12 coordinates' contact indices.
struct Pair {
    point: usize,
    facet: [usize; 3],
}

impl SelfBarrier {
    /// The barrier of reach `reach` (m) and stiffness `kappa` over the points `points` (each
    /// with the surface's area around it, m²) against the facets `triangles` (contact indices
    /// of `embedded` over nodes at `reference`), each point kept from the facets `own` leaves
    /// it; pairs within reach at `start` (displacements from `reference`) are left out.
    pub fn new(
        embedded: EmbeddedPoints,
        reference: Vec<Vector3<f64>>,
        (triangles, points): (Vec<[usize; 3]>, Vec<(usize, f64)>),
        own: Arc<OwnNeighbourhood>,
        (reach, kappa): (f64, f64),
        start: &[f64],
    ) -> SelfBarrier {
        assert!(
            reach > 0.0 && kappa > 0.0,
            "a barrier's reach and stiffness are > 0"
        );
        let positions = place(&embedded, &reference, start);
        let surface = ContactSurface::new(0, triangles, &positions);
        let mut area = vec![0.0; positions.len()];
        for &(p, a) in &points {
            assert!(a >= 0.0 && a.is_finite(), "a point's area is ≥ 0");
            area[p] = a;
        }
        let points = points.into_iter().map(|(p, _)| p).collect();
        let mut barrier = SelfBarrier {
            embedded,
            reference,
            surface,
            points,
            area,
            own,
            at_start: HashSet::new(),
            reach,
            kappa,
        };
        barrier.at_start = barrier
            .pairs(&positions)
            .into_iter()
            .map(|(p, t, _)| (p, t))
            .collect();
        barrier
    }

    /// Leaves out for good the pairs nearer than `within` (m) at `u` (displacements from the
    /// reference): skin already pressed onto its own where the barrier starts (solved without
    /// it) cannot be held apart from there.
    pub fn leave_out_within(&mut self, u: &[f64], within: f64) {
        let positions = place(&self.embedded, &self.reference, u);
        let near: Vec<(usize, usize)> = self
            .pairs(&positions)
            .into_iter()
            .filter(|&(_, _, d2)| d2 < within * within)
            .map(|(p, t, _)| (p, t))
            .collect();
        self.at_start.extend(near);
    }

    /// The barrier's reach d̂, m.
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// Every (point, facet index, squared distance) nearer than the reach at `positions`,
    /// but a point's own facets.
    fn pairs(&self, positions: &[Vector3<f64>]) -> Vec<(usize, usize, f64)> {
        let bvh = self.surface.hierarchy(positions, self.reach);
        let reach2 = self.reach * self.reach;
        self.points
            .par_iter()
            .flat_map_iter(|&v| {
                let x = positions[v];
                bvh.facets_meeting(&Bounds::of([&x]))
                    .into_iter()
                    .filter_map(move |t| {
                        let facet = self.surface.triangles[t];
                        if self.own.excludes(v, &facet) {
                            return None;
                        }
                        let [a, b, c] = facet.map(|n| positions[n]);
                        let d2 = point_triangle_distance2(&x, &a, &b, &c);
                        (d2 < reach2).then_some((v, t, d2))
                    })
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// The pairs held apart at `positions` (within reach, not left out).
    fn active(&self, positions: &[Vector3<f64>]) -> Vec<(Pair, f64)> {
        self.pairs(positions)
            .into_iter()
            .filter(|(p, t, _)| !self.at_start.contains(&(*p, *t)))
            .map(|(point, t, d2)| {
                (
                    Pair {
                        point,
                        facet: self.surface.triangles[t],
                    },
                    d2,
                )
            })
            .collect()
    }

    /// The pair's four points' corners, in the order (point, facet's three).
    fn corners(pair: &Pair) -> [usize; 4] {
        [pair.point, pair.facet[0], pair.facet[1], pair.facet[2]]
    }

    /// The force each contact index feels from the barrier at `u` (N, the magnitude of −∂B/∂x
    /// of that point), the pairs held and the sum of the points' forces (N).
    pub fn forces(&self, u: &[f64]) -> (Vec<f64>, usize, f64) {
        let positions = place(&self.embedded, &self.reference, u);
        let mut out = vec![0.0; positions.len()];
        let (mut count, mut total) = (0, 0.0);
        let reach2 = self.reach * self.reach;
        for (pair, _) in self.active(&positions) {
            let c = Self::corners(&pair);
            let [p, a, b, cc] = c.map(|i| positions[i]);
            if let Some(e) =
                pair_barrier(&p, &a, &b, &cc, reach2, self.kappa * self.area[pair.point])
            {
                if !e.energy.is_finite() {
                    continue;
                }
                count += 1;
                for (k, &i) in c.iter().enumerate() {
                    let f = e.gradient.fixed_rows::<3>(3 * k).norm();
                    out[i] += f;
                    if k == 0 {
                        total += f;
                    }
                }
            }
        }
        (out, count, total)
    }

    /// The nodes (and their weights) of the pair's 12 coordinates, as a dense map W (3N × 12)
    /// from the four points' coordinates to the nodes' (x = Wᵀ·u per point).
    fn weights(&self, corners: &[usize; 4]) -> (Vec<usize>, DMatrix<f64>) {
        let mut nodes: Vec<usize> = Vec::new();
        let mut terms: Vec<(usize, usize, f64)> = Vec::new();
        for (k, &c) in corners.iter().enumerate() {
            self.embedded.for_each(c, |n, w| {
                let at = match nodes.iter().position(|&m| m == n) {
                    Some(at) => at,
                    None => {
                        nodes.push(n);
                        nodes.len() - 1
                    }
                };
                terms.push((at, k, w));
            });
        }
        let mut w = DMatrix::zeros(3 * nodes.len(), 12);
        for (at, k, weight) in terms {
            for a in 0..3 {
                w[(3 * at + a, 3 * k + a)] += weight;
            }
        }
        (nodes, w)
    }
}

impl AddedEnergy for SelfBarrier {
    fn energy(&self, u: &[f64], gradient: &mut [f64]) -> Option<f64> {
        let positions = place(&self.embedded, &self.reference, u);
        let reach2 = self.reach * self.reach;
        let mut energy = 0.0;
        let mut grad = vec![0.0; gradient.len()];
        for (pair, d2) in self.active(&positions) {
            if d2 <= 0.0 {
                return None;
            }
            let c = Self::corners(&pair);
            let [p, a, b, cc] = c.map(|i| positions[i]);
            let Some(e) = pair_barrier(&p, &a, &b, &cc, reach2, self.kappa * self.area[pair.point])
            else {
                continue;
            };
            if !e.energy.is_finite() {
                return None;
            }
            energy += e.energy;
            for (k, &i) in c.iter().enumerate() {
                let g: Vector3<f64> = e.gradient.fixed_rows::<3>(3 * k).into_owned();
                self.embedded.for_each(i, |n, w| {
                    for a in 0..3 {
                        grad[3 * n + a] += w * g[a];
                    }
                });
            }
        }
        for (g, d) in gradient.iter_mut().zip(grad) {
            *g += d;
        }
        Some(energy)
    }

    fn hessian(&self, u: &[f64], projected: bool) -> Vec<NodeBlock> {
        let positions = place(&self.embedded, &self.reference, u);
        let reach2 = self.reach * self.reach;
        self.active(&positions)
            .into_par_iter()
            .filter_map(|(pair, d2)| {
                let c = Self::corners(&pair);
                let [p, a, b, cc] = c.map(|i| positions[i]);
                let kappa = self.kappa * self.area[pair.point];
                if d2.is_nan() || d2 <= 0.0 {
                    return None;
                }
                let h: SMatrix<f64, 12, 12> = if projected {
                    pair_barrier(&p, &a, &b, &cc, reach2, kappa)?.hessian
                } else {
                    // (The exact Hessian: no eigen-decomposition to throw away.)
                    let dist = point_triangle_derivatives(&p, &a, &b, &cc);
                    let (_, de, dde) = barrier(dist.d2, reach2);
                    let g = &dist.gradient;
                    (g * g.transpose() * dde + dist.hessian * de) * kappa
                };
                let (nodes, w) = self.weights(&c);
                let h = DMatrix::from_fn(12, 12, |i, j| h[(i, j)]);
                let matrix = &w * h * w.transpose();
                Some(NodeBlock { nodes, matrix })
            })
            .collect()
    }

    fn largest_step(&self, u: &[f64], du: &[f64]) -> f64 {
        let start = place(&self.embedded, &self.reference, u);
        let end_u: Vec<f64> = u.iter().zip(du).map(|(a, b)| a + b).collect();
        let end = place(&self.embedded, &self.reference, &end_u);
        let bvh = self.surface.swept_hierarchy(&start, &end);
        let first = self
            .points
            .par_iter()
            .map(|&v| {
                let path = Bounds::of([&start[v], &end[v]]);
                let mut first = 1.0f64;
                for t in bvh.facets_meeting(&path) {
                    let facet = self.surface.triangles[t];
                    if self.own.excludes(v, &facet) || self.at_start.contains(&(v, t)) {
                        continue;
                    }
                    let (s, e) = (facet.map(|n| start[n]), facet.map(|n| end[n]));
                    // Either way through: the facet as it is, and turned over.
                    let flip = |q: [Vector3<f64>; 3]| [q[0], q[2], q[1]];
                    let ways = [
                        passes_through([&start[v], &end[v]], &s, &e),
                        passes_through([&start[v], &end[v]], &flip(s), &flip(e)),
                    ];
                    for t in ways.into_iter().flatten() {
                        first = first.min(t);
                    }
                }
                first
            })
            .reduce(|| 1.0, f64::min);
        if first >= 1.0 {
            1.0
        } else {
            TO_CROSSING * first
        }
    }
}

/// The contact indices' positions (nodes, then embedded points) for nodal displacements `u`
/// from `reference`.
fn place(embedded: &EmbeddedPoints, reference: &[Vector3<f64>], u: &[f64]) -> Vec<Vector3<f64>> {
    let nodes: Vec<Vector3<f64>> = reference
        .iter()
        .enumerate()
        .map(|(n, x)| x + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
        .collect();
    embedded.extend(&nodes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two strips of 1 mm squares along x, one facing up at z = 0 and one facing down at
    /// `gap` (m) above it (offset along x and y): node positions and triangles (the nodes are the points).
    fn strips(gap: f64) -> (Vec<Vector3<f64>>, Vec<[usize; 3]>) {
        let mut nodes = Vec::new();
        let mut triangles = Vec::new();
        // (The upper strip offset along both axes: its points off the lower one's edges,
        // where the distance's Hessian jumps between the formulas of a face and an edge.)
        for (z, up, off) in [(0.0, true, 0.0), (gap, false, 0.3e-3)] {
            let first = nodes.len();
            for i in 0..=6 {
                for j in 0..=1 {
                    nodes.push(Vector3::new(
                        i as f64 * 1e-3 + off,
                        j as f64 * 1e-3 + 0.7 * off,
                        z,
                    ));
                }
            }
            let v = |i: usize, j: usize| first + 2 * i + j;
            for i in 0..6 {
                let (a, b, c, d) = (v(i, 0), v(i + 1, 0), v(i + 1, 1), v(i, 1));
                triangles.extend(if up {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, c, b], [a, d, c]]
                });
            }
        }
        (nodes, triangles)
    }

    /// The strips 2 mm apart where the barrier is built (reach 0.5 mm, κ = 10¹⁵ N/m⁵, 1 mm² a
    /// point).
    fn barrier() -> (SelfBarrier, usize) {
        barrier_at(2e-3)
    }

    /// The barrier over the strips `gap` apart where it is built.
    fn barrier_at(gap: f64) -> (SelfBarrier, usize) {
        let (nodes, triangles) = strips(gap);
        let n = nodes.len();
        let own = OwnNeighbourhood::new(nodes.clone(), &triangles, 0.5e-3, (0.0, 0.0), 0.0);
        let b = SelfBarrier::new(
            EmbeddedPoints::none(n),
            nodes,
            (triangles, (0..n).map(|p| (p, 1e-6)).collect()),
            Arc::new(own),
            (0.5e-3, 1e15),
            &vec![0.0; 3 * n],
        );
        (b, n)
    }

    /// The upper strip moved down by `down` (m) and tilted about x by `tilt` (m per m of y).
    fn moved(n: usize, down: f64, tilt: f64) -> Vec<f64> {
        let mut u = vec![0.0; 3 * n];
        for i in n / 2..n {
            let y = ((i - n / 2) % 2) as f64 * 1e-3;
            u[3 * i + 2] = -down + tilt * y;
        }
        u
    }

    #[test]
    fn the_gradient_and_hessian_are_the_energys_derivatives_and_push_the_strips_apart() {
        let (b, n) = barrier();
        let u = moved(n, 1.7e-3, 0.1);
        let mut g = vec![0.0; 3 * n];
        let e = b.energy(&u, &mut g).unwrap();
        assert!(e > 0.0 && e.is_finite());
        // The upper strip is pushed up, the lower one down; the forces balance.
        let up: f64 = (n / 2..n).map(|i| -g[3 * i + 2]).sum();
        let down: f64 = (0..n / 2).map(|i| -g[3 * i + 2]).sum();
        assert!(up > 0.0 && (up + down).abs() < 1e-9 * up, "{up} {down}");
        let h = 1e-6;
        let blocks = b.hessian(&u, false);
        let dir: Vec<f64> = (0..3 * n).map(|i| ((i * 7) % 5) as f64 - 2.0).collect();
        let mut hd = vec![0.0; 3 * n];
        for blk in &blocks {
            for (r, &a) in blk.nodes.iter().enumerate() {
                for (c, &m) in blk.nodes.iter().enumerate() {
                    for i in 0..3 {
                        for j in 0..3 {
                            hd[3 * a + i] += blk.matrix[(3 * r + i, 3 * c + j)] * dir[3 * m + j];
                        }
                    }
                }
            }
        }
        let at = |s: f64| {
            let v: Vec<f64> = u.iter().zip(&dir).map(|(a, d)| a + s * d * 1e-3).collect();
            let mut g = vec![0.0; 3 * n];
            let e = b.energy(&v, &mut g).unwrap();
            (e, g)
        };
        let ((ep, gp), (em, gm)) = (at(h), at(-h));
        let slope: f64 = g.iter().zip(&dir).map(|(a, d)| a * d * 1e-3).sum();
        let fd = (ep - em) / (2.0 * h);
        assert!((slope - fd).abs() < 1e-5 * slope.abs(), "{slope} {fd}");
        let scale = hd.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for k in 0..3 * n {
            let fd = (gp[k] - gm[k]) / (2.0 * h * 1e-3);
            assert!((hd[k] - fd).abs() < 1e-4 * scale, "dof {k}: {} {fd}", hd[k]);
        }
        // Projected, every block is positive semi-definite.
        for blk in b.hessian(&u, true) {
            let least = blk.matrix.symmetric_eigenvalues().min();
            assert!(least > -1e-9 * blk.matrix.norm(), "{least}");
        }
    }

    #[test]
    fn a_step_through_the_other_strip_is_cut_short_of_the_crossing() {
        let (b, n) = barrier();
        let u = vec![0.0; 3 * n];
        // 4 mm down from 2 mm above: through the lower strip half way.
        let alpha = b.largest_step(&u, &moved(n, 4e-3, 0.0));
        assert!((alpha - TO_CROSSING * 0.5).abs() < 1e-9, "{alpha}");
        // 1 mm down stays clear; so does a step along the strips.
        assert_eq!(b.largest_step(&u, &moved(n, 1e-3, 0.0)), 1.0);
        // On each other: not admissible.
        let mut g = vec![0.0; 3 * n];
        assert!(b.energy(&moved(n, 2e-3, 0.0), &mut g).is_none());
        // Beyond the reach: nothing.
        assert_eq!(b.energy(&moved(n, 1e-3, 0.0), &mut g), Some(0.0));
    }

    #[test]
    fn pairs_within_reach_where_it_starts_are_left_out() {
        let (b, n) = barrier_at(0.2e-3);
        let mut g = vec![0.0; 3 * n];
        assert_eq!(b.energy(&vec![0.0; 3 * n], &mut g), Some(0.0));
        assert!(g.iter().all(|&x| x == 0.0));
    }
}
