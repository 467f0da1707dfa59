//! `prehensile bench region`: modelling only what a scene requires, measured. The grasp
//! animation is solved twice: as Prehensile does by default (flexion by FEM only near the joints
//! that move, skinning elsewhere; the contact solved with the flesh within `contact_region` of
//! the touching skin; bodies that do not touch solved apart and composed), and with everything
//! everywhere (the whole flesh by FEM in every increment, the whole flesh solved with the
//! contact). The table gives the time saved and what it costs in the result.

use crate::headless::solve_scene;
use crate::scene::{FarFromContact, FleshRegionName, Scene};
use crate::state::Frame;
use nalgebra::Vector3;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

/// One way of solving the scene.
pub struct RegionRun {
    /// "required only" or "everything everywhere".
    pub label: &'static str,
    /// Wall time of the whole animation, s.
    pub seconds: f64,
    /// FEM cells of the flexion increments, summed over keyframes.
    pub flexion_cells: usize,
    /// Cells near moving joints left to skinning because their part of the hand was far from
    /// contact, summed over keyframes.
    pub far_cells: usize,
    /// Hand cells solved with the contact, per frame.
    pub contact_cells: Vec<usize>,
    /// The frames.
    pub frames: Vec<Frame>,
    /// Node ranges of the hands.
    pub hand_nodes: Vec<std::ops::Range<usize>>,
}

/// Solves `file` both ways.
pub fn region_runs(file: &str) -> anyhow::Result<Vec<RegionRun>> {
    let scene = Scene::load(Path::new(file))?;
    let mut runs = Vec::new();
    for (label, everything) in [("required only", false), ("everything everywhere", true)] {
        let mut s = scene.clone();
        if everything {
            s.solver.flesh_region = Some(FleshRegionName::Whole);
            s.solver.far_from_contact = Some(FarFromContact::Solve);
            // Farther than any hand is long: every FEM cell of the flesh.
            s.solver.contact_region = Some(1.0);
        }
        let t = Instant::now();
        let solved = solve_scene(&s, file)?;
        let seconds = t.elapsed().as_secs_f64();
        runs.push(RegionRun {
            label,
            seconds,
            flexion_cells: solved
                .frames
                .iter()
                .flat_map(|f| &f.hands)
                .map(|h| h.stats.fem_cells)
                .sum(),
            far_cells: solved
                .frames
                .iter()
                .flat_map(|f| &f.hands)
                .map(|h| h.stats.far_cells)
                .sum(),
            contact_cells: solved
                .frames
                .iter()
                .map(|f| f.contact.as_ref().map_or(0, |c| c.region_cells))
                .collect(),
            hand_nodes: solved
                .model
                .bodies
                .iter()
                .filter(|b| b.hand.is_some())
                .map(|b| b.nodes.clone())
                .collect(),
            frames: solved.frames,
        });
    }
    Ok(runs)
}

fn hand_force(frame: &Frame) -> Vector3<f64> {
    frame
        .hands
        .iter()
        .flat_map(|h| &h.contact_force)
        .sum::<Vector3<f64>>()
}

/// The Markdown tables: cost of each way, then per frame the difference of the cheap result
/// from the full one.
pub fn region_table(runs: &[RegionRun]) -> String {
    let mut out = String::from(
        "| solved | whole animation (s) | FEM cells in the flexion increments | cells skinned far from contact | hand cells solved with the contact (per frame) |\n|---|---|---|---|---|\n",
    );
    for r in runs {
        let cells: Vec<String> = r.contact_cells.iter().map(|c| c.to_string()).collect();
        let _ = writeln!(
            out,
            "| {} | {:.2} | {} | {} | {} |",
            r.label,
            r.seconds,
            r.flexion_cells,
            r.far_cells,
            cells.join(", ")
        );
    }
    let [cheap, full] = [&runs[0], &runs[runs.len() - 1]];
    let _ = writeln!(
        out,
        "\nTime saved: {:.2} s of {:.2} s ({:.0} %).\n",
        full.seconds - cheap.seconds,
        full.seconds,
        100.0 * (full.seconds - cheap.seconds) / full.seconds
    );
    out.push_str(
        "| frame | largest skin/flesh node difference (mm) | largest object displacement difference (mm) | force on the hand (N): required only / everything | largest bone reaction difference (N) |\n|---|---|---|---|---|\n",
    );
    for (i, (a, b)) in cheap.frames.iter().zip(&full.frames).enumerate() {
        let mut hand_gap: f64 = 0.0;
        let mut bone_gap: f64 = 0.0;
        for (ha, hb) in a.hands.iter().zip(&b.hands) {
            for (p, q) in ha.positions.iter().zip(&hb.positions) {
                hand_gap = hand_gap.max((p - q).norm());
            }
            for (p, q) in ha.bone_reactions.iter().zip(&hb.bone_reactions) {
                bone_gap = bone_gap.max((p - q).norm());
            }
        }
        // Object nodes: those of no hand.
        let mut object_gap: f64 = 0.0;
        let u = (&a.solution.displacement, &b.solution.displacement);
        for n in 0..u.0.len() / 3 {
            if cheap.hand_nodes.iter().any(|r| r.contains(&n)) {
                continue;
            }
            let d = Vector3::from_fn(|k, _| u.0[3 * n + k] - u.1[3 * n + k]);
            object_gap = object_gap.max(d.norm());
        }
        let _ = writeln!(
            out,
            "| {i} | {:.3} | {:.3} | {:.3} / {:.3} | {:.3} |",
            hand_gap * 1e3,
            object_gap * 1e3,
            hand_force(a).norm(),
            hand_force(b).norm(),
            bone_gap
        );
    }
    out
}
