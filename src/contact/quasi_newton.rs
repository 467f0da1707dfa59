//! The interface quasi-Newton method with an approximation of the inverse Jacobian from a
//! least-squares model (IQN-ILS; Degroote, Bathe and Vierendeels 2009, "Performance of a new
//! partitioned procedure versus a monolithic procedure in fluid–structure interaction"), the
//! accelerator of partitioned Dirichlet–Neumann couplings that Aitken's scalar factor cannot
//! stabilise: here the paper's iteration F ↦ H(F) on the contact forces it transfers (its
//! steps 2–4), whose fixed point is the contact's equilibrium.
//!
//! Each iteration gives the forces tried x and the forces the object answered with, x̃ = H(x);
//! the residual r = x̃ − x. The differences of the residuals and of the answers kept from the
//! previous iterations, V = [Δr] and W = [Δx̃], are a secant model of how the answer moves with
//! the forces: the next forces are x̃ + W·c with c minimising ‖V·c + r‖ (Anderson's mixing of
//! type II, with mixing 1). On an affine map with a fixed active set this is GMRES on the
//! coupling's interface equation, so it converges however much stiffer the object is than the
//! flesh — the case where the plain iteration diverges (its rate is that stiffness ratio).
//! Without history (the first iteration, or after [`QuasiNewton::restart`]) the step is a
//! relaxed one, x + ω₀·r.

use nalgebra::{DMatrix, DVector};

/// The secant history of one sequence of the paper's iterations.
pub struct QuasiNewton {
    /// The factor of a step without history.
    first: f64,
    /// Most columns kept (the oldest dropped first).
    columns: usize,
    /// The last residual and answer, the differences' origin.
    last: Option<(Vec<f64>, Vec<f64>)>,
    /// Columns of V (residual differences) and W (answer differences), newest last.
    dr: Vec<Vec<f64>>,
    dh: Vec<Vec<f64>>,
}

impl QuasiNewton {
    /// An empty history; `first` relaxes the steps taken without one, `columns` bounds it.
    pub fn new(first: f64, columns: usize) -> QuasiNewton {
        QuasiNewton {
            first,
            columns: columns.max(1),
            last: None,
            dr: Vec::new(),
            dh: Vec::new(),
        }
    }

    /// Forgets everything: the next step is a relaxed one.
    pub fn restart(&mut self) {
        self.last = None;
        self.dr.clear();
        self.dh.clear();
    }

    /// The next forces from the forces tried `x` and the answer `h` = H(x).
    pub fn next(&mut self, x: &[f64], h: &[f64]) -> Vec<f64> {
        let r: Vec<f64> = h.iter().zip(x).map(|(h, x)| h - x).collect();
        if let Some((r0, h0)) = &self.last {
            let dr: Vec<f64> = r.iter().zip(r0).map(|(a, b)| a - b).collect();
            let dh: Vec<f64> = h.iter().zip(h0).map(|(a, b)| a - b).collect();
            if dr.iter().any(|v| *v != 0.0) {
                self.dr.push(dr);
                self.dh.push(dh);
                if self.dr.len() > self.columns {
                    self.dr.remove(0);
                    self.dh.remove(0);
                }
            }
        }
        self.last = Some((r.clone(), h.to_vec()));
        match self.coefficients(&r) {
            Some(c) => {
                let mut next = h.to_vec();
                for (w, ci) in self.dh.iter().zip(c.iter()) {
                    for (n, wi) in next.iter_mut().zip(w) {
                        *n += ci * wi;
                    }
                }
                next
            }
            None => x.iter().zip(&r).map(|(x, r)| x + self.first * r).collect(),
        }
    }

    /// c minimising ‖V·c + r‖ over the rows where anything is non-zero, by a QR factorization;
    /// columns that are (nearly) dependent on the newer ones are dropped first. `None` without
    /// a usable column.
    fn coefficients(&mut self, r: &[f64]) -> Option<DVector<f64>> {
        let rows: Vec<usize> = (0..r.len())
            .filter(|&i| r[i] != 0.0 || self.dr.iter().any(|c| c[i] != 0.0))
            .collect();
        loop {
            let m = self.dr.len();
            if m == 0 || rows.len() < m {
                return None;
            }
            // Newest first, so that a dependent column found is an old one.
            let v = DMatrix::from_fn(rows.len(), m, |i, j| self.dr[m - 1 - j][rows[i]]);
            let qr = v.qr();
            let rr = qr.r();
            let scale = (0..m).map(|j| rr[(j, j)].abs()).fold(0.0, f64::max);
            if let Some(j) = (0..m).find(|&j| rr[(j, j)].abs() <= 1e-10 * scale) {
                // Column j of the newest-first order is the (m-1-j)-th oldest.
                self.dr.remove(m - 1 - j);
                self.dh.remove(m - 1 - j);
                continue;
            }
            let rhs = DVector::from_fn(rows.len(), |i, _| -r[rows[i]]);
            let qtb = qr.q().transpose() * rhs;
            let c_newest_first = rr.solve_upper_triangular(&qtb)?;
            // Back to the stored (oldest-first) order.
            return Some(DVector::from_fn(m, |j, _| c_newest_first[m - 1 - j]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An affine map H(x) = A·x + b whose plain iteration diverges (A's eigenvalues −40 and
    /// −3): the quasi-Newton iteration reaches its fixed point x = (I − A)⁻¹·b in as many
    /// secant steps as the dimension, to round-off.
    #[test]
    fn converges_on_an_affine_map_the_plain_iteration_diverges_on() {
        let a = [[-40.0, 2.0], [1.0, -3.0]];
        let b = [5.0, -7.0];
        let h = |x: &[f64]| -> Vec<f64> {
            (0..2)
                .map(|i| a[i][0] * x[0] + a[i][1] * x[1] + b[i])
                .collect()
        };
        // (I − A)·x = b.
        let det = 41.0 * 4.0 - 2.0;
        let exact = [(4.0 * b[0] + 2.0 * b[1]) / det, (b[0] + 41.0 * b[1]) / det];
        let mut qn = QuasiNewton::new(0.1, 10);
        let mut x = vec![0.0, 0.0];
        let mut iterations = 0;
        while iterations < 10 {
            let hx = h(&x);
            if hx.iter().zip(&x).all(|(h, x)| (h - x).abs() < 1e-12) {
                break;
            }
            x = qn.next(&x, &hx);
            iterations += 1;
        }
        assert!(iterations <= 4, "{iterations} iterations");
        for (x, e) in x.iter().zip(exact) {
            assert!((x - e).abs() < 1e-12, "{x} against {e}");
        }
        // The plain iteration from the same start runs away.
        let mut y = vec![0.0, 0.0];
        for _ in 0..5 {
            y = h(&y);
        }
        assert!(y[0].abs() > 1e6, "{y:?}");
    }
}
