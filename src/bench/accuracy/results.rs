//! Running the bench: every variant of every problem at each resolution, timed and measured.

use super::reference::{hand_reference, HandReference, ReferenceInfo};
use super::run::{run_scene, RunError};
use super::variant::{self, Variant};
use super::ProblemId;
use crate::util::timing::ms;

/// What one variant gave at one resolution.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Solved and measured: solve time (ms, all frames, meshing excluded), the time per
    /// keyframe or solve (ms), and the problem's measures.
    Measured {
        /// Time of the solve of every frame, ms.
        solve_ms: f64,
        /// Per keyframe (hand problems) or per solve, ms.
        per_frame_ms: f64,
        /// The problem's measures, [`ProblemId::columns`] order.
        values: Vec<f64>,
    },
    /// The tier does not apply to the problem: why.
    NotApplicable(String),
    /// The tier applies but the solve stopped: the solver's message.
    Failed(String),
}

/// One row: a variant of the solver on one problem at one resolution.
#[derive(Clone, Debug)]
pub struct Row {
    /// Problem.
    pub problem: ProblemId,
    /// Tier and options.
    pub variant: Variant,
    /// The resolution parameter.
    pub resolution: f64,
    /// Elements of the model (all bodies), 0 when not built.
    pub elements: usize,
    /// Result.
    pub outcome: Outcome,
}

impl Row {
    /// The plotted error (on its axis scale), when measured.
    pub fn error(&self) -> Option<f64> {
        let i = self.problem.plotted();
        match &self.outcome {
            Outcome::Measured { values, .. } => Some(self.problem.columns()[i].scaled(values[i])),
            _ => None,
        }
    }

    /// Time per keyframe or solve, ms, when measured.
    pub fn ms(&self) -> Option<f64> {
        match &self.outcome {
            Outcome::Measured { per_frame_ms, .. } => Some(*per_frame_ms),
            _ => None,
        }
    }
}

/// What the bench measured.
#[derive(Clone, Debug, Default)]
pub struct Results {
    /// Every row.
    pub rows: Vec<Row>,
    /// The references of the hand problems.
    pub references: Vec<ReferenceInfo>,
    /// Whether the quick set of resolutions was used.
    pub quick: bool,
    /// Wall time of the whole bench, s.
    pub total_s: f64,
}

/// What to run.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The smaller set of resolutions.
    pub quick: bool,
    /// Problems to run.
    pub problems: Vec<ProblemId>,
    /// Largest increments of the incremental and corotational tiers, degrees.
    pub steps: Vec<f64>,
}

impl Settings {
    /// Every problem; steps 20° and 10° (quick: 10°).
    pub fn new(quick: bool) -> Settings {
        Settings {
            quick,
            problems: ProblemId::ALL.to_vec(),
            steps: if quick { vec![10.0] } else { vec![20.0, 10.0] },
        }
    }

    /// Checks the settings: a clear message for each bad value.
    pub fn validate(&self) -> Result<(), String> {
        if self.problems.is_empty() {
            return Err("no problem to run".into());
        }
        for &s in &self.steps {
            if !(s > 0.0 && s <= 45.0) {
                return Err(format!(
                    "step {s}°: the largest increment must lie in (0, 45] degrees"
                ));
            }
        }
        if self.steps.is_empty() {
            return Err("no step given for the incremental and corotational tiers".into());
        }
        Ok(())
    }
}

/// Runs the bench; `progress` receives one line per solve.
pub fn accuracy_results(
    settings: &Settings,
    progress: &mut dyn FnMut(&str),
) -> Result<Results, String> {
    settings.validate()?;
    let start = std::time::Instant::now();
    let mut results = Results {
        quick: settings.quick,
        ..Default::default()
    };
    for &problem in &settings.problems {
        let reference = if problem.is_hand() {
            let (r, info) = hand_reference(problem, settings.quick, progress)?;
            results.references.push(info);
            Some(r)
        } else {
            None
        };
        for variant in variant::variants(problem, &settings.steps) {
            results.rows.extend(problem_rows(
                problem,
                &variant,
                settings.quick,
                reference.as_ref(),
                progress,
            ));
        }
    }
    results.total_s = start.elapsed().as_secs_f64();
    Ok(results)
}

/// The rows of one variant on one problem, coarsest resolution first. A variant the solver
/// refuses (not applicable) is tried once, at the coarsest resolution.
pub fn problem_rows(
    problem: ProblemId,
    variant: &Variant,
    quick: bool,
    reference: Option<&HandReference>,
    progress: &mut dyn FnMut(&str),
) -> Vec<Row> {
    let mut rows = Vec::new();
    for r in problem.resolutions(quick) {
        let row = |elements, outcome| Row {
            problem,
            variant: variant.clone(),
            resolution: r,
            elements,
            outcome,
        };
        if let Some(reason) = variant.not_applicable(problem) {
            rows.push(row(0, Outcome::NotApplicable(reason)));
            continue;
        }
        if let Some(Outcome::NotApplicable(reason)) = rows.first().map(|r: &Row| &r.outcome) {
            let reason = reason.clone();
            rows.push(row(0, Outcome::NotApplicable(reason)));
            continue;
        }
        let mut scene = problem.scene(r);
        variant.apply(&mut scene);
        let name = format!("{} r={r} {}", problem.key(), variant.label());
        let (elements, outcome) = match run_scene(&scene, &name) {
            Ok(solved) => {
                let elements = solved.model.mesh.cell_count();
                let t = std::time::Instant::now();
                let measured = problem.measure(&solved, r, reference);
                progress(&format!(
                    "{name}: built in {:.0} ms, solved in {:.0} ms, measured in {:.0} ms",
                    solved.build_ms,
                    solved.solve_ms,
                    ms(t)
                ));
                let outcome = match measured {
                    Ok(values) => Outcome::Measured {
                        solve_ms: solved.solve_ms,
                        per_frame_ms: solved.solve_ms / solved.keyframes as f64,
                        values,
                    },
                    Err(e) => Outcome::Failed(e),
                };
                (elements, outcome)
            }
            Err(RunError::Refused(reason)) => (0, Outcome::NotApplicable(reason)),
            Err(RunError::Failed(reason)) => (0, Outcome::Failed(reason)),
        };
        progress(&match &outcome {
            Outcome::Measured {
                per_frame_ms,
                values,
                ..
            } => format!(
                "{name}: {per_frame_ms:.1} ms, {} = {}",
                problem.columns()[problem.plotted()].name,
                problem.columns()[problem.plotted()].format(values[problem.plotted()])
            ),
            Outcome::NotApplicable(why) => format!("{name}: n/a: {why}"),
            Outcome::Failed(why) => format!("{name}: failed: {why}"),
        });
        rows.push(row(elements, outcome));
    }
    rows
}
