//! An element's tangent made positive semi-definite: its symmetric 24 × 24 matrix with each
//! negative eigenvalue replaced by its absolute value (Teran et al. 2005 clamp them to
//! zero; the absolute value, Chen et al. 2024, "absolute eigenvalue filtering", keeps the
//! step's scale along the turned mode). Assembled, such tangents give a positive definite K wherever the supports
//! hold the bodies: a Newton-like step from a state where the exact tangent is indefinite (a
//! body squeezed until its compressive stress outweighs its material stiffness in some mode),
//! to be corrected by iterations on the exact residual.

use super::hex8::ElementStiffness;
use nalgebra::{DMatrix, Matrix3, SymmetricEigen};

/// `ke` with its negative eigenvalues turned positive (and its round-off asymmetry removed).
pub fn absolute_eigenvalues(ke: &ElementStiffness) -> ElementStiffness {
    let mut m = DMatrix::<f64>::zeros(24, 24);
    for a in 0..8 {
        for b in 0..8 {
            for i in 0..3 {
                for j in 0..3 {
                    m[(3 * a + i, 3 * b + j)] = 0.5 * (ke[a][b][(i, j)] + ke[b][a][(j, i)]);
                }
            }
        }
    }
    // Most elements are positive semi-definite already: a Cholesky factorization (a small
    // fraction of the eigen-decomposition's cost) of the matrix shifted by round-off tells.
    let scale = (0..24).map(|i| m[(i, i)].abs()).fold(0.0, f64::max);
    let mut shifted = m.clone();
    for i in 0..24 {
        shifted[(i, i)] += 1e-12 * scale;
    }
    if scale > 0.0 && scale.is_finite() && shifted.cholesky().is_some() {
        return *ke;
    }
    let eigen = SymmetricEigen::new(m);
    if eigen.eigenvalues.iter().all(|&l| l >= 0.0) {
        return *ke;
    }
    let q = &eigen.eigenvectors;
    let mut scaled = q.clone();
    for (c, &l) in eigen.eigenvalues.iter().enumerate() {
        scaled.column_mut(c).scale_mut(l.abs());
    }
    let m = scaled * q.transpose();
    std::array::from_fn(|a| {
        std::array::from_fn(|b| Matrix3::from_fn(|i, j| m[(3 * a + i, 3 * b + j)]))
    })
}

#[cfg(test)]
mod tests {
    use super::absolute_eigenvalues;
    use nalgebra::{DMatrix, Matrix3, SymmetricEigen};

    fn dense(ke: &super::ElementStiffness) -> DMatrix<f64> {
        DMatrix::from_fn(24, 24, |r, c| ke[r / 3][c / 3][(r % 3, c % 3)])
    }

    #[test]
    fn negative_eigenvalues_turn_positive_and_the_rest_is_kept() {
        // A symmetric matrix with known spectrum: Q diag(λ) Qᵀ, Q from a fixed irregular basis.
        let raw = DMatrix::from_fn(24, 24, |r, c| ((r * 31 + c * 17) as f64 * 0.37).sin());
        let q = raw.qr().q();
        let lambda: Vec<f64> = (0..24).map(|i| i as f64 - 5.5).collect();
        let m = &q
            * DMatrix::from_diagonal(&nalgebra::DVector::from_vec(lambda.clone()))
            * q.transpose();
        let ke = std::array::from_fn(|a| {
            std::array::from_fn(|b| Matrix3::from_fn(|i, j| m[(3 * a + i, 3 * b + j)]))
        });
        let p = dense(&absolute_eigenvalues(&ke));
        let mut got: Vec<f64> = SymmetricEigen::new(p.clone())
            .eigenvalues
            .iter()
            .copied()
            .collect();
        got.sort_by(f64::total_cmp);
        let mut want: Vec<f64> = lambda.iter().map(|l| l.abs()).collect();
        want.sort_by(f64::total_cmp);
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-10, "{g} vs {w}");
        }
        // The eigenvectors of positive eigenvalues are unchanged: P q = λ q there.
        let v = q.column(20).into_owned();
        assert!((&p * &v - &v * lambda[20]).norm() < 1e-10);
        // A positive semi-definite element is returned as it was.
        let psd = &q
            * DMatrix::from_diagonal(&nalgebra::DVector::from_fn(24, |i, _| i as f64 + 1.0))
            * q.transpose();
        let ke = std::array::from_fn(|a| {
            std::array::from_fn(|b| Matrix3::from_fn(|i, j| psd[(3 * a + i, 3 * b + j)]))
        });
        assert_eq!(absolute_eigenvalues(&ke), ke);
        // So is one with zero eigenvalues, as an element's rigid motions give (the Cholesky
        // factorization that tells, of the matrix shifted by round-off, passes it); an
        // eigenvalue a thousandth below zero is still turned.
        let element = |lowest: f64| {
            let m =
                &q * DMatrix::from_diagonal(&nalgebra::DVector::from_fn(24, |i, _| {
                    if i < 6 {
                        0.0
                    } else if i == 6 {
                        lowest
                    } else {
                        i as f64
                    }
                })) * q.transpose();
            let ke: super::ElementStiffness = std::array::from_fn(|a| {
                std::array::from_fn(|b| Matrix3::from_fn(|i, j| m[(3 * a + i, 3 * b + j)]))
            });
            ke
        };
        assert_eq!(absolute_eigenvalues(&element(0.0)), element(0.0));
        let turned = dense(&absolute_eigenvalues(&element(-1e-3)));
        let lowest = SymmetricEigen::new(turned).eigenvalues.min();
        assert!(lowest > -1e-12, "{lowest}");
        assert_ne!(absolute_eigenvalues(&element(-1e-3)), element(-1e-3));
        // An eigenvalue 10⁻⁹ of the largest below zero is not round-off: turned too.
        let turned = dense(&absolute_eigenvalues(&element(-2e-8)));
        let mut spectrum: Vec<f64> = SymmetricEigen::new(turned)
            .eigenvalues
            .iter()
            .copied()
            .collect();
        spectrum.sort_by(f64::total_cmp);
        // (Six zeros, as given, then the turned one.)
        assert!(spectrum[0] > -1e-12, "{spectrum:?}");
        assert!((spectrum[6] - 2e-8).abs() < 1e-11, "{spectrum:?}");
        // A zero element is kept (nothing to turn).
        let zero: super::ElementStiffness = [[Matrix3::zeros(); 8]; 8];
        assert_eq!(absolute_eigenvalues(&zero), zero);
    }
}
