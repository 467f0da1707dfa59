//! What the tests of the barrier's kernels (`barrier.rs`, `edge_edge.rs`) share: a
//! deterministic random generator, central differences over the 12 coordinates of a pair, and
//! the relative error of a derivative.

use super::barrier::PointTriangle;
use nalgebra::{SMatrix, SVector, Vector3};

/// The 12 coordinates of a pair: a matrix over them.
pub type M12 = SMatrix<f64, 12, 12>;
/// The 12 coordinates of a pair: a vector over them.
pub type V12 = SVector<f64, 12>;

/// The point (x, y, z).
pub fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

/// A small deterministic generator (xorshift64*), uniform in [0, 1).
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Each coordinate uniform in [−scale, scale).
    pub fn vector(&mut self, scale: f64) -> Vector3<f64> {
        v(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ) * scale
    }
}

/// Central differences of `f` (gradient) and of `g` (Hessian, by columns) at `x`, step `h`.
pub fn central(x: &V12, h: f64, f: impl Fn(&V12) -> f64, g: impl Fn(&V12) -> V12) -> (V12, M12) {
    let mut gradient = V12::zeros();
    let mut hessian = M12::zeros();
    for k in 0..12 {
        let (mut plus, mut minus) = (*x, *x);
        plus[k] += h;
        minus[k] -= h;
        gradient[k] = (f(&plus) - f(&minus)) / (2.0 * h);
        hessian.set_column(k, &((g(&plus) - g(&minus)) / (2.0 * h)));
    }
    (gradient, hessian)
}

/// |got − want| / |want| (Frobenius).
pub fn relative<const R: usize, const C: usize>(
    got: &SMatrix<f64, R, C>,
    want: &SMatrix<f64, R, C>,
) -> f64 {
    (got - want).norm() / want.norm().max(f64::MIN_POSITIVE)
}

/// Whether a distance and its derivatives are all finite.
pub fn all_finite(d: &PointTriangle) -> bool {
    d.d2.is_finite()
        && d.gradient
            .iter()
            .chain(d.hessian.iter())
            .all(|x| x.is_finite())
}
