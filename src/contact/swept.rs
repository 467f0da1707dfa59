//! A point passing through a moving triangle over a step (continuous collision detection): the
//! point and the triangle's corners each move along a straight line from where the step starts
//! (t = 0) to where it ends (t = 1). They are coplanar where
//!
//!   f(t) = ((b − a) × (c − a)) · (p − a) = 0,
//!
//! a cubic in t (f is the signed gap times twice the triangle's area); the point passes through
//! the triangle at a root where it lies inside the triangle, from its front (the side its normal
//! points to) to its back where f falls there. Skin that merely lies behind the plane of a facet
//! of the other side of a fold has not passed through it; skin that went through it has,
//! whichever way the two faced where the step started.
//!
//! Likewise an edge passing through another (`edges_cross`): the two are coplanar where
//! ((x1 − x0) × (x3 − x2)) · (x2 − x0) vanishes, again a cubic, and cross at a root where the
//! segments meet, whichever way.

use super::bounds::Bounds;
use super::edge_edge::edge_edge_distance2;
use nalgebra::Vector3;

/// Barycentric slack at a crossing: a point passing through an edge shared by two triangles
/// passes through both.
const EDGE_SLACK: f64 = 1e-9;

/// Two coplanar edges meet where they come within this fraction of the longer one's length of
/// each other (round-off at the root of their coplanarity cubic is far below it).
const MEET: f64 = 1e-6;

/// The first time t ∈ [0, 1] at which the point moving from `p[0]` to `p[1]` passes through the
/// triangle whose corners move from `start` to `end`, from its front to its back; `None` if it
/// does not (a triangle that stays flat or moves in the point's plane included).
pub fn passes_through(
    p: [&Vector3<f64>; 2],
    start: &[Vector3<f64>; 3],
    end: &[Vector3<f64>; 3],
) -> Option<f64> {
    // The point stays in its path's box, the triangle in its corners' swept box: apart, they
    // never meet (most facets near a point, cheaply).
    let swept = Bounds::of(start.iter().chain(end));
    if !Bounds::of(p).meets(&swept.grown(1e-6 * swept.largest_side())) {
        return None;
    }
    let (a0, da) = (start[0], end[0] - start[0]);
    let (e1, de1) = (start[1] - a0, (end[1] - end[0]) - (start[1] - a0));
    let (e2, de2) = (start[2] - a0, (end[2] - end[0]) - (start[2] - a0));
    let (q, dq) = (p[0] - a0, (p[1] - p[0]) - da);
    let k = coplanarity([&e1, &de1], [&e2, &de2], [&q, &dq]);
    first_root(&k, Through::Falling, |t| {
        let at = |x0: &Vector3<f64>, x1: &Vector3<f64>| x0 + (x1 - x0) * t;
        let corners = [0, 1, 2].map(|i| at(&start[i], &end[i]));
        inside(&at(p[0], p[1]), &corners)
    })
}

/// The first time t ∈ [0, 1] at which the edge (x0, x1) passes through the edge (x2, x3), each
/// end moving in a straight line from `start` to `end`, either way through: where the two are
/// coplanar,
///
///   f(t) = ((x1 − x0) × (x3 − x2)) · (x2 − x0) = 0
///
/// (a cubic in t; any sign change or touching zero counts, at a step's ends too), and the
/// segments there meet: come within `MEET` of the longer one's length (crossing, or an end on
/// the other, to that slack). `None` if they do not. Edges that stay parallel (f ≡ 0), even
/// sliding through each other in their common plane, and edges of zero length are `None`:
/// their ends' paths through the facets tell. Edges sharing an end always meet: the caller leaves such pairs
/// out.
pub fn edges_cross(start: &[Vector3<f64>; 4], end: &[Vector3<f64>; 4]) -> Option<f64> {
    // Each edge stays in its ends' swept box: apart, they never meet.
    let first = Bounds::of(start[..2].iter().chain(&end[..2]));
    let second = Bounds::of(start[2..].iter().chain(&end[2..]));
    let margin = 1e-6 * first.largest_side().max(second.largest_side());
    if !first.meets(&second.grown(margin)) {
        return None;
    }
    let x0 = start[0];
    let (ea, dea) = (start[1] - x0, (end[1] - end[0]) - (start[1] - x0));
    let (eb, deb) = (
        start[3] - start[2],
        (end[3] - end[2]) - (start[3] - start[2]),
    );
    let (w, dw) = (start[2] - x0, (end[2] - end[0]) - (start[2] - x0));
    let k = coplanarity([&ea, &dea], [&eb, &deb], [&w, &dw]);
    first_root(&k, Through::EitherWay, |t| {
        let x = [0, 1, 2, 3].map(|i| start[i] + (end[i] - start[i]) * t);
        let longer = (x[1] - x[0]).norm().max((x[3] - x[2]).norm());
        edge_edge_distance2(&x[0], &x[1], &x[2], &x[3]) <= (MEET * longer).powi(2)
    })
}

/// The cubic f(t) = k[0] + k[1] t + k[2] t² + k[3] t³ = (e1(t) × e2(t)) · q(t) of three vectors
/// each moving linearly, x(t) = x + t dx, given as [x, dx].
fn coplanarity(
    [e1, de1]: [&Vector3<f64>; 2],
    [e2, de2]: [&Vector3<f64>; 2],
    [q, dq]: [&Vector3<f64>; 2],
) -> [f64; 4] {
    let c0 = e1.cross(e2);
    let c1 = e1.cross(de2) + de1.cross(e2);
    let c2 = de1.cross(de2);
    [
        c0.dot(q),
        c0.dot(dq) + c1.dot(q),
        c1.dot(dq) + c2.dot(q),
        c2.dot(dq),
    ]
}

/// Which way a cubic must pass through zero for a root to count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Through {
    /// From f ≥ 0 to f < 0, falling there (a point from a facet's front to its back).
    Falling,
    /// Either way, touching zero included.
    EitherWay,
}

/// The first root t ∈ [0, 1] of the cubic f(t) = k[0] + k[1] t + k[2] t² + k[3] t³ passing
/// through zero `through` that `meets` accepts, found on the monotone pieces of [0, 1] in
/// turn by bisection; `None` if there is none (f ≡ 0 or non-finite coefficients included).
fn first_root(k: &[f64; 4], through: Through, mut meets: impl FnMut(f64) -> bool) -> Option<f64> {
    let f = |t: f64| ((k[3] * t + k[2]) * t + k[1]) * t + k[0];
    let df = |t: f64| (3.0 * k[3] * t + 2.0 * k[2]) * t + k[1];
    let scale = k.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    // Monotone pieces of [0, 1]: split where f' = 3k3 t² + 2k2 t + k1 vanishes.
    let (mut cuts, mut count) = ([0.0; 4], 1);
    let mut cut = |t: f64| {
        if t > 0.0 && t < 1.0 {
            cuts[count] = t;
            count += 1;
        }
    };
    let (qa, qb, qc) = (3.0 * k[3], 2.0 * k[2], k[1]);
    if qa.abs() > 1e-14 * scale {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc > 0.0 {
            let s = disc.sqrt();
            let mut r = [(-qb - s) / (2.0 * qa), (-qb + s) / (2.0 * qa)];
            r.sort_by(f64::total_cmp);
            r.into_iter().for_each(&mut cut);
        }
    } else if qb.abs() > 1e-14 * scale {
        cut(-qc / qb);
    }
    cuts[count] = 1.0;
    count += 1;
    for w in cuts[..count].windows(2) {
        let (mut lo, mut hi) = (w[0], w[1]);
        let (flo, fhi) = (f(lo), f(hi));
        // The sign that makes f fall through zero on this piece (≥ 0 at its start, < 0 at its
        // end; ≤ 0 either way, where touching zero at either end counts).
        let sign = match through {
            Through::Falling if flo >= 0.0 && fhi < 0.0 => 1.0,
            Through::EitherWay if flo >= 0.0 && fhi <= 0.0 => 1.0,
            Through::EitherWay if flo <= 0.0 && fhi >= 0.0 => -1.0,
            _ => continue,
        };
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if sign * f(mid) >= 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let t = 0.5 * (lo + hi);
        if through == Through::Falling && df(t) > 0.0 {
            continue;
        }
        if meets(t) {
            return Some(t);
        }
    }
    None
}

/// Whether `x` (in the triangle's plane, or nearly) projects inside the triangle `t`.
fn inside(x: &Vector3<f64>, t: &[Vector3<f64>; 3]) -> bool {
    let (e1, e2, q) = (t[1] - t[0], t[2] - t[0], x - t[0]);
    let (d11, d12, d22) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
    let (d1q, d2q) = (e1.dot(&q), e2.dot(&q));
    let det = d11 * d22 - d12 * d12;
    // A sliver (its corners in a line, to round-off) has no inside: its weights would be
    // round-off, and take points far off it.
    if det <= 1e-12 * d11 * d22 {
        return false;
    }
    let v = (d22 * d1q - d12 * d2q) / det;
    let w = (d11 * d2q - d12 * d1q) / det;
    v >= -EDGE_SLACK && w >= -EDGE_SLACK && v + w <= 1.0 + EDGE_SLACK
}

/// A sliver of the hand's skin at a split seam (two corners equal to round-off), as measured:
/// a fixture for the tests of what meets facets.
#[cfg(test)]
pub(super) fn seam_sliver() -> [Vector3<f64>; 3] {
    [
        Vector3::new(
            0.07417617434452912,
            -0.01876104239298431,
            -0.017491644524492103,
        ),
        Vector3::new(
            0.07259962671363271,
            -0.018366977706266028,
            -0.01749175252458943,
        ),
        Vector3::new(
            0.0725996267136327,
            -0.018366977706266024,
            -0.01749175252458943,
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
        Vector3::new(x, y, z)
    }

    /// The unit right triangle in z = 0, facing +z.
    fn flat() -> [Vector3<f64>; 3] {
        [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]
    }

    #[test]
    fn a_point_falling_through_a_still_triangle_passes_at_the_plane() {
        let t = passes_through([&v(0.2, 0.2, 1.0), &v(0.2, 0.2, -3.0)], &flat(), &flat());
        assert!((t.unwrap() - 0.25).abs() < 1e-12);
        // Back to front is leaving, not passing through; beside the triangle is missing it.
        assert!(
            passes_through([&v(0.2, 0.2, -1.0), &v(0.2, 0.2, 1.0)], &flat(), &flat()).is_none()
        );
        assert!(
            passes_through([&v(0.8, 0.8, 1.0), &v(0.8, 0.8, -1.0)], &flat(), &flat()).is_none()
        );
        // Stopping short of it, or behind it from the start.
        assert!(passes_through([&v(0.2, 0.2, 1.0), &v(0.2, 0.2, 0.1)], &flat(), &flat()).is_none());
        assert!(
            passes_through([&v(0.2, 0.2, -1.0), &v(0.2, 0.2, -2.0)], &flat(), &flat()).is_none()
        );
    }

    /// The triangle turning about its x edge through a still point: met when the plane sweeps
    /// it, at the angle the geometry says.
    #[test]
    fn a_turning_triangle_meets_a_still_point_where_its_plane_sweeps_it() {
        // The far corner moves from (0, 1, 0) to (0, 0, 1) in a straight line: the point
        // (0.1, 0.3, 0.3) lies on the plane through the x axis and (0, 1 − t, t) where
        // t/(1 − t) = 0.3/0.3, t = 0.5; there the corner is (0, 0.5, 0.5) and the point (at
        // y, z = 0.3) inside. It starts in front (z > 0) and ends behind (y > 0 behind a
        // triangle facing −y).
        let end = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 0.0, 1.0)];
        let p = v(0.1, 0.3, 0.3);
        let t = passes_through([&p, &p], &flat(), &end).unwrap();
        assert!((t - 0.5).abs() < 1e-12, "t = {t}");
        // A point beyond the turning triangle's reach is not met.
        let far = v(0.1, 0.8, 0.8);
        assert!(passes_through([&far, &far], &flat(), &end).is_none());
    }

    /// A sliver — two corners coinciding to round-off, as where a split skin's seam vertices
    /// meet — has no inside: its weights are round-off (here 0, 0: "at its first corner") and
    /// took a point 14 mm from it as passing through it (measured on the hand's skin).
    #[test]
    fn a_sliver_is_passed_through_by_nothing() {
        let seam = seam_sliver();
        let far = v(
            0.06309855501524515,
            -0.02732014069309691,
            -0.016654095830110988,
        );
        assert!(!inside(&far, &seam));
        // A proper triangle still has its inside, to its edges.
        assert!(inside(&v(0.2, 0.2, 0.0), &flat()) && inside(&v(0.5, 0.0, 0.0), &flat()));
        assert!(!inside(&v(0.6, 0.6, 0.0), &flat()));
        // Far from a triangle's sweep: nothing (the boxes alone tell).
        let p = [&v(5.0, 5.0, 1.0), &v(5.0, 5.0, -1.0)];
        assert!(passes_through(p, &flat(), &flat()).is_none());
    }

    /// The cubic's three roots: a point crossing the plane three times (the triangle moving
    /// through it and back while it moves) counts at its first fall through the triangle.
    #[test]
    fn the_first_fall_through_the_triangle_counts() {
        // A point moving down through the still triangle at t = 0.5 with nothing else moving.
        let t = passes_through([&v(0.3, 0.3, 0.5), &v(0.3, 0.3, -0.5)], &flat(), &flat());
        assert!((t.unwrap() - 0.5).abs() < 1e-12);
        // The same with the triangle moving up by 0.5 meanwhile: it meets it sooner, at
        // 0.5 − t = 0.5 t, t = 1/3.
        let up = flat().map(|c| c + v(0.0, 0.0, 0.5));
        let t = passes_through([&v(0.3, 0.3, 0.5), &v(0.3, 0.3, -0.5)], &flat(), &up).unwrap();
        assert!((t - 1.0 / 3.0).abs() < 1e-12);
    }

    /// The edge along y at x = z = 0 from y = −1 to 1.
    fn along_y() -> [Vector3<f64>; 2] {
        [v(0.0, -1.0, 0.0), v(0.0, 1.0, 0.0)]
    }

    /// The four ends of edges `a` and `b`, in order.
    fn ends(a: [Vector3<f64>; 2], b: [Vector3<f64>; 2]) -> [Vector3<f64>; 4] {
        [a[0], a[1], b[0], b[1]]
    }

    /// An edge along x at y = 0.3 moving straight down (or up) through the still edge along y:
    /// they cross where it passes z = 0, whichever way and whichever edge is named first.
    #[test]
    fn an_edge_moving_through_a_still_edge_crosses_it_where_they_meet() {
        let a = along_y();
        let b = |x0: f64, x1: f64, y: f64, z: f64| [v(x0, y, z), v(x1, y, z)];
        let step = |z0: f64, z1: f64| {
            edges_cross(
                &ends(a, b(-1.0, 1.0, 0.3, z0)),
                &ends(a, b(-1.0, 1.0, 0.3, z1)),
            )
        };
        assert!((step(1.0, -1.0).unwrap() - 0.5).abs() < 1e-12);
        assert!((step(1.0, -3.0).unwrap() - 0.25).abs() < 1e-12);
        assert!((step(-1.0, 3.0).unwrap() - 0.25).abs() < 1e-12);
        let (s, e) = (b(-1.0, 1.0, 0.3, 1.0), b(-1.0, 1.0, 0.3, -3.0));
        for (start, end) in [
            (ends(s, a), ends(e, a)),
            (ends([a[1], a[0]], s), ends([a[1], a[0]], e)),
            (ends(a, [s[1], s[0]]), ends(a, [e[1], e[0]])),
        ] {
            assert!((edges_cross(&start, &end).unwrap() - 0.25).abs() < 1e-12);
        }
        // Touching at the step's end counts; stopping short does not.
        assert!((step(1.0, 0.0).unwrap() - 1.0).abs() < 1e-12);
        assert!(step(1.0, 0.1).is_none());
        // Coplanar at t = 0.5 but apart: beyond a's end (y = 1.5), or beside it (x ≥ 0.5).
        for (x0, x1, y) in [(-1.0, 1.0, 1.5), (0.5, 2.0, 0.3), (-2.0, -0.5, 0.3)] {
            let (s, e) = (b(x0, x1, y, 1.0), b(x0, x1, y, -1.0));
            assert!(
                edges_cross(&ends(a, s), &ends(a, e)).is_none(),
                "{x0}, {x1}, {y}"
            );
        }
        // Far apart: the boxes alone tell. Parallel (f ≡ 0), even passing through each other
        // as here: none (their ends' paths through the facets tell).
        let far = b(4.0, 6.0, 0.3, 1.0);
        assert!(edges_cross(&ends(a, far), &ends(a, b(4.0, 6.0, 0.3, -1.0))).is_none());
        let (s, e) = (
            [v(0.0, 0.5, 1.0), v(0.0, 2.0, 1.0)],
            [v(0.0, 0.5, -1.0), v(0.0, 2.0, -1.0)],
        );
        assert!(edges_cross(&ends(a, s), &ends(a, e)).is_none());
    }

    /// An edge turning about a still end through the still edge along y (its free end moving
    /// in a straight line): they cross when its line passes through (0, 0.2, 0), at t = 0.5,
    /// its middle then.
    #[test]
    fn a_turning_edge_crosses_a_still_edge_where_its_line_sweeps_it() {
        let pivot = v(-1.0, 0.2, -1.0);
        let (from, to) = (v(3.0, 0.2, -1.0), v(-1.0, 0.2, 3.0));
        let t = edges_cross(
            &ends(along_y(), [pivot, from]),
            &ends(along_y(), [pivot, to]),
        );
        assert!((t.unwrap() - 0.5).abs() < 1e-12, "{t:?}");
        // The still edge ending short of y = 0.2: swept past, not met.
        let short = [v(0.0, -1.0, 0.0), v(0.0, 0.1, 0.0)];
        assert!(edges_cross(&ends(short, [pivot, from]), &ends(short, [pivot, to])).is_none());
        // Turning short of it: never coplanar.
        let less = v(3.0, 0.2, 0.5);
        assert!(edges_cross(
            &ends(along_y(), [pivot, from]),
            &ends(along_y(), [pivot, less])
        )
        .is_none());
    }

    /// Both ends of an edge moving differently: coplanar with the still edge along y at
    /// t = 0.25 and 0.75 (f = 4 (t − 1/4)(t − 3/4)), crossing it at (0, 0.3, 0) each time; the
    /// first counts, and a step over either half finds its own.
    #[test]
    fn the_first_of_two_crossings_counts() {
        let b = |t: f64| {
            [
                v(-1.0, 0.3, 0.5 - t),
                v(1.0 + 2.0 * t, 0.3, -0.875 + 2.0 * t),
            ]
        };
        let over = |t0: f64, t1: f64| edges_cross(&ends(along_y(), b(t0)), &ends(along_y(), b(t1)));
        assert!((over(0.0, 1.0).unwrap() - 0.25).abs() < 1e-12);
        assert!((over(0.0, 0.5).unwrap() - 0.5).abs() < 1e-12);
        assert!((over(0.5, 1.0).unwrap() - 0.5).abs() < 1e-12);
        assert!(over(0.3, 0.7).is_none());
        // Grazing: f = (1 − 2t)², b lying along x through (0, 0.3, 0) at t = 0.5 only.
        let graze = |t: f64| [v(-1.0, 0.3, 0.5 - t), v(1.0 + 2.0 * t, 0.3, -1.0 + 2.0 * t)];
        let t = edges_cross(&ends(along_y(), graze(0.0)), &ends(along_y(), graze(1.0)));
        assert!((t.unwrap() - 0.5).abs() < 1e-9, "{t:?}");
    }
}
