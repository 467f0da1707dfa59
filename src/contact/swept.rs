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

use super::bounds::Bounds;
use nalgebra::Vector3;

/// Barycentric slack at a crossing: a point passing through an edge shared by two triangles
/// passes through both.
const EDGE_SLACK: f64 = 1e-9;

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
    let c0 = e1.cross(&e2);
    let c1 = e1.cross(&de2) + de1.cross(&e2);
    let c2 = de1.cross(&de2);
    // f(t) = k0 + k1 t + k2 t² + k3 t³.
    let k = [
        c0.dot(&q),
        c0.dot(&dq) + c1.dot(&q),
        c1.dot(&dq) + c2.dot(&q),
        c2.dot(&dq),
    ];
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
        // A fall through zero on this piece (front to back); touching zero at its start counts.
        if !(flo >= 0.0 && fhi < 0.0) {
            continue;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if f(mid) >= 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let t = 0.5 * (lo + hi);
        if df(t) > 0.0 {
            continue;
        }
        let at = |x0: &Vector3<f64>, x1: &Vector3<f64>| x0 + (x1 - x0) * t;
        let corners = [0, 1, 2].map(|i| at(&start[i], &end[i]));
        if inside(&at(p[0], p[1]), &corners) {
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
}
