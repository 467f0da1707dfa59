//! `prehensile bench gentle`: the gentlest grip (issue 17) from preshape to grip — per grasp and
//! hand resolution, whether it holds, where the closing stopped, the grip, the margin, how far
//! the object moved let go of, the poses solved by FEM and the whole solve's wall time. Over
//! several resolutions the table is the grip's refinement study.

use crate::headless::solve_scene;
use crate::scene::Scene;
use std::fmt::Write;
use std::time::Instant;

/// The Power-grasp scene (the default hand, the pressurised ball on its stand under the palm)
/// with skin on rubber μ = 0.8 and one grasp keyframe: the power preshape closed until the
/// ball, let go of, is held against gravity with the margin 1.5 (`tests/let_go.rs`).
pub const POWER_HELD: &str = "power grasp held against gravity (hand-power-grasp.toml, μ 0.8)";

/// One grasp searched at one resolution.
pub struct GentleRow {
    /// The grasp: a case name or a scene file.
    pub case: String,
    /// Hand mesh resolution.
    pub resolution: f64,
    /// Wall time of the whole scene, s.
    pub total_s: f64,
    /// The last grasp keyframe's outcome, or why the solve failed.
    pub outcome: Result<crate::state::GraspOutcome, String>,
}

/// The Power-grasp scene with friction and a gravity-hold grasp keyframe.
pub fn power_held_scene() -> anyhow::Result<Scene> {
    let s = include_str!("../../assets/scenes/hand-power-grasp.toml");
    let base = &s[..s.find("[[keyframe]]").unwrap_or(s.len())];
    let text = format!(
        "{base}[[friction]]\nbetween = [\"flesh\", \"rubber\"]\nmu = 0.8\n\n[[keyframe]]\n\
         time = 1.0\ngrasp = {{ object = \"ball\", preshape = \"power\" }}\n"
    );
    Ok(Scene::parse(&text, "hand-power-grasp.toml")?)
}

/// The cases: `power` (the gravity hold) and scene files with grasp keyframes.
fn cases(cases: &[String]) -> anyhow::Result<Vec<(String, Scene)>> {
    let mut out = Vec::new();
    for case in cases.iter().map(|c| c.trim()).filter(|c| !c.is_empty()) {
        if case == "power" {
            out.push((POWER_HELD.to_string(), power_held_scene()?));
        } else {
            let scene = Scene::load(std::path::Path::new(case))?;
            if !scene.keyframe.iter().any(|k| k.grasp.is_some()) {
                anyhow::bail!(
                    "{case}: no grasp keyframe (`grasp = {{ object = …, preshape = … }}`)"
                );
            }
            out.push((case.to_string(), scene));
        }
    }
    Ok(out)
}

/// Searches every case at every hand resolution; each row is also printed to standard error as
/// it is done.
pub fn gentle_rows(names: &[String], resolutions: &[f64]) -> anyhow::Result<Vec<GentleRow>> {
    let mut rows = Vec::new();
    for (case, scene) in cases(names)? {
        for &resolution in resolutions {
            let s = super::grasp::at_hand_resolution(&scene, resolution);
            let t = Instant::now();
            let solved = solve_scene(&s, &case);
            let total_s = t.elapsed().as_secs_f64();
            let outcome = match solved {
                Ok(solved) => solved
                    .frames
                    .iter()
                    .rev()
                    .flat_map(|f| &f.hands)
                    .find_map(|h| h.grasp.clone())
                    .ok_or_else(|| "no grasp outcome".to_string()),
                Err(e) => Err(e.to_string()),
            };
            let row = GentleRow {
                case: case.clone(),
                resolution,
                total_s,
                outcome,
            };
            eprint!("{}", gentle_table_rows(std::slice::from_ref(&row)));
            rows.push(row);
        }
    }
    Ok(rows)
}

/// The rows as a Markdown table.
pub fn gentle_table(rows: &[GentleRow]) -> String {
    let mut out = String::from(
        "| grasp | resolution | held | closing past first contact (°) | grip (N) | margin \
         (asked) | grip / margin (N) | drift let go of (mm) | poses | whole solve (s) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    out.push_str(&gentle_table_rows(rows));
    out
}

/// `text` as one table cell of at most `chars` characters: no column bars or line breaks, an
/// ellipsis where it was cut.
fn cell(text: &str, chars: usize) -> String {
    let flat: String = text
        .chars()
        .map(|c| match c {
            '|' => '/',
            '\n' | '\r' => ' ',
            c => c,
        })
        .collect();
    if flat.chars().count() > chars {
        format!("{}…", flat.chars().take(chars).collect::<String>())
    } else {
        flat
    }
}

/// The table's rows, without its header.
fn gentle_table_rows(rows: &[GentleRow]) -> String {
    let mut out = String::new();
    for r in rows {
        match &r.outcome {
            Ok(g) => {
                let asked = match (g.margin_target, g.force_target) {
                    (Some(m), _) => format!("{:.3} ({m})", g.margin),
                    (None, Some(f)) => format!("— (grip {f} N)"),
                    _ => format!("{:.3}", g.margin),
                };
                let per = if g.margin_target.is_some() && g.margin > 0.0 {
                    format!("{:.3}", g.grip / g.margin)
                } else {
                    "—".into()
                };
                let drift = g.drift.map_or("—".into(), |d| format!("{:.2}", d * 1e3));
                let held = match (&g.reason, g.held) {
                    (_, true) => "yes".to_string(),
                    (Some(why), false) => format!("no: {}", cell(why, 100)),
                    (None, false) => "no".into(),
                };
                let _ = writeln!(
                    out,
                    "| {} | {} | {held} | {:.3} | {:.3} | {asked} | {per} | {drift} | {} | {:.1} |",
                    r.case, r.resolution, g.closing_deg, g.grip, g.trials, r.total_s
                );
            }
            Err(e) => {
                let _ = writeln!(
                    out,
                    "| {} | {} | stopped: {} | — | — | — | — | — | — | {:.1} |",
                    r.case,
                    r.resolution,
                    cell(e, 140),
                    r.total_s
                );
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cell_has_no_bars_or_breaks_and_an_ellipsis_only_where_cut() {
        assert_eq!(cell("a | b\nc", 10), "a / b c");
        assert_eq!(cell("abcdef", 3), "abc…");
        assert_eq!(cell("abc", 3), "abc");
    }

    #[test]
    fn the_cases_are_grasp_keyframes_and_a_scene_without_one_is_refused_by_name() {
        let found = cases(&["power".into(), "assets/scenes/hand-gentle-grip.toml".into()]).unwrap();
        assert_eq!(found.len(), 2);
        let power = &found[0].1;
        assert!(
            power.friction.iter().any(|f| f.mu == 0.8),
            "{:?}",
            power.friction
        );
        assert!(power.keyframe.iter().any(|k| k.grasp.is_some()));
        let e = cases(&["assets/scenes/finger-press-ball.toml".into()])
            .map(|c| c.len())
            .expect_err("no grasp keyframe: refused")
            .to_string();
        assert!(
            e.starts_with("assets/scenes/finger-press-ball.toml: no grasp keyframe"),
            "{e}"
        );
    }
}
