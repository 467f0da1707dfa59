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
//! sweep crawls). A step that does not reduce the residual is halved; where no step along the
//! direction does, the scales r grow (the same law: its kinks move, and the cycle ends).

use super::point::{Adhesion, ContactError};
use super::row::{coupling, fill_couplings, slot_of, slot_offsets, Couplings, Row};
use crate::fem::DofPartition;
use faer::linalg::solvers::Solve;
use nalgebra::{DMatrix, DVector, Vector2};

/// Newton steps before giving up.
const MAX_STEPS: usize = 200;
/// Tresca problems of the fixed point at most; Newton steps on each before it is solved by
/// interior point instead (where Newton settles them, in 1–18 steps on the hand's grasps), and
/// interior-point solves at most (over the contacts that may carry force: 1.6–3.8 s for
/// 340–470 contacts of the upturned hand's grip, 2026-11-29; over all of them, 6–25 s).
const TRESCA_PROBLEMS: usize = 60;
const TRESCA_STEPS: usize = 30;
const TRESCA_INTERIOR_POINTS: usize = 2;
/// Newton steps on Coulomb's law before turning to Tresca's fixed point (where it converges,
/// Newton takes 2–46 steps on the hand's grasps, up to 133 on a ball let go of sliding out
/// of a μ = 0.2 grip with the scales grown).
const FIRST_STEPS: usize = 150;
/// Where no step along Newton's direction reduces the residual, the scales r_n, r_t of the
/// equations stepped on grow by this factor, at most this many times (2-cycles and creeping on
/// a ball let go of, whose ground springs make its compliance a million times the flesh's
/// along its rigid motion: its contacts' r = 1/G_ii is then far below their own stiffness).
const R_GROWTH: f64 = 2.0;
const R_GROWTHS: usize = 30;
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
#[derive(Clone, Copy)]
struct Local {
    o: usize,
    k: usize,
    mu: f64,
    rn: f64,
    rt: f64,
    /// A slip bound of its own (Tresca's law), instead of μ times the normal force.
    bound: Option<f64>,
}

impl Local {
    /// The contact whose rows start at slot `o` (`k`: 1, or 3 with friction μ): its scales are
    /// the inverse of its normal compliance and of its largest tangential one.
    fn new(g: &DMatrix<f64>, o: usize, k: usize, mu: f64) -> Local {
        let rn = 1.0 / g[(o, o)].max(f64::MIN_POSITIVE);
        let rt = if k == 3 {
            let (a, b, d) = (g[(o + 1, o + 1)], g[(o + 1, o + 2)], g[(o + 2, o + 2)]);
            1.0 / (0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b * b).sqrt()).max(f64::MIN_POSITIVE)
        } else {
            0.0
        };
        Local {
            o,
            k,
            mu,
            rn,
            rt,
            bound: None,
        }
    }
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
            let radius = c
                .bound
                .map_or(c.mu * sn.max(0.0), |b| if sn > 0.0 { b } else { 0.0 });
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
        .map(|(r, row)| Local::new(&g, offset[r], row.axes(), row.mu))
        .collect();
    let mut solved = newton(&g, &c, &locals, lambda, FIRST_STEPS)?;
    // Where Newton stalls (the hand's grasp with μ = 0.8: runs of 1/1024 steps, then a
    // 2-cycle; the five-digit grasp with μ = 0.5: the stick and slip states of a few contacts
    // switching back and forth), Coulomb's law as a sequence of Tresca problems, each with the
    // slip bounds of the last normal forces, which settle in a few Newton steps each; Newton
    // then finishes from there.
    if !solved.converged {
        let steps = solved.steps;
        if let Some(fixed) = tresca_fixed_point(&g, &c, &locals, solved.lambda.clone()) {
            solved = newton(&g, &c, &locals, fixed, MAX_STEPS)?;
            solved.steps += steps;
        }
    }
    // Where that fails too, block Gauss–Seidel sweeps on the same law, which creep but do not
    // cycle, bring the multipliers near the solution; Newton then finishes from there.
    if !solved.converged {
        let swept = gauss_seidel(&g, &c, &locals, solved.lambda.clone());
        let steps = solved.steps;
        solved = newton(&g, &c, &locals, swept, MAX_STEPS)?;
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
    lambda: DVector<f64>,
    max_steps: usize,
) -> Result<Newton, ContactError> {
    newton_growing(g, c, locals, lambda, max_steps, R_GROWTHS)
}

/// [`newton`] whose scales grow at most `growths` times. The equations are the contact law at
/// any scales r > 0; Newton steps on them at scales that grow by [`R_GROWTH`] each time no
/// step along its direction reduces their residual (the step is then taken nevertheless, as
/// before), which moves their kinks and ends the cycle. Convergence is judged on the equations
/// at the contacts' own scales (at grown ones the gaps weigh more: the tolerance on them would
/// loosen the one on the forces of contacts that carry none).
fn newton_growing(
    g: &DMatrix<f64>,
    c: &DVector<f64>,
    locals: &[Local],
    mut lambda: DVector<f64>,
    max_steps: usize,
    growths: usize,
) -> Result<Newton, ContactError> {
    let mut scaled = locals.to_vec();
    let mut grown = 0;
    let gaps_scale = c.amax() * locals.iter().map(|l| l.rn).fold(0.0, f64::max);
    let mut w = times_sparse(g, &lambda) + c;
    let mut steps = 0;
    loop {
        let f = residual(locals, lambda.as_slice(), w.as_slice());
        let scale = lambda.amax().max(gaps_scale);
        let converged = max_abs(&f) <= TOLERANCE * scale.max(f64::MIN_POSITIVE);
        if converged || steps == max_steps {
            return Ok(Newton {
                lambda,
                w,
                f,
                steps,
                converged,
            });
        }
        steps += 1;
        let f = residual(&scaled, lambda.as_slice(), w.as_slice());
        let step = newton_step(g, &scaled, &lambda, &w, &f);
        if !step.iter().all(|v| v.is_finite()) {
            return Err(ContactError::Singular {
                active: locals.len(),
            });
        }
        // Halve the step until the residual decreases (a few times at most): the gaps along
        // the step are w + t·G·Δλ.
        let before = max_abs(&f);
        let g_step = times_sparse(g, &step);
        let mut t = 1.0;
        loop {
            let trial = &lambda + &step * t;
            let wt = &w + &g_step * t;
            let decreased = max_abs(&residual(&scaled, trial.as_slice(), wt.as_slice())) < before;
            if decreased || t < 1e-3 {
                if !decreased && grown < growths {
                    grown += 1;
                    for l in scaled.iter_mut() {
                        l.rn *= R_GROWTH;
                        l.rt *= R_GROWTH;
                    }
                }
                // The gaps anew, free of the steps' round-off.
                w = times_sparse(g, &trial) + c;
                lambda = trial;
                break;
            }
            t *= 0.5;
        }
    }
}

/// G·x over the nonzero entries of x (most multipliers of a grasp's set, and most of a step's
/// entries, are zero: the open contacts').
fn times_sparse(g: &DMatrix<f64>, x: &DVector<f64>) -> DVector<f64> {
    let mut out = DVector::zeros(g.nrows());
    for (j, &v) in x.iter().enumerate() {
        if v != 0.0 {
            out.axpy(v, &g.column(j), 1.0);
        }
    }
    out
}

/// The Newton step of the Alart–Curnier equations at `lambda` (w = G·λ + c, F(λ) = `f`).
///
/// A contact whose augmented normal force σ_n is not positive is released: its rows of the
/// generalized Jacobian are the identity's and its step is −F, which returns its multipliers to
/// zero. Only the closed contacts' rows are solved for, with the released ones' steps moved to
/// the right-hand side: the same step as the whole system's, on a dense LU of the closed rows
/// alone (most of the set is released in a grasp: 7–9 closed of 262 on the upturned hand).
fn newton_step(
    g: &DMatrix<f64>,
    locals: &[Local],
    lambda: &DVector<f64>,
    w: &DVector<f64>,
    f: &[f64],
) -> DVector<f64> {
    let n = lambda.len();
    let mut step = DVector::from_fn(n, |i, _| -f[i]);
    // The closed contacts' slots, and where each sits in the reduced system.
    let mut closed = Vec::new();
    for l in locals {
        if lambda[l.o] - l.rn * w[l.o] > 0.0 {
            closed.extend(l.o..l.o + l.k);
        }
    }
    let m = closed.len();
    if m == 0 {
        return step;
    }
    let mut at = vec![usize::MAX; n];
    for (a, &i) in closed.iter().enumerate() {
        at[i] = a;
    }
    let released = |j: usize| at[j] == usize::MAX;
    // The closed rows of the generalized Jacobian, row by row: J_AA into `jac`, J_AI·Δλ_I
    // taken to the right-hand side `rhs` = −F_A − J_AI·Δλ_I.
    let mut jac = faer::Mat::<f64>::zeros(m, m);
    let mut rhs = faer::Mat::<f64>::from_fn(m, 1, |a, _| -f[closed[a]]);
    let put = |i: usize, j: usize, v: f64, jac: &mut faer::Mat<f64>, rhs: &mut faer::Mat<f64>| {
        if released(j) {
            rhs[(at[i], 0)] -= v * step[j];
        } else {
            jac[(at[i], at[j])] = v;
        }
    };
    for l in locals {
        let o = l.o;
        let sn = lambda[o] - l.rn * w[o];
        if sn <= 0.0 {
            continue;
        }
        for j in 0..n {
            put(o, j, l.rn * g[(o, j)], &mut jac, &mut rhs);
        }
        if l.k < 3 {
            continue;
        }
        let lt = Vector2::new(lambda[o + 1], lambda[o + 2]);
        let st = lt - l.rt * Vector2::new(w[o + 1], w[o + 2]);
        let radius = l.bound.map_or(l.mu * sn, |b| b);
        if st.norm() <= radius {
            for a in 1..3 {
                for j in 0..n {
                    put(o + a, j, l.rt * g[(o + a, j)], &mut jac, &mut rhs);
                }
            }
        } else {
            // F_t = λ_t − ρ·e, e = σ_t/|σ_t|, ρ = μ·σ_n:
            // dF_t = dλ_t − μ·e·dσ_n − (ρ/|σ_t|)(I − e·eᵀ)·dσ_t.
            let e = st / st.norm();
            let q = radius / st.norm();
            let mm = nalgebra::Matrix2::identity() - e * e.transpose();
            for j in 0..n {
                let dsn = if j == o { 1.0 } else { 0.0 } - l.rn * g[(o, j)];
                let dst = Vector2::new(
                    if j == o + 1 { 1.0 } else { 0.0 } - l.rt * g[(o + 1, j)],
                    if j == o + 2 { 1.0 } else { 0.0 } - l.rt * g[(o + 2, j)],
                );
                let dradius = if l.bound.is_some() { 0.0 } else { l.mu * dsn };
                let d = -e * dradius - mm * dst * q;
                put(
                    o + 1,
                    j,
                    d.x + if j == o + 1 { 1.0 } else { 0.0 },
                    &mut jac,
                    &mut rhs,
                );
                put(
                    o + 2,
                    j,
                    d.y + if j == o + 2 { 1.0 } else { 0.0 },
                    &mut jac,
                    &mut rhs,
                );
            }
        }
    }
    // Dense LU (faer: blocked, parallel) of the closed rows' Jacobian.
    jac.partial_piv_lu().solve_in_place(rhs.as_mut());
    for (a, &i) in closed.iter().enumerate() {
        step[i] = rhs[(a, 0)];
    }
    step
}

/// Fixed-point iterations of Tresca problems converging on Coulomb's law (Panagiotopoulos 1975;
/// Acary and Brogliato 2008, §13): with the slip bound b_i = μ_i·λ_n,i of the last normal
/// forces, min ½λᵀGλ + cᵀλ over λ_n ≥ 0 and |λ_t| ≤ b_i is convex (G is a compliance, positive
/// semi-definite), and its optimality conditions are the contact law with that bound — gaps
/// w_n = (Gλ + c)_n ≥ 0 complementary to λ_n, and slips w_t = −s·λ_t, s ≥ 0, only where
/// |λ_t| = b_i. Each is solved by the semi-smooth Newton method on its Alart–Curnier equations
/// (no coupling of the bound to the normal force: far better behaved), or where that fails by
/// interior point (`clarabel`); the bound is then renewed, until the multipliers change by less
/// than 10⁻⁸ of the largest (at most 60 problems). Returns the last multipliers, or `None` where
/// a problem could not be solved.
fn tresca_fixed_point(
    g: &DMatrix<f64>,
    c: &DVector<f64>,
    locals: &[Local],
    mut lambda: DVector<f64>,
) -> Option<DVector<f64>> {
    let mut bounded = locals.to_vec();
    // The normal forces the bounds are taken from: the last multipliers, or, where the
    // iteration stops contracting (a contact's normal force flipping between two values as its
    // friction bound does), the mean of the last two.
    let mut from = lambda.clone();
    let mut last_change = f64::INFINITY;
    let mut interior_points = 0;
    for _ in 0..TRESCA_PROBLEMS {
        for l in bounded.iter_mut().filter(|l| l.k == 3) {
            l.bound = Some(l.mu * from[l.o].max(0.0));
        }
        let next = match newton(g, c, &bounded, lambda.clone(), TRESCA_STEPS) {
            Ok(solved) if solved.converged => solved.lambda,
            _ if interior_points < TRESCA_INTERIOR_POINTS => {
                interior_points += 1;
                tresca_by_interior_point(g, c, &bounded, &lambda)?
            }
            _ => return None,
        };
        let change = (&next - &lambda).amax();
        from = if change > 0.5 * last_change {
            (&next + &lambda) * 0.5
        } else {
            next.clone()
        };
        last_change = change;
        lambda = next;
        if change <= 1e-8 * lambda.amax().max(f64::MIN_POSITIVE) {
            return Some(lambda);
        }
    }
    Some(lambda)
}

/// The Tresca problem of `locals` (each with its slip bound) by interior point, over the contacts
/// that may carry force: `None` where it is not solved.
///
/// Most of a grasp's contacts are open (7–9 of 262 closed on the upturned hand), and the
/// programme's dense compliance makes its cost cubic in the contacts it holds (25 s for 469).
/// A contact that carries no force adds nothing to the others' gaps, so the programme is solved
/// over those that can — a slip bound, a normal force in `hint`, or closed at it — and a contact
/// left out that the solution would put through (its gap below −10⁻⁹ of the largest) joins and
/// the programme is solved again: the minimiser of the whole programme where every contact left
/// out stays open, which is its optimality condition with no force.
fn tresca_by_interior_point(
    g: &DMatrix<f64>,
    c: &DVector<f64>,
    locals: &[Local],
    hint: &DVector<f64>,
) -> Option<DVector<f64>> {
    let n = c.len();
    let w = g * hint + c;
    let mut taken: Vec<bool> = locals
        .iter()
        .map(|l| l.bound.is_some_and(|b| b > 0.0) || hint[l.o] > 0.0 || w[l.o] <= 0.0)
        .collect();
    let through = 1e-9 * c.amax();
    for round in 0..=TRESCA_ROUNDS {
        if round == TRESCA_ROUNDS {
            taken.iter_mut().for_each(|t| *t = true);
        }
        // The contacts taken, their slots renumbered in order.
        let mut slots = Vec::new();
        let mut sub = Vec::new();
        for (l, _) in locals.iter().zip(&taken).filter(|(_, t)| **t) {
            sub.push(Local {
                o: slots.len(),
                ..*l
            });
            slots.extend(l.o..l.o + l.k);
        }
        let gs = DMatrix::from_fn(slots.len(), slots.len(), |i, j| g[(slots[i], slots[j])]);
        let cs = DVector::from_fn(slots.len(), |i, _| c[slots[i]]);
        let x = if slots.is_empty() {
            DVector::zeros(0)
        } else {
            match interior_point(&gs, &cs, &sub) {
                Some(x) => x,
                None if taken.iter().all(|t| *t) => return None,
                // Where the part is not solved, the whole programme.
                None => return interior_point(g, c, locals),
            }
        };
        let mut lambda = DVector::zeros(n);
        for (i, &s) in slots.iter().enumerate() {
            lambda[s] = x[i];
        }
        let w = g * &lambda + c;
        let mut joined = false;
        for (l, t) in locals.iter().zip(taken.iter_mut()) {
            if !*t && w[l.o] < -through {
                *t = true;
                joined = true;
            }
        }
        if !joined {
            return Some(lambda);
        }
    }
    None
}

/// Rounds of [`tresca_by_interior_point`] over some of the contacts before it takes them all.
const TRESCA_ROUNDS: usize = 6;

/// The Tresca problem of `locals` (each with its slip bound) as a convex quadratic programme
/// over second-order cones, solved by interior point: `None` where it is not solved.
fn interior_point(g: &DMatrix<f64>, c: &DVector<f64>, locals: &[Local]) -> Option<DVector<f64>> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    };
    let n = c.len();
    // Scaled to order one: the same minimiser.
    let scale = g.amax().max(f64::MIN_POSITIVE);
    let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..=j {
            if g[(i, j)] != 0.0 {
                rows.push(i);
                cols.push(j);
                vals.push(g[(i, j)] / scale);
            }
        }
    }
    let p = CscMatrix::new_from_triplets(n, n, rows, cols, vals);
    let q: Vec<f64> = c.iter().map(|v| v / scale).collect();
    // s = b − A·λ: λ_n ≥ 0 for every contact, then (b_i, λ_t) in a Lorentz cone for each
    // contact with friction.
    let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    for (k, l) in locals.iter().enumerate() {
        rows.push(k);
        cols.push(l.o);
        vals.push(-1.0);
    }
    let mut m = locals.len();
    let mut b = vec![0.0; m];
    let mut cones: Vec<SupportedConeT<f64>> = vec![SupportedConeT::NonnegativeConeT(m)];
    for l in locals.iter().filter(|l| l.k == 3) {
        b.extend([l.bound.unwrap_or(0.0), 0.0, 0.0]);
        for a in 1..3 {
            rows.push(m + a);
            cols.push(l.o + a);
            vals.push(-1.0);
        }
        cones.push(SupportedConeT::SecondOrderConeT(3));
        m += 3;
    }
    let a = CscMatrix::new_from_triplets(m, n, rows, cols, vals);
    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: 1e-12,
        tol_gap_rel: 1e-12,
        tol_feas: 1e-12,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).ok()?;
    solver.solve();
    if !matches!(
        solver.solution.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    ) {
        return None;
    }
    let x = DVector::from_column_slice(&solver.solution.x);
    x.iter().all(|v| v.is_finite()).then_some(x)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Contacts of three rows each (friction μ) over the compliance `g`.
    fn frictional(g: &DMatrix<f64>, mu: f64) -> Vec<Local> {
        (0..g.nrows() / 3)
            .map(|i| Local::new(g, 3 * i, 3, mu))
            .collect()
    }

    /// Coulomb's law at λ with gaps and slips w = G·λ + c, to `tol` of the largest multiplier.
    fn obeys_coulomb(g: &DMatrix<f64>, c: &DVector<f64>, locals: &[Local], lambda: &DVector<f64>) {
        let w = g * lambda + c;
        let tol = 1e-7 * lambda.amax();
        let wtol = 1e-7 * c.amax();
        for l in locals {
            let (o, ln) = (l.o, lambda[l.o]);
            assert!(ln >= -tol, "pull {ln}");
            assert!(w[o] >= -wtol, "penetration {}", w[o]);
            assert!(
                ln.min(w[o] / g[(o, o)]) <= tol,
                "λ_n {ln} with gap {}",
                w[o]
            );
            let lt = Vector2::new(lambda[o + 1], lambda[o + 2]);
            let wt = Vector2::new(w[o + 1], w[o + 2]);
            assert!(
                lt.norm() <= l.mu * ln + tol,
                "outside the cone: {} > {}",
                lt.norm(),
                l.mu * ln
            );
            if lt.norm() < l.mu * ln - tol {
                assert!(wt.norm() <= wtol, "slips {} inside the cone", wt.norm());
            } else if wt.norm() > wtol && ln > tol {
                // Slips against its friction force: w_t = −s·λ_t, s ≥ 0.
                let cos = wt.dot(&lt) / (wt.norm() * lt.norm());
                assert!(
                    cos <= -(1.0 - 1e-6),
                    "slips at cos {cos} to its friction force (|w_t| {}, |λ_t| {}, μλ_n {})",
                    wt.norm(),
                    lt.norm(),
                    l.mu * ln
                );
            }
        }
    }

    #[test]
    fn one_contact_sticks_or_slips_as_the_closed_form_says() {
        // Compliances 2e-4 m/N normal, 5e-4 m/N tangential; 1 mm pressed in, so λ_n = 5 N,
        // and a tangential offset of s: it sticks (λ_t = s / 5e-4) while that is ≤ μ·λ_n.
        let g = DMatrix::from_diagonal(&DVector::from_vec(vec![2e-4, 5e-4, 5e-4]));
        let mu = 0.5;
        for (s, sticks) in [(0.5e-3, true), (2.0e-3, false)] {
            let c = DVector::from_vec(vec![-1e-3, s, 0.0]);
            let locals = frictional(&g, mu);
            let lambda = tresca_fixed_point(&g, &c, &locals, DVector::zeros(3)).unwrap();
            assert!((lambda[0] - 5.0).abs() < 1e-6, "λ_n {}", lambda[0]);
            let expected = if sticks { -s / 5e-4 } else { -mu * 5.0 };
            assert!(
                (lambda[1] - expected).abs() < 1e-6,
                "λ_t {} against {expected}",
                lambda[1]
            );
            assert!(lambda[2].abs() < 1e-6);
        }
    }

    #[test]
    fn the_tresca_fixed_point_meets_coulombs_law_where_newton_does() {
        // Twelve coupled contacts (G = A·Aᵀ + small diagonal, positive definite), some pressed
        // in, some apart, with tangential offsets: both solvers satisfy the law, and agree.
        let n = 36;
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let a = DMatrix::from_fn(n, n + 6, |_, _| next() * 1e-2);
        let g = &a * a.transpose() + DMatrix::identity(n, n) * 1e-5;
        let c = DVector::from_fn(n, |i, _| {
            if i % 3 == 0 {
                if i % 9 == 0 {
                    4e-4
                } else {
                    -1e-3 * (1.0 + next())
                }
            } else {
                next() * 2e-3
            }
        });
        for mu in [0.2, 0.5, 1.0] {
            let locals = frictional(&g, mu);
            let fixed = tresca_fixed_point(&g, &c, &locals, DVector::zeros(n)).unwrap();
            obeys_coulomb(&g, &c, &locals, &fixed);
            let polished = newton(&g, &c, &locals, fixed.clone(), MAX_STEPS).unwrap();
            assert!(polished.converged, "μ = {mu}: Newton from the fixed point");
            obeys_coulomb(&g, &c, &locals, &polished.lambda);
            let diff = (&polished.lambda - &fixed).amax() / fixed.amax();
            assert!(
                diff < 1e-6,
                "μ = {mu}: the fixed point is {diff} off Newton's"
            );
        }
    }

    /// A coupled set of `count` three-row contacts, a third of them apart by 0.4 mm, the others
    /// pressed in with tangential offsets: (G, c), G positive definite; with `spread`, every
    /// compliance positive (a force anywhere opens every other gap, as on one side of a body).
    fn coupled(count: usize, seed: u64, spread: bool) -> (DMatrix<f64>, DVector<f64>) {
        let n = 3 * count;
        let mut seed = seed;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let shift = if spread { 0.5 } else { 0.0 };
        let a = DMatrix::from_fn(n, n + 6, |_, _| (next() + shift) * 1e-2);
        let g = &a * a.transpose() + DMatrix::identity(n, n) * 1e-5;
        let c = DVector::from_fn(n, |i, _| match (i % 3, i % 9) {
            (0, 0) => 4e-4,
            (0, _) => -1e-3 * (1.0 + next()),
            _ => next() * 2e-3,
        });
        (g, c)
    }

    /// The Newton step over the closed contacts' rows alone is the step of the whole system
    /// (the generalized Jacobian with identity rows for the released contacts), to round-off:
    /// at multipliers where some contacts are released while carrying force, some stick, some
    /// slip.
    #[test]
    fn the_step_over_the_closed_contacts_is_the_whole_systems() {
        let (g, c) = coupled(12, 11, false);
        let n = c.len();
        let locals = frictional(&g, 0.5);
        let lambda = DVector::from_fn(n, |i, _| match i % 3 {
            0 => [3.0, 0.0, 0.5, 8.0][(i / 3) % 4],
            _ => [0.4, -2.5, 0.1][(i / 3) % 3],
        });
        let w = &g * &lambda + &c;
        let f = residual(&locals, lambda.as_slice(), w.as_slice());
        let closed = locals
            .iter()
            .filter(|l| lambda[l.o] - l.rn * w[l.o] > 0.0)
            .count();
        assert!(closed > 0 && closed < locals.len(), "{closed} closed");
        // The whole generalized Jacobian by central differences of F (piecewise smooth: away
        // from its kinks at this λ, exact for the linear pieces up to round-off).
        let h = 1e-7 * lambda.amax();
        let mut jac = DMatrix::zeros(n, n);
        for j in 0..n {
            let mut lp = lambda.clone();
            let mut lm = lambda.clone();
            lp[j] += h;
            lm[j] -= h;
            let fp = residual(&locals, lp.as_slice(), (&g * &lp + &c).as_slice());
            let fm = residual(&locals, lm.as_slice(), (&g * &lm + &c).as_slice());
            for i in 0..n {
                jac[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
            }
        }
        let whole = jac.lu().solve(&-DVector::from_vec(f.clone())).unwrap();
        let reduced = newton_step(&g, &locals, &lambda, &w, &f);
        let diff = (&reduced - &whole).amax() / whole.amax();
        assert!(
            diff < 1e-5,
            "the reduced step is {diff} off the whole system's"
        );
    }

    /// The Tresca programme solved over the contacts that may carry force, others joining
    /// where they would be put through, is the whole programme's minimiser: from a hint with
    /// no force anywhere (every contact pressed in must join) and from the fixed point's own.
    #[test]
    fn the_programme_over_the_contacts_that_may_carry_force_is_the_whole_ones() {
        let (g, c) = coupled(20, 3, true);
        let n = c.len();
        let mut locals = frictional(&g, 0.5);
        for (i, l) in locals.iter_mut().enumerate() {
            l.bound = Some(if i % 2 == 0 { 0.0 } else { 2.0 });
        }
        let whole = interior_point(&g, &c, &locals).unwrap();
        // A hint pushing hard on one contact that carries no force, every other apart there:
        // those that do carry force must join.
        let idle = locals
            .iter()
            .position(|l| l.bound == Some(0.0) && whole[l.o] < 1e-9 * whole.amax())
            .unwrap();
        let mut pushing = DVector::zeros(n);
        pushing[3 * idle] = 10.0 * whole.amax();
        let w = &g * &pushing + &c;
        let left_out = |l: &Local| l.bound == Some(0.0) && pushing[l.o] == 0.0 && w[l.o] > 0.0;
        assert!(locals.iter().any(|l| left_out(l) && whole[l.o] > 0.0));
        for hint in [DVector::zeros(n), whole.clone(), pushing] {
            let some = tresca_by_interior_point(&g, &c, &locals, &hint).unwrap();
            let diff = (&some - &whole).amax() / whole.amax();
            assert!(diff < 1e-6, "{diff} off the whole programme's minimiser");
        }
        // Some contacts carry no force at the minimiser: the restriction leaves something out.
        assert!(locals
            .iter()
            .any(|l| whole[l.o].abs() < 1e-9 * whole.amax()));
    }

    /// Contacts all apart with no slip bound: none may carry force, the programme over none of
    /// them is solved without the interior point, and no force is the answer.
    #[test]
    fn contacts_all_apart_carry_no_force() {
        let (g, c) = coupled(4, 5, true);
        let c = DVector::from_fn(c.len(), |i, _| if i % 3 == 0 { 1e-3 } else { c[i] });
        let mut locals = frictional(&g, 0.5);
        for l in locals.iter_mut() {
            l.bound = Some(0.0);
        }
        let lambda = tresca_by_interior_point(&g, &c, &locals, &DVector::zeros(c.len())).unwrap();
        assert_eq!(lambda.amax(), 0.0);
    }

    /// A friction problem of 17 contacts (51 multipliers) on which Newton stalled: a settle of
    /// the upturned hand's grip on a ball let go of (tests/let_go.rs's scene), written as
    /// little-endian u64 n and contact count, then f64: G (n×n, by columns), c, the starting
    /// λ, and per contact its first slot, rows, μ, r_n, r_t.
    fn stalled_problem() -> (DMatrix<f64>, DVector<f64>, Vec<Local>, DVector<f64>) {
        let bytes: &[u8] = include_bytes!("../../tests/fixtures/friction-stall-17-contacts.bin");
        let words: Vec<u64> = bytes
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect();
        let (n, count) = (words[0] as usize, words[1] as usize);
        let numbers: Vec<f64> = words[2..].iter().map(|&w| f64::from_bits(w)).collect();
        assert_eq!(numbers.len(), n * n + 2 * n + 5 * count);
        let g = DMatrix::from_column_slice(n, n, &numbers[..n * n]);
        let c = DVector::from_column_slice(&numbers[n * n..n * n + n]);
        let lambda = DVector::from_column_slice(&numbers[n * n + n..n * n + 2 * n]);
        let locals = numbers[n * n + 2 * n..]
            .chunks_exact(5)
            .map(|v| Local {
                o: v[0] as usize,
                k: v[1] as usize,
                mu: v[2],
                rn: v[3],
                rt: v[4],
                bound: None,
            })
            .collect();
        (g, c, locals, lambda)
    }

    /// Where Newton at the contacts' own scales stalls (200 steps, not converged), with the
    /// scales grown where no step reduces the residual it converges in a few steps, to
    /// multipliers that obey Coulomb's law and agree with Tresca's fixed point finished by
    /// Newton at fixed scales (the path such a settle took before, but for the fixed point's
    /// inner Newton, which grows its scales too now).
    #[test]
    fn newton_that_stalls_converges_with_its_scales_grown() {
        let (g, c, locals, start) = stalled_problem();
        let fixed = newton_growing(&g, &c, &locals, start.clone(), 200, 0).unwrap();
        assert!(!fixed.converged, "converged in {} steps", fixed.steps);
        let grown = newton(&g, &c, &locals, start, FIRST_STEPS).unwrap();
        assert!(
            grown.converged && grown.steps <= 30,
            "{} steps",
            grown.steps
        );
        obeys_coulomb(&g, &c, &locals, &grown.lambda);
        let tresca = tresca_fixed_point(&g, &c, &locals, fixed.lambda).unwrap();
        let before = newton_growing(&g, &c, &locals, tresca, MAX_STEPS, 0).unwrap();
        assert!(before.converged);
        let scale = before.lambda.amax();
        assert!(scale > 0.0);
        assert!(
            (&grown.lambda - &before.lambda).amax() <= 1e-6 * scale,
            "{} apart of {scale}",
            (&grown.lambda - &before.lambda).amax()
        );
    }
}
