//! Static equilibrium of a hyperelastic body at large deformation: Newton–Raphson on
//! R(u) = f_ext − ∂W/∂u = 0 with a backtracking line search, under load stepping with automatic
//! step cutting (Bonet & Wood, ch. 9; Wriggers, *Nonlinear Finite Element Methods*, ch. 5).
//!
//! The loads (dead loads, fixed in the reference configuration) and the prescribed displacements
//! are applied in increments of the load factor t ∈ (0, 1]. Each Newton iteration solves the
//! partitioned system of the paper's equations (6)–(7) with the tangent K_T = ∂²W/∂u²:
//! K_T,11·Δu_u = R_u − K_T,12·Δu_k, where Δu_k is what the prescribed dofs still have to move
//! to reach t·U_k (non-zero only in the first iteration of a step). Reactions follow from
//! equation (8) in its nonlinear form, R_k = f_int,k − f_ext,k.
//!
//! Line search: the step length α ∈ {1, ½, ¼, …} is the first for which no element inverts and
//! either the total potential Π = W − f_extᵀu decreases by at least 10⁻⁴·α·|∂Π/∂α| (Armijo) or
//! the residual norm decreases; while the prescribed dofs are still moving (Π is then not a
//! merit function), the first α with no inverted element is taken. A step that fails (an element
//! inverts for every α, the tangent is not positive definite, or Newton does not converge) is
//! restarted from the last equilibrium with half the increment; after two easy steps the
//! increment doubles again, up to its initial size.

use super::added_energy::{with_blocks, AddedEnergy, NodeBlock};
use super::assembly::Stiffness;
use super::elastic_energy::ElasticEnergy;
use super::hex8_hyperelastic::Volumetric;
use super::hyperelastic_body::{HyperelasticBody, InvertedElement};
use super::material::Material;
use super::negative_curvature::lowest_mode;
use super::partition::DofPartition;
use super::solve::{FillOrdering, PartitionedSolver, SolveError};
use crate::mesh::Mesh;
use crate::util::timing::ms;
use nalgebra::Vector3;
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// Settings of the Newton solver.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NewtonSettings {
    /// Integration of the volumetric energy (mean dilatation by default: no locking).
    pub volumetric: Volumetric,
    /// Initial number of equal load increments (≥ 1).
    pub increments: usize,
    /// Halvings of the initial increment allowed before giving up: the smallest increment is
    /// 2^−max_cuts of the initial one.
    pub max_cuts: usize,
    /// Newton iterations allowed per increment.
    pub max_iterations: usize,
    /// Convergence: ‖R_u‖ ≤ tolerance · max(‖f_ext‖, ‖f_int‖).
    pub tolerance: f64,
    /// Halvings of the step length α in the line search.
    pub line_search_halvings: usize,
    /// Fill-reducing ordering of the tangent's Cholesky factorization.
    pub ordering: FillOrdering,
    /// Also measure the residual against the largest ‖f_int‖ met in the increment: a
    /// displacement-driven increment whose equilibrium carries almost no force (flesh that
    /// ends up turning rigidly) is then judged against the forces its iterations dealt with,
    /// not against round-off.
    pub relative_to_peak: bool,
    /// When the tangent is not positive definite (a fold, buckling, or an iterate whose
    /// volume change puts a huge pressure in a nearly incompressible material), retry the
    /// factorization with an added energy's Hessian projected positive semi-definite, then
    /// without the pressure's Hessian, then with each element's tangent made positive
    /// semi-definite (its negative eigenvalues turned positive, `fem::definite`), and only
    /// should that fail with τ·diag added to the last tangent tried, τ = 10⁻⁴, 10⁻³, … 10
    /// (Nocedal & Wright, *Numerical Optimization*, §3.4): a descent direction of the energy,
    /// so the line search keeps lowering it towards a stable equilibrium, where plain Newton
    /// steps resume.
    pub regularise: bool,
    /// Once the prescribed dofs are in place, accept a step length only when it lowers the
    /// total potential (Armijo) — not also when it merely lowers the residual, which lets
    /// the iterates climb in energy and cycle around an unstable equilibrium — unless the
    /// change of the potential is lost in round-off. With [`NewtonSettings::regularise`], a
    /// descent method for the minimum of the energy (a stable equilibrium).
    pub energy_descent: bool,
    /// Where the exact tangent is indefinite near equilibrium (residual below
    /// [`SADDLE_RESIDUAL`]), step out along its most negative curvature
    /// ([`Increment::escape`]): an unstable equilibrium of the body (buckling) is left. Off
    /// where the body's energy is convex and only the added energy's Hessian is indefinite
    /// (a barrier's, whose pairs' distances curve): there an escape only undoes progress.
    /// (Only with [`NewtonSettings::regularise`]: without it an indefinite tangent fails.)
    pub escape_saddles: bool,
    /// Once the prescribed dofs are in place, a full step that lowers the potential is tried
    /// twice, four times … [`MAX_EXPANSION`] times as long (short of any crossing the added
    /// energy forbids) while that lowers it further: the tangent made positive definite over a
    /// direction of negative curvature (skin pressed on skin sliding off a ridge) gives steps
    /// far too short, and Newton creeps along it.
    pub expand_steps: bool,
    /// Iterations allowed to put the prescribed dofs in place (each step toward them cut short
    /// where the added energy forbids going further: flesh squeezed between bones that come
    /// too close for it); past them the increment fails ([`StepFailure::NotPlaced`]) instead
    /// of creeping on. `usize::MAX`: no limit.
    pub placing_iterations: usize,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            volumetric: Volumetric::MeanDilatation,
            increments: 1,
            max_cuts: 10,
            max_iterations: 25,
            tolerance: 1e-10,
            line_search_halvings: 10,
            ordering: FillOrdering::Auto,
            relative_to_peak: false,
            regularise: false,
            energy_descent: false,
            escape_saddles: true,
            expand_steps: false,
            placing_iterations: usize::MAX,
        }
    }
}

impl NewtonSettings {
    /// A descent method for a stable equilibrium of a displacement-driven increment: the
    /// residual against the largest force met, the tangent regularised where it is not
    /// positive definite, steps taken only where they lower the energy (with an energy added,
    /// a barrier, as the hand's flexion increments are solved).
    pub fn descent(max_iterations: usize, ordering: FillOrdering) -> Self {
        NewtonSettings {
            max_iterations,
            ordering,
            relative_to_peak: true,
            regularise: true,
            energy_descent: true,
            ..NewtonSettings::default()
        }
    }
}

/// One converged load increment.
#[derive(Clone, Debug, Serialize)]
pub struct StepRecord {
    /// Load factor reached, in (0, 1].
    pub load_factor: f64,
    /// Size of the increment.
    pub step: f64,
    /// Newton iterations (tangent factorizations).
    pub iterations: usize,
    /// Relative residual ‖R_u‖ / max(‖f_ext‖, ‖f_int‖) before each iteration and at convergence.
    pub residuals: Vec<f64>,
    /// Step length α accepted by the line search at each iteration (above 1 where lengthened,
    /// [`NewtonSettings::expand_steps`]; 0 an escape from a saddle).
    pub step_lengths: Vec<f64>,
    /// Factorizations retried with a diagonal shift because the tangent was not positive
    /// definite ([`NewtonSettings::regularise`]); each is one more factorization.
    pub regularised: usize,
    /// Steps taken along a direction of negative curvature, away from an unstable equilibrium
    /// (with [`NewtonSettings::regularise`]; their step length is recorded as 0).
    pub escapes: usize,
    /// Where the time went (not serialised).
    #[serde(skip)]
    pub cost: NewtonCost,
}

/// Time spent by the Newton iterations of an increment, ms.
#[derive(Clone, Copy, Debug, Default)]
pub struct NewtonCost {
    /// Internal forces and energy (residuals and line-search trials).
    pub forces_ms: f64,
    /// Tangent assembly.
    pub tangent_ms: f64,
    /// Symbolic analysis of the tangent's K11 (once while the prescribed set is unchanged).
    pub symbolic_ms: f64,
    /// Numeric Cholesky factorizations.
    pub factorization_ms: f64,
    /// Substitutions.
    pub solve_ms: f64,
}

/// The equilibrium reached.
#[derive(Clone, Debug)]
pub struct NonlinearSolution {
    /// Displacement of every dof, m.
    pub displacement: Vec<f64>,
    /// At prescribed dofs, the force the support exerts on the body (f_int − f_ext), N; zero at
    /// free dofs.
    pub reaction: Vec<f64>,
    /// Stored energy, J.
    pub energy: f64,
    /// The converged increments, in order.
    pub steps: Vec<StepRecord>,
    /// Increments that failed and were retried with half the size.
    pub rejected_steps: usize,
}

impl NonlinearSolution {
    /// Displacement of node `n`.
    pub fn node_displacement(&self, n: usize) -> Vector3<f64> {
        Vector3::new(
            self.displacement[3 * n],
            self.displacement[3 * n + 1],
            self.displacement[3 * n + 2],
        )
    }

    /// Newton iterations over all increments.
    pub fn iterations(&self) -> usize {
        self.steps.iter().map(|s| s.iterations).sum()
    }
}

/// Why one load increment failed.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum StepFailure {
    /// Every step length tried inverted an element.
    #[error("element {cell} turns inside out (det F = {det_f:.3e} at a Gauss point)")]
    Inverted {
        /// The cell.
        cell: usize,
        /// det F at the failing Gauss point.
        det_f: f64,
    },
    /// Newton ran out of iterations.
    #[error(
        "Newton did not converge in {iterations} iterations (relative residual {residual:.3e})"
    )]
    NotConverged {
        /// Iterations done.
        iterations: usize,
        /// Relative residual reached.
        residual: f64,
    },
    /// No step length reduced the energy or the residual.
    #[error(
        "the line search found no step length reducing the energy or the residual (relative \
         residual {residual:.3e})"
    )]
    LineSearch {
        /// Relative residual reached.
        residual: f64,
    },
    /// The tangent is not positive definite: a limit point or bifurcation (buckling,
    /// snap-through), or elements close to collapse.
    #[error(
        "the tangent stiffness is not positive definite (pivot at node {node}): an instability \
         such as buckling, or elements close to collapse"
    )]
    NotPositiveDefinite {
        /// A node at the failing pivot.
        node: usize,
    },
    /// The tangent could not be factorized for another reason.
    #[error("the tangent stiffness could not be factorized: {0}")]
    Tangent(String),
    /// The prescribed dofs were not in place after [`NewtonSettings::placing_iterations`]:
    /// each step toward them was cut short by the added energy.
    #[error(
        "the prescribed displacements could not be reached in {iterations} iterations: each \
         step toward them was cut short where the added energy forbids going further"
    )]
    NotPlaced {
        /// Iterations done.
        iterations: usize,
    },
}

/// Why the nonlinear solve failed.
#[derive(Debug, Error)]
pub enum NonlinearError {
    /// A cell is inverted before any load.
    #[error(
        "element {cell} is inverted or flat in the reference configuration (smallest det J / \
         size³ = {relative_det:.3e})"
    )]
    InvertedReference {
        /// The cell.
        cell: usize,
        /// Its smallest relative det J.
        relative_det: f64,
    },
    /// An input was NaN or infinite.
    #[error("{0} holds a value that is not a finite number")]
    NonFinite(&'static str),
    /// A load increment failed even at the smallest increment allowed.
    #[error(
        "the load increment from {from:.4} to {to:.4} of the full load failed at the smallest \
         increment allowed ({step:.3e}, the initial one halved {cuts} times): {reason}{}",
        inversion_note(.inverted)
    )]
    StepFailed {
        /// Load factor of the last equilibrium.
        from: f64,
        /// Load factor the increment aimed at.
        to: f64,
        /// Its size.
        step: f64,
        /// How many times the initial increment was halved to get `step`.
        cuts: usize,
        /// Why its last attempt failed.
        reason: StepFailure,
        /// The last element that a trial state of this increment turned inside out (the line
        /// search then shortened the step), if any: where the load is too much for the mesh.
        inverted: Option<usize>,
    },
}

fn inversion_note(inverted: &Option<usize>) -> String {
    inverted.map_or(String::new(), |c| {
        format!("; element {c} turned inside out in trial steps of this increment")
    })
}

/// Solves the static equilibrium of the Neo-Hookean body `mesh` (reference configuration at its
/// nodes) with `materials[c]` per cell: the dofs marked in `partition` move to `prescribed`
/// (read at prescribed dofs), the others carry the dead loads `loads` (N, 3 per node).
pub fn solve_nonlinear(
    mesh: &Mesh,
    materials: &[Material],
    partition: &DofPartition,
    prescribed: &[f64],
    loads: &[f64],
    settings: &NewtonSettings,
) -> Result<NonlinearSolution, NonlinearError> {
    let body = HyperelasticBody::new(mesh, materials, settings.volumetric).map_err(|e| {
        NonlinearError::InvertedReference {
            cell: e.cell,
            relative_det: e.relative_det,
        }
    })?;
    solve_body(&body, partition, prescribed, loads, settings)
}

/// As [`solve_nonlinear`] on an already built body.
pub fn solve_body(
    body: &HyperelasticBody,
    partition: &DofPartition,
    prescribed: &[f64],
    loads: &[f64],
    settings: &NewtonSettings,
) -> Result<NonlinearSolution, NonlinearError> {
    let dofs = body.pattern().dofs;
    assert_eq!(partition.prescribed.len(), dofs);
    assert_eq!(prescribed.len(), dofs);
    assert_eq!(loads.len(), dofs);
    if loads.iter().any(|v| !v.is_finite()) {
        return Err(NonlinearError::NonFinite("the load vector"));
    }
    if (0..dofs).any(|d| partition.prescribed[d] && !prescribed[d].is_finite()) {
        return Err(NonlinearError::NonFinite("the prescribed displacements"));
    }
    let mut solver = PartitionedSolver::new(settings.ordering);
    let mut u = vec![0.0; dofs];
    let mut steps = Vec::new();
    let mut rejected = 0;
    let full = 1.0 / settings.increments.max(1) as f64;
    let (mut t, mut dt, mut easy) = (0.0, full, 0);
    let mut seen = None;
    let smallest = full * 0.5f64.powi(settings.max_cuts.min(60) as i32);
    while t < 1.0 - 1e-12 {
        let step = dt.min(1.0 - t);
        let target = (t + step).min(1.0);
        let mut record = StepRecord::at(target);
        let attempt = Increment {
            body,
            partition,
            prescribed,
            loads,
            factor: target,
            settings,
            added: None,
        }
        .solve(&mut solver, &u, &mut seen, &mut record);
        match attempt {
            Ok(u_new) => {
                u = u_new;
                t = target;
                record.step = step;
                easy = if record.iterations <= 6 { easy + 1 } else { 0 };
                if easy >= 2 {
                    dt = (2.0 * step).min(full);
                    easy = 0;
                }
                seen = None;
                steps.push(record);
            }
            Err(reason) => {
                // The smallest increment allowed is fixed (not relative to the last success), so
                // a load beyond what the body can carry cannot creep towards its limit forever.
                if step <= smallest * (1.0 + 1e-9) {
                    return Err(NonlinearError::StepFailed {
                        from: t,
                        to: target,
                        step,
                        cuts: (full / step).log2().round() as usize,
                        reason,
                        inverted: seen.map(|e: InvertedElement| e.cell),
                    });
                }
                rejected += 1;
                easy = 0;
                dt = step * 0.5;
            }
        }
    }
    let (energy, fint) = body
        .internal_forces(&u)
        .map_err(|e| NonlinearError::StepFailed {
            from: t,
            to: t,
            step: 0.0,
            cuts: 0,
            reason: inverted(e),
            inverted: Some(e.cell),
        })?;
    let reaction = (0..dofs)
        .map(|d| {
            if partition.prescribed[d] {
                fint[d] - loads[d]
            } else {
                0.0
            }
        })
        .collect();
    if u.iter().any(|v| !v.is_finite()) {
        return Err(NonlinearError::NonFinite("the computed displacement"));
    }
    Ok(NonlinearSolution {
        displacement: u,
        reaction,
        energy,
        steps,
        rejected_steps: rejected,
    })
}

/// What [`solve_increment`] reached.
#[derive(Debug)]
pub struct IncrementOutcome {
    /// The displacement at equilibrium, or why Newton failed.
    pub result: Result<Vec<f64>, StepFailure>,
    /// Iterations, residuals, step lengths and cost (of the failed attempt too).
    pub record: StepRecord,
    /// The last element a trial state turned inside out (the line search then shortened the
    /// step), if any.
    pub inverted_in_trials: Option<InvertedElement>,
}

/// One Newton increment on `body` from the displacement `start` (any admissible state, e.g. a
/// previous equilibrium or a predictor) to equilibrium with the prescribed dofs of `partition`
/// at `target` (read at prescribed dofs) and the dead loads `loads`: the building block of
/// [`solve_body`], for callers that step their own boundary conditions (the hand's flexion
/// moves its bones increment by increment). The first iteration moves the prescribed dofs that
/// `start` does not already place; `solver` keeps its symbolic analysis between calls.
pub fn solve_increment(
    body: &HyperelasticBody,
    partition: &DofPartition,
    start: &[f64],
    target: &[f64],
    loads: &[f64],
    settings: &NewtonSettings,
    solver: &mut PartitionedSolver,
) -> IncrementOutcome {
    solve_increment_with(
        body,
        (partition, start, target, loads),
        None,
        settings,
        solver,
    )
}

/// [`solve_increment`] with an energy added to the body's (`added`: a barrier keeping its
/// surfaces apart): Newton lowers their sum, its tangent holds the added energy's Hessian, and
/// every step is cut short where the surfaces would pass through each other.
pub fn solve_increment_with(
    body: &dyn ElasticEnergy,
    (partition, start, target, loads): (&DofPartition, &[f64], &[f64], &[f64]),
    added: Option<&dyn AddedEnergy>,
    settings: &NewtonSettings,
    solver: &mut PartitionedSolver,
) -> IncrementOutcome {
    let dofs = 3 * body.mesh().node_count();
    assert_eq!(partition.prescribed.len(), dofs);
    assert_eq!(start.len(), dofs);
    assert_eq!(target.len(), dofs);
    assert_eq!(loads.len(), dofs);
    let mut record = StepRecord::at(1.0);
    let mut seen = None;
    let result = if !start
        .iter()
        .chain(target)
        .chain(loads)
        .all(|v| v.is_finite())
    {
        Err(StepFailure::Tangent(
            "the start, the prescribed displacements or the loads hold a value that is not a \
             finite number"
                .into(),
        ))
    } else {
        Increment {
            body,
            partition,
            prescribed: target,
            loads,
            factor: 1.0,
            settings,
            added,
        }
        .solve(solver, start, &mut seen, &mut record)
    };
    IncrementOutcome {
        result,
        record,
        inverted_in_trials: seen,
    }
}

impl StepRecord {
    fn at(load_factor: f64) -> Self {
        StepRecord {
            load_factor,
            step: 0.0,
            iterations: 0,
            residuals: Vec::new(),
            step_lengths: Vec::new(),
            regularised: 0,
            escapes: 0,
            cost: NewtonCost::default(),
        }
    }
}

/// One load increment: Newton iterations at load factor `factor` from a previous equilibrium.
struct Increment<'a> {
    body: &'a dyn ElasticEnergy,
    partition: &'a DofPartition,
    prescribed: &'a [f64],
    loads: &'a [f64],
    factor: f64,
    settings: &'a NewtonSettings,
    /// An energy added to the body's, if any.
    added: Option<&'a dyn AddedEnergy>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn inverted(e: InvertedElement) -> StepFailure {
    StepFailure::Inverted {
        cell: e.cell,
        det_f: e.det_f,
    }
}

impl Increment<'_> {
    /// ‖R_u‖ over the free dofs and the relative residual (against `peak` too, the largest
    /// ‖f_int‖ met when [`NewtonSettings::relative_to_peak`]; 0 otherwise).
    fn residual(&self, ext: &[f64], fint: &[f64], peak: f64) -> (f64, f64) {
        let free: f64 = self
            .partition
            .free
            .iter()
            .map(|&d| (ext[d] - fint[d]).powi(2))
            .sum::<f64>()
            .sqrt();
        let scale = dot(ext, ext).sqrt().max(dot(fint, fint).sqrt()).max(peak);
        let relative = if free == 0.0 { 0.0 } else { free / scale };
        (free, relative)
    }

    fn solve(
        &self,
        solver: &mut PartitionedSolver,
        start: &[f64],
        seen: &mut Option<InvertedElement>,
        record: &mut StepRecord,
    ) -> Result<Vec<f64>, StepFailure> {
        let s = self.settings;
        let p = self.partition;
        let dofs = start.len();
        let target: Vec<f64> = (0..dofs)
            .map(|d| {
                if p.prescribed[d] {
                    self.factor * self.prescribed[d]
                } else {
                    0.0
                }
            })
            .collect();
        let ext: Vec<f64> = self.loads.iter().map(|f| f * self.factor).collect();
        let mut u = start.to_vec();
        let forces = |record: &mut StepRecord, u: &[f64]| {
            let t = Instant::now();
            let out = self.state(u);
            record.cost.forces_ms += ms(t);
            out
        };
        let (mut energy, mut fint) = forces(record, &u).map_err(inverted)?;
        if !energy.is_finite() {
            return Err(StepFailure::Tangent(
                "the surfaces kept apart touch or cross where the increment starts".into(),
            ));
        }
        let mut peak = 0.0f64;
        let mut last_shift = 0.0f64;
        for iteration in 0..=s.max_iterations {
            if s.relative_to_peak {
                peak = peak.max(dot(&fint, &fint).sqrt());
            }
            let (norm, relative) = self.residual(&ext, &fint, peak);
            record.residuals.push(relative);
            let placed =
                p.free.len() == dofs || (0..dofs).all(|d| !p.prescribed[d] || u[d] == target[d]);
            if placed && relative <= s.tolerance {
                record.iterations = iteration;
                return Ok(u);
            }
            record.iterations = iteration;
            if !placed && iteration >= s.placing_iterations {
                return Err(StepFailure::NotPlaced {
                    iterations: iteration,
                });
            }
            if iteration == s.max_iterations || !relative.is_finite() {
                return Err(StepFailure::NotConverged {
                    iterations: iteration,
                    residual: relative,
                });
            }
            let t = Instant::now();
            let body_tangent = self.body.tangent(&u).map_err(inverted)?;
            // (The body's own tangent kept only where an energy is added: its projected retry.)
            let (exact, body_tangent) = match self.added {
                Some(added) => {
                    let blocks = added.hessian(&u, false);
                    let k = with_blocks(&body_tangent, &blocks);
                    (k, (!blocks.is_empty()).then_some(body_tangent))
                }
                None => (body_tangent, None),
            };
            let mut modified: Option<Stiffness> = None;
            // With an added energy that acts here, its Hessian projected positive
            // semi-definite is tried before the body's tangent is changed.
            let mut projected = body_tangent.is_none();
            let mut without_pressure = false;
            // The added energy's projected blocks, found once for both retries that take them.
            let mut projected_blocks: Option<Vec<NodeBlock>> = None;
            let mut projected_at = |added: &dyn AddedEnergy| -> Vec<NodeBlock> {
                projected_blocks
                    .get_or_insert_with(|| added.hessian(&u, true))
                    .clone()
            };
            record.cost.tangent_ms += ms(t);
            let r: Vec<f64> = ext.iter().zip(&fint).map(|(e, f)| e - f).collect();
            let delta: Vec<f64> = (0..dofs).map(|d| target[d] - u[d]).collect();
            // The factorization counts as an iteration even when it fails.
            record.iterations = iteration + 1;
            let nodes = &self.body.mesh().nodes;
            let mut shift = 0.0;
            let mut definite = false;
            // The first shift tried: a tenth of the last iterate's, τ changing slowly.
            let first_shift = (last_shift * 0.1).max(1e-4);
            let solution = loop {
                let k = modified.as_ref().unwrap_or(&exact);
                let attempt = if shift == 0.0 {
                    solver.solve(k, p, &delta, &r, nodes)
                } else {
                    let mut shifted = k.clone();
                    for &d in &p.free {
                        let v = shifted.diagonal(d).abs();
                        shifted.add_to_diagonal(d, shift * v);
                    }
                    solver.solve(&shifted, p, &delta, &r, nodes)
                };
                match attempt {
                    Ok(solution) => break solution,
                    Err(SolveError::NotPositiveDefinite { .. }) if s.regularise && !projected => {
                        let t = Instant::now();
                        if let (Some(added), Some(k)) = (self.added, &body_tangent) {
                            modified = Some(with_blocks(k, &projected_at(added)));
                        }
                        projected = true;
                        record.cost.tangent_ms += ms(t);
                        record.regularised += 1;
                    }
                    Err(SolveError::NotPositiveDefinite { .. })
                        if s.regularise && !without_pressure =>
                    {
                        without_pressure = true;
                        let t = Instant::now();
                        let k = self
                            .body
                            .tangent_without_pressure_hessian(&u)
                            .map_err(inverted)?;
                        modified = Some(match self.added {
                            Some(added) => with_blocks(&k, &projected_at(added)),
                            None => k,
                        });
                        record.cost.tangent_ms += ms(t);
                        record.regularised += 1;
                    }
                    Err(SolveError::NotPositiveDefinite { .. })
                        if s.regularise && !definite && shift == 0.0 =>
                    {
                        // Each element's tangent made definite: where the body's own tangent
                        // is indefinite (the flesh buckling into a fold), a far better model
                        // of it than the shifts below (the two creases folded at resolution
                        // 1.5: 6 455 → 1 077 factorizations, docs/performance.md).
                        // (A body without one goes on to the shifts.)
                        definite = true;
                        record.regularised += 1;
                        let t = Instant::now();
                        match self.body.tangent_definite(&u) {
                            Some(k) => {
                                let k = k.map_err(inverted)?;
                                modified = Some(match self.added {
                                    Some(added) => with_blocks(&k, &projected_at(added)),
                                    None => k,
                                });
                            }
                            None => shift = first_shift,
                        }
                        record.cost.tangent_ms += ms(t);
                    }
                    Err(SolveError::NotPositiveDefinite { .. }) if s.regularise && shift < 10.0 => {
                        shift = if shift == 0.0 {
                            first_shift
                        } else {
                            shift * 10.0
                        };
                        record.regularised += 1;
                    }
                    Err(SolveError::NotPositiveDefinite { node, .. }) => {
                        return Err(StepFailure::NotPositiveDefinite { node })
                    }
                    Err(other) => return Err(StepFailure::Tangent(other.to_string())),
                }
            };
            record.cost.symbolic_ms += solution.stats.symbolic_ms;
            record.cost.factorization_ms += solution.stats.factorization_ms;
            record.cost.solve_ms += solution.stats.solve_ms;
            let du = solution.displacement;
            last_shift = shift;
            // Nearly at equilibrium, but the exact tangent is indefinite: an unstable
            // equilibrium (a saddle of the energy). Newton steps would only creep around it;
            // leave it along the direction of negative curvature.
            let unstable = modified.is_some() || shift > 0.0;
            if s.escape_saddles && unstable && placed && relative < SADDLE_RESIDUAL {
                // (With an added energy the escape is cut short where surfaces would cross.)
                if let Some((trial, e_trial, f_trial)) = self.escape(
                    solver,
                    &exact,
                    &u,
                    &r,
                    potential_of(energy, &ext, &u),
                    record,
                ) {
                    record.escapes += 1;
                    record.step_lengths.push(0.0);
                    u = trial;
                    energy = e_trial;
                    fint = f_trial;
                    continue;
                }
            }
            // Line search along du.
            let slope = -dot(&r, &du);
            let potential = energy - dot(&ext, &u);
            let mut alpha = self.added.map_or(1.0, |a| a.largest_step(&u, &du)).min(1.0);
            let mut accepted = None;
            let mut last_inverted = None;
            for _ in 0..=s.line_search_halvings {
                let trial: Vec<f64> = (0..dofs)
                    .map(|d| {
                        if alpha == 1.0 && p.prescribed[d] {
                            target[d]
                        } else {
                            u[d] + alpha * du[d]
                        }
                    })
                    .collect();
                match forces(record, &trial) {
                    Err(e) => {
                        last_inverted = Some(e);
                        *seen = Some(e);
                    }
                    Ok((e_trial, f_trial)) => {
                        let good = if !placed {
                            true
                        } else {
                            let decrease = e_trial - dot(&ext, &trial)
                                <= potential + 1e-4 * alpha * slope.min(0.0);
                            let (n_trial, _) = self.residual(&ext, &f_trial, peak);
                            let fewer = n_trial <= (1.0 - 1e-4 * alpha) * norm;
                            if s.energy_descent && slope < 0.0 {
                                // The residual only decides where the energy change is lost
                                // in round-off.
                                let change = e_trial - dot(&ext, &trial) - potential;
                                let noise = 1e-12 * (energy.abs() + dot(&ext, &u).abs());
                                decrease || (change.abs() <= noise && fewer)
                            } else {
                                (slope < 0.0 && decrease) || fewer
                            }
                        };
                        if good && e_trial.is_finite() {
                            accepted = Some((trial, e_trial, f_trial));
                            break;
                        }
                    }
                }
                alpha *= 0.5;
            }
            let Some((mut trial, mut e_trial, mut f_trial)) = accepted else {
                return Err(match last_inverted {
                    Some(e) => inverted(e),
                    None => StepFailure::LineSearch { residual: relative },
                });
            };
            if s.expand_steps && placed && alpha == 1.0 {
                // The full step lowered the potential: where the energy curves less than the
                // (modified) tangent says — down a direction of negative curvature, the tangent
                // made positive definite — longer steps along du lower it further.
                // (Each longer step must lower it by more than round-off: near convergence the
                // change is below it, and a longer step there would only overshoot.)
                let noise = 1e-12 * (energy.abs() + dot(&ext, &u).abs());
                let mut best = potential_of(e_trial, &ext, &trial);
                let longest = self.added.map_or(MAX_EXPANSION, |a| {
                    let far: Vec<f64> = du.iter().map(|d| MAX_EXPANSION * d).collect();
                    MAX_EXPANSION * a.largest_step(&u, &far)
                });
                let mut longer = 2.0;
                while longer <= longest {
                    let t: Vec<f64> = u.iter().zip(&du).map(|(x, d)| x + longer * d).collect();
                    match forces(record, &t) {
                        Ok((e, f)) if e.is_finite() && potential_of(e, &ext, &t) < best - noise => {
                            best = potential_of(e, &ext, &t);
                            (trial, e_trial, f_trial, alpha) = (t, e, f, longer);
                            longer *= 2.0;
                        }
                        _ => break,
                    }
                }
            }
            record.step_lengths.push(alpha);
            u = trial;
            energy = e_trial;
            fint = f_trial;
        }
        unreachable!("the loop returns at its last iteration")
    }
}

impl Increment<'_> {
    /// The energy and the internal forces at `u`, the added energy's included (an infinite
    /// energy where it is not admissible: no step goes there).
    fn state(&self, u: &[f64]) -> Result<(f64, Vec<f64>), InvertedElement> {
        let (mut energy, mut fint) = self.body.internal_forces(u)?;
        if let Some(added) = self.added {
            match added.energy(u, &mut fint) {
                Some(e) => energy += e,
                None => energy = f64::INFINITY,
            }
        }
        Ok((energy, fint))
    }
}

/// Relative residual below which an indefinite exact tangent means an unstable equilibrium
/// nearby, to be left along the negative curvature ([`Increment::escape`]).
const SADDLE_RESIDUAL: f64 = 1e-3;

/// The longest step [`NewtonSettings::expand_steps`] tries, as a multiple of the Newton step.
const MAX_EXPANSION: f64 = 64.0;

/// The total potential Π = W − f_extᵀu.
fn potential_of(energy: f64, ext: &[f64], u: &[f64]) -> f64 {
    energy - dot(ext, u)
}

impl Increment<'_> {
    /// A step from `u` along the direction v of most negative curvature of `k` (the exact
    /// tangent), if it has one: signed so
    /// that the potential does not rise to first order (rᵀv ≥ 0, r = f_ext − f_int), of length
    /// the first of ⅒, 1/20, … of the mean element size (as a largest nodal move) that lowers
    /// the potential by at least 10⁻⁴ of the quadratic model's decrease and inverts no element.
    fn escape(
        &self,
        solver: &mut PartitionedSolver,
        k: &Stiffness,
        u: &[f64],
        r: &[f64],
        potential: f64,
        record: &mut StepRecord,
    ) -> Option<(Vec<f64>, f64, Vec<f64>)> {
        // The preconditioner: K + τ·diag(K) with the smallest τ = 10⁻⁴, 10⁻³, … that makes it
        // positive definite, so that its inverse amplifies the modes of K's lowest eigenvalues.
        let p = self.partition;
        let zeros = vec![0.0; u.len()];
        let mut tau = 1e-4;
        loop {
            let mut shifted = k.clone();
            for &d in &p.free {
                let v = shifted.diagonal(d).abs();
                shifted.add_to_diagonal(d, tau * v);
            }
            record.regularised += 1;
            match solver.solve(&shifted, p, &zeros, &zeros, &self.body.mesh().nodes) {
                Ok(solution) => {
                    record.cost.symbolic_ms += solution.stats.symbolic_ms;
                    record.cost.factorization_ms += solution.stats.factorization_ms;
                    break;
                }
                Err(SolveError::NotPositiveDefinite { .. }) if tau < 10.0 => tau *= 10.0,
                Err(_) => return None,
            }
        }
        let t = Instant::now();
        let mode = lowest_mode(solver, k, p, 10);
        record.cost.solve_ms += ms(t);
        let (mut v, curvature) = mode?;
        if curvature >= 0.0 {
            return None;
        }
        if dot(r, &v) < 0.0 {
            v.iter_mut().for_each(|x| *x = -*x);
        }
        let largest = (0..v.len() / 3)
            .map(|n| (v[3 * n].powi(2) + v[3 * n + 1].powi(2) + v[3 * n + 2].powi(2)).sqrt())
            .fold(0.0, f64::max);
        let ext: Vec<f64> = self.loads.iter().map(|f| f * self.factor).collect();
        let mut alpha = 0.1 * self.body.element_size() / largest;
        if let Some(added) = self.added {
            let step: Vec<f64> = v.iter().map(|x| alpha * x).collect();
            alpha *= added.largest_step(u, &step);
        }
        for _ in 0..=self.settings.line_search_halvings {
            let trial: Vec<f64> = u.iter().zip(&v).map(|(a, b)| a + alpha * b).collect();
            let t = Instant::now();
            let state = self.state(&trial);
            record.cost.forces_ms += ms(t);
            if let Ok((e, f)) = state {
                let model = -alpha * dot(r, &v) + 0.5 * alpha * alpha * curvature;
                if e.is_finite()
                    && potential_of(e, &ext, &trial) <= potential + 1e-4 * model.min(0.0)
                {
                    return Some((trial, e, f));
                }
            }
            alpha *= 0.5;
        }
        None
    }
}
