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
//! repeated until no displacement changes by more than a tolerance between two iterations; a
//! bone whose reaction then overruns its threshold stops the motion there (the grasp is not
//! realisable further).
//!
//! Three things make the published procedure follow a grasp, where it failed at the first
//! contact step of the shipped scenes (measured 2026-11-29: `finger-press-ball` at 0 % of its
//! keyframe, `hand-grasp-ball` at 83 %):
//!
//! - **Which side step 3 solves.** The iteration is Dirichlet–Neumann: the side solved in
//!   step 3 answers the other's position with its reactions, F ↦ S_solved·(g − C_held·F), and
//!   its plain rate is the ratio of the solved side's stiffness to the held side's. The paper
//!   solves the object with the skin held — right for a ball softer than the flesh; for a
//!   stiffer one the roles are exchanged and the flesh is solved against the object held
//!   (`held`, chosen in `solve/paper_roles.rs`).
//! - **Step 3 is a contact solve of the side solved against the held one, both ways**: its
//!   penetrating nodes repelled onto the held surface's facets and prescribed there (the
//!   paper's step 2, with a node that would pull released), and the held surface's nodes and
//!   skin points kept out of its facets too — with the exact method on that one side
//!   (`solve_lagrange`, its factor kept from iteration to iteration). One-sided, a fine skin
//!   sank between the nodes of a coarse ball.
//! - **The transferred forces are accelerated** by the interface quasi-Newton method
//!   (`quasi_newton.rs`, the default) or relaxed (Aitken's factor, or a fixed one), and along
//!   a motion the first iterate is the last step's forces (`ContactProblem::forces_before`):
//!   each step resolves only its own step of penetration.
//!
//! The forces found are those of the exact method to within the iteration's change tolerance
//! and the difference of the two methods' contact pairs (skin points only, for the exact method
//! by default): `tests/paper_along_motion.rs`.
//!
//! The prescribed node cannot slide on the facet, so the published procedure is sticking
//! contact (it has no friction law); step 3 applies the scene's Coulomb friction where it has
//! one.

use super::lagrange::solve_lagrange;
use super::point::{
    held_nodes, transferred_forces, ContactError, ContactMethod, ContactPoint, ContactResult,
    ContactSettings, ContactSummary, ContactTimes, PairSides, Relaxation,
};
use super::problem::ContactProblem;
use super::quasi_newton::QuasiNewton;
use crate::fem::solve::PartitionedSolver;
use crate::fem::DofPartition;
use crate::util::timing::ms;
use std::ops::Range;
use std::time::Instant;

/// The secant pairs the quasi-Newton method keeps. Measured on the five-digit grasp at hand
/// resolution 0.75 (2026-11-29): with 8 or 15 the motion is followed, with 25 or 40 the older
/// pairs, from other contact sets, slow the iteration down until a step fails in 50.
const SECANT_COLUMNS: usize = 10;

/// An accelerated step moving the displacements by less than this share of the plain
/// iteration's step is a stagnating secant model.
const STAGNATION: f64 = 1e-3;

/// Runs the paper's iteration. `held` lists the node ranges whose displacements step 2
/// prescribes where the last iterate left them (the paper's: the hand's, whose facets repel
/// the object's nodes; the object's when it is the stiffer, `solve/paper_roles.rs`).
pub fn solve_paper(
    solver: &mut PartitionedSolver,
    problem: &ContactProblem,
    settings: &ContactSettings,
    held: &[Range<usize>],
) -> Result<ContactResult, ContactError> {
    let partition = problem.partition;
    // Step 3's solver: the solved side with the held one prescribed (its factor kept from one
    // iteration to the next).
    let mut step3_solver = PartitionedSolver::new(solver.ordering());
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
    let mut u = u0.clone();
    // F: transferred contact forces (loads of step 5); along a motion, the ones the last step
    // converged to, with the displacements they hold.
    let mut force = vec![0.0; dofs];
    let mut factorizations = 1;
    let mut substitutions = 0;
    let warm = problem.forces_before.len() == dofs;
    if warm {
        force.copy_from_slice(problem.forces_before);
        u = released_solve(solver, partition, &u0, &force, &mut times)?;
        substitutions += 1;
    }
    // The held side's dofs, prescribed in step 3 where step 6 left them.
    let mut held_mask = partition.prescribed.clone();
    for r in held {
        for d in 3 * r.start..3 * r.end {
            held_mask[d] = true;
        }
    }
    let held_dofs = DofPartition::new(held_mask);
    // Step 3's contact, both ways.
    let step3_settings = ContactSettings {
        pairs: PairSides::Both,
        method: ContactMethod::Lagrange,
        ..*settings
    };
    let mut accelerator = Accelerator::new(settings.relaxation);
    // The contacts of the last step 3 (their nodes: the next one's warm start).
    let mut contacts: Vec<ContactPoint> = Vec::new();
    let mut touching: Vec<usize> = if warm {
        problem.held_before.to_vec()
    } else {
        Vec::new()
    };
    let mut skin_points = Vec::new();
    let mut change = f64::INFINITY;
    let mut stopped = false;
    let mut iterations = 0;
    let mut settled = false;
    while iterations < settings.max_iterations {
        iterations += 1;
        // Step 2: the held side where step 6 left it.
        let mut values = problem.prescribed.to_vec();
        for r in held {
            for d in 3 * r.start..3 * r.end {
                if !partition.prescribed[d] {
                    values[d] = u[d];
                }
            }
        }
        // Step 3: the solved side against the held one, its penetrating nodes repelled onto
        // the held surface's facets (and the held surface's points off its facets), exactly.
        let s = solve_lagrange(
            &mut step3_solver,
            &ContactProblem {
                partition: &held_dofs,
                prescribed: &values,
                stop: None,
                held_before: &touching,
                forces_before: &[],
                ..*problem
            },
            &step3_settings,
        )?;
        factorizations += s.summary.factorizations;
        substitutions += s.summary.substitutions;
        times.add(&s.summary.times);
        contacts = s.summary.contacts;
        skin_points = s.summary.skin_points;
        touching = held_nodes(&contacts);
        // Step 4: the contact forces on the solved side, equal and opposite on the held one.
        let fresh = transferred_forces(&contacts, dofs);
        // Steps 5–6 with these forces as they are (the published, unrelaxed iteration): how far
        // they move the displacements is the iteration's measure of convergence.
        let plain = released_solve(solver, partition, &u0, &fresh, &mut times)?;
        substitutions += 1;
        change = largest_difference(&plain, &u);
        if change < settings.change_tolerance {
            force = fresh;
            u = plain;
            settled = true;
            // The paper's threshold: a bone overloaded by the settled forces.
            if let Some(stop) = problem.stop {
                stopped = stop(&support_reactions(problem, &u, &force));
            }
            break;
        }
        // The next forces, accelerated or relaxed. Across a change of the contact set the
        // secant history is kept: the map is piecewise affine, and its secants across the kinks
        // lead to the fixed point (restarted at each change, the iteration cycled between
        // sets). A step that would barely move while the plain one moves (the secant model
        // stagnating) is taken again without history.
        let mut next_force = accelerator.next(&force, &fresh);
        let mut next = released_solve(solver, partition, &u0, &next_force, &mut times)?;
        substitutions += 1;
        if largest_difference(&next, &u) < STAGNATION * change {
            accelerator.restart();
            next_force = accelerator.next(&force, &fresh);
            next = released_solve(solver, partition, &u0, &next_force, &mut times)?;
            substitutions += 1;
        }
        force = next_force;
        u = next;
    }
    if !settled {
        return Err(ContactError::NotConverged {
            method: ContactMethod::Paper.name(),
            iterations,
            active: contacts.len(),
            penetration: problem.max_penetration(&u, settings),
            tolerance: settings.tolerance,
            change: Some(change),
            advice: "solve with [solver] contact = \"lagrange\", which resolves the contact \
                     exactly",
        });
    }
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
            skin_points,
            objects_kept: None,
            at_iteration_cap: false,
        },
    })
}

/// The largest difference between two displacement vectors, m.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// How the transferred forces move from one iteration to the next.
enum Accelerator {
    Fixed(f64),
    Aitken {
        omega: f64,
        previous: Option<Vec<f64>>,
    },
    QuasiNewton(QuasiNewton),
}

impl Accelerator {
    fn new(relaxation: Relaxation) -> Accelerator {
        match relaxation {
            Relaxation::Fixed(w) => Accelerator::Fixed(w),
            Relaxation::Aitken => Accelerator::Aitken {
                omega: 0.5,
                previous: None,
            },
            Relaxation::QuasiNewton => {
                Accelerator::QuasiNewton(QuasiNewton::new(0.5, SECANT_COLUMNS))
            }
        }
    }

    /// Forgets what the last iterations taught.
    fn restart(&mut self) {
        match self {
            Accelerator::Fixed(_) => {}
            Accelerator::Aitken { previous, .. } => *previous = None,
            Accelerator::QuasiNewton(qn) => qn.restart(),
        }
    }

    /// The next forces from those tried, `force`, and the answer of steps 2–4, `fresh`.
    fn next(&mut self, force: &[f64], fresh: &[f64]) -> Vec<f64> {
        let residual: Vec<f64> = fresh.iter().zip(force).map(|(f, g)| f - g).collect();
        let omega = match self {
            Accelerator::QuasiNewton(qn) => return qn.next(force, fresh),
            Accelerator::Fixed(w) => *w,
            Accelerator::Aitken { omega, previous } => {
                if let Some(prev) = previous {
                    let mut num = 0.0;
                    let mut den = 0.0;
                    for (r, p) in residual.iter().zip(prev.iter()) {
                        num += p * (r - p);
                        den += (r - p) * (r - p);
                    }
                    if den > 0.0 {
                        *omega = (-*omega * num / den).clamp(1e-3, 1.0);
                    }
                }
                *previous = Some(residual.clone());
                *omega
            }
        };
        force
            .iter()
            .zip(&residual)
            .map(|(f, r)| f + omega * r)
            .collect()
    }
}

/// Steps 5–6: every dof of object and skin released, the contact forces `force` as loads on
/// top of the base solution `u0` (one substitution with the base factor).
fn released_solve(
    solver: &mut PartitionedSolver,
    partition: &DofPartition,
    u0: &[f64],
    force: &[f64],
    times: &mut ContactTimes,
) -> Result<Vec<f64>, ContactError> {
    let mut rhs: Vec<f64> = partition.free.iter().map(|&d| force[d]).collect();
    let ts = Instant::now();
    solver.solve_factored(&mut rhs, 1)?;
    times.substitution += ms(ts);
    let mut next = u0.to_vec();
    for (e, &d) in partition.free.iter().enumerate() {
        next[d] += rhs[e];
    }
    Ok(next)
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
