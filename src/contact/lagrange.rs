//! Contact exact at convergence: an active set of Lagrange multipliers solved through the Schur
//! complement of the stiffness, factored once, with Coulomb friction.
//!
//! With K11 factored once (equation (7) without contact, U⁰), each active contact j adds the
//! linearised constraint g_j(U) = n·Σ_k w_k (X_k + U_k) − n·a ≥ 0, where the terms are the node
//! (w = 1) and either a rigid obstacle's nearest point a, or the nodes of the facet it touches
//! (w = −h_i, Figure 5): the gap between the node and the point C. Its multiplier λ_j ≥ 0 is the
//! normal contact force:
//!
//!   K·U = R + Cᵀλ,  C·U = b on the active set  ⇒  (C·K11⁻¹·Cᵀ)·λ = b − C·U⁰,
//!   U = U⁰ + K11⁻¹·Cᵀ·λ.
//!
//! K11⁻¹·C_jᵀ is one substitution with the existing factor per constraint row (no
//! refactorization). Friction adds two tangential rows per contact: sticking contacts hold the
//! node's tangential position relative to the facet — from where the step started for a node
//! held at the step before (the slip of a step is its increment: incremental Coulomb friction),
//! from the moment it touched for a node new to the contact; a contact whose
//! tangential multiplier exceeds μ·λ_n slips, and its tangential force becomes μ·λ_n against the
//! sliding (the column of its normal multiplier takes the friction along, which makes the
//! system unsymmetric: it is solved by LU). Nodes that penetrate join the set, contacts whose
//! normal force would pull leave it, stick and slip are switched, until nothing changes: then no
//! node penetrates by more than the tolerance and every contact force is compressive and inside
//! the friction cone.

use super::coulomb::settle_coulomb;
use super::embedded::EmbeddedPoints;
use super::obstacle::Obstacle;
use super::point::{
    transferred_forces, Adhesion, ContactError, ContactMethod, ContactPoint, ContactResult,
    ContactSettings, ContactSummary, ContactTimes, Master, DEFAULT_MAX_ITERATIONS,
};
use super::problem::ContactProblem;
use super::row::{coupling, fill_couplings, Couplings, Row, Solved};
use crate::fem::assembly::Stiffness;
use crate::fem::forward::HalfSolved;
use crate::fem::solve::PartitionedSolver;
use crate::fem::DofPartition;
use crate::util::timing::ms;
use nalgebra::{DMatrix, DVector, Vector2, Vector3};
use std::time::Instant;

/// Share of the deepest penetration below which candidates join in one iteration.
const JOIN_SHARE: f64 = 0.3;

/// A contact step whose displacements move a node more than this many search depths runs away.
pub const RUNAWAY: f64 = 10.0;

/// Solves the contact problem by the active set (see the module documentation).
pub fn solve_lagrange(
    solver: &mut PartitionedSolver,
    problem: &ContactProblem,
    settings: &ContactSettings,
) -> Result<ContactResult, ContactError> {
    let partition = problem.partition;
    let base = solver.solve(
        problem.k,
        partition,
        problem.prescribed,
        problem.loads,
        problem.node_positions(),
    )?;
    let t = Instant::now();
    let mut times = ContactTimes::default();
    times.add_solve(&base.stats);
    let u0 = base.displacement.clone();
    let neq = partition.free_count();
    let mut rows: Vec<Row> = Vec::new();
    let mut lambda = DVector::zeros(0);
    let mut u = u0.clone();
    let mut substitutions = 0;
    let mut iterations = 0;
    // Candidates: every contact possible on the reference geometry (U = 0), within the search
    // depth, its facet, weights and normal frozen there (small sliding).
    let zero = vec![0.0; u.len()];
    let ts = Instant::now();
    let mut pool: Vec<Row> = Vec::new();
    for p in problem.penetrations(&zero, settings, settings.search_depth, settings.pairs) {
        if pool.iter().all(|r| r.key() != (p.node, p.source)) {
            let mu = (problem.friction)(p.node, &p.master);
            pool.push(Row::new(&p, problem, &zero, mu));
        }
    }
    times.search += ms(ts);
    let mut couplings = Couplings::new();
    let mut refreshes = 0;
    let mut at_iteration_cap = false;
    // Rounds of new rows on the current geometry: between bodies, where a soft body's facets
    // fold around the skin, up to eight (a pit found at each round's geometry: three left a
    // soft ball's press at 81 % of its keyframe, tests/soft_ball_press.rs); on a body's own
    // skin, three (more let the rows of a crease chase each other: the fist's self-contact then
    // stops earlier, tests/self_contact.rs).
    let max_refresh = if problem.pairs.iter().any(|p| p.own.is_some()) {
        3
    } else {
        8
    };
    loop {
        iterations += 1;
        if iterations > settings.max_iterations {
            at_iteration_cap = true;
            // The active set still changes (rows that hardly touch join and leave in turn,
            // where the smooth skin's points share the nodes of a cell): the last settled set
            // is in equilibrium with no pulling contact; it stands if nothing penetrates
            // beyond the penetration limit on the current geometry (checked below).
            iterations -= 1;
            break;
        }
        // Join: candidates whose linearised gap is closed beyond the tolerance — the deeper
        // ones first (within a factor JOIN_SHARE of the deepest): the shallow ones are often
        // lifted by their neighbours' contact and would cost a substitution for nothing.
        let gaps: Vec<f64> = pool.iter().map(|r| r.apply(0, &u) - r.bound).collect();
        let deepest = gaps.iter().copied().fold(0.0, f64::min);
        let cut = (JOIN_SHARE * deepest).min(-settings.tolerance);
        // Warm start: in the first iteration only the nodes held before join, wherever they
        // penetrate (held, they lift most of the others out).
        let warm = iterations == 1 && !problem.held_before.is_empty();
        let joins = |r: &Row, gap: f64| {
            if warm {
                gap < -settings.tolerance && problem.held_before.binary_search(&r.node).is_ok()
            } else {
                gap < cut
            }
        };
        let mut fresh: Vec<Row> = Vec::new();
        let mut i = 0;
        let mut gaps = gaps;
        while i < pool.len() {
            if joins(&pool[i], gaps[i]) {
                gaps.swap_remove(i);
                let mut row = pool.swap_remove(i);
                // A node held at the step before sticks where the step started (U = 0, as the
                // row was made); measured from where this iteration's U has it instead — the
                // bodies already sprung back along the surface without the contact — its
                // friction did not hold it where it was, and the corrections at a pose swung
                // by 10 % without settling (the Power grasp with μ = 0.5,
                // tests/friction_grasp.rs).
                if problem.held_before.binary_search(&row.node).is_err() {
                    row.reference = Vector2::new(row.apply(1, &u), row.apply(2, &u));
                }
                fresh.push(row);
            } else {
                i += 1;
            }
        }
        if fresh.is_empty() {
            // The linearised problem is solved. Where a node still penetrates on the current
            // geometry (it slid onto another facet, or the facet turned), it gets a constraint
            // there too, a few rounds at most.
            if refreshes >= max_refresh {
                break;
            }
            refreshes += 1;
            let ts = Instant::now();
            let found = problem.penetrations(&u, settings, -settings.tolerance, settings.pairs);
            times.search += ms(ts);
            for p in found {
                let key = (p.node, p.source);
                // A row of this node on the very point it is found at now — the same facet
                // and the same weights h_i (`Master` compares both): a node whose projection
                // is clamped to a corner or an edge of the facet finds that point again.
                let same_point = |r: &Row| r.key() == key && r.master == p.master;
                if let Some(i) = rows.iter().position(|r| r.key() == key) {
                    if matches!(p.master, Master::Obstacle(_)) {
                        continue;
                    }
                    if let Some(j) = rows.iter().position(same_point) {
                        // Held there, yet through the facet on the current geometry beyond
                        // the limit: the facet turned or dented since the row was linearised.
                        // The row is linearised again where the node and the facet are now
                        // (its id is new: no coupling is reused).
                        if -p.gap > settings.penetration_limit() {
                            let old = rows.remove(j);
                            let mut row = Row::new(&p, problem, &u, old.mu);
                            row.reference = old.reference;
                            fresh.push(row);
                        }
                        continue;
                    }
                    // The node slid onto another facet, or along its facet to another point
                    // of it (the usual case: a frictionless point slides along its row's
                    // plane, which is normal to the smoothed normal, not to the facet, so it
                    // leaves the facet's plane by the tilt between the two times the slide).
                    // A new row joins, linearised where the node and the facet are now, and
                    // the old one stays: where the other body dents (a concave surface) the
                    // node must stay out of both planes, and where it is convex, or the new row
                    // holds the node further out, the old one stops pushing and the active set
                    // releases it. Round by round the deepest penetration falls about five
                    // times, from ≈ 10⁻⁵ m to the tolerance in four to eight rounds of a
                    // grasp's step (docs/performance.md, "Where a drag's first solved frame goes").
                    let mut row = Row::new(&p, problem, &u, rows[i].mu);
                    row.reference = rows[i].reference;
                    fresh.push(row);
                } else {
                    pool.retain(|r| r.key() != key);
                    let mu = (problem.friction)(p.node, &p.master);
                    let mut row = Row::new(&p, problem, &u, mu);
                    // (Held at the step before: from where the step started, as above.)
                    if problem.held_before.binary_search(&p.node).is_ok() {
                        row.reference = Vector2::zeros();
                    }
                    fresh.push(row);
                }
            }
            if fresh.is_empty() {
                break;
            }
        }
        // K11⁻¹·C_aᵀ for the new rows, in one multi-column substitution.
        let mut wanted: Vec<(usize, usize)> = Vec::new();
        let mut block: Vec<f64> = Vec::new();
        let mut keep: Vec<bool> = Vec::new();
        for (r, row) in fresh.iter().enumerate() {
            if row.axes() > 0 {
                keep.push(true);
                continue;
            }
            let axes = if row.mu > 0.0 { 3 } else { 1 };
            let start = block.len();
            let mut any = false;
            for axis in 0..axes {
                let mut col = vec![0.0; neq];
                any |= row.scatter(axis, 1.0, &mut col, partition);
                block.extend(col);
                wanted.push((r, axis));
            }
            if !any {
                // Nothing of this contact can move: it cannot be enforced.
                block.truncate(start);
                wanted.truncate(wanted.len() - axes);
            }
            keep.push(any);
        }
        if !wanted.is_empty() {
            let ts = Instant::now();
            // The axes of one row are consecutive in `wanted`: one group each.
            let mut groups: Vec<(usize, usize)> = Vec::new();
            for &(r, _) in &wanted {
                match groups.last_mut() {
                    Some((last, k)) if *last == r => *k += 1,
                    _ => groups.push((r, 1)),
                }
            }
            let sizes: Vec<usize> = groups.iter().map(|g| g.1).collect();
            match solver.forward_sparse(&block, &sizes)? {
                Some(halves) => {
                    for (&(r, _), h) in groups.iter().zip(halves) {
                        fresh[r].solved = Solved::Half(h);
                    }
                }
                None => {
                    solver.solve_factored(&mut block, wanted.len())?;
                    let mut j = 0;
                    for &(r, k) in &groups {
                        let cols = (j..j + k)
                            .map(|c| block[c * neq..(c + 1) * neq].to_vec())
                            .collect();
                        fresh[r].solved = Solved::Full(cols);
                        j += k;
                    }
                }
            }
            times.substitution += ms(ts);
            substitutions += wanted.len();
        }
        rows.extend(
            fresh
                .into_iter()
                .zip(keep)
                .filter(|(_, k)| *k)
                .map(|(r, _)| r),
        );
        if rows.is_empty() {
            continue;
        }
        let ts = Instant::now();
        lambda = if rows.iter().any(|r| r.mu > 0.0) {
            settle_coulomb(
                &mut rows,
                &u0,
                partition,
                &mut couplings,
                settings.tolerance,
            )?
        } else {
            settle(&mut rows, &mut pool, &u0, partition, &mut couplings)?
        };
        times.settle += ms(ts);
        let ts = Instant::now();
        substitutions += displace(&rows, &lambda, &u0, &mut u, partition, solver)?;
        times.substitution += ms(ts);
        // A body that only weak ground springs hold runs away: no equilibrium with contact.
        let (node, distance) = (0..u.len() / 3)
            .map(|n| (n, Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]).norm()))
            .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        if distance > RUNAWAY * settings.search_depth {
            return Err(ContactError::Runaway {
                node,
                distance,
                contacts: rows.len(),
                slipping: rows.iter().filter(|r| r.state == Adhesion::Slip).count(),
            });
        }
    }
    if rows.is_empty() {
        u = u0.clone();
    }
    // Reactions at the prescribed dofs: K·U − R − Cᵀλ (a contact force on a prescribed node
    // goes straight into its support).
    let mut contacts = contact_points(&rows, &lambda, problem, &u);
    // Rows kept without force (friction) are no contact.
    contacts.retain(|c| c.force > 0.0);
    let contact_force = transferred_forces(&contacts, u.len());
    let ku = problem.k.mul(&u);
    let mut solution = base;
    for d in 0..u.len() {
        solution.reaction[d] = if partition.prescribed[d] {
            ku[d] - problem.loads[d] - contact_force[d]
        } else {
            0.0
        };
    }
    solution.displacement = u;
    let max_penetration = problem.max_penetration(&solution.displacement, settings);
    if max_penetration > settings.penetration_limit() {
        return Err(ContactError::NotConverged {
            method: ContactMethod::Lagrange.name(),
            iterations,
            active: rows.len(),
            penetration: max_penetration,
            tolerance: settings.penetration_limit(),
            change: None,
            advice: if at_iteration_cap && settings.max_iterations < DEFAULT_MAX_ITERATIONS {
                "the active set was still changing at the cap: raise \
                 solver.contact_max_iterations (it is below its default, 50)"
            } else if at_iteration_cap {
                // At its default or above the set cycles (contacts that hardly touch joining
                // and leaving in turn): a higher cap only cycles longer.
                "the active set was still changing at the cap, contacts that hardly touch \
                 joining and leaving in turn"
            } else {
                "the facets under the contact turned further than the linearised contact step \
                 follows (the iteration cap was not reached, so raising it does not help)"
            },
        });
    }
    Ok(ContactResult {
        solution,
        summary: ContactSummary {
            contacts,
            method: ContactMethod::Lagrange,
            iterations,
            factorizations: 1,
            substitutions,
            max_penetration,
            contact_ms: ms(t),
            last_change: 0.0,
            stopped_by_threshold: false,
            region_cells: 0,
            times,
            skin_points: Vec::new(),
            objects_kept: None,
            at_iteration_cap,
        },
    })
}

/// Primal–dual active-set rounds before the settle falls back to releasing one row at a time.
const ACTIVE_SET_ROUNDS: usize = 30;

/// The normal multipliers of frictionless rows: the linear complementarity problem of the
/// Schur complement, w = G·λ + c with c = C·U⁰ − b: λ ≥ 0, w ≥ 0, λ·w = 0 (a row carries force
/// only where its gap is closed, and none pulls). Rows left without force are released (they
/// may join again from the pool). Returns λ of the rows kept, in row order.
///
/// Solved by the primal–dual active set method (Hintermüller, Ito and Kunisch 2002: a
/// semi-smooth Newton method on min(λ, w) = 0): the rows held are those with λ − w/G_ii > 0,
/// G_AA·λ_A = −c_A on them, until the set repeats — a few factorizations where releasing the
/// most pulling row at a time took one per row released (a refreshed grasp step: 190 of 250
/// rows). Where the rounds do not settle (nearly dependent rows: skin points embedded in the
/// same cells) the rows are released the old way, one at a time, from the last set.
fn settle(
    rows: &mut Vec<Row>,
    released: &mut Vec<Row>,
    u0: &[f64],
    partition: &DofPartition,
    cache: &mut Couplings,
) -> Result<DVector<f64>, ContactError> {
    debug_assert!(rows.iter().all(|r| r.axes() == 1));
    let m = rows.len();
    if m == 0 {
        return Ok(DVector::zeros(0));
    }
    let g = normal_couplings(rows, partition, cache);
    let c = DVector::from_fn(m, |i, _| rows[i].apply(0, u0) - rows[i].bound);
    // Rows off the set are released; where the rounds did not settle, the most pulling row
    // is then released one at a time from their last set.
    let (held, lambda) = match complementary(&g, &c) {
        Ok((held, lambda)) => (held, Some(lambda)),
        Err(last) => (last, None),
    };
    let mut out = Vec::with_capacity(m);
    for (i, row) in std::mem::take(rows).into_iter().enumerate() {
        if held[i] {
            if let Some(l) = &lambda {
                out.push(l[i]);
            }
            rows.push(row);
        } else {
            released.push(row);
        }
    }
    match lambda {
        Some(_) => Ok(DVector::from_vec(out)),
        None => release_one_at_a_time(rows, released, u0, partition, cache),
    }
}

/// G = C·K11⁻¹·Cᵀ over the normal axes of `rows` (frictionless), from the coupling cache.
fn normal_couplings(rows: &[Row], partition: &DofPartition, cache: &mut Couplings) -> DMatrix<f64> {
    let m = rows.len();
    fill_couplings(cache, rows, partition);
    let mut g = DMatrix::zeros(m, m);
    for i in 0..m {
        for j in i..m {
            g[(i, j)] = coupling(cache, &rows[i], 0, &rows[j], 0, partition);
            g[(j, i)] = g[(i, j)];
        }
    }
    g
}

/// The solution of the linear complementarity problem w = G·λ + c, λ ≥ 0, w ≥ 0, λ·w = 0 (G
/// symmetric positive definite) by the primal–dual active set method, from every row held:
/// which rows are held (λ > 0 there, w = 0) and λ. `Err` with the last set when
/// [`ACTIVE_SET_ROUNDS`] rounds do not settle or a held system cannot be solved.
fn complementary(
    g: &DMatrix<f64>,
    c: &DVector<f64>,
) -> Result<(Vec<bool>, DVector<f64>), Vec<bool>> {
    let m = c.len();
    let mut held = vec![true; m];
    let mut lambda = DVector::zeros(m);
    for _ in 0..ACTIVE_SET_ROUNDS {
        let set: Vec<usize> = (0..m).filter(|&i| held[i]).collect();
        let sub = DMatrix::from_fn(set.len(), set.len(), |a, b| g[(set[a], set[b])]);
        let rhs = DVector::from_fn(set.len(), |a, _| -c[set[a]]);
        let Some(x) = solve_held(sub, &rhs) else {
            return Err(held);
        };
        lambda.fill(0.0);
        for (a, &i) in set.iter().enumerate() {
            lambda[i] = x[a];
        }
        let w = g * &lambda + c;
        let next: Vec<bool> = (0..m)
            .map(|i| lambda[i] - w[i] / g[(i, i)].max(f64::MIN_POSITIVE) > 0.0)
            .collect();
        if next == held {
            return Ok((held, lambda));
        }
        held = next;
    }
    Err(held)
}

/// λ of G_AA·λ = rhs by Cholesky, or with a relative shift of 1e-12 of the diagonal where the
/// rows are nearly dependent (a node and the facet it touches both in contact); `None` when
/// even that fails.
fn solve_held(g: DMatrix<f64>, rhs: &DVector<f64>) -> Option<DVector<f64>> {
    let m = g.nrows();
    if m == 0 {
        return Some(DVector::zeros(0));
    }
    match g.clone().cholesky().map(|c| c.solve(rhs)) {
        Some(l) if l.iter().all(|v| v.is_finite()) => Some(l),
        _ => {
            let scale = (0..m).map(|i| g[(i, i)].abs()).fold(0.0, f64::max);
            let shifted = g + DMatrix::identity(m, m) * (1e-12 * scale);
            match shifted.lu().solve(rhs) {
                Some(l) if l.iter().all(|v| v.is_finite()) => Some(l),
                _ => None,
            }
        }
    }
}

/// The normal multipliers of frictionless rows: the Schur complement system G·λ = b − C·U⁰ on
/// the active set, the most pulling contact (λ < 0) released until none pulls (rows released
/// here may join again from the pool). Returns λ in row order.
fn release_one_at_a_time(
    rows: &mut Vec<Row>,
    released: &mut Vec<Row>,
    u0: &[f64],
    partition: &DofPartition,
    cache: &mut Couplings,
) -> Result<DVector<f64>, ContactError> {
    loop {
        let m = rows.len();
        if m == 0 {
            return Ok(DVector::zeros(0));
        }
        let g = normal_couplings(rows, partition, cache);
        let rhs = DVector::from_fn(m, |i, _| rows[i].bound - rows[i].apply(0, u0));
        let Some(lambda) = solve_held(g, &rhs) else {
            return Err(ContactError::Singular { active: m });
        };
        if lambda.iter().all(|&l| l >= 0.0) {
            return Ok(lambda);
        }
        // The most pulling row is released, one at a time: releasing every pulling row at once
        // cycles where rows are nearly dependent (skin points embedded in the same cells), as
        // each release makes its neighbours pull or push in turn.
        let worst = lambda.imin();
        released.push(rows.remove(worst));
    }
}

/// U = U⁰ + K11⁻¹·Cᵀ·λ (a slipping row's normal column carries its friction along); returns
/// the substitutions it took.
fn displace(
    rows: &[Row],
    lambda: &DVector<f64>,
    u0: &[f64],
    u: &mut [f64],
    partition: &DofPartition,
    solver: &mut PartitionedSolver,
) -> Result<usize, ContactError> {
    u.copy_from_slice(u0);
    if rows.is_empty() {
        return Ok(0);
    }
    // (row, axis, multiplier) of every column in the sum.
    let mut terms: Vec<(usize, usize, f64)> = Vec::new();
    let mut j = 0;
    for (r, row) in rows.iter().enumerate() {
        let l = lambda[j];
        terms.push((r, 0, l));
        match row.state {
            Adhesion::Stick => {
                terms.push((r, 1, lambda[j + 1]));
                terms.push((r, 2, lambda[j + 2]));
                j += 3;
            }
            Adhesion::Slip => {
                terms.push((r, 1, l * row.mu * row.slip.x));
                terms.push((r, 2, l * row.mu * row.slip.y));
                j += 1;
            }
            Adhesion::Frictionless => j += 1,
        }
    }
    let full = rows
        .first()
        .is_some_and(|r| matches!(r.solved, Solved::Full(_)));
    if full {
        for &(r, a, l) in &terms {
            let Solved::Full(cols) = &rows[r].solved else {
                unreachable!("one kind of column per solve")
            };
            for (e, &d) in partition.free.iter().enumerate() {
                u[d] += l * cols[a][e];
            }
        }
        return Ok(0);
    }
    // The half substitutions of the rows are known: the backward half only.
    let halves: Vec<(&HalfSolved, usize, f64)> = terms
        .iter()
        .filter(|t| t.2 != 0.0)
        .filter_map(|&(r, a, l)| match &rows[r].solved {
            Solved::Half(h) => Some((h, a, l)),
            _ => None,
        })
        .collect();
    if halves.len() == terms.iter().filter(|t| t.2 != 0.0).count() {
        if let Some(x) = solver.backward_from_halves(&halves)? {
            for (e, &d) in partition.free.iter().enumerate() {
                u[d] += x[e];
            }
            return Ok(1);
        }
    }
    let mut rhs = vec![0.0; partition.free_count()];
    for &(r, a, l) in &terms {
        if l != 0.0 {
            rows[r].scatter(a, l, &mut rhs, partition);
        }
    }
    solver.solve_factored(&mut rhs, 1)?;
    for (e, &d) in partition.free.iter().enumerate() {
        u[d] += rhs[e];
    }
    Ok(1)
}

fn contact_points(
    rows: &[Row],
    lambda: &DVector<f64>,
    problem: &ContactProblem,
    u: &[f64],
) -> Vec<ContactPoint> {
    let mut out = Vec::new();
    let mut j = 0;
    for row in rows {
        let ln = lambda[j];
        let [n, t1, t2] = row.basis;
        let tangential = match row.state {
            Adhesion::Stick => {
                let t = t1 * lambda[j + 1] + t2 * lambda[j + 2];
                j += 3;
                t
            }
            Adhesion::Slip => {
                j += 1;
                (t1 * row.slip.x + t2 * row.slip.y) * (row.mu * ln)
            }
            Adhesion::Frictionless => {
                j += 1;
                Vector3::zeros()
            }
        };
        let gap = match row.master {
            Master::Obstacle(o) => {
                problem.obstacles[o]
                    .nearest(&problem.position(u, row.node))
                    .0
            }
            Master::Facet { .. } => row.apply(0, u) - row.bound,
        };
        out.push(ContactPoint {
            node: row.node,
            terms: row.terms.clone(),
            slave_terms: problem.embedded.term_count(row.node),
            master: row.master,
            normal: n,
            force: ln,
            tangential,
            adhesion: row.state,
            gap,
        });
    }
    out
}

/// Solves K·U = R with the prescribed dofs of `partition` and the nodes `candidates` kept out of
/// `obstacles`, frictionless.
#[allow(clippy::too_many_arguments)]
pub fn solve_with_obstacles(
    solver: &mut PartitionedSolver,
    k: &Stiffness,
    partition: &DofPartition,
    prescribed: &[f64],
    loads: &[f64],
    positions: &[Vector3<f64>],
    candidates: &[usize],
    obstacles: &[Obstacle],
    settings: ContactSettings,
) -> Result<ContactResult, ContactError> {
    let problem = ContactProblem {
        k,
        partition,
        prescribed,
        loads,
        positions,
        embedded: &EmbeddedPoints::none(positions.len()),
        obstacles,
        obstacle_candidates: candidates,
        surfaces: &[],
        pairs: &[],
        friction: &|_, _| 0.0,
        stop: None,
        crossings: &[],
        held_before: &[],
        forces_before: &[],
    };
    solve_lagrange(solver, &problem, &settings)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pseudo-random number in [−1, 1) (a linear congruential generator: no dependency).
    fn next(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// The primal–dual active set gives the solution of the complementarity problem of a
    /// coupled, positive definite G (contacts sharing the nodes of a patch): no row pulls
    /// (λ ≥ 0), none penetrates (w ≥ 0), and a row carries force only where its gap is closed
    /// (λ·w = 0), to round-off — with most rows released, as in a refreshed grasp step.
    #[test]
    fn settles_the_complementarity_problem() {
        let mut state = 7;
        for (m, pushed) in [(40, 0.3), (250, 0.2), (120, 0.9)] {
            // G = B·Bᵀ + 0.05·I: rows coupled through shared nodes, positive definite.
            let b = DMatrix::from_fn(m, m / 2, |_, _| next(&mut state));
            let g = &b * b.transpose() + DMatrix::identity(m, m) * 0.05;
            // c < 0: the row penetrates where nothing pushes (a share `pushed` of them).
            let c = DVector::from_fn(m, |_, _| {
                let r = next(&mut state);
                if (r + 1.0) / 2.0 < pushed {
                    -1.0 - r
                } else {
                    0.5 + r
                }
            });
            let (held, lambda) = complementary(&g, &c).expect("settles");
            let w = &g * &lambda + &c;
            let scale = c.amax() * (1.0 + g.amax());
            for i in 0..m {
                assert!(lambda[i] >= 0.0, "m {m}, row {i}: λ = {}", lambda[i]);
                assert!(w[i] >= -1e-12 * scale, "m {m}, row {i}: w = {}", w[i]);
                assert!(
                    (lambda[i] * w[i]).abs() <= 1e-12 * scale * (1.0 + lambda.amax()),
                    "m {m}, row {i}: λ·w = {}",
                    lambda[i] * w[i]
                );
                assert_eq!(held[i], lambda[i] > 0.0, "m {m}, row {i}");
            }
            let count = held.iter().filter(|&&h| h).count();
            println!("m = {m}: {count} rows held");
            assert!(count > 0 && count < m, "a mixed set: {count} of {m}");
        }
    }
}
