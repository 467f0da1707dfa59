//! The references of the hand problems: the most exact hand tier the solver accepts, with the
//! smallest step, at the reference resolution (the finest) and at each resolution of the rows
//! (the same mesh: its gap to a row is the tier's and the step's error alone).

use super::run::{run_scene, RunError, Solved};
use super::variant::{self, Variant};
use super::{flexion, grasp, ProblemId};

/// The reference of a hand problem.
#[derive(Clone, Debug)]
pub struct ReferenceInfo {
    /// The problem.
    pub problem: ProblemId,
    /// The variant that gave it (the most exact tier the solver accepted).
    pub variant: Variant,
    /// Resolution.
    pub resolution: f64,
    /// Largest increment, degrees.
    pub step_deg: f64,
    /// Solve time, ms.
    pub solve_ms: f64,
    /// Tiers tried before it and why they were not used.
    pub skipped: Vec<(Variant, String)>,
    /// What the reference gives, in words (largest displacement, volume, forces).
    pub facts: String,
}

/// What a hand problem's reference gives, in words.
fn reference_facts(problem: ProblemId, solved: &Solved) -> String {
    match problem {
        ProblemId::Grasp => match grasp::reference_forces(solved) {
            Ok((grip, parts)) => format!(
                "grip Σ|F| = {grip:.3} N ({})",
                parts
                    .iter()
                    .filter(|p| p.1 > 0.0)
                    .map(|(name, f)| format!("{name} {f:.3} N"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Err(e) => e,
        },
        _ => match flexion::hand_result(solved) {
            Ok(h) => format!(
                "largest flesh displacement {:.1} mm, flesh volume change {:+.3} %",
                h.positions
                    .iter()
                    .zip(&h.hand.flesh.mesh.nodes)
                    .map(|(p, q)| (p - q).norm())
                    .fold(0.0, f64::max)
                    * 1e3,
                h.volume_change * 100.0
            ),
            Err(e) => e,
        },
    }
}

/// The reference of a hand problem: the most exact hand tier the solver accepts, at the
/// reference resolution and step.
pub fn find_reference(
    problem: ProblemId,
    quick: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<(Solved, ReferenceInfo), String> {
    let (resolution, step) = problem.reference(quick);
    let mut skipped = Vec::new();
    for variant in variant::reference_candidates(step) {
        if let Some(why) = problem.not_a_reference(&variant) {
            progress(&format!(
                "{} reference {}: not used: {why}",
                problem.key(),
                variant.label()
            ));
            skipped.push((variant, why.to_string()));
            continue;
        }
        let mut scene = problem.scene(resolution);
        variant.apply(&mut scene);
        let name = format!(
            "{} reference r={resolution} {}",
            problem.key(),
            variant.label()
        );
        match run_scene(&scene, &name) {
            Ok(solved) => {
                progress(&format!("{name}: {:.0} ms", solved.solve_ms));
                let info = ReferenceInfo {
                    problem,
                    variant,
                    resolution,
                    step_deg: step,
                    solve_ms: solved.solve_ms,
                    skipped,
                    facts: reference_facts(problem, &solved),
                };
                return Ok((solved, info));
            }
            Err(RunError::Refused(why) | RunError::Failed(why)) => {
                progress(&format!("{name}: not used: {why}"));
                skipped.push((variant, why));
            }
        }
    }
    Err(format!(
        "{}: no tier gave a reference: {}",
        problem.key(),
        skipped
            .iter()
            .map(|(v, why)| format!("{}: {why}", v.label()))
            .collect::<Vec<_>>()
            .join("; ")
    ))
}

/// The references of a hand problem: the finest, and one on each row resolution's mesh (the
/// same tier and step as the finest).
pub struct HandReference {
    /// At the reference resolution.
    pub finest: Solved,
    /// At each row resolution.
    pub same_mesh: Vec<(f64, Solved)>,
}

impl HandReference {
    /// The reference on the mesh of resolution `r`.
    pub fn at(&self, r: f64) -> Option<&Solved> {
        self.same_mesh.iter().find(|(q, _)| *q == r).map(|(_, s)| s)
    }
}

/// Both references of a hand problem (the finest first, then one per row resolution).
pub fn hand_reference(
    problem: ProblemId,
    quick: bool,
    progress: &mut dyn FnMut(&str),
) -> Result<(HandReference, ReferenceInfo), String> {
    let (finest, info) = find_reference(problem, quick, progress)?;
    let mut same_mesh = Vec::new();
    for r in problem.resolutions(quick) {
        let mut scene = problem.scene(r);
        info.variant.apply(&mut scene);
        let name = format!(
            "{} same-mesh reference r={r} {}",
            problem.key(),
            info.variant.label()
        );
        let solved = run_scene(&scene, &name).map_err(|e| match e {
            RunError::Refused(why) | RunError::Failed(why) => format!("{name}: {why}"),
        })?;
        progress(&format!("{name}: {:.0} ms", solved.solve_ms));
        same_mesh.push((r, solved));
    }
    Ok((HandReference { finest, same_mesh }, info))
}
