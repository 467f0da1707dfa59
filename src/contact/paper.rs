//! The paper's grasping iteration (section "ball grasping and pressing", steps 2–6):
//!
//! 2. prescribe the skin's displacements; repel every penetrating object node onto the skin
//!    facet along the facet normal n_F (point C, Figure 5) and prescribe it there;
//! 3. solve (7)–(8): the object's displacements, and the reactions R_u at the repelled nodes;
//! 4. apply equal and opposite forces to the skin, shared among the facet's nodes as
//!    R_i = h_i·R_C;
//! 5. release every degree of freedom of object and skin: the contact forces become loads;
//! 6. solve (7)–(8) again for object and skin together, and the reactions on the bones;
//!
//! repeated until no displacement changes by more than a tolerance between two iterations, or
//! stopped when a bone's reaction overruns its threshold. Step 3 changes which dofs are
//! prescribed, so each iteration factors the object's stiffness again ("we rearrange matrix
//! relation (6) because the number of equations is modified"); step 6 reuses one factorization.
//!
//! A repelled node stays in contact while its reaction pushes; one that is pulled is released.
//! The prescribed node cannot slide on the facet, so the published procedure is sticking
//! contact (it has no friction law). Unrelaxed (ω = 1) the iteration is a fixed point of
//! F ↦ S_object·(g − C_skin·F), which diverges when the object is stiffer than the flesh under
//! it; the transferred forces are therefore relaxed, by default with Aitken's factor.

use super::point::{
    Adhesion, ContactError, ContactMethod, ContactPoint, ContactResult, ContactSettings,
    ContactSummary, ContactTimes, Master, PairSides, Relaxation,
};
use super::problem::{ContactProblem, Penetration};
use crate::fem::solve::PartitionedSolver;
use crate::fem::DofPartition;
use crate::util::timing::ms;
use std::collections::BTreeMap;
use std::ops::Range;
use std::time::Instant;

/// Runs the paper's iteration. `skin` lists the node ranges whose displacements step 2
/// prescribes (the bodies whose facets repel: the hand).
pub fn solve_paper(
    solver: &mut PartitionedSolver,
    problem: &ContactProblem,
    settings: &ContactSettings,
    skin: &[Range<usize>],
) -> Result<ContactResult, ContactError> {
    let partition = problem.partition;
    let ordering = solver.ordering();
    let ordering_solver = || PartitionedSolver::new(ordering);
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
    let dofs = base.displacement.len();
    let u0 = base.displacement.clone();
    let neq = partition.free_count();
    let mut u = u0.clone();
    let mut force = vec![0.0; dofs]; // F: transferred contact forces (loads of step 5)
    let mut previous_residual: Option<Vec<f64>> = None;
    let mut omega = match settings.relaxation {
        Relaxation::Fixed(w) => w,
        Relaxation::Aitken => 0.5,
    };
    let mut active: BTreeMap<usize, Penetration> = BTreeMap::new();
    let mut factorizations = 1;
    let mut substitutions = 0;
    let mut change = f64::INFINITY;
    let mut stopped = false;
    let mut iterations = 0;
    let mut reactions: BTreeMap<usize, nalgebra::Vector3<f64>> = BTreeMap::new();
    let in_skin = |n: usize| skin.iter().any(|r| r.contains(&n));
    while iterations < settings.max_iterations {
        iterations += 1;
        // Step 2: repel penetrating nodes (and keep those already in contact on the facet).
        let found =
            problem.penetrations(&u, settings, settings.search_depth, PairSides::ObjectNodes);
        let mut now: BTreeMap<usize, Penetration> = BTreeMap::new();
        for p in found {
            // The repelled nodes are the object's (an embedded skin point is not a node).
            if in_skin(p.node) || p.node >= problem.embedded.first() {
                continue;
            }
            if p.gap < -settings.tolerance || active.contains_key(&p.node) {
                let keep = now.get(&p.node).is_none_or(|q| p.gap < q.gap);
                if keep {
                    now.insert(p.node, p);
                }
            }
        }
        if now.is_empty() && iterations > 1 && active.is_empty() {
            change = 0.0;
            break;
        }
        let mut mask = partition.prescribed.clone();
        let mut values = problem.prescribed.to_vec();
        for r in skin {
            for n in r.clone() {
                for a in 0..3 {
                    if !mask[3 * n + a] {
                        mask[3 * n + a] = true;
                        values[3 * n + a] = u[3 * n + a];
                    }
                }
            }
        }
        for p in now.values() {
            let target = problem.position(&u, p.node) - p.normal * p.gap;
            for a in 0..3 {
                mask[3 * p.node + a] = true;
                values[3 * p.node + a] = target[a] - problem.positions[p.node][a];
            }
        }
        // Step 3: the object with its repelled nodes prescribed (a new factorization).
        let step3 = if mask.iter().all(|&m| m) {
            None
        } else {
            let sub = DofPartition::new(mask);
            let s = ordering_solver().solve(
                problem.k,
                &sub,
                &values,
                problem.loads,
                problem.node_positions(),
            )?;
            factorizations += 1;
            times.add_solve(&s.stats);
            Some(s)
        };
        // Step 4: the reactions at the repelled nodes, equal and opposite on the skin.
        let mut fresh = vec![0.0; dofs];
        reactions.clear();
        let mut released = Vec::new();
        for (&node, p) in &now {
            let r = match &step3 {
                Some(s) => s.reaction_at(node),
                None => nalgebra::Vector3::zeros(),
            };
            if r.dot(&p.normal) < 0.0 {
                released.push(node);
                continue;
            }
            reactions.insert(node, r);
            for (m, w) in problem.contact_terms(node, &p.master) {
                for a in 0..3 {
                    fresh[3 * m + a] += w * r[a];
                }
            }
        }
        for n in released {
            now.remove(&n);
        }
        active = now;
        // Relaxation of the transferred forces.
        let residual: Vec<f64> = fresh.iter().zip(&force).map(|(f, g)| f - g).collect();
        if let (Relaxation::Aitken, Some(prev)) = (settings.relaxation, &previous_residual) {
            let mut num = 0.0;
            let mut den = 0.0;
            for (r, p) in residual.iter().zip(prev) {
                num += p * (r - p);
                den += (r - p) * (r - p);
            }
            if den > 0.0 {
                omega = (-omega * num / den).clamp(1e-3, 1.0);
            }
        }
        for (f, r) in force.iter_mut().zip(&residual) {
            *f += omega * r;
        }
        previous_residual = Some(residual);
        // Steps 5–6: everything released, the contact forces as loads (the base factor).
        let mut rhs = vec![0.0; neq];
        for (e, &d) in partition.free.iter().enumerate() {
            rhs[e] = force[d];
        }
        let ts = Instant::now();
        solver.solve_factored(&mut rhs, 1)?;
        times.substitution += ms(ts);
        substitutions += 1;
        let mut next = u0.clone();
        for (e, &d) in partition.free.iter().enumerate() {
            next[d] += rhs[e];
        }
        change = next
            .iter()
            .zip(&u)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        u = next;
        if let Some(stop) = problem.stop {
            let reaction = support_reactions(problem, &u, &force);
            if stop(&reaction) {
                stopped = true;
                break;
            }
        }
        if change < settings.change_tolerance && iterations > 1 {
            break;
        }
    }
    if stopped && change >= settings.change_tolerance {
        return Err(ContactError::StoppedBeforeConvergence {
            iterations,
            change,
            tolerance: settings.change_tolerance,
        });
    }
    if !stopped && change >= settings.change_tolerance {
        return Err(ContactError::NotConverged {
            method: ContactMethod::Paper.name(),
            iterations,
            active: active.len(),
            penetration: problem.max_penetration(&u, settings),
            tolerance: settings.tolerance,
            change: Some(change),
            advice: "solve with [solver] contact = \"lagrange\", which resolves the contact \
                     exactly",
        });
    }
    let contacts: Vec<ContactPoint> = active
        .values()
        .filter_map(|p| {
            let r = reactions.get(&p.node)?;
            let normal_force = r.dot(&p.normal);
            let x = problem.position(&u, p.node);
            let gap = match p.master {
                Master::Obstacle(o) => problem.obstacles[o].nearest(&x).0,
                Master::Facet { nodes, weights, .. } => {
                    let c: nalgebra::Vector3<f64> = nodes
                        .iter()
                        .zip(weights)
                        .map(|(&n, h)| problem.position(&u, n) * h)
                        .sum();
                    (x - c).dot(&p.normal)
                }
            };
            Some(ContactPoint {
                node: p.node,
                terms: problem.contact_terms(p.node, &p.master),
                slave_terms: problem.embedded.term_count(p.node),
                master: p.master,
                normal: p.normal,
                force: normal_force,
                tangential: r - p.normal * normal_force,
                adhesion: Adhesion::Stick,
                gap,
            })
        })
        .collect();
    let reaction = support_reactions(problem, &u, &force);
    let mut solution = base;
    solution.reaction = reaction;
    solution.displacement = u;
    let max_penetration = problem.max_penetration(&solution.displacement, settings);
    Ok(ContactResult {
        solution,
        summary: ContactSummary {
            contacts,
            method: ContactMethod::Paper,
            iterations,
            factorizations,
            substitutions,
            max_penetration,
            contact_ms: ms(t),
            last_change: change,
            stopped_by_threshold: stopped,
            region_cells: 0,
            times,
            skin_points: Vec::new(),
            at_iteration_cap: false,
        },
    })
}

/// Reactions at the prescribed dofs, K·U − R − F (zero at free dofs).
fn support_reactions(problem: &ContactProblem, u: &[f64], force: &[f64]) -> Vec<f64> {
    let ku = problem.k.mul(u);
    (0..u.len())
        .map(|d| {
            if problem.partition.prescribed[d] {
                ku[d] - problem.loads[d] - force[d]
            } else {
                0.0
            }
        })
        .collect()
}
