//! The barrier of incremental potential contact (IPC; Li et al. 2020, "Incremental Potential
//! Contact: Intersection- and Inversion-free, Large-Deformation Dynamics", ACM Trans. Graph.
//! 39(4)) on point–facet pairs, for a Newton solver that minimises energy: the squared distance
//! d² from a point p to a triangle (a, b, c), with its gradient and Hessian in the 12
//! coordinates (p, a, b, c); the log barrier on d²; and a pair's energy κ·b(d²) with its
//! gradient and positive semi-definite Hessian.
//!
//! As in IPC, the distance is that to the nearest feature of the closed triangle — its face,
//! an edge (as a line) or a corner — and its derivatives are those of that feature's formula,
//! smooth within the feature's region. Lengths are in metres, squared distances in m².
//! Continuous collision (whether a point passes through a facet over a step) is `swept.rs`.

use nalgebra::{Matrix3, SMatrix, SVector, SymmetricEigen, Vector3};

/// A triangle whose sine of the angle at `a` squared, |e1 × e2|² / (|e1|² |e2|²), is at most
/// this is a sliver: it has no face region, and its edges give the distance (off from the exact
/// one by at most its width, 10⁻⁸ of its sides).
const SLIVER: f64 = 1e-16;

/// The squared distance d² from a point to a triangle, with its derivatives in the 12
/// coordinates (p, a, b, c), each x, y, z.
#[derive(Clone, Debug, PartialEq)]
pub struct PointTriangle {
    /// Squared distance d² from the point to the closed triangle, m².
    pub d2: f64,
    /// ∂d²/∂x over x = (p, a, b, c), m.
    pub gradient: SVector<f64, 12>,
    /// ∂²d²/∂x² over x = (p, a, b, c), dimensionless (symmetric).
    pub hessian: SMatrix<f64, 12, 12>,
}

/// A point–triangle pair's barrier energy κ·b(d²) and its derivatives in the 12 coordinates
/// (p, a, b, c).
#[derive(Clone, Debug, PartialEq)]
pub struct PairBarrier {
    /// κ·b(d²), in the units of κ times m⁴; +∞ where the pair touches or crosses (d² ≤ 0).
    pub energy: f64,
    /// κ·b'(d²)·∇d² over (p, a, b, c).
    pub gradient: SVector<f64, 12>,
    /// κ·(b''·∇d²∇d²ᵀ + b'·∇²d²) with its negative eigenvalues set to zero.
    pub hessian: SMatrix<f64, 12, 12>,
}

/// The feature of a triangle nearest a point; corners numbered 0 = a, 1 = b, 2 = c.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Feature {
    /// The face: the point projects inside the triangle.
    Face,
    /// The edge from corner i to corner j, at a point strictly between them.
    Edge(usize, usize),
    /// Corner i.
    Vertex(usize),
}

/// The squared distance from `p` to the closed triangle (a, b, c), m²; cheap, no derivatives.
/// Degenerate triangles (corners in a line, or equal) give the distance to their edges or
/// corner; non-finite coordinates give NaN.
pub fn point_triangle_distance2(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> f64 {
    nearest_feature(p, [a, b, c]).1
}

/// The squared distance from `p` to the closed triangle (a, b, c) with its gradient and
/// Hessian in (p, a, b, c): those of the nearest feature's formula, the point–plane distance
/// ((p − a)·n)² / (n·n) with n = (b − a) × (c − a), the point–line distance
/// |(p − x) × (y − x)|² / |y − x|² or the point–point distance |p − x|². A sliver or degenerate
/// triangle is measured by its edges and corners: always finite for finite coordinates.
pub fn point_triangle_derivatives(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
) -> PointTriangle {
    let corners = [a, b, c];
    match nearest_feature(p, corners).0 {
        Feature::Face => {
            let (d2, g, h) = point_plane(&(p - a), &(b - a), &(c - a));
            lift(d2, g, h, &[(0, 1), (2, 1), (3, 1)])
        }
        Feature::Edge(i, j) => {
            let (x, y) = (corners[i], corners[j]);
            let (d2, g, h) = point_line(&(p - x), &(y - x));
            lift(d2, g, h, &[(0, i + 1), (j + 1, i + 1)])
        }
        Feature::Vertex(i) => {
            let u = p - corners[i];
            let h = Matrix3::identity() * 2.0;
            lift(u.norm_squared(), u * 2.0, h, &[(0, i + 1)])
        }
    }
}

/// IPC's log barrier on the squared distance x = d² with cutoff x̂ = `dhat2` (m²):
/// b(x) = −(x − x̂)² ln(x / x̂) for 0 < x < x̂, 0 for x ≥ x̂ (C² there: b, b' and b'' all vanish
/// at x̂). Returns (b, db/dx, d²b/dx²). For x ≤ 0 (or NaN), inadmissible, it returns
/// (+∞, −∞, +∞).
pub fn barrier(d2: f64, dhat2: f64) -> (f64, f64, f64) {
    if d2.is_nan() || d2 <= 0.0 {
        return (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
    }
    if d2 >= dhat2 {
        return (0.0, 0.0, 0.0);
    }
    let (gap, log) = (d2 - dhat2, (d2 / dhat2).ln());
    let ratio = gap / d2;
    (
        -gap * gap * log,
        -2.0 * gap * log - gap * ratio,
        -2.0 * log - 4.0 * ratio + ratio * ratio,
    )
}

/// The symmetric part of `m` with its negative eigenvalues set to zero: the nearest positive
/// semi-definite matrix (in the Frobenius norm). A matrix with a non-finite entry is returned
/// symmetrized as it is (its eigen-decomposition would not converge).
pub fn project_psd(m: &SMatrix<f64, 12, 12>) -> SMatrix<f64, 12, 12> {
    let sym = (m + m.transpose()) * 0.5;
    if !sym.iter().all(|x| x.is_finite()) {
        return sym;
    }
    let eigen = SymmetricEigen::new(sym);
    if eigen.eigenvalues.iter().all(|&l| l >= 0.0) {
        return sym;
    }
    let v = &eigen.eigenvectors;
    let kept = eigen.eigenvalues.map(|l| l.max(0.0));
    let projected = v * SMatrix::<f64, 12, 12>::from_diagonal(&kept) * v.transpose();
    (projected + projected.transpose()) * 0.5
}

impl PairBarrier {
    /// A pair that touches or crosses: energy +∞, no derivatives (the state is inadmissible and
    /// the step must be shortened).
    pub fn inadmissible() -> PairBarrier {
        PairBarrier {
            energy: f64::INFINITY,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }

    /// The same with its Hessian projected positive semi-definite (`project_psd`; an
    /// inadmissible pair's zero Hessian as it is).
    pub fn projected(mut self) -> PairBarrier {
        if self.energy.is_finite() {
            self.hessian = project_psd(&self.hessian);
        }
        self
    }
}

/// The barrier of point `p` against triangle (a, b, c) with cutoff distance² `dhat2` (m²) and
/// stiffness `kappa`: `None` when the pair is inactive (d² ≥ d̂²); otherwise energy κ·b(d²),
/// gradient κ·b'·∇d² and the exact Hessian κ·(b''·∇d²∇d²ᵀ + b'·∇²d²) (indefinite in general,
/// no eigen-decomposition: a Newton step tries it first; [`PairBarrier::projected`] makes it
/// positive semi-definite). Where the point touches or crosses the triangle (d² ≤ 0, or NaN for
/// non-finite coordinates) it returns energy +∞ with zero gradient and Hessian: the state is
/// inadmissible and the step must be shortened.
pub fn pair_barrier(
    p: &Vector3<f64>,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    c: &Vector3<f64>,
    dhat2: f64,
    kappa: f64,
) -> Option<PairBarrier> {
    let d2 = point_triangle_distance2(p, a, b, c);
    if d2 >= dhat2 {
        return None;
    }
    if d2.is_nan() || d2 <= 0.0 {
        return Some(PairBarrier::inadmissible());
    }
    // The same formulas as the distance's: the same d².
    let dist = point_triangle_derivatives(p, a, b, c);
    let (e, de, dde) = barrier(dist.d2, dhat2);
    let g = &dist.gradient;
    Some(PairBarrier {
        energy: kappa * e,
        gradient: g * (kappa * de),
        hessian: (g * g.transpose() * dde + dist.hessian * de) * kappa,
    })
}

/// The nearest feature of triangle `t` to `p` and the squared distance to it.
fn nearest_feature(p: &Vector3<f64>, t: [&Vector3<f64>; 3]) -> (Feature, f64) {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let n = e1.cross(&e2);
    let m = n.norm_squared();
    if m > SLIVER * e1.norm_squared() * e2.norm_squared() {
        // Weights of b and c at the projection of p on the plane.
        let q = p - t[0];
        let wb = q.cross(&e2).dot(&n) / m;
        let wc = e1.cross(&q).dot(&n) / m;
        if wb >= 0.0 && wc >= 0.0 && wb + wc <= 1.0 {
            let g = q.dot(&n);
            return (Feature::Face, g * g / m);
        }
    }
    // Outside the face (or a sliver): the nearest point is on an edge. A NaN distance stays
    // (the first edge's), and tells the caller.
    let mut best = (Feature::Vertex(0), f64::NAN);
    for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
        let (x, y) = (t[i], t[j]);
        let (u, e) = (p - x, y - x);
        let q = e.norm_squared();
        let s = u.dot(&e) / q;
        let near = if !(s > 0.0 && q > 0.0) {
            (Feature::Vertex(i), u.norm_squared())
        } else if s >= 1.0 {
            (Feature::Vertex(j), (p - y).norm_squared())
        } else {
            (Feature::Edge(i, j), (u - e * s).norm_squared())
        };
        if k == 0 || near.1 < best.1 {
            best = near;
        }
    }
    best
}

/// d² = ((u·n)² / (n·n)) with n = e1 × e2, over (u, e1, e2): its value, gradient and Hessian.
pub(super) fn point_plane(
    u: &Vector3<f64>,
    e1: &Vector3<f64>,
    e2: &Vector3<f64>,
) -> (f64, SVector<f64, 9>, SMatrix<f64, 9, 9>) {
    let n = e1.cross(e2);
    let m = n.norm_squared();
    let g = u.dot(&n);
    let h = g / m;
    let id = Matrix3::identity();
    // First over (u, n): ∂/∂u = 2h n, ∂/∂n = w = 2h (u − h n).
    let w = (u - n * h) * (2.0 * h);
    let v = u - n * (2.0 * h);
    let h_uu = n * n.transpose() * (2.0 / m);
    let h_un = id * (2.0 * h) + n * v.transpose() * (2.0 / m);
    let h_nn = v * v.transpose() * (2.0 / m) - id * (2.0 * h * h);
    let mut h6 = SMatrix::<f64, 6, 6>::zeros();
    h6.fixed_view_mut::<3, 3>(0, 0).copy_from(&h_uu);
    h6.fixed_view_mut::<3, 3>(0, 3).copy_from(&h_un);
    h6.fixed_view_mut::<3, 3>(3, 0).copy_from(&h_un.transpose());
    h6.fixed_view_mut::<3, 3>(3, 3).copy_from(&h_nn);
    let mut g6 = SVector::<f64, 6>::zeros();
    g6.fixed_rows_mut::<3>(0).copy_from(&(n * (2.0 * h)));
    g6.fixed_rows_mut::<3>(3).copy_from(&w);
    // Then through n = e1 × e2: dn = −[e2]× de1 + [e1]× de2, and w·(de1 × de2) from its
    // second derivative.
    let mut jn = SMatrix::<f64, 6, 9>::zeros();
    jn.fixed_view_mut::<3, 3>(0, 0).copy_from(&id);
    jn.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(-e2.cross_matrix()));
    jn.fixed_view_mut::<3, 3>(3, 6)
        .copy_from(&e1.cross_matrix());
    let mut hessian = jn.transpose() * h6 * jn;
    let wx = w.cross_matrix();
    let mut cross = hessian.fixed_view_mut::<3, 3>(3, 6);
    cross -= wx;
    let mut cross = hessian.fixed_view_mut::<3, 3>(6, 3);
    cross += wx;
    (g * g / m, jn.transpose() * g6, hessian)
}

/// d² = |u × e|² / |e|² = |r|² with r = u − t e, t = u·e / e·e, over (u, e): its value,
/// gradient and Hessian.
pub(super) fn point_line(
    u: &Vector3<f64>,
    e: &Vector3<f64>,
) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let q = e.norm_squared();
    let t = u.dot(e) / q;
    let r = u - e * t;
    let id = Matrix3::identity();
    let s = r - e * t;
    let mut hessian = SMatrix::<f64, 6, 6>::zeros();
    let h_ue = -id * (2.0 * t) - e * s.transpose() * (2.0 / q);
    hessian
        .fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&((id - e * e.transpose() / q) * 2.0));
    hessian.fixed_view_mut::<3, 3>(0, 3).copy_from(&h_ue);
    hessian
        .fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&h_ue.transpose());
    hessian
        .fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(id * (2.0 * t * t) - s * s.transpose() * (2.0 / q)));
    let mut gradient = SVector::<f64, 6>::zeros();
    gradient.fixed_rows_mut::<3>(0).copy_from(&(r * 2.0));
    gradient.fixed_rows_mut::<3>(3).copy_from(&(r * (-2.0 * t)));
    (r.norm_squared(), gradient, hessian)
}

/// A distance's derivatives over differences of the corners, block k being
/// x[pairs[k].0] − x[pairs[k].1] (x = p, a, b, c), carried to (p, a, b, c).
pub(super) fn lift<const N: usize>(
    d2: f64,
    gradient: SVector<f64, N>,
    hessian: SMatrix<f64, N, N>,
    pairs: &[(usize, usize)],
) -> PointTriangle {
    debug_assert_eq!(N, 3 * pairs.len());
    let mut j = SMatrix::<f64, N, 12>::zeros();
    for (k, &(plus, minus)) in pairs.iter().enumerate() {
        for d in 0..3 {
            j[(3 * k + d, 3 * plus + d)] = 1.0;
            j[(3 * k + d, 3 * minus + d)] = -1.0;
        }
    }
    let hessian = j.transpose() * hessian * j;
    PointTriangle {
        d2,
        gradient: j.transpose() * gradient,
        hessian: (hessian + hessian.transpose()) * 0.5,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::differences::{all_finite, central, relative, v, Rng, M12, V12};
    use crate::contact::project_on_triangle;

    /// The unit right triangle in z = 0.
    fn flat() -> [Vector3<f64>; 3] {
        [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]
    }

    impl Rng {
        /// A well-shaped triangle of size `scale`: every angle above 20°.
        fn triangle(&mut self, scale: f64) -> [Vector3<f64>; 3] {
            loop {
                let t = [self.vector(scale), self.vector(scale), self.vector(scale)];
                let sine2 = |i: usize| {
                    let (x, y) = (t[(i + 1) % 3] - t[i], t[(i + 2) % 3] - t[i]);
                    x.cross(&y).norm_squared() / (x.norm_squared() * y.norm_squared())
                };
                let short = (0..3).any(|i| (t[(i + 1) % 3] - t[i]).norm() < 0.3 * scale);
                if !short && (0..3).all(|i| sine2(i) > 0.342_f64.powi(2)) {
                    return t;
                }
            }
        }
    }

    /// Where a sampled point lies relative to its triangle.
    #[derive(Clone, Copy, Debug)]
    enum Region {
        Face,
        /// Beyond the edge from corner i to corner i + 1.
        Edge(usize),
        Vertex(usize),
    }

    /// A point in `region` of `t`, away from the region's boundaries, and its squared distance
    /// by construction.
    fn sample(
        rng: &mut Rng,
        t: &[Vector3<f64>; 3],
        region: Region,
        scale: f64,
    ) -> (Vector3<f64>, f64) {
        let normal = (t[1] - t[0]).cross(&(t[2] - t[0])).normalize();
        let height = rng.range(-1.0, 1.0) * scale;
        match region {
            Region::Face => loop {
                let (wb, wc) = (rng.range(0.1, 0.8), rng.range(0.1, 0.8));
                if wb + wc <= 0.9 {
                    let height = height.signum() * (0.1 * scale + height.abs());
                    let on = t[0] + (t[1] - t[0]) * wb + (t[2] - t[0]) * wc;
                    return (on + normal * height, height * height);
                }
            },
            Region::Edge(i) => {
                let (x, y, z) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                let mut out = (y - x).cross(&normal).normalize();
                if out.dot(&(z - x)) > 0.0 {
                    out = -out;
                }
                let beyond = rng.range(0.1, 1.0) * scale;
                let on = x + (y - x) * rng.range(0.15, 0.85);
                (
                    on + out * beyond + normal * height,
                    beyond * beyond + height * height,
                )
            }
            Region::Vertex(i) => loop {
                let (x, y, z) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                let (ty, tz) = ((y - x).normalize(), (z - x).normalize());
                let d = -(ty * rng.range(0.2, 1.0) + tz * rng.range(0.2, 1.0)).normalize();
                if d.dot(&ty) < -0.2 && d.dot(&tz) < -0.2 {
                    let away = rng.range(0.1, 1.0) * scale;
                    return (
                        x + d * away + normal * height,
                        away * away + height * height,
                    );
                }
            },
        }
    }

    const REGIONS: [Region; 7] = [
        Region::Face,
        Region::Edge(0),
        Region::Edge(1),
        Region::Edge(2),
        Region::Vertex(0),
        Region::Vertex(1),
        Region::Vertex(2),
    ];

    fn split(x: &SVector<f64, 12>) -> [Vector3<f64>; 4] {
        [0, 1, 2, 3].map(|k| x.fixed_rows::<3>(3 * k).into_owned())
    }

    fn join(p: &Vector3<f64>, t: &[Vector3<f64>; 3]) -> SVector<f64, 12> {
        let mut x = SVector::<f64, 12>::zeros();
        for (k, y) in [p, &t[0], &t[1], &t[2]].into_iter().enumerate() {
            x.fixed_rows_mut::<3>(3 * k).copy_from(y);
        }
        x
    }

    fn distance2_at(x: &SVector<f64, 12>) -> f64 {
        let [p, a, b, c] = split(x);
        point_triangle_distance2(&p, &a, &b, &c)
    }

    fn derivatives_at(x: &SVector<f64, 12>) -> PointTriangle {
        let [p, a, b, c] = split(x);
        point_triangle_derivatives(&p, &a, &b, &c)
    }

    #[test]
    fn distances_of_known_configurations_are_exact() {
        let [a, b, c] = flat();
        let d2 = |p: Vector3<f64>| point_triangle_distance2(&p, &a, &b, &c);
        // Above and below the face's interior.
        assert_eq!(d2(v(0.25, 0.25, 2.0)), 4.0);
        assert_eq!(d2(v(0.25, 0.5, -0.5)), 0.25);
        // Beyond each edge: the hypotenuse (nearest (0.5, 0.5, 0)), y = 0, x = 0.
        assert_eq!(d2(v(1.0, 1.0, 0.0)), 0.5);
        assert_eq!(d2(v(1.0, 1.0, 1.0)), 1.5);
        assert_eq!(d2(v(0.5, -3.0, 4.0)), 25.0);
        assert_eq!(d2(v(-2.0, 0.75, 1.0)), 5.0);
        // Beyond each corner.
        assert_eq!(d2(v(-1.0, -2.0, 2.0)), 9.0);
        assert_eq!(d2(v(3.0, -1.0, 0.0)), 5.0);
        assert_eq!(d2(v(-0.5, 2.0, -1.0)), 2.25);
        // On it: in the face, on an edge, at a corner.
        assert_eq!(d2(v(0.2, 0.3, 0.0)), 0.0);
        assert_eq!(d2(v(0.5, 0.0, 0.0)), 0.0);
        assert_eq!(d2(c), 0.0);
        // The derivatives' distance is the same number.
        for p in [v(0.25, 0.25, 2.0), v(1.0, 1.0, 1.0), v(-1.0, -2.0, 2.0)] {
            assert_eq!(point_triangle_derivatives(&p, &a, &b, &c).d2, d2(p));
        }
    }

    /// Sampled points in every region, at hand scale (centimetres) and at metres: the distance
    /// by construction, the closest point of `project_on_triangle` (Ericson), and the
    /// derivatives' distance all agree.
    #[test]
    fn distances_in_every_region_agree_with_the_construction() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        for scale in [1.0, 0.01] {
            for _ in 0..40 {
                let t = rng.triangle(scale);
                for region in REGIONS {
                    let (p, want) = sample(&mut rng, &t, region, scale);
                    let got = point_triangle_distance2(&p, &t[0], &t[1], &t[2]);
                    assert!(
                        (got - want).abs() <= 1e-12 * want,
                        "{region:?}: {got} vs {want}"
                    );
                    let ericson = project_on_triangle(&p, &t).unwrap().distance.powi(2);
                    assert!((got - ericson).abs() <= 1e-12 * want, "{got} vs {ericson}");
                    assert_eq!(point_triangle_derivatives(&p, &t[0], &t[1], &t[2]).d2, got);
                }
            }
        }
    }

    #[test]
    fn derivatives_match_central_differences_in_every_region() {
        let mut rng = Rng(0xD1B5_4A32_D192_ED03);
        for scale in [1.0, 0.01] {
            for _ in 0..20 {
                let t = rng.triangle(scale);
                for region in REGIONS {
                    let (p, _) = sample(&mut rng, &t, region, scale);
                    let x = join(&p, &t);
                    let exact = derivatives_at(&x);
                    let (gradient, hessian) = central(&x, 1e-6 * scale, distance2_at, |y| {
                        derivatives_at(y).gradient
                    });
                    let (eg, eh) = (
                        relative(&exact.gradient, &gradient),
                        relative(&exact.hessian, &hessian),
                    );
                    assert!(eg < 1e-6, "{region:?} gradient: relative error {eg:e}");
                    assert!(eh < 1e-6, "{region:?} Hessian: relative error {eh:e}");
                    // Symmetric, and moving everything together changes nothing.
                    assert_eq!(exact.hessian, exact.hessian.transpose());
                    let mut shift = SVector::<f64, 12>::zeros();
                    for k in 0..4 {
                        shift[3 * k] = 1.0;
                    }
                    assert!(exact.gradient.dot(&shift).abs() < 1e-12 * exact.gradient.norm());
                }
            }
        }
    }

    #[test]
    fn the_barrier_matches_its_differences_and_vanishes_smoothly_at_the_cutoff() {
        let dhat2 = 1e-6; // 1 mm, squared.
        for fraction in [1e-3, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9] {
            let x = fraction * dhat2;
            let (b, db, ddb) = barrier(x, dhat2);
            assert!(
                b > 0.0 && db < 0.0 && ddb > 0.0,
                "x = {x}: {b}, {db}, {ddb}"
            );
            let h = 1e-6 * x;
            let fd = (barrier(x + h, dhat2).0 - barrier(x - h, dhat2).0) / (2.0 * h);
            let fdd = (barrier(x + h, dhat2).1 - barrier(x - h, dhat2).1) / (2.0 * h);
            assert!((fd - db).abs() < 1e-6 * db.abs(), "b' at {x}: {fd} vs {db}");
            assert!(
                (fdd - ddb).abs() < 1e-6 * ddb.abs(),
                "b'' at {x}: {fdd} vs {ddb}"
            );
        }
        // A value by hand: x = x̂/e gives (x̂ (1 − 1/e))².
        let e = std::f64::consts::E;
        let want = (dhat2 * (1.0 - 1.0 / e)).powi(2);
        assert!((barrier(dhat2 / e, dhat2).0 - want).abs() < 1e-14 * want);
        // C¹ (indeed C²) at the cutoff, zero beyond.
        assert_eq!(barrier(dhat2, dhat2), (0.0, 0.0, 0.0));
        assert_eq!(barrier(2.0 * dhat2, dhat2), (0.0, 0.0, 0.0));
        // A distance ε below it: b ≈ ε³ x̂², b' ≈ −3 ε² x̂, b'' ≈ 6 ε, vanishing with ε.
        let eps = 1e-6;
        let (b, db, ddb) = barrier(dhat2 * (1.0 - eps), dhat2);
        let near = |got: f64, want: f64| (got / want - 1.0).abs() < 1e-3;
        assert!(near(b, eps.powi(3) * dhat2 * dhat2), "{b:e}");
        assert!(near(db, -3.0 * eps * eps * dhat2), "{db:e}");
        assert!(near(ddb, 6.0 * eps), "{ddb:e}");
        // Inadmissible: touching, crossing, NaN.
        let inadmissible = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY);
        assert_eq!(barrier(0.0, dhat2), inadmissible);
        assert_eq!(barrier(-1e-9, dhat2), inadmissible);
        assert_eq!(barrier(f64::NAN, dhat2), inadmissible);
    }

    /// Q diag(λ) Qᵀ with Q orthogonal from a QR factorization.
    fn with_eigenvalues(
        rng: &mut Rng,
        lambda: &[f64; 12],
    ) -> (SMatrix<f64, 12, 12>, SMatrix<f64, 12, 12>) {
        let random = SMatrix::<f64, 12, 12>::from_fn(|_, _| rng.range(-1.0, 1.0));
        let q = random.qr().q();
        let m = |l: &[f64; 12]| {
            q * SMatrix::<f64, 12, 12>::from_diagonal(&SVector::from(*l)) * q.transpose()
        };
        (m(lambda), m(&lambda.map(|l| l.max(0.0))))
    }

    #[test]
    fn project_psd_drops_the_negative_eigenvalues_only() {
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        let lambda = [
            -3.0, -1.0, -1e-3, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0,
        ];
        let (m, want) = with_eigenvalues(&mut rng, &lambda);
        let got = project_psd(&m);
        assert!(relative(&got, &want) < 1e-12, "{:e}", relative(&got, &want));
        let mut eigen: Vec<f64> = SymmetricEigen::new(got)
            .eigenvalues
            .iter()
            .copied()
            .collect();
        eigen.sort_by(f64::total_cmp);
        let expected = [0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0];
        for (g, w) in eigen.iter().zip(expected) {
            assert!((g - w).abs() < 1e-12, "{eigen:?}");
        }
        // Already semi-definite: unchanged; negative definite: zero; the skew part dropped.
        let (psd, _) = with_eigenvalues(
            &mut rng,
            &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 1.0, 2.0],
        );
        let psd = (psd + psd.transpose()) * 0.5;
        assert_eq!(project_psd(&psd), psd);
        assert_eq!(
            project_psd(&(-SMatrix::<f64, 12, 12>::identity())),
            M12::zeros()
        );
        let mut skew = SMatrix::<f64, 12, 12>::identity();
        skew[(0, 1)] = 1.0;
        skew[(1, 0)] = -1.0;
        assert_eq!(project_psd(&skew), M12::identity());
    }

    #[test]
    fn pair_barrier_is_the_barrier_of_the_distance_with_a_semi_definite_hessian() {
        let mut rng = Rng(0x0DDB_A11C_AFE0_F00D);
        let kappa = 1e4;
        let mut projected_something = false;
        for _ in 0..20 {
            let t = rng.triangle(0.01);
            for region in REGIONS {
                let (p, d2) = sample(&mut rng, &t, region, 0.002);
                let dhat2 = d2 / rng.range(0.2, 0.8);
                let pair = pair_barrier(&p, &t[0], &t[1], &t[2], dhat2, kappa)
                    .unwrap()
                    .projected();
                // Energy and gradient: κ b, κ b' ∇d², the gradient by differences too.
                let x = join(&p, &t);
                let dist = derivatives_at(&x);
                let (b, db, ddb) = barrier(dist.d2, dhat2);
                assert_eq!(pair.energy, kappa * b);
                let energy = |y: &SVector<f64, 12>| {
                    let [p, a, b, c] = split(y);
                    pair_barrier(&p, &a, &b, &c, dhat2, kappa).map_or(0.0, |e| e.energy)
                };
                let gradient = |y: &SVector<f64, 12>| {
                    let [p, a, b, c] = split(y);
                    pair_barrier(&p, &a, &b, &c, dhat2, kappa).map_or(V12::zeros(), |e| e.gradient)
                };
                let (fd, _) = central(&x, 1e-6 * d2.sqrt(), energy, gradient);
                assert!(relative(&pair.gradient, &fd) < 1e-6, "{region:?}");
                // The Hessian: the projection of the exact one, with no negative eigenvalue.
                let full =
                    (dist.gradient * dist.gradient.transpose() * ddb + dist.hessian * db) * kappa;
                assert!(relative(&pair.hessian, &project_psd(&full)) < 1e-15);
                let eigen = SymmetricEigen::new(pair.hessian).eigenvalues;
                let largest = eigen.amax();
                assert!(eigen.min() >= -1e-12 * largest, "{region:?}: {eigen}");
                projected_something |=
                    SymmetricEigen::new(full).eigenvalues.min() < -1e-6 * largest;
            }
        }
        assert!(
            projected_something,
            "no sample had an indefinite Hessian to project"
        );
    }

    #[test]
    fn pair_barrier_is_inactive_beyond_the_cutoff_and_infinite_at_contact() {
        let [a, b, c] = flat();
        let dhat2 = 1e-6;
        // 1 mm above the face: at the cutoff, inactive; just inside it, active.
        assert!(pair_barrier(&v(0.2, 0.2, 1e-3), &a, &b, &c, dhat2, 1.0).is_none());
        assert!(pair_barrier(&v(0.2, 0.2, 0.5), &a, &b, &c, dhat2, 1.0).is_none());
        assert!(pair_barrier(&v(-0.01, 0.5, 0.0), &a, &b, &c, dhat2, 1.0).is_none());
        let near = pair_barrier(&v(0.2, 0.2, 0.9e-3), &a, &b, &c, dhat2, 1.0).unwrap();
        assert!(near.energy > 0.0 && near.energy.is_finite());
        // Pushed away from the face: the energy falls as p rises (z gradient negative).
        assert!(near.gradient[2] < 0.0);
        // Touching (in the face, on an edge, at a corner): inadmissible.
        for p in [v(0.2, 0.2, 0.0), v(0.5, 0.5, 0.0), b] {
            let contact = pair_barrier(&p, &a, &b, &c, dhat2, 1.0).unwrap();
            assert_eq!(contact.energy, f64::INFINITY);
            assert_eq!(contact.gradient, V12::zeros());
            assert_eq!(contact.hessian, M12::zeros());
        }
    }

    #[test]
    fn degenerate_triangles_give_finite_distances_of_their_edges_and_corners() {
        let (a, b, c) = (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(3.0, 0.0, 0.0));
        // Corners in a line: the segment from a to c.
        for (p, want) in [
            (v(2.0, 1.0, 1.0), 2.0),
            (v(0.5, 0.0, -2.0), 4.0),
            (v(4.0, 0.0, 1.0), 2.0),
            (v(-1.0, 1.0, 0.0), 2.0),
            (v(2.0, 0.0, 0.0), 0.0),
        ] {
            for [x, y, z] in [[a, b, c], [b, c, a], [c, a, b], [a, c, b]] {
                assert_eq!(point_triangle_distance2(&p, &x, &y, &z), want);
                let d = point_triangle_derivatives(&p, &x, &y, &z);
                assert!(all_finite(&d) && d.d2 == want, "{d:?}");
            }
        }
        // All corners at one point, and two corners at one point.
        let p = v(1.0, 2.0, 2.0);
        let d = point_triangle_derivatives(&p, &a, &a, &a);
        assert!(all_finite(&d) && d.d2 == 9.0);
        let d = point_triangle_derivatives(&p, &a, &b, &b);
        assert!(all_finite(&d) && d.d2 == 8.0);
        let d = point_triangle_derivatives(&a, &a, &a, &a);
        assert!(all_finite(&d) && d.d2 == 0.0);
        // The point on a corner, on an edge, in the face: d² = 0, finite derivatives.
        let [a, b, c] = flat();
        for p in [a, v(0.5, 0.5, 0.0), v(0.1, 0.2, 0.0)] {
            let d = point_triangle_derivatives(&p, &a, &b, &c);
            assert!(all_finite(&d) && d.d2 == 0.0 && d.gradient == V12::zeros());
        }
        // A seam's sliver on the hand's skin (two corners equal to round-off): measured by its
        // edges, finite, and its barrier semi-definite.
        let seam = super::super::swept::seam_sliver();
        let p = (seam[0] + seam[1]) * 0.5 + v(0.0, 0.0, 5e-4);
        let d = point_triangle_derivatives(&p, &seam[0], &seam[1], &seam[2]);
        assert!(all_finite(&d) && (d.d2 - 2.5e-7).abs() < 1e-12, "{d:?}");
        let pair = pair_barrier(&p, &seam[0], &seam[1], &seam[2], 1e-6, 1e4)
            .unwrap()
            .projected();
        assert!(pair.energy.is_finite() && pair.hessian.iter().all(|x| x.is_finite()));
        assert!(SymmetricEigen::new(pair.hessian).eigenvalues.min() >= -1e-9 * pair.hessian.norm());
        // Non-finite coordinates: NaN distance, and an inadmissible pair (not an inactive one).
        let nan = v(f64::NAN, 0.0, 0.0);
        assert!(point_triangle_distance2(&nan, &a, &b, &c).is_nan());
        assert_eq!(
            pair_barrier(&nan, &a, &b, &c, 1e-6, 1.0).unwrap().energy,
            f64::INFINITY
        );
        assert!(project_psd(&SMatrix::from_element(f64::NAN))[(0, 0)].is_nan());
    }
}
