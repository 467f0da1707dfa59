//! `docs/speed-vs-accuracy.md`: machine and date, how to read the tables, the plot, the tables
//! and their fronts, the references of the hand problems. The section between
//! [`GUIDANCE_BEGIN`] and [`GUIDANCE_END`] is written by people from the numbers and kept
//! when the bench rewrites the file. Written atomically (temporary file, then rename).

use super::table::{problem_table, summary};
use super::{Machine, ProblemId, Results};
use std::fmt::Write;
use std::path::Path;

/// Start of the hand-written guidance kept across runs.
pub const GUIDANCE_BEGIN: &str = "<!-- guidance: written from the numbers, kept by the bench -->";
/// End of the hand-written guidance.
pub const GUIDANCE_END: &str = "<!-- end of guidance -->";

/// What each problem is and what its error means.
fn description(problem: ProblemId) -> &'static str {
    match problem {
        ProblemId::Cantilever => {
            "8 × 1 × 1 m beam, E = 1 MPa, ν = 0.3, clamped at x = 0, 1 N along −z shared by the \
             end nodes; 8k × k × k hexahedra. Error: mean tip deflection against Timoshenko \
             (δ = PL³/3EI + PL/κGA, κ = 5/6). Tip deflection / length = 2.5·10⁻⁴: the \
             small-strain answer is exact to far below the errors shown, for every tier."
        }
        ProblemId::Lame => {
            "Hollow sphere a = 50 mm, b = 100 mm, E = 1 MPa, ν = 0.3, inner pressure 1 kPa \
             (wall strain ≈ 0.1 %), three poles held tangentially; cubed sphere of n × n quads \
             per face and n/2 layers. Error: the largest relative error of the radial \
             displacement over all nodes against Lamé."
        }
        ProblemId::Hertz => {
            "Ball R = 50 mm, E = 100 kPa, ν = 0.3, its top cap (z > 1.9R) pushed 1.5 mm down onto \
             the rigid plane z = 0 (frictionless, exact contact by Lagrange multipliers); the \
             ball graded toward the contact (`refine`): cells of R/n there growing by 1.25 to \
             the base of 12 cells across (R/32 is the default refinement). Error: the contact \
             radius from the second moment of the nodal contact forces against Hertz's a = (3FR/4E*)^(1/3) at the force F found; the peak \
             of the tactile map against p0 = 3F/(2πa²) is shown beside it."
        }
        ProblemId::Flexion30 | ProblemId::Flexion90 => {
            "Right hand, flesh E = 50 kPa, ν = 0.45; the index PIP flexed from rest in one \
             keyframe, local FEM region (the default). Error: the distance between each free \
             flesh node of the run (bone nodes move exactly with their bones in every tier) and \
             the reference's flesh at the same material point: the node is located in the \
             reference's rest mesh (within a quarter of its lattice spacing outside it, at the \
             nearest point; cells of the node's own digit or palm only, since fingers touching \
             at rest are meshed apart along a seam that moves with the resolution) and the \
             reference's displacement interpolated there; `free nodes compared` says how many \
             were so located. The largest distance is set by a few nodes over the joint, where \
             the flesh's displacement changes by centimetres across one cell and meshes of other \
             resolutions put that change elsewhere; the RMS distance weighs the whole flesh and \
             is the one plotted. `largest distance from the same mesh's reference` compares \
             node by node with the reference tier and step on the row's own mesh: the tier's \
             and the step's error alone. Then the flesh volume change, and its difference from \
             the reference's."
        }
        ProblemId::Grasp => {
            "`assets/scenes/hand-grasp-ball.toml` (the paper's Figure 4): fingers and thumb \
             close on a pressurised rubber shell; hand resolution r, shell of 12r cells per face \
             edge (even) and 2r layers (at least 2); contact by Lagrange multipliers. Error: the \
             grip Σ|F| over palm and digits against the reference's (plotted), the largest \
             error of one part's force vector relative to the reference's grip, and the grip \
             against the reference tier and step on the row's own mesh (the tier's and the \
             step's error alone). Time per keyframe: the solve of the two frames (rest → initial \
             pose, then the grasp keyframe with contact) divided by two. With the `nonlinear` \
             tier the hand flexes by Newton increments and the ball is Neo-Hookean in the \
             contact steps (one Newton iteration each, iterated at the pose), the flesh near the \
             contact linearised about its posed state; the air follows the wall, its load \
             stiffness in the corrections' tangent (since 2026-11-29)."
        }
    }
}

/// The guidance section of an existing document, markers included; a placeholder when none.
fn kept_guidance(existing: Option<&str>) -> String {
    if let Some(text) = existing {
        if let (Some(a), Some(b)) = (text.find(GUIDANCE_BEGIN), text.find(GUIDANCE_END)) {
            if a < b {
                return text[a..b + GUIDANCE_END.len()].to_string();
            }
        }
    }
    format!(
        "{GUIDANCE_BEGIN}\n## Choosing a tier\n\n(To be written from the measured numbers; this \
         section is kept when the bench rewrites the file.)\n{GUIDANCE_END}"
    )
}

/// The document's text. `plot_link` is the plot's path relative to the document; `command`
/// the command line that made it; `existing` the current document (for its guidance).
pub fn doc_text(
    results: &Results,
    machine: &Machine,
    plot_link: &str,
    command: &str,
    existing: Option<&str>,
) -> String {
    let mut s = String::from("# Speed against accuracy\n\n");
    let _ = writeln!(
        s,
        "Written by `{command}` on {}. Release build; the whole bench took {:.0} s. Single \
         runs on a shared machine: times move by tens of per cent between runs (compare \
         within a table, and ratios more than absolute values); errors are deterministic.\n",
        machine.summary(),
        results.total_s
    );
    s.push_str(
        "## How to read it\n\n\
         - One table per problem. A row is one solver variant at one mesh resolution: the \
         `[solver] tier` (with `element` for the static problems, and `max_step_deg` — the \
         largest joint rotation per increment — for `incremental` and `corotational`), the \
         resolution, the elements of the model, the time, then the errors.\n\
         - Time: the solve of the scene's frames, meshing excluded: per solve for the static \
         problems (a)–(c), per keyframe for the hand (d)–(e). It includes assembly, \
         factorization, contact iterations and stresses.\n\
         - Errors: (a)–(c) against closed-form solutions; (d)–(e) against a reference computed \
         by the most exact hand tier the solver accepts, at a finer resolution and a smaller \
         step than any row (below), and, in a column of their own, against the same reference \
         tier and step on the row's own mesh. The first error column is the one plotted, except \
         for (d), where it is the RMS distance (see there).\n\
         - `front` (●): no other run on the problem is both faster and more accurate. To choose, \
         find your error budget on the problem closest to your scene and take the fastest ● run \
         within it.\n\
         - `n/a`: the tier does not apply to the problem, with the reason; for a tier the \
         solver refuses (none today) the reason is the solver's own message. `failed`: the tier applies, but the solve stopped (the solver's message).\n\n",
    );
    let _ = writeln!(
        s,
        "![log time against log error, one panel per problem, one curve per tier]({plot_link})\n"
    );
    s.push_str(
        "In the plot each curve is one variant through its three resolutions (time grows with the \
         resolution); colour is the tier, the marker the option (circle: hex8 or a 10° step; \
         triangle: incompatible modes or a 20° step; square: a 5° step). Down and to the left \
         is better.\n\n",
    );
    s.push_str(&kept_guidance(existing));
    s.push_str("\n\n");
    let problems: Vec<ProblemId> = ProblemId::ALL
        .into_iter()
        .filter(|p| results.rows.iter().any(|r| r.problem == *p))
        .collect();
    for p in problems {
        s.push_str(&problem_section(results, p));
    }
    let _ = writeln!(
        s,
        "Reproduce: `cargo run --release -- bench accuracy` (`--quick` for a smaller run, \
         `--only cantilever,lame` for some problems; `--steps 20,10,5` for other increments)."
    );
    s
}

/// One problem's section: title, description, reference (hand problems), table and front.
pub fn problem_section(results: &Results, p: ProblemId) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## {}\n\n{}\n", p.title(), description(p));
    if let Some(r) = results.references.iter().find(|r| r.problem == p) {
        let _ = writeln!(
            s,
            "Reference: tier `{}` at resolution {} with increments of at most {}° ({:.1} s); \
             it gives {}.{}\n",
            r.variant.tier_name(),
            r.resolution,
            r.step_deg,
            r.solve_ms / 1e3,
            r.facts,
            r.skipped
                .iter()
                .map(|(v, why)| format!(
                    " Tier `{}` was tried first and not used: {}.",
                    v.tier_name(),
                    why
                ))
                .collect::<String>()
        );
    }
    s.push_str(&problem_table(results, p));
    s.push('\n');
    s.push_str(&summary(results, p));
    s.push('\n');
    s
}

/// `existing` (the document) with the sections of the problems in `results` replaced by this
/// run's (`--only`): the other problems' sections, the guidance and the plot stay as they were,
/// and each replaced section says which run it is from.
pub fn merged_text(existing: &str, results: &Results, machine: &Machine, command: &str) -> String {
    let mut text = existing.to_string();
    for p in ProblemId::ALL
        .into_iter()
        .filter(|p| results.rows.iter().any(|r| r.problem == *p))
    {
        let section = problem_section(results, p);
        let section = section.replacen(
            "\n\n",
            &format!(
                "\n\nRows of `{command}` on {} (the other sections, and the plot, are from earlier \
                 runs).\n\n",
                machine.summary()
            ),
            1,
        );
        let title = format!("## {}\n", p.title());
        let reproduce = text.find("Reproduce: ").unwrap_or(text.len());
        match text.find(&title) {
            Some(a) => {
                let after = a + title.len();
                let b = text[after..]
                    .find("\n## ")
                    .map(|i| after + i + 1)
                    .unwrap_or(reproduce.max(after));
                text.replace_range(a..b, &section);
            }
            None => text.insert_str(reproduce, &section),
        }
    }
    text
}

/// Writes `text` to `path` through a temporary file and a rename.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    crate::export::png::write_bytes_atomic(path, text.as_bytes())
}

/// Writes the document to `path` (keeping its guidance section) with the plot linked as
/// `plot_link`.
pub fn write_doc(
    path: &Path,
    results: &Results,
    machine: &Machine,
    plot_link: &str,
    command: &str,
) -> Result<(), String> {
    let existing = std::fs::read_to_string(path).ok();
    let text = doc_text(results, machine, plot_link, command, existing.as_deref());
    write_atomic(path, &text).map_err(|e| format!("{}: {e}", path.display()))
}
