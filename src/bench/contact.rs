//! `prehensile bench contact`: the contact methods on the same scenes — time per keyframe,
//! iterations, factorizations, substitutions, and the outcome (the paper's iteration may fail
//! to converge where the object is stiffer than the flesh under it).

use crate::headless::solve_scene;
use crate::scene::ContactMethodName;
use crate::scene::Scene;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

/// One scene solved by one method.
pub struct ContactRow {
    /// Scene file.
    pub scene: String,
    /// Method.
    pub method: ContactMethodName,
    /// Coulomb friction set for every pair (`None`: the scene's own).
    pub friction: Option<f64>,
    /// Where the last keyframe's contact time went (Lagrange: factorization, substitutions,
    /// the multipliers; the rest), ms.
    pub times: Option<crate::contact::ContactTimes>,
    /// The last keyframe's contact: (iterations, factorizations, substitutions, contact ms,
    /// total contact force on the hand N), or the error.
    pub outcome: Result<(usize, usize, usize, f64, f64, bool), String>,
    /// Wall time of the whole scene, s.
    pub total_s: f64,
}

/// Solves every scene with every method, and with Lagrange again at each friction coefficient
/// of `friction` (the paper's iteration has no friction).
pub fn contact_rows(scenes: &[String], friction: &[f64]) -> anyhow::Result<Vec<ContactRow>> {
    let mut rows = Vec::new();
    for file in scenes {
        let scene = Scene::load(Path::new(file))?;
        let cases = [
            (ContactMethodName::Lagrange, None),
            (ContactMethodName::Paper, None),
        ]
        .into_iter()
        .chain(
            friction
                .iter()
                .map(|&mu| (ContactMethodName::Lagrange, Some(mu))),
        );
        for (method, mu) in cases {
            let mut s = scene.clone();
            s.solver.contact = Some(method);
            if mu.is_some() {
                s.solver.friction = mu;
            }
            let mut times = None;
            let t = Instant::now();
            let outcome = match solve_scene(&s, file) {
                Ok(solved) => {
                    let f = solved.report.frames.last().expect("a frame");
                    match &f.contact {
                        Some(c) => {
                            times = Some(c.times.clone());
                            let force: f64 = c
                                .bodies
                                .iter()
                                .filter(|(k, _)| k.ends_with("/hand"))
                                .map(|(_, v)| nalgebra::Vector3::from(v.force).norm())
                                .sum();
                            Ok((
                                c.iterations,
                                c.factorizations,
                                c.substitutions,
                                c.contact_ms,
                                force,
                                c.stopped_by_threshold,
                            ))
                        }
                        None => Err("no contact".into()),
                    }
                }
                Err(e) => Err(e.to_string()),
            };
            rows.push(ContactRow {
                scene: file.clone(),
                method,
                friction: mu,
                times,
                outcome,
                total_s: t.elapsed().as_secs_f64(),
            });
        }
    }
    Ok(rows)
}

/// The Markdown table.
pub fn contact_table(rows: &[ContactRow]) -> String {
    let mut out = String::from(
        "| scene | method | μ | iterations | factorizations | substitutions | contact solve of the last keyframe (ms) | of which factorization / substitutions / multipliers (ms) | force on the hand (N) | stopped by a bone threshold | whole scene (s) |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let name = Path::new(&r.scene)
            .file_name()
            .map_or(r.scene.clone(), |n| n.to_string_lossy().into_owned());
        let mu = r.friction.map_or("scene".to_string(), |m| format!("{m}"));
        match &r.outcome {
            Ok((it, fa, su, ms, f, stopped)) => {
                let split = r.times.as_ref().map_or("—".to_string(), |t| {
                    format!(
                        "{:.0} / {:.0} / {:.0}",
                        t.factorization, t.substitution, t.settle
                    )
                });
                let _ = writeln!(
                    out,
                    "| {name} | {} | {mu} | {it} | {fa} | {su} | {ms:.0} | {split} | {f:.2} | {} | {:.1} |",
                    r.method.name(),
                    if *stopped { "yes" } else { "no" },
                    r.total_s
                );
            }
            Err(e) => {
                let short: String = e.chars().take(90).collect();
                let _ = writeln!(
                    out,
                    "| {name} | {} | {mu} | — | — | — | failed: {short}… | — | — | — | {:.1} |",
                    r.method.name(),
                    r.total_s
                );
            }
        }
    }
    out
}
