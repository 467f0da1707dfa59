//! Coulomb friction on the Schur complement: the multipliers of the active contacts found by a
//! semi-smooth Newton method on Alart and Curnier's augmented Lagrangian equations.
//!
//! With G = C·K11⁻¹·Cᵀ over the normal and tangential rows of the active contacts and
//! c = C·U⁰ − (b, reference), the gaps and slips are w = G·λ + c. Coulomb's law asks, per
//! contact: λ_n ≥ 0, w_n ≥ 0, λ_n·w_n = 0 (no penetration, no pull), |λ_t| ≤ μ·λ_n, and w_t = 0
//! (stick) unless |λ_t| = μ·λ_n, when the node slides against its friction force
//! (w_t = −s·λ_t, s ≥ 0: maximal dissipation). Alart and Curnier write the law as equations,
//! with σ_n = λ_n − r_n·w_n and σ_t = λ_t − r_t·w_t (r > 0 any scale):
//!
//!   λ_n − max(0, σ_n) = 0,   λ_t − proj_{|x| ≤ μ·max(0, σ_n)}(σ_t) = 0,
//!
//! piecewise smooth in λ; Newton's method on them switches every contact between released,
//! sticking and slipping at once, and converges in a few steps once the switching settles
//! (even when a floating body's sliding makes G very ill-conditioned, where a Gauss–Seidel
//! sweep crawls). A step that does not reduce the residual is halved.

use super::point::{Adhesion, ContactError};
use super::row::{coupling, fill_couplings, slot_of, slot_offsets, Couplings, Row};
use crate::fem::DofPartition;
use faer::linalg::solvers::Solve;
use nalgebra::{DMatrix, DVector, Vector2};

/// Newton steps before giving up.
const MAX_STEPS: usize = 200;
/// What [`newton`] ends with.
struct Newton {
    /// The multipliers λ.
    lambda: DVector<f64>,
    /// The gaps and slips w = G·λ + c.
    w: DVector<f64>,
    /// The residual F(λ).
    f: Vec<f64>,
    /// Newton steps taken.
    steps: usize,
    /// Whether F(λ) met the tolerance.
    converged: bool,
}

/// The largest |f_i|.
fn max_abs(f: &[f64]) -> f64 {
    f.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}
/// Gauss–Seidel sweeps tried where Newton stalls.
const SWEEPS: usize = 3000;
/// Converged when the residual is below this share of the largest multiplier.
const TOLERANCE: f64 = 1e-11;

/// Per contact, its slots and the scales r_n, r_t.
struct Local {
    o: usize,
    k: usize,
    mu: f64,
    rn: f64,
    rt: f64,
}

/// The residual F(λ) of the Alart–Curnier equations, given w = G·λ + c.
fn residual(locals: &[Local], lambda: &[f64], w: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; lambda.len()];
    for c in locals {
        let o = c.o;
        let sn = lambda[o] - c.rn * w[o];
        f[o] = lambda[o] - sn.max(0.0);
        if c.k == 3 {
            let lt = Vector2::new(lambda[o + 1], lambda[o + 2]);
            let st = lt - c.rt * Vector2::new(w[o + 1], w[o + 2]);
            let radius = c.mu * sn.max(0.0);
            let p = if st.norm() > radius {
                st * (radius / st.norm())
            } else {
                st
            };
            f[o + 1] = lt.x - p.x;
            f[o + 2] = lt.y - p.y;
        }
    }
    f
}

/// Settles the multipliers of `rows` with friction: each carries no force, sticks or slips
/// (`tolerance`: the contact's penetration tolerance, m, which a failure is told against). Returns λ in row order: λ_n, then (λ_t1, λ_t2) for a
/// sticking row (a slipping row's tangential force is μ·λ_n along `slip`).
pub(super) fn settle_coulomb(
    rows: &mut [Row],
    u0: &[f64],
    partition: &DofPartition,
    cache: &mut Couplings,
    tolerance: f64,
) -> Result<DVector<f64>, ContactError> {
    let offset = slot_offsets(rows);
    let n = *offset.last().unwrap_or(&0);
    fill_couplings(cache, rows, partition);
    let mut g = DMatrix::zeros(n, n);
    for i in 0..n {
        let (r, a) = slot_of(&offset, i);
        for j in i..n {
            let (q, b) = slot_of(&offset, j);
            g[(i, j)] = coupling(cache, &rows[r], a, &rows[q], b, partition);
            g[(j, i)] = g[(i, j)];
        }
    }
    // c = C·U⁰ − target, and the starting multipliers (the last settle's).
    let mut c = DVector::zeros(n);
    let mut lambda = DVector::zeros(n);
    for (r, row) in rows.iter().enumerate() {
        for a in 0..row.axes() {
            let target = match a {
                0 => row.bound,
                1 => row.reference.x,
                _ => row.reference.y,
            };
            c[offset[r] + a] = row.apply(a, u0) - target;
            lambda[offset[r] + a] = row.last[a];
        }
    }
    let locals: Vec<Local> = rows
        .iter()
        .enumerate()
        .map(|(r, row)| {
            let o = offset[r];
            let k = row.axes();
            let rn = 1.0 / g[(o, o)].max(f64::MIN_POSITIVE);
            let rt = if k == 3 {
                let (a, b, d) = (g[(o + 1, o + 1)], g[(o + 1, o + 2)], g[(o + 2, o + 2)]);
                1.0 / (0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b * b).sqrt())
                    .max(f64::MIN_POSITIVE)
            } else {
                0.0
            };
            Local {
                o,
                k,
                mu: row.mu,
                rn,
                rt,
            }
        })
        .collect();
    let mut solved = newton(&g, &c, &locals, lambda)?;
    // Where Newton stalls (the hand's grasp with μ = 0.8: runs of 1/1024 steps, then a
    // 2-cycle), block Gauss–Seidel sweeps on the same law, which creep but do not cycle, bring
    // the multipliers near the solution; Newton then finishes from there.
    if !solved.converged {
        let swept = gauss_seidel(&g, &c, &locals, solved.lambda);
        let steps = solved.steps;
        solved = newton(&g, &c, &locals, swept)?;
        solved.steps += steps;
    }
    let Newton {
        lambda,
        w,
        f,
        steps,
        converged,
    } = solved;
    if !converged {
        return Err(ContactError::NotConverged {
            method: "lagrange (Coulomb friction, semi-smooth Newton)",
            iterations: steps,
            active: rows.len(),
            // The normal rows' gaps only (the others are slip velocities).
            penetration: locals.iter().fold(0.0_f64, |m, l| m.max(-w[l.o])),
            tolerance,
            change: Some(max_abs(&f)),
            advice: "the semi-smooth Newton iteration of the friction did not converge (its \
                     steps are not limited by solver.contact_max_iterations)",
        });
    }
    // The state of every contact. One without force stays in the set (it may carry force
    // again as others join; releasing it could make the set cycle): its λ is zero.
    for (r, row) in rows.iter_mut().enumerate() {
        let o = offset[r];
        let ln = lambda[o].max(0.0);
        row.last = [ln, 0.0, 0.0];
        if row.axes() < 3 {
            continue;
        }
        let lt = Vector2::new(lambda[o + 1], lambda[o + 2]);
        if ln > 0.0 && lt.norm() >= row.mu * ln * (1.0 - 1e-9) && lt.norm() > 0.0 {
            row.state = Adhesion::Slip;
            row.slip = lt / lt.norm();
            row.last = [ln, lt.x, lt.y];
        } else if ln > 0.0 {
            row.state = Adhesion::Stick;
            row.last = [ln, lt.x, lt.y];
        } else {
            row.state = Adhesion::Stick;
        }
    }
    let mut out = Vec::new();
    for row in rows.iter() {
        out.push(row.last[0]);
        if row.state == Adhesion::Stick {
            out.push(row.last[1]);
            out.push(row.last[2]);
        }
    }
    Ok(DVector::from_vec(out))
}

/// Newton's method on the Alart–Curnier equations from `lambda`; an error where a step is not
/// finite (the contacts' compliance singular).
fn newton(
    g: &DMatrix<f64>,
    c: &DVector<f64>,
    locals: &[Local],
    mut lambda: DVector<f64>,
) -> Result<Newton, ContactError> {
    let n = lambda.len();
    let mut w = g * &lambda + c;
    let mut f = residual(locals, lambda.as_slice(), w.as_slice());
    let norm = max_abs;
    let mut converged = false;
    let mut steps = 0;
    while steps < MAX_STEPS {
        let scale = lambda
            .amax()
            .max(c.amax() * locals.iter().map(|l| l.rn).fold(0.0, f64::max));
        if norm(&f) <= TOLERANCE * scale.max(f64::MIN_POSITIVE) {
            converged = true;
            break;
        }
        steps += 1;
        // The generalized Jacobian, row by row.
        let mut jac = DMatrix::zeros(n, n);
        for l in locals {
            let o = l.o;
            let sn = lambda[o] - l.rn * w[o];
            if sn <= 0.0 {
                jac[(o, o)] = 1.0;
            } else {
                for j in 0..n {
                    jac[(o, j)] = l.rn * g[(o, j)];
                }
            }
            if l.k < 3 {
                continue;
            }
            let lt = Vector2::new(lambda[o + 1], lambda[o + 2]);
            let st = lt - l.rt * Vector2::new(w[o + 1], w[o + 2]);
            let radius = l.mu * sn.max(0.0);
            if sn <= 0.0 {
                jac[(o + 1, o + 1)] = 1.0;
                jac[(o + 2, o + 2)] = 1.0;
            } else if st.norm() <= radius {
                for a in 1..3 {
                    for j in 0..n {
                        jac[(o + a, j)] = l.rt * g[(o + a, j)];
                    }
                }
            } else {
                // F_t = λ_t − ρ·e, e = σ_t/|σ_t|, ρ = μ·σ_n:
                // dF_t = dλ_t − μ·e·dσ_n − (ρ/|σ_t|)(I − e·eᵀ)·dσ_t.
                let e = st / st.norm();
                let q = radius / st.norm();
                let m = nalgebra::Matrix2::identity() - e * e.transpose();
                for j in 0..n {
                    let dsn = if j == o { 1.0 } else { 0.0 } - l.rn * g[(o, j)];
                    let dst = Vector2::new(
                        if j == o + 1 { 1.0 } else { 0.0 } - l.rt * g[(o + 1, j)],
                        if j == o + 2 { 1.0 } else { 0.0 } - l.rt * g[(o + 2, j)],
                    );
                    let d = -e * (l.mu * dsn) - m * dst * q;
                    jac[(o + 1, j)] = d.x + if j == o + 1 { 1.0 } else { 0.0 };
                    jac[(o + 2, j)] = d.y + if j == o + 2 { 1.0 } else { 0.0 };
                }
            }
        }
        // Dense LU (faer: blocked, parallel) of the generalized Jacobian.
        let lu = faer::Mat::from_fn(n, n, |i, j| jac[(i, j)]).partial_piv_lu();
        let mut x = faer::Mat::from_fn(n, 1, |i, _| -f[i]);
        lu.solve_in_place(x.as_mut());
        let step = DVector::from_fn(n, |i, _| x[(i, 0)]);
        if !step.iter().all(|v| v.is_finite()) {
            return Err(ContactError::Singular {
                active: locals.len(),
            });
        }
        // Halve the step until the residual decreases (a few times at most).
        let before = norm(&f);
        let mut t = 1.0;
        loop {
            let trial = &lambda + &step * t;
            let wt = g * &trial + c;
            let ft = residual(locals, trial.as_slice(), wt.as_slice());
            if norm(&ft) < before || t < 1e-3 {
                lambda = trial;
                w = wt;
                f = ft;
                break;
            }
            t *= 0.5;
        }
    }
    Ok(Newton {
        lambda,
        w,
        f,
        steps,
        converged,
    })
}

/// Block Gauss–Seidel on Coulomb's law from `lambda`: contact by contact, the normal multiplier
/// that closes its gap given the others, clipped at zero, then the tangential ones that stop its
/// slip, projected onto the cone μ·λ_n (De Saxcé's and Jean's non-smooth contact dynamics
/// sweep), for at most [`SWEEPS`] sweeps or until a sweep changes no multiplier by more than
/// 1e-10 of the largest.
fn gauss_seidel(
    g: &DMatrix<f64>,
    c: &DVector<f64>,
    locals: &[Local],
    mut lambda: DVector<f64>,
) -> DVector<f64> {
    let mut w = g * &lambda + c;
    for _ in 0..SWEEPS {
        let mut change = 0.0_f64;
        for l in locals {
            let o = l.o;
            let mut delta = [0.0; 3];
            let gnn = g[(o, o)].max(f64::MIN_POSITIVE);
            let ln = (lambda[o] - w[o] / gnn).max(0.0);
            delta[0] = ln - lambda[o];
            if l.k == 3 {
                // The tangential gaps with the new normal multiplier.
                let wt = Vector2::new(
                    w[o + 1] + g[(o + 1, o)] * delta[0],
                    w[o + 2] + g[(o + 2, o)] * delta[0],
                );
                let block = nalgebra::Matrix2::new(
                    g[(o + 1, o + 1)],
                    g[(o + 1, o + 2)],
                    g[(o + 2, o + 1)],
                    g[(o + 2, o + 2)],
                );
                let lt = Vector2::new(lambda[o + 1], lambda[o + 2]);
                let free = match block.try_inverse() {
                    Some(inv) => lt - inv * wt,
                    None => lt,
                };
                let radius = l.mu * ln;
                let new = if free.norm() > radius {
                    free * (radius / free.norm())
                } else {
                    free
                };
                delta[1] = new.x - lt.x;
                delta[2] = new.y - lt.y;
            }
            for (a, d) in delta.iter().enumerate().take(l.k) {
                if *d != 0.0 {
                    lambda[o + a] += d;
                    w.axpy(*d, &g.column(o + a), 1.0);
                    change = change.max(d.abs());
                }
            }
        }
        if change <= 1e-10 * lambda.amax().max(f64::MIN_POSITIVE) {
            break;
        }
    }
    lambda
}
