//! A surface kept out of itself by an energy (issue 16, the nonlinear tier): the barrier of
//! incremental potential contact (Li et al. 2020, `barrier.rs`) summed over every pair of a
//! surface point and a facet of the same surface nearer than the barrier's reach d̂, and every
//! pair of the surface's edges nearer than d̂ (`edge_edge.rs`, `edge_pairs.rs`), beyond their
//! own neighbourhood (`OwnNeighbourhood`: flesh, not contact, keeps those apart):
//!
//!   B(u) = κ Σ A_p b(d²(p, t), d̂²) + κ Σ (A_e + A_f) m(e, f) b(d²(e, f), d̂²),
//!
//! (A_p the surface's area around the point, A_e an edge's share of it — a third of the facets
//! on either side: the barrier is a pressure's, and refining the surface does not add points'
//! barriers to it; but a point within reach of several facets — near their shared edge or
//! corner — counts each, as in incremental potential contact's first form, and more of them as
//! the facets shrink below the reach; m fades the barrier of nearly parallel edges, whose ends
//! against the facets hold them) which grows without bound as a point comes onto a facet or an
//! edge onto an edge. Two closed surfaces that did not cross come to cross only where a point
//! passes through a facet or an edge through an edge: with both held, none does. Newton lowers
//! the flesh's energy plus B (`fem::newton::solve_increment_with`), so the press of skin on
//! skin is part of the energy it minimises — its line search, its escape from saddles and its
//! regularised tangents work as they do without contact — and each step is cut short before a
//! point would pass through a facet or an edge through an edge (continuous collision,
//! `swept.rs`), so that from a state with the surface clear of itself, it stays clear. The
//! points and facets are the hand's smooth skin, embedded in the flesh cells
//! (`EmbeddedPoints`): a pair's gradient and Hessian reach the nodes through the points'
//! weights.
//!
//! Pairs already nearer than d̂ where the barrier is built (at rest: skin that meets skin at the
//! webs) are left out for good: skin that merely touches at rest does not lock.

use super::barrier::{pair_barrier, point_triangle_distance2, PairBarrier};
use super::bounds::Bounds;
use super::edge_edge::{edge_edge_mollifier_threshold, edge_pair_barrier};
use super::edge_pairs::SurfaceEdgeSet;
use super::embedded::EmbeddedPoints;
use super::self_contact::OwnNeighbourhood;
use super::surface::{ContactSurface, SurfaceBvh};
use super::swept::passes_through;
use crate::fem::added_energy::{AddedEnergy, NodeBlock};
use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use std::collections::HashSet;
use std::sync::{Arc, Mutex};

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
    /// The surface's edges.
    edges: SurfaceEdgeSet,
    /// The points that may press on facets (contact indices).
    points: Vec<usize>,
    /// The surface's area around each contact index (m²; 0 but at the points).
    area: Vec<f64>,
    /// Which facets each point may not meet.
    own: Arc<OwnNeighbourhood>,
    /// (point, facet) pairs within reach where the barrier was built: never held apart.
    at_start: HashSet<(usize, usize)>,
    /// (edge, edge) pairs within reach where the barrier was built: never held apart.
    edges_at_start: HashSet<(usize, usize)>,
    /// The barrier's reach d̂, m.
    reach: f64,
    /// Its stiffness κ, N/m⁵ (b on squared distances, m⁴, times an area and κ: J).
    kappa: f64,
    /// The pairs found at the last positions asked: a Newton iteration asks for them at one
    /// iterate up to three times (its energy in the line search that chose it, its Hessian,
    /// its Hessian projected), and finding them is most of the barrier's cost.
    last: Mutex<Option<FoundAt>>,
}

/// The pairs found at some positions, and the positions.
type FoundAt = (Vec<Vector3<f64>>, Arc<Vec<Pair>>);

/// One pair within reach: its four corners (contact indices: a point and a facet's three, or
/// two edges' ends), which it is, its share of the surface's area (m²) and its squared distance
/// (m²).
struct Pair {
    corners: [usize; 4],
    kind: Kind,
    area: f64,
    d2: f64,
}

/// Which a pair is.
#[derive(Clone, Copy)]
enum Kind {
    /// A point (the first corner) and a facet.
    PointFacet,
    /// Two edges; the mollifier's threshold on |e × f|² (m⁴) that fades the barrier of nearly
    /// parallel edges (whose points against facets hold them).
    EdgeEdge(f64),
}

impl SelfBarrier {
    /// The barrier of reach `reach` (m) and stiffness `kappa` over the points `points` (each
    /// with the surface's area around it, m²) against the facets `triangles` (contact indices
    /// of `embedded` over nodes at `reference`), and over the facets' edges against each other,
    /// each point (edge) kept from the facets (edges) `own` leaves it; pairs within reach at
    /// `start` (displacements from `reference`) are left out.
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
        let rest = place(&embedded, &reference, &vec![0.0; 3 * reference.len()]);
        // (Edges shorter than a millionth of the reach: a seam's slivers.)
        let edges = SurfaceEdgeSet::new(&triangles, &rest, 1e-6 * reach);
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
            edges,
            points,
            area,
            own,
            at_start: HashSet::new(),
            edges_at_start: HashSet::new(),
            reach,
            kappa,
            last: Mutex::new(None),
        };
        barrier.leave_out_within(start, f64::INFINITY);
        barrier
    }

    /// Leaves out for good the pairs nearer than `within` (m) at `u` (displacements from the
    /// reference): skin already pressed onto its own where the barrier starts (solved without
    /// it) cannot be held apart from there.
    pub fn leave_out_within(&mut self, u: &[f64], within: f64) {
        let positions = place(&self.embedded, &self.reference, u);
        let within2 = within * within;
        let bvh = self.surface.hierarchy(&positions, self.reach);
        let near: Vec<(usize, usize)> = self
            .pairs(&positions, &bvh)
            .into_iter()
            .filter(|&(_, _, d2)| d2 < within2)
            .map(|(p, t, _)| (p, t))
            .collect();
        self.at_start.extend(near);
        let near: Vec<(usize, usize)> = self
            .edges
            .near_pairs(&bvh, &positions, self.reach, &self.own)
            .into_iter()
            .filter(|&(_, _, d2)| d2 < within2)
            .map(|(e, f, _)| (e, f))
            .collect();
        self.edges_at_start.extend(near);
        // (The pairs found before may hold some left out now.)
        *self.last.get_mut().unwrap_or_else(|e| e.into_inner()) = None;
    }

    /// The barrier's reach d̂, m.
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// Every (point, facet index, squared distance) nearer than the reach at `positions`,
    /// but a point's own facets.
    fn pairs(&self, positions: &[Vector3<f64>], bvh: &SurfaceBvh) -> Vec<(usize, usize, f64)> {
        let reach2 = self.reach * self.reach;
        self.points
            .par_iter()
            .flat_map_iter(|&v| {
                let x = positions[v];
                bvh.facets_meeting_iter(&Bounds::of([&x]))
                    .filter_map(move |t| {
                        let facet = self.surface.triangles[t];
                        if self.own.excludes(v, &facet) {
                            return None;
                        }
                        let [a, b, c] = facet.map(|n| positions[n]);
                        let d2 = point_triangle_distance2(&x, &a, &b, &c);
                        (d2 < reach2).then_some((v, t, d2))
                    })
            })
            .collect()
    }

    /// The pairs held apart at `positions` (within reach, not left out): points against
    /// facets, then edges against edges; found again only where the positions are not the
    /// last asked for.
    fn active(&self, positions: &[Vector3<f64>]) -> Arc<Vec<Pair>> {
        let lock = || self.last.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((at, pairs)) = lock().as_ref() {
            if at.as_slice() == positions {
                return pairs.clone();
            }
        }
        // (Found with the lock released: the search runs on the thread pool, whose threads
        // may take up other work meanwhile.)
        let pairs = Arc::new(self.find_active(positions));
        *lock() = Some((positions.to_vec(), pairs.clone()));
        pairs
    }

    /// [`SelfBarrier::active`], found.
    fn find_active(&self, positions: &[Vector3<f64>]) -> Vec<Pair> {
        let bvh = self.surface.hierarchy(positions, self.reach);
        let points = self
            .pairs(positions, &bvh)
            .into_iter()
            .filter(|(p, t, _)| !self.at_start.contains(&(*p, *t)))
            .map(|(point, t, d2)| {
                let [a, b, c] = self.surface.triangles[t];
                Pair {
                    corners: [point, a, b, c],
                    kind: Kind::PointFacet,
                    area: self.area[point],
                    d2,
                }
            });
        let edges = self
            .edges
            .near_pairs(&bvh, positions, self.reach, &self.own)
            .into_iter()
            .filter(|(e, f, _)| !self.edges_at_start.contains(&(*e, *f)))
            .map(|(e, f, d2)| {
                let ([a0, a1], [b0, b1]) = (self.edges.edges[e], self.edges.edges[f]);
                let (ea, eb, o) = (self.edges.rest[e], self.edges.rest[f], Vector3::zeros());
                Pair {
                    corners: [a0, a1, b0, b1],
                    kind: Kind::EdgeEdge(edge_edge_mollifier_threshold(&o, &ea, &o, &eb)),
                    // (Each pair of edges is counted once, each point against a facet from
                    // both sides: the two edges' shares.)
                    area: self.edges.area[e] + self.edges.area[f],
                    d2,
                }
            });
        points.chain(edges).collect()
    }

    /// The pair's barrier at `positions` (`None` beyond reach; energy +∞ where it touches or
    /// crosses), its Hessian projected or exact.
    fn evaluate(
        &self,
        pair: &Pair,
        positions: &[Vector3<f64>],
        projected: bool,
    ) -> Option<PairBarrier> {
        let [x0, x1, x2, x3] = pair.corners.map(|i| positions[i]);
        let (reach2, kappa) = (self.reach * self.reach, self.kappa * pair.area);
        let exact = match pair.kind {
            Kind::PointFacet => pair_barrier(&x0, &x1, &x2, &x3, reach2, kappa)?,
            Kind::EdgeEdge(threshold) => {
                edge_pair_barrier(&x0, &x1, &x2, &x3, threshold, reach2, kappa)?
            }
        };
        Some(if projected { exact.projected() } else { exact })
    }

    /// The force each contact index feels from the barrier at `u` (N, the magnitude of −∂B/∂x
    /// of that point), the pairs held and the press: the sum of the forces on the pairs' one
    /// side (a point's; of two edges, half what their four ends feel), N.
    pub fn forces(&self, u: &[f64]) -> (Vec<f64>, usize, f64) {
        let positions = place(&self.embedded, &self.reference, u);
        let mut out = vec![0.0; positions.len()];
        let (mut count, mut total) = (0, 0.0);
        for pair in self.active(&positions).iter() {
            let Some(PairBarrier {
                energy, gradient, ..
            }) = self.evaluate(pair, &positions, false)
            else {
                continue;
            };
            if !energy.is_finite() {
                continue;
            }
            count += 1;
            let mut felt = 0.0;
            for (k, &i) in pair.corners.iter().enumerate() {
                let f = gradient.fixed_rows::<3>(3 * k).norm();
                out[i] += f;
                felt += f;
                if k == 0 && matches!(pair.kind, Kind::PointFacet) {
                    total += f;
                }
            }
            if let Kind::EdgeEdge(_) = pair.kind {
                // Half what its four ends feel: each edge's, but where the pair's barrier fades
                // (nearly parallel edges) its fading turns the ends' forces apart, unequally.
                total += 0.5 * felt;
            }
        }
        (out, count, total)
    }
}

impl AddedEnergy for SelfBarrier {
    fn energy(&self, u: &[f64], gradient: &mut [f64]) -> Option<f64> {
        let positions = place(&self.embedded, &self.reference, u);
        let mut energy = 0.0;
        let mut grad = vec![0.0; gradient.len()];
        for pair in self.active(&positions).iter() {
            if pair.d2 <= 0.0 {
                return None;
            }
            let Some(PairBarrier {
                energy: e,
                gradient: g,
                ..
            }) = self.evaluate(pair, &positions, false)
            else {
                continue;
            };
            if !e.is_finite() {
                return None;
            }
            energy += e;
            for (k, &i) in pair.corners.iter().enumerate() {
                let g: Vector3<f64> = g.fixed_rows::<3>(3 * k).into_owned();
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

    /// The pairs' 12 × 12 Hessians summed over the contact indices they share, then carried
    /// to the nodes through the embedding weights: one block per pair of nodes coupled (the
    /// pairs of a press share most of their corners, and each corner reaches up to eight
    /// nodes, so summing first spares the tangent's assembly most of its work).
    fn hessian(&self, u: &[f64], projected: bool) -> Vec<NodeBlock> {
        let positions = place(&self.embedded, &self.reference, u);
        let pairs: Vec<([usize; 4], SMatrix<f64, 12, 12>)> = self
            .active(&positions)
            .par_iter()
            .filter_map(|pair| {
                if pair.d2.is_nan() || pair.d2 <= 0.0 {
                    return None;
                }
                let h = self.evaluate(pair, &positions, projected)?.hessian;
                Some((pair.corners, h))
            })
            .collect();
        // Over the contact indices, every ordered pair of corners; each sum taken in the
        // pairs' order and the sums then put in the order of their keys: the same to the last
        // bit from run to run. (Hashed, not in a tree as until 2026-12-07: the nodes' sums
        // below are a million updates in a closed fist.)
        let mut corners: FxHashMap<(usize, usize), Matrix3<f64>> = FxHashMap::default();
        for (c, h) in &pairs {
            for (k, &ck) in c.iter().enumerate() {
                for (l, &cl) in c.iter().enumerate() {
                    *corners.entry((ck, cl)).or_insert_with(Matrix3::zeros) +=
                        h.fixed_view::<3, 3>(3 * k, 3 * l);
                }
            }
        }
        let mut corners: Vec<((usize, usize), Matrix3<f64>)> = corners.into_iter().collect();
        corners.sort_unstable_by_key(|(key, _)| *key);
        // Over the nodes, the upper triangle (node n's rows against node m's columns, n ≤ m).
        let mut nodes: FxHashMap<(usize, usize), Matrix3<f64>> = FxHashMap::default();
        for &((ck, cl), block) in &corners {
            self.embedded.for_each(ck, |n, wn| {
                self.embedded.for_each(cl, |m, wm| {
                    if n <= m {
                        *nodes.entry((n, m)).or_insert_with(Matrix3::zeros) += block * (wn * wm);
                    }
                });
            });
        }
        let mut nodes: Vec<((usize, usize), Matrix3<f64>)> = nodes.into_iter().collect();
        nodes.sort_unstable_by_key(|(key, _)| *key);
        nodes
            .into_iter()
            .map(|((n, m), block)| {
                if n == m {
                    let matrix = DMatrix::from_fn(3, 3, |i, j| block[(i, j)]);
                    NodeBlock {
                        nodes: vec![n],
                        matrix,
                    }
                } else {
                    let mut matrix = DMatrix::zeros(6, 6);
                    matrix.view_mut((0, 3), (3, 3)).copy_from(&block);
                    matrix
                        .view_mut((3, 0), (3, 3))
                        .copy_from(&block.transpose());
                    NodeBlock {
                        nodes: vec![n, m],
                        matrix,
                    }
                }
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
                for t in bvh.facets_meeting_iter(&path) {
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
        let first = first.min(self.edges.first_crossing(
            &bvh,
            (&start, &end),
            &self.own,
            &self.edges_at_start,
        ));
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
        (barrier_over(nodes, triangles), n)
    }

    /// The barrier (reach 0.5 mm, κ = 10¹⁵ N/m⁵, 1 mm² a point) over the surface `triangles`
    /// on `nodes` (the nodes are the points), built where they are.
    fn barrier_over(nodes: Vec<Vector3<f64>>, triangles: Vec<[usize; 3]>) -> SelfBarrier {
        let n = nodes.len();
        let own = OwnNeighbourhood::new(nodes.clone(), &triangles, 0.5e-3, (0.0, 0.0), 0.0);
        SelfBarrier::new(
            EmbeddedPoints::none(n),
            nodes,
            (triangles, (0..n).map(|p| (p, 1e-6)).collect()),
            Arc::new(own),
            (0.5e-3, 1e15),
            &vec![0.0; 3 * n],
        )
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
        // Projected, the blocks sum to a positive semi-definite matrix (each pair's is).
        let mut sum = DMatrix::<f64>::zeros(3 * n, 3 * n);
        for blk in b.hessian(&u, true) {
            for (r, &a) in blk.nodes.iter().enumerate() {
                for (c, &m) in blk.nodes.iter().enumerate() {
                    let mut to = sum.view_mut((3 * a, 3 * m), (3, 3));
                    to += blk.matrix.view((3 * r, 3 * c), (3, 3));
                }
            }
        }
        let least = sum.clone().symmetric_eigenvalues().min();
        assert!(least > -1e-9 * sum.norm(), "{least}");
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

    #[test]
    fn the_pairs_found_at_an_iterate_serve_its_hessian_but_not_a_barrier_that_left_them_out() {
        let (mut b, n) = barrier();
        let u = moved(n, 1.7e-3, 0.1);
        let mut g = vec![0.0; 3 * n];
        let e = b.energy(&u, &mut g).unwrap();
        assert!(e > 0.0);
        // The Hessian at the same iterate: the same pairs, found once.
        let at = place(&b.embedded, &b.reference, &u);
        let first = b.active(&at);
        assert!(!b.hessian(&u, false).is_empty());
        assert!(Arc::ptr_eq(&first, &b.active(&at)));
        // Elsewhere, found again: 0.1 mm lower, nearer, more energy.
        let lower = moved(n, 1.8e-3, 0.1);
        assert!(b.energy(&lower, &mut vec![0.0; 3 * n]).unwrap() > e);
        // The pairs within reach at `u` (found last) left out: none is held there any more.
        assert_eq!(b.energy(&u, &mut vec![0.0; 3 * n]), Some(e));
        b.leave_out_within(&u, f64::INFINITY);
        let mut g = vec![0.0; 3 * n];
        assert_eq!(b.energy(&u, &mut g), Some(0.0));
        assert!(b.hessian(&u, false).is_empty());
    }

    /// Two long thin strips (10 mm × 0.2 mm, two triangles each) crossed at right angles, the
    /// second `gap` (m) above the first: no corner of either lies over the other, so only
    /// their edges can meet. Nodes and triangles.
    fn crossed(gap: f64) -> (Vec<Vector3<f64>>, Vec<[usize; 3]>) {
        let (l, w) = (5e-3, 0.1e-3);
        let nodes = vec![
            Vector3::new(-l, -w, 0.0),
            Vector3::new(l, -w, 0.0),
            Vector3::new(l, w, 0.0),
            Vector3::new(-l, w, 0.0),
            Vector3::new(-w, -l, gap),
            Vector3::new(-w, l, gap),
            Vector3::new(w, l, gap),
            Vector3::new(w, -l, gap),
        ];
        (nodes, vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    }

    /// The barrier over the crossed strips.
    fn crossed_barrier(gap: f64) -> SelfBarrier {
        let (nodes, triangles) = crossed(gap);
        barrier_over(nodes, triangles)
    }

    /// The upper strip moved down by `down` (m).
    fn lowered(down: f64) -> Vec<f64> {
        let mut u = vec![0.0; 24];
        for i in 4..8 {
            u[3 * i + 2] = -down;
        }
        u
    }

    #[test]
    fn edges_crossing_with_no_corner_over_a_facet_are_held_apart_and_not_passed_through() {
        let b = crossed_barrier(2e-3);
        let u = vec![0.0; 24];
        // 4 mm down from 2 mm above: the strips' long edges meet half way, no corner passes
        // through a facet (the points against facets alone let the step go).
        let alpha = b.largest_step(&u, &lowered(4e-3));
        assert!((alpha - TO_CROSSING * 0.5).abs() < 1e-9, "{alpha}");
        assert_eq!(b.largest_step(&u, &lowered(1.5e-3)), 1.0);
        // 0.2 mm apart, within reach: only edge pairs act, pushing the strips apart with
        // action equal to reaction, the energy's gradient its differences.
        let at = lowered(1.8e-3);
        let mut g = vec![0.0; 24];
        let e = b.energy(&at, &mut g).unwrap();
        assert!(e > 0.0 && e.is_finite(), "{e}");
        let up: f64 = (4..8).map(|i| -g[3 * i + 2]).sum();
        let down: f64 = (0..4).map(|i| -g[3 * i + 2]).sum();
        assert!(up > 0.0 && (up + down).abs() < 1e-9 * up, "{up} {down}");
        let h = 1e-9;
        let (mut gp, mut gm) = (vec![0.0; 24], vec![0.0; 24]);
        let ep = b.energy(&lowered(1.8e-3 + h), &mut gp).unwrap();
        let em = b.energy(&lowered(1.8e-3 - h), &mut gm).unwrap();
        let slope = -(4..8).map(|i| g[3 * i + 2]).sum::<f64>();
        assert!(((ep - em) / (2.0 * h) - slope).abs() < 1e-5 * slope.abs());
        // Its Hessian along the lowering is the slope's differences.
        let dir = lowered(1.0);
        let mut hd = [0.0; 24];
        for blk in b.hessian(&at, false) {
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
        let curvature: f64 = hd.iter().zip(&dir).map(|(a, d)| a * d).sum();
        let fd = (ep - 2.0 * e + em) / (h * h);
        assert!(
            (curvature - fd).abs() < 1e-3 * curvature,
            "{curvature} {fd}"
        );
        // The pairs held: each strip's two long edges and its diagonal cross the other's three
        // in plan (its short edges lie 5 mm out); each pair's both edges feel its force, the
        // first edge's counted as the press.
        let (felt, count, press) = b.forces(&at);
        assert_eq!(count, 9);
        assert!((press - up).abs() < 1e-9 * up, "{press} {up}");
        assert!((felt.iter().sum::<f64>() - 2.0 * press).abs() < 1e-9 * press);
    }
}
