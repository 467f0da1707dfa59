//! The barrier of incremental potential contact (IPC; Li et al. 2020, "Incremental Potential
//! Contact: Intersection- and Inversion-free, Large-Deformation Dynamics", ACM Trans. Graph.
//! 39(4)) on pairs of edges. Two closed surfaces that did not cross come to cross only where a
//! point passes through a facet (`barrier.rs`) or an edge through an edge: here the squared
//! distance d² between two segments (a0, a1) and (b0, b1), with its gradient and Hessian in the
//! 12 coordinates (a0, a1, b0, b1); IPC's mollifier, which fades the barrier of nearly parallel
//! edges (their ends against the other's facets hold them); and a pair's energy κ·m·b(d²) with
//! its gradient and Hessian.
//!
//! As in IPC, the distance is that between the nearest features: the two lines, when both
//! closest points lie strictly inside their edges; otherwise an end of one edge against the
//! other edge (as a line, when the end projects inside it) or against one of its ends. Its
//! derivatives are those of that feature's formula, smooth within the feature's region.
//! Lengths are in metres, squared distances in m². Whether an edge passes through another over
//! a step is `swept::edges_cross`.

use super::barrier::{barrier, lift, point_line, point_plane, PairBarrier, PointTriangle};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Edges whose sine of the angle between them squared, |ea × eb|² / (|ea|² |eb|²), is at most
/// this are parallel: the line–line formula divides by |ea × eb|² and its closest points run
/// off along the lines, so their ends measure the distance instead (off from the exact one by
/// at most this times the shorter edge's length squared).
const PARALLEL: f64 = 1e-12;

/// IPC's mollifier threshold as a fraction of |ea|² |eb|² at rest: edges whose sine of the
/// angle between them squared falls below it (about 1.8° from parallel) fade their barrier.
const MOLLIFIED: f64 = 1e-3;

/// The features of two edges nearest each other; ends numbered 0 = a0, 1 = a1, 2 = b0,
/// 3 = b1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    /// Both closest points strictly inside their edges: the lines' distance.
    Lines,
    /// End `point` against the edge from end `from` to end `to`, at a point strictly between.
    PointEdge {
        point: usize,
        from: usize,
        to: usize,
    },
    /// End `.0` against end `.1`.
    Points(usize, usize),
}

/// IPC's mollifier of an edge pair's barrier, with its derivatives in the 12 coordinates
/// (a0, a1, b0, b1), each x, y, z.
#[derive(Clone, Debug, PartialEq)]
pub struct EdgeMollifier {
    /// m(x) with x = |ea × eb|²: 0 for parallel edges, rising to 1 at the threshold ε_x and
    /// 1 beyond; dimensionless.
    pub value: f64,
    /// ∂m/∂x over (a0, a1, b0, b1), per metre.
    pub gradient: SVector<f64, 12>,
    /// ∂²m/∂x² over (a0, a1, b0, b1), per square metre (symmetric).
    pub hessian: SMatrix<f64, 12, 12>,
}

/// The squared distance between the closed segments [a0, a1] and [b0, b1], m²; cheap, no
/// derivatives. Parallel edges, and edges of zero length (points), give the distance of their
/// ends; non-finite coordinates give NaN.
pub fn edge_edge_distance2(
    a0: &Vector3<f64>,
    a1: &Vector3<f64>,
    b0: &Vector3<f64>,
    b1: &Vector3<f64>,
) -> f64 {
    nearest_feature([a0, a1, b0, b1]).1
}

/// The squared distance between the closed segments [a0, a1] and [b0, b1] with its gradient and
/// Hessian in the 12 coordinates (a0, a1, b0, b1) (in the fields named for a point and a
/// triangle: `PointTriangle`'s 12 are here the two edges' ends): those of the nearest
/// features' formula, the line–line distance ((ea × eb)·(b0 − a0))² / |ea × eb|² with
/// ea = a1 − a0, eb = b1 − b0, the point–line distance |(p − x) × (y − x)|² / |y − x|² of an end
/// p against the other edge (x, y), or the point–point distance |p − x|². Parallel edges (see
/// `PARALLEL`) and edges of zero length are measured by their ends: always finite for finite
/// coordinates, and d² is `edge_edge_distance2`'s. Non-finite coordinates give NaN throughout.
pub fn edge_edge_derivatives(
    a0: &Vector3<f64>,
    a1: &Vector3<f64>,
    b0: &Vector3<f64>,
    b1: &Vector3<f64>,
) -> PointTriangle {
    let x = [a0, a1, b0, b1];
    match nearest_feature(x) {
        (_, d2) if d2.is_nan() => PointTriangle {
            d2,
            gradient: SVector::from_element(f64::NAN),
            hessian: SMatrix::from_element(f64::NAN),
        },
        (Feature::Lines, _) => {
            // The point b0 against the plane through a0 spanned by ea and eb.
            let (d2, g, h) = point_plane(&(b0 - a0), &(a1 - a0), &(b1 - b0));
            lift(d2, g, h, &[(2, 0), (1, 0), (3, 2)])
        }
        (Feature::PointEdge { point, from, to }, _) => {
            let (d2, g, h) = point_line(&(x[point] - x[from]), &(x[to] - x[from]));
            lift(d2, g, h, &[(point, from), (to, from)])
        }
        (Feature::Points(p, i), _) => {
            let u = x[p] - x[i];
            let h = Matrix3::identity() * 2.0;
            lift(u.norm_squared(), u * 2.0, h, &[(p, i)])
        }
    }
}

/// IPC's mollifier threshold ε_x for the edges (a0, a1), (b0, b1) at rest: 10⁻³·|ea|²·|eb|²
/// (m⁴), as in ipc-toolkit's `edge_edge_mollifier_threshold`.
pub fn edge_edge_mollifier_threshold(
    a0: &Vector3<f64>,
    a1: &Vector3<f64>,
    b0: &Vector3<f64>,
    b1: &Vector3<f64>,
) -> f64 {
    MOLLIFIED * (a1 - a0).norm_squared() * (b1 - b0).norm_squared()
}

/// IPC's mollifier for nearly parallel edges (Li et al. 2020, §4.3): with x = |ea × eb|²
/// (ea = a1 − a0, eb = b1 − b0) and threshold ε_x (`edge_edge_mollifier_threshold` at rest),
/// m(x) = (2 − x/ε_x)·x/ε_x for x < ε_x and 1 beyond (C¹ there). The barrier of two edges
/// turning parallel — where their distance's nearest features jump, and the line–line
/// formula's derivatives grow without bound — fades to nothing as κ·m·b(d²); their ends'
/// pairs against the facets hold them instead. A threshold ≤ 0 (or NaN) leaves m = 1.
pub fn edge_edge_mollifier(
    a0: &Vector3<f64>,
    a1: &Vector3<f64>,
    b0: &Vector3<f64>,
    b1: &Vector3<f64>,
    eps_x: f64,
) -> EdgeMollifier {
    let (ea, eb) = (a1 - a0, b1 - b0);
    let n = ea.cross(&eb);
    let x = n.norm_squared();
    // At or beyond the threshold (or NaN): no fading.
    let fading = x < eps_x;
    if !fading {
        return EdgeMollifier {
            value: 1.0,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        };
    }
    let r = x / eps_x;
    let (dm, ddm) = (2.0 * (1.0 - r) / eps_x, -2.0 / (eps_x * eps_x));
    // x over (ea, eb): dn = −[eb]× dea + [ea]× deb, ∂x/∂ea = 2 eb × n, ∂x/∂eb = 2 n × ea, and
    // its Hessian 2 Jₙᵀ Jₙ with ±2 [n]× between ea and eb (from 2 n·(dea × deb)).
    let mut gx = SVector::<f64, 6>::zeros();
    gx.fixed_rows_mut::<3>(0).copy_from(&(eb.cross(&n) * 2.0));
    gx.fixed_rows_mut::<3>(3).copy_from(&(n.cross(&ea) * 2.0));
    let mut jn = SMatrix::<f64, 3, 6>::zeros();
    jn.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(-eb.cross_matrix()));
    jn.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&ea.cross_matrix());
    let mut hx = jn.transpose() * jn * 2.0;
    let nx = n.cross_matrix() * 2.0;
    let mut block = hx.fixed_view_mut::<3, 3>(0, 3);
    block -= nx;
    let mut block = hx.fixed_view_mut::<3, 3>(3, 0);
    block += nx;
    // Then m(x): ∇m = m'∇x, ∇²m = m''∇x∇xᵀ + m'∇²x.
    let h = gx * gx.transpose() * ddm + hx * dm;
    let lifted = lift((2.0 - r) * r, gx * dm, h, &[(1, 0), (3, 2)]);
    EdgeMollifier {
        value: lifted.d2,
        gradient: lifted.gradient,
        hessian: lifted.hessian,
    }
}

/// The barrier of edge (a0, a1) against edge (b0, b1), mollified with threshold `eps_x` (m⁴;
/// `edge_edge_mollifier_threshold` at rest), with cutoff distance² `dhat2` (m²) and stiffness
/// `kappa`: `None` when the pair is inactive (d² ≥ d̂²); otherwise energy κ·m·b(d²), gradient
/// κ·(b ∇m + m b' ∇d²) and the exact Hessian
///
///   H = κ·(b ∇²m + b' (∇m ∇d²ᵀ + ∇d² ∇mᵀ) + m (b'' ∇d² ∇d²ᵀ + b' ∇²d²)),
///
/// over (a0, a1, b0, b1) (`PairBarrier`'s 12; indefinite in general, no eigen-decomposition:
/// [`PairBarrier::projected`] makes it positive semi-definite). Where the edges touch or cross
/// (d² ≤ 0, or NaN for non-finite coordinates) it returns energy +∞ with zero gradient and
/// Hessian, parallel or not: the state is inadmissible and the step must be shortened.
pub fn edge_pair_barrier(
    a0: &Vector3<f64>,
    a1: &Vector3<f64>,
    b0: &Vector3<f64>,
    b1: &Vector3<f64>,
    eps_x: f64,
    dhat2: f64,
    kappa: f64,
) -> Option<PairBarrier> {
    let d2 = edge_edge_distance2(a0, a1, b0, b1);
    if d2 >= dhat2 {
        return None;
    }
    if d2.is_nan() || d2 <= 0.0 {
        return Some(PairBarrier::inadmissible());
    }
    // The same formulas as the distance's: the same d².
    let dist = edge_edge_derivatives(a0, a1, b0, b1);
    let (b, db, ddb) = barrier(dist.d2, dhat2);
    let m = edge_edge_mollifier(a0, a1, b0, b1, eps_x);
    let (g, gm) = (&dist.gradient, &m.gradient);
    let cross = gm * g.transpose() * db;
    let hessian = (g * g.transpose() * ddb + dist.hessian * db) * m.value
        + m.hessian * b
        + cross
        + cross.transpose();
    Some(PairBarrier {
        energy: kappa * m.value * b,
        gradient: (g * (m.value * db) + gm * b) * kappa,
        hessian: hessian * kappa,
    })
}

/// The nearest features of the edges x[0]–x[1] and x[2]–x[3] and the squared distance between
/// them; NaN for non-finite coordinates.
fn nearest_feature(x: [&Vector3<f64>; 4]) -> (Feature, f64) {
    if !x.iter().all(|c| c.iter().all(|v| v.is_finite())) {
        return (Feature::Points(0, 2), f64::NAN);
    }
    let (ea, eb, w) = (x[1] - x[0], x[3] - x[2], x[2] - x[0]);
    let n = ea.cross(&eb);
    let m = n.norm_squared();
    if m > PARALLEL * ea.norm_squared() * eb.norm_squared() {
        // The lines' closest points, a0 + s ea and b0 + t eb: s ea − t eb = w + λ n.
        let s = w.cross(&eb).dot(&n) / m;
        let t = w.cross(&ea).dot(&n) / m;
        if s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0 {
            let g = w.dot(&n);
            return (Feature::Lines, g * g / m);
        }
    }
    // Otherwise (or parallel, or an edge of zero length) one closest point is an end: the
    // nearest of the four ends against the other edge.
    let mut best = (Feature::Points(0, 2), f64::INFINITY);
    for (point, from, to) in [(0, 2, 3), (1, 2, 3), (2, 0, 1), (3, 0, 1)] {
        let (p, y0, y1) = (x[point], x[from], x[to]);
        let (u, e) = (p - y0, y1 - y0);
        let q = e.norm_squared();
        let s = u.dot(&e) / q;
        let near = if !(s > 0.0 && q > 0.0) {
            (Feature::Points(point, from), u.norm_squared())
        } else if s >= 1.0 {
            (Feature::Points(point, to), (p - y1).norm_squared())
        } else {
            (
                Feature::PointEdge { point, from, to },
                (u - e * s).norm_squared(),
            )
        };
        if near.1 < best.1 {
            best = near;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::barrier::project_psd;
    use crate::contact::differences::{all_finite, central, relative, v, Rng, M12, V12};
    use nalgebra::SymmetricEigen;

    impl Rng {
        /// A unit vector, uniform on the sphere.
        fn direction(&mut self) -> Vector3<f64> {
            loop {
                let d = self.vector(1.0);
                let n = d.norm();
                if n > 0.1 && n <= 1.0 {
                    return d / n;
                }
            }
        }
        /// A unit vector perpendicular to `e`.
        fn perpendicular(&mut self, e: &Vector3<f64>) -> Vector3<f64> {
            loop {
                let d = self.direction();
                let p = d - e * (d.dot(e) / e.norm_squared());
                if p.norm() > 0.1 {
                    return p.normalize();
                }
            }
        }
        /// An edge's direction and length, 0.5 to 1.5 times `scale`.
        fn edge(&mut self, scale: f64) -> Vector3<f64> {
            self.direction() * self.range(0.5, 1.5) * scale
        }
    }

    /// Where the closest points of a sampled pair lie.
    #[derive(Clone, Copy, Debug)]
    enum Region {
        /// Both strictly inside their edges.
        Lines,
        /// An end of b (before relabelling) against the inside of a.
        EndOnEdge,
        /// An end of a against an end of b.
        Ends,
    }

    const REGIONS: [Region; 3] = [Region::Lines, Region::EndOnEdge, Region::Ends];

    /// The relabellings that carry a sample's b0 (and a0) to every end: b reversed, a
    /// reversed, the edges swapped.
    const RELABELLINGS: [(bool, bool, bool); 8] = [
        (false, false, false),
        (true, false, false),
        (false, true, false),
        (true, true, false),
        (false, false, true),
        (true, false, true),
        (false, true, true),
        (true, true, true),
    ];

    fn relabel(
        x: [Vector3<f64>; 4],
        (flip_b, flip_a, swap): (bool, bool, bool),
    ) -> [Vector3<f64>; 4] {
        let [mut a0, mut a1, mut b0, mut b1] = x;
        if flip_b {
            std::mem::swap(&mut b0, &mut b1);
        }
        if flip_a {
            std::mem::swap(&mut a0, &mut a1);
        }
        if swap {
            [b0, b1, a0, a1]
        } else {
            [a0, a1, b0, b1]
        }
    }

    /// A pair in `region`, away from the region's boundaries (closest-point parameters inside
    /// an edge in [0.15, 0.85], lines at 20° to 160°, an edge leaving its nearest end with at
    /// least 0.3 of its direction along the gap), and its squared distance by construction:
    /// the nearest points d apart along a unit u perpendicular to the edges they lie inside.
    fn sample(rng: &mut Rng, region: Region, scale: f64) -> ([Vector3<f64>; 4], f64) {
        let a0 = rng.vector(scale);
        let ea = rng.edge(scale);
        let d = rng.range(0.05, 1.0) * scale;
        let (length_b, e_a) = (rng.range(0.5, 1.5) * scale, ea.normalize());
        match region {
            Region::Lines => {
                // b perpendicular to u through a's point moved d along u, at 20° to 160° to a.
                let on_a = a0 + ea * rng.range(0.15, 0.85);
                let u = rng.perpendicular(&ea);
                let angle = rng.range(0.35, std::f64::consts::PI - 0.35);
                let eb = (e_a * angle.cos() + u.cross(&e_a) * angle.sin()) * length_b;
                let b0 = on_a + u * d - eb * rng.range(0.15, 0.85);
                ([a0, a0 + ea, b0, b0 + eb], d * d)
            }
            Region::EndOnEdge => loop {
                // b0 off a's inside along u ⟂ a; b leaving a (its direction along u ≥ 0.3).
                let u = rng.perpendicular(&ea);
                let e_b = rng.direction();
                if e_b.dot(&u) >= 0.3 {
                    let b0 = a0 + ea * rng.range(0.15, 0.85) + u * d;
                    return ([a0, a0 + ea, b0, b0 + e_b * length_b], d * d);
                }
            },
            Region::Ends => loop {
                // b0 off a0 along u; a leaving b0 and b leaving a0 (along u, ≤ −0.3 and ≥ 0.3).
                let (u, e_b) = (rng.direction(), rng.direction());
                if e_a.dot(&u) <= -0.3 && e_b.dot(&u) >= 0.3 {
                    let b0 = a0 + u * d;
                    return ([a0, a0 + ea, b0, b0 + e_b * length_b], d * d);
                }
            },
        }
    }

    /// The feature a sample in `region`, relabelled, must be measured by: its special ends
    /// (a0, and b0) and a's edge, where the relabelling put them.
    fn expected(region: Region, (flip_b, flip_a, swap): (bool, bool, bool)) -> Feature {
        let (a_end, b_end) = (usize::from(flip_a), 2 + usize::from(flip_b));
        let (a_end, b_end, a_from) = if swap {
            (a_end + 2, b_end - 2, 2)
        } else {
            (a_end, b_end, 0)
        };
        match region {
            Region::Lines => Feature::Lines,
            Region::EndOnEdge => Feature::PointEdge {
                point: b_end,
                from: a_from,
                to: a_from + 1,
            },
            // (Of two equal candidates, a's end against b's is tried first.)
            Region::Ends => Feature::Points(a_end.min(b_end), a_end.max(b_end)),
        }
    }

    fn split(x: &V12) -> [Vector3<f64>; 4] {
        [0, 1, 2, 3].map(|k| x.fixed_rows::<3>(3 * k).into_owned())
    }

    fn join(x: &[Vector3<f64>; 4]) -> V12 {
        let mut out = V12::zeros();
        for (k, y) in x.iter().enumerate() {
            out.fixed_rows_mut::<3>(3 * k).copy_from(y);
        }
        out
    }

    fn distance2_at(x: &V12) -> f64 {
        let [a0, a1, b0, b1] = split(x);
        edge_edge_distance2(&a0, &a1, &b0, &b1)
    }

    fn derivatives_at(x: &V12) -> PointTriangle {
        let [a0, a1, b0, b1] = split(x);
        edge_edge_derivatives(&a0, &a1, &b0, &b1)
    }

    fn feature_at(x: &[Vector3<f64>; 4]) -> Feature {
        nearest_feature([&x[0], &x[1], &x[2], &x[3]]).0
    }

    /// The least of a convex `f` over [0, 1] by grids of 21 points, each narrowed to the two
    /// cells about the last one's least (where a convex function's least lies), down to cells
    /// of 10⁻¹³.
    fn grid_min(f: impl Fn(f64) -> f64) -> f64 {
        let (mut lo, mut hi, mut best) = (0.0_f64, 1.0_f64, f64::INFINITY);
        while hi - lo > 1e-13 {
            let h = (hi - lo) / 20.0;
            let (mut at, mut least) = (lo, f64::INFINITY);
            for k in 0..=20 {
                let s = lo + h * k as f64;
                let y = f(s);
                if y < least {
                    (at, least) = (s, y);
                }
            }
            best = best.min(least);
            (lo, hi) = ((at - h).max(0.0), (at + h).min(1.0));
        }
        best
    }

    /// The squared distance by brute force: the least over the edges' parameters of
    /// |a0 + s ea − b0 − t eb|², on refined grids (over t for each s: both convex).
    fn brute_force(x: &[Vector3<f64>; 4]) -> f64 {
        let (ea, eb) = (x[1] - x[0], x[3] - x[2]);
        grid_min(|s| {
            let on_a = x[0] + ea * s;
            grid_min(|t| (on_a - x[2] - eb * t).norm_squared())
        })
    }

    #[test]
    fn distances_of_known_configurations_are_exact() {
        let d2 = |a0: Vector3<f64>, a1: Vector3<f64>, b0: Vector3<f64>, b1: Vector3<f64>| {
            let d2 = edge_edge_distance2(&a0, &a1, &b0, &b1);
            assert_eq!(edge_edge_derivatives(&a0, &a1, &b0, &b1).d2, d2);
            // The same distance for the edges swapped and either reversed.
            assert_eq!(edge_edge_distance2(&b0, &b1, &a0, &a1), d2);
            assert_eq!(edge_edge_distance2(&a1, &a0, &b1, &b0), d2);
            d2
        };
        let (x, o) = (v(1.0, 0.0, 0.0), v(0.0, 0.0, 0.0));
        // Skew edges crossing 1 above each other, their midpoints nearest; and meeting.
        assert_eq!(d2(-x, x, v(0.0, -1.0, 1.0), v(0.0, 1.0, 1.0)), 1.0);
        assert_eq!(d2(-x, x, v(0.0, -1.0, 0.0), v(0.0, 1.0, 0.0)), 0.0);
        // Skew, nearest at a quarter of a and 3/8 of b, (1, 0, 0) and (1, 0.5, 0.5).
        assert_eq!(d2(o, x * 4.0, v(1.0, -1.0, 2.0), v(1.0, 3.0, -2.0)), 0.5);
        // Lines crossing beyond the edges: the nearest ends, a1 and b0, √2 apart.
        assert_eq!(d2(o, x, v(2.0, 1.0, 0.0), v(2.0, 3.0, 0.0)), 2.0);
        // Parallel, 0.5 apart and overlapping (same way and opposite); collinear, 1 apart.
        assert_eq!(d2(o, x, v(0.25, 0.5, 0.0), v(2.0, 0.5, 0.0)), 0.25);
        assert_eq!(d2(o, x, v(2.0, 0.0, 0.5), v(0.25, 0.0, 0.5)), 0.25);
        assert_eq!(d2(o, x, v(2.0, 0.0, 0.0), v(3.0, 0.0, 0.0)), 1.0);
        // Parallel, apart along their line too: the nearest ends.
        assert_eq!(d2(o, x, v(3.0, 1.0, 0.0), v(5.0, 1.0, 0.0)), 5.0);
        // An end against the inside of the other: b0 1 above a's middle, b leaving it.
        assert_eq!(d2(o, x * 2.0, v(1.0, 1.0, 0.0), v(1.0, 3.0, 5.0)), 1.0);
        assert_eq!(d2(o, x * 2.0, v(1.0, 3.0, 5.0), v(1.0, 1.0, 0.0)), 1.0);
        // Ends against ends.
        assert_eq!(d2(o, x, v(-1.0, 0.0, 2.0), v(-3.0, 1.0, 2.0)), 5.0);
        // Degenerate: a reduced to a point (against b's inside, and its end), both points.
        assert_eq!(d2(o, o, v(1.0, -1.0, 1.0), v(1.0, 1.0, 1.0)), 2.0);
        assert_eq!(d2(o, o, v(1.0, 1.0, 1.0), v(1.0, 2.0, 1.0)), 3.0);
        assert_eq!(d2(o, o, v(1.0, 2.0, 2.0), v(1.0, 2.0, 2.0)), 9.0);
        // Non-finite coordinates: NaN, whichever end.
        let nan = v(f64::NAN, 0.0, 0.0);
        let inf = v(0.0, f64::INFINITY, 0.0);
        for (k, bad) in [nan, inf].into_iter().cycle().take(8).enumerate() {
            let mut e = [o, x, v(0.0, 1.0, 1.0), v(1.0, 1.0, 1.0)];
            e[k % 4] = bad;
            assert!(edge_edge_distance2(&e[0], &e[1], &e[2], &e[3]).is_nan());
            assert!(edge_edge_derivatives(&e[0], &e[1], &e[2], &e[3])
                .d2
                .is_nan());
        }
    }

    /// Sampled pairs in every region (each end's turn by relabelling), at metres and at hand
    /// scale (centimetres), and pairs at random: the distance by construction, by brute force
    /// over the parameters, and the derivatives' distance all agree; each region is measured
    /// by its feature.
    #[test]
    fn distances_in_every_region_agree_with_the_construction_and_brute_force() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for scale in [1.0, 0.01] {
            for _ in 0..6 {
                for region in REGIONS {
                    let (x, want) = sample(&mut rng, region, scale);
                    for r in RELABELLINGS {
                        let x = relabel(x, r);
                        let got = distance2_at(&join(&x));
                        assert!(
                            (got - want).abs() <= 1e-12 * want,
                            "{region:?} {r:?}: {got} vs {want}"
                        );
                        assert_eq!(feature_at(&x), expected(region, r), "{region:?} {r:?}");
                        assert_eq!(derivatives_at(&join(&x)).d2, got);
                        let brute = brute_force(&x);
                        assert!(
                            (brute - want).abs() <= 1e-12 * want,
                            "{region:?} {r:?}: brute force {brute} vs {want}"
                        );
                    }
                }
            }
            // At random (mostly ends), nearly parallel, exactly parallel.
            for k in 0..60 {
                let a0 = rng.vector(scale);
                let ea = rng.edge(scale);
                let eb = match k % 3 {
                    0 => rng.edge(scale),
                    1 => {
                        (ea + rng.perpendicular(&ea) * ea.norm() * rng.range(1e-7, 1e-3))
                            * rng.range(-1.5, 1.5)
                    }
                    _ => ea * rng.range(-1.5, 1.5),
                };
                let b0 = a0 + rng.vector(scale);
                let x = [a0, a0 + ea, b0, b0 + eb];
                let got = distance2_at(&join(&x));
                let brute = brute_force(&x);
                let tolerance = 1e-12 * scale * scale;
                assert!(got <= brute + tolerance, "{k}: {got} above {brute}");
                assert!(brute - got <= tolerance, "{k}: {got} below {brute}");
                let d = derivatives_at(&join(&x));
                assert!(all_finite(&d) && d.d2 == got, "{d:?}");
            }
        }
    }

    #[test]
    fn derivatives_match_central_differences_in_every_region() {
        let mut rng = Rng(0xD1B5_4A32_D192_ED03);
        for scale in [1.0, 0.01] {
            for _ in 0..5 {
                for region in REGIONS {
                    let (x, _) = sample(&mut rng, region, scale);
                    for r in RELABELLINGS {
                        let x = join(&relabel(x, r));
                        let exact = derivatives_at(&x);
                        let (gradient, hessian) = central(&x, 1e-6 * scale, distance2_at, |y| {
                            derivatives_at(y).gradient
                        });
                        let (eg, eh) = (
                            relative(&exact.gradient, &gradient),
                            relative(&exact.hessian, &hessian),
                        );
                        assert!(
                            eg < 1e-6,
                            "{region:?} {r:?} gradient: relative error {eg:e}"
                        );
                        assert!(eh < 1e-6, "{region:?} {r:?} Hessian: relative error {eh:e}");
                        // Symmetric, and moving both edges together changes nothing.
                        assert_eq!(exact.hessian, exact.hessian.transpose());
                        let mut shift = V12::zeros();
                        for k in 0..4 {
                            shift[3 * k] = 1.0;
                        }
                        assert!(exact.gradient.dot(&shift).abs() < 1e-12 * exact.gradient.norm());
                    }
                }
            }
        }
    }

    #[test]
    fn parallel_and_degenerate_edges_give_finite_derivatives_of_their_ends() {
        let (o, x) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
        // Exactly parallel and overlapping: an end against the other's inside, as a line.
        let (b0, b1) = (v(0.25, 0.5, 0.0), v(2.0, 0.5, 0.0));
        let d = edge_edge_derivatives(&o, &x, &b0, &b1);
        assert!(all_finite(&d) && d.d2 == 0.25, "{d:?}");
        assert!(matches!(
            feature_at(&[o, x, b0, b1]),
            Feature::PointEdge { .. }
        ));
        // Parallel to round-off (sin² ≈ 2·10⁻¹⁴, below `PARALLEL`) and above it (2·10⁻¹⁰),
        // the lines nearest at a's 0.875 and b's middle: finite, and the distance the brute
        // force finds.
        for tilt in [1e-7, 1e-5] {
            let (b0, b1) = (v(0.25, 0.5, -0.875 * tilt), v(1.5, 0.5, 0.875 * tilt));
            let e = [o, x, b0, b1];
            let d = edge_edge_derivatives(&o, &x, &b0, &b1);
            assert!(all_finite(&d), "{d:?}");
            assert!(
                (d.d2 - brute_force(&e)).abs() < 1e-14,
                "{} vs {}",
                d.d2,
                brute_force(&e)
            );
            assert_eq!(feature_at(&e) == Feature::Lines, tilt > 1e-6);
        }
        // Zero-length edges: points against an edge, and against each other.
        let p = v(0.5, 1.0, 1.0);
        for (e, want) in [
            ([p, p, o, x], 2.0),
            ([o, x, p, p], 2.0),
            ([p, p, o, o], 2.25),
        ] {
            let d = edge_edge_derivatives(&e[0], &e[1], &e[2], &e[3]);
            assert!(all_finite(&d) && d.d2 == want, "{d:?}");
        }
        // Touching (crossing, end on edge, end on end): d² = 0, finite, zero gradient.
        let y = v(0.0, 1.0, 0.0);
        for e in [[-x, x, -y, y], [o, x * 2.0, x, x + y], [o, x, x, x + y]] {
            let d = edge_edge_derivatives(&e[0], &e[1], &e[2], &e[3]);
            assert!(
                all_finite(&d) && d.d2 == 0.0 && d.gradient == V12::zeros(),
                "{d:?}"
            );
        }
    }

    /// Nearly parallel pairs: b turned from a by a small angle about a random axis.
    fn nearly_parallel(rng: &mut Rng, scale: f64) -> [Vector3<f64>; 4] {
        let a0 = rng.vector(scale);
        let ea = rng.edge(scale);
        let turn = rng.perpendicular(&ea) * ea.norm() * rng.range(0.005, 0.05);
        let eb = (ea + turn).normalize() * rng.range(0.5, 1.5) * scale;
        let b0 = a0 + rng.vector(scale);
        [a0, a0 + ea, b0, b0 + eb]
    }

    fn mollifier_at(x: &V12, eps_x: f64) -> EdgeMollifier {
        let [a0, a1, b0, b1] = split(x);
        edge_edge_mollifier(&a0, &a1, &b0, &b1, eps_x)
    }

    #[test]
    fn the_mollifier_matches_its_formula_and_differences_and_is_one_beyond_its_threshold() {
        // Its threshold: 10⁻³ |ea|² |eb|² at rest.
        let (o, x) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
        let eps = edge_edge_mollifier_threshold(&o, &(x * 2.0), &x, &v(1.0, 3.0, 0.0));
        assert!((eps - 1e-3 * 4.0 * 9.0).abs() < 1e-18);
        // Unit edges at sin² θ = x/ε_x·10⁻³ for x/ε_x = r: m = (2 − r) r.
        let eps: f64 = 1e-3;
        for r in [0.0, 0.1, 0.25, 0.5, 0.9, 0.999] {
            let sine = (r * eps).sqrt();
            let b1 = v((1.0 - sine * sine).sqrt(), sine, 0.0);
            let m = edge_edge_mollifier(&o, &x, &o, &b1, eps);
            let want = (2.0 - r) * r;
            assert!(
                (m.value - want).abs() < 1e-12,
                "r = {r}: {} vs {want}",
                m.value
            );
        }
        // At and beyond the threshold: 1, no derivatives; continuous (m → 1, m' → 0) there.
        for sine in [eps.sqrt(), 0.1, 1.0] {
            let b1 = v((1.0 - sine * sine).sqrt(), sine, 0.0);
            let m = edge_edge_mollifier(&o, &x, &o, &b1, eps * (1.0 - 1e-15));
            assert_eq!(m.value, 1.0);
            assert_eq!((m.gradient, m.hessian), (V12::zeros(), M12::zeros()));
        }
        let sine = (eps * (1.0 - 1e-9)).sqrt();
        let just_below = v((1.0 - sine * sine).sqrt(), sine, 0.0);
        let m = edge_edge_mollifier(&o, &x, &o, &just_below, eps);
        assert!(1.0 - m.value < 1e-15 && m.gradient.norm() < 1e-6, "{m:?}");
        // No threshold (zero-length edges at rest): 1.
        assert_eq!(edge_edge_mollifier(&o, &x, &o, &x, 0.0).value, 1.0);
        // Derivatives against central differences, below the threshold, at metres and at
        // hand scale.
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        for scale in [1.0, 0.01] {
            for _ in 0..20 {
                let e = nearly_parallel(&mut rng, scale);
                let x = join(&e);
                let cross2 = (e[1] - e[0]).cross(&(e[3] - e[2])).norm_squared();
                let eps_x = cross2 / rng.range(0.1, 0.9);
                let m = mollifier_at(&x, eps_x);
                assert!(m.value > 0.0 && m.value < 1.0);
                // (A step of 10⁻⁷: m varies over the edges' turning, sin θ·|e| ~ 10⁻² |e|.)
                let (gradient, hessian) = central(
                    &x,
                    1e-7 * scale,
                    |y| mollifier_at(y, eps_x).value,
                    |y| mollifier_at(y, eps_x).gradient,
                );
                let (eg, eh) = (
                    relative(&m.gradient, &gradient),
                    relative(&m.hessian, &hessian),
                );
                assert!(eg < 1e-6, "gradient: relative error {eg:e}");
                assert!(eh < 1e-6, "Hessian: relative error {eh:e}");
                assert_eq!(m.hessian, m.hessian.transpose());
            }
        }
    }

    fn energy_at(x: &V12, eps_x: f64, dhat2: f64, kappa: f64) -> Option<PairBarrier> {
        let [a0, a1, b0, b1] = split(x);
        edge_pair_barrier(&a0, &a1, &b0, &b1, eps_x, dhat2, kappa)
    }

    /// In every region (each end's turn), mollified or not, at hand scale: the energy is κ m b,
    /// its gradient and exact Hessian match differences, and the projected Hessian is the
    /// exact one's projection, with no negative eigenvalue.
    #[test]
    fn edge_pair_barrier_is_the_mollified_barrier_with_a_semi_definite_hessian() {
        let mut rng = Rng(0x0DDB_A11C_AFE0_F00D);
        let kappa = 1e4;
        let mut projected_something = false;
        for k in 0..12 {
            for region in REGIONS {
                let (x, d2) = sample(&mut rng, region, 0.01);
                let x = relabel(x, RELABELLINGS[k % 8]);
                let [a0, a1, b0, b1] = x;
                let dhat2 = d2 / rng.range(0.2, 0.8);
                let cross2 = (a1 - a0).cross(&(b1 - b0)).norm_squared();
                // Mollified (the threshold above |ea × eb|²) on every other sample.
                let eps_x = if k % 2 == 0 {
                    cross2 / rng.range(0.2, 0.9)
                } else {
                    edge_edge_mollifier_threshold(&a0, &a1, &b0, &b1)
                };
                let exact = edge_pair_barrier(&a0, &a1, &b0, &b1, eps_x, dhat2, kappa).unwrap();
                let pair = exact.clone().projected();
                let m = edge_edge_mollifier(&a0, &a1, &b0, &b1, eps_x);
                assert_eq!(m.value < 1.0, k % 2 == 0);
                let (b, _, _) = barrier(d2_of(&x), dhat2);
                assert_eq!(pair.energy, kappa * m.value * b);
                assert_eq!((exact.energy, exact.gradient), (pair.energy, pair.gradient));
                let y = join(&x);
                let (gradient, hessian) = central(
                    &y,
                    1e-6 * d2.sqrt(),
                    |z| energy_at(z, eps_x, dhat2, kappa).map_or(0.0, |e| e.energy),
                    |z| energy_at(z, eps_x, dhat2, kappa).map_or(V12::zeros(), |e| e.gradient),
                );
                let (eg, eh) = (
                    relative(&pair.gradient, &gradient),
                    relative(&exact.hessian, &hessian),
                );
                assert!(eg < 1e-6, "{region:?} gradient: relative error {eg:e}");
                assert!(eh < 1e-6, "{region:?} Hessian: relative error {eh:e}");
                assert!(relative(&pair.hessian, &project_psd(&exact.hessian)) < 1e-15);
                let eigen = SymmetricEigen::new(pair.hessian).eigenvalues;
                let largest = eigen.amax();
                assert!(eigen.min() >= -1e-12 * largest, "{region:?}: {eigen}");
                projected_something |=
                    SymmetricEigen::new(exact.hessian).eigenvalues.min() < -1e-6 * largest;
            }
        }
        assert!(
            projected_something,
            "no sample had an indefinite Hessian to project"
        );
    }

    fn d2_of(x: &[Vector3<f64>; 4]) -> f64 {
        edge_edge_distance2(&x[0], &x[1], &x[2], &x[3])
    }

    #[test]
    fn edge_pair_barrier_is_inactive_beyond_the_cutoff_and_infinite_at_contact() {
        // Edges of 2⁻⁶ m (about 16 mm): touching exactly, in floating point too.
        let (x, y) = (v(0.0078125, 0.0, 0.0), v(0.0, 0.0078125, 0.0));
        let dhat2 = 1e-6;
        let eps_x = edge_edge_mollifier_threshold(&-x, &x, &-y, &y);
        let above = |h: f64| [-x, x, v(0.0, -y.y, h), v(0.0, y.y, h)];
        let pair =
            |e: [Vector3<f64>; 4]| edge_pair_barrier(&e[0], &e[1], &e[2], &e[3], eps_x, dhat2, 1.0);
        // 1 mm apart: at the cutoff, inactive; beyond it too; just inside it, active.
        assert!(pair(above(1e-3)).is_none() && pair(above(0.5)).is_none());
        let near = pair(above(0.9e-3)).unwrap();
        assert!(near.energy > 0.0 && near.energy.is_finite());
        // Pushed apart: the energy falls as b rises (its z gradient negative, a's positive).
        assert!(near.gradient[8] < 0.0 && near.gradient[11] < 0.0 && near.gradient[2] > 0.0);
        // Touching (crossing, end on edge, end on end) or crossed: inadmissible.
        for e in [above(0.0), [-x, x, x * 0.5, x * 0.5 + y], [-x, x, x, x + y]] {
            let contact = pair(e).unwrap();
            assert_eq!(contact.energy, f64::INFINITY);
            assert_eq!(
                (contact.gradient, contact.hessian),
                (V12::zeros(), M12::zeros())
            );
        }
        // Exactly parallel and within reach: faded to nothing (their ends hold them), unless
        // touching.
        let beside = pair([-x, x, v(-x.x, 0.0, 5e-4), v(x.x, 0.0, 5e-4)]).unwrap();
        assert_eq!(beside.energy, 0.0);
        assert_eq!(
            pair([-x, x, -x * 0.5, x * 2.0]).unwrap().energy,
            f64::INFINITY
        );
        // Non-finite coordinates: inadmissible, not inactive.
        let nan = v(f64::NAN, 0.0, 0.0);
        assert_eq!(pair([-x, nan, -y, y]).unwrap().energy, f64::INFINITY);
    }
}
