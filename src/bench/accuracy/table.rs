//! The Markdown tables of the bench, one per problem, and the runs on each problem's front (no
//! other run both faster and more accurate).

use super::{Outcome, ProblemId, Results, Row};
use std::fmt::Write;

/// A message fit for one table cell.
fn cell(text: &str) -> String {
    let one_line: String = text
        .replace('|', "\\|")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    if one_line.chars().count() > 160 {
        one_line.chars().take(160).collect::<String>() + "…"
    } else {
        one_line
    }
}

/// The measured rows of `problem` that no other measured row beats in both time and error.
pub fn front(results: &Results, problem: ProblemId) -> Vec<&Row> {
    let measured: Vec<(&Row, f64, f64)> = results
        .rows
        .iter()
        .filter(|r| r.problem == problem)
        .filter_map(|r| Some((r, r.ms()?, r.error()?)))
        .collect();
    let mut out: Vec<&Row> = measured
        .iter()
        .filter(|(_, t, e)| {
            !measured
                .iter()
                .any(|(_, t2, e2)| t2 <= t && e2 <= e && (t2 < t || e2 < e))
        })
        .map(|(r, _, _)| *r)
        .collect();
    out.sort_by(|a, b| {
        a.ms()
            .partial_cmp(&b.ms())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    out
}

/// The table of one problem: a row per variant and resolution; a variant that does not apply
/// gets one row saying why.
pub fn problem_table(results: &Results, problem: ProblemId) -> String {
    let columns = problem.columns();
    let time = if problem.is_hand() {
        "ms / keyframe"
    } else {
        "ms / solve"
    };
    let mut s = format!("| tier | resolution | elements | {time} | front |");
    for c in columns {
        let _ = write!(s, " {} |", c.name);
    }
    s.push_str("\n|---|---|---|---|---|");
    s.push_str(&"---|".repeat(columns.len()));
    s.push('\n');
    let dash = " — |".repeat(columns.len());
    let on_front = front(results, problem);
    let rows: Vec<&Row> = results
        .rows
        .iter()
        .filter(|r| r.problem == problem)
        .collect();
    for (i, r) in rows.iter().enumerate() {
        let label = r.variant.label();
        match &r.outcome {
            Outcome::NotApplicable(why) => {
                // One row for the variant: the same reason at every resolution.
                let first = i == 0 || rows[i - 1].variant != r.variant;
                if first {
                    let _ = writeln!(
                        s,
                        "| {label} | all | — | — | | n/a: {} |{}",
                        cell(why),
                        { " — |".repeat(columns.len().saturating_sub(1)) }
                    );
                }
            }
            Outcome::Failed(why) => {
                let _ = writeln!(
                    s,
                    "| {label} | {} | {} | — | | failed: {} |{}",
                    problem.resolution_label(r.resolution),
                    r.elements,
                    cell(why),
                    " — |".repeat(columns.len().saturating_sub(1))
                );
            }
            Outcome::Measured {
                per_frame_ms,
                values,
                ..
            } => {
                let mark = if on_front.iter().any(|f| std::ptr::eq(*f, *r)) {
                    "●"
                } else {
                    ""
                };
                let _ = write!(
                    s,
                    "| {label} | {} | {} | {per_frame_ms:.1} | {mark} |",
                    problem.resolution_label(r.resolution),
                    r.elements,
                );
                for (c, v) in columns.iter().zip(values) {
                    let _ = write!(s, " {} |", c.format(*v));
                }
                s.push('\n');
            }
        }
    }
    let _ = dash;
    s
}

/// What the numbers of one problem show, in a few lines: the front from the fastest to the
/// most accurate run.
pub fn summary(results: &Results, problem: ProblemId) -> String {
    let f = front(results, problem);
    if f.is_empty() {
        return "No run was measured.\n".into();
    }
    let i = problem.plotted();
    let c = &problem.columns()[i];
    let mut s =
        String::from("Front, fastest first (no other run is both faster and more accurate): ");
    let items: Vec<String> = f
        .iter()
        .map(|r| {
            format!(
                "{} at {} ({:.1} ms, {})",
                r.variant.label(),
                problem.resolution_label(r.resolution),
                r.ms().unwrap_or(0.0),
                match &r.outcome {
                    Outcome::Measured { values, .. } =>
                        format!("{} {}", c.name, c.format(values[i])),
                    _ => String::new(),
                }
            )
        })
        .collect();
    s += &items.join("; ");
    s.push_str(".\n");
    s
}
