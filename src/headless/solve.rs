//! From a scene file to solved frames and written output: what `prehensile solve` does.

use crate::export::gltf_animation::{animated_surfaces, animation_glb};
use crate::export::hand_geometry::{bones_vtu, frame_obj, skin_vtu};
use crate::export::output::OutputSet;
use crate::export::report::{frame_report, model_summary, FrameReport, Report};
use crate::export::vtu::{collection_pvd, frame_vtu};
use crate::export::vtu_grid::VtuEncoding;
use crate::model::Model;
use crate::scene::{Scene, SceneError};
use crate::solve::{solve_frames, SimError};
use crate::state::outcome::keyframe_warnings;
use crate::state::{small_strain_warnings, Frame};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a scene could not be solved or written.
#[derive(Debug, Error)]
pub enum PipelineError {
    /// The scene is unusable.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The solve failed.
    #[error("{file}: {error}")]
    Sim {
        /// The scene file.
        file: String,
        /// Why.
        error: Box<SimError>,
    },
    /// Output could not be written.
    #[error("{dir}: cannot write the output: {reason}")]
    Output {
        /// The output folder.
        dir: String,
        /// Why (kept out of the error chain so that it is said once).
        reason: std::io::Error,
    },
}

/// A solved scene.
pub struct Solved {
    /// The model.
    pub model: Model,
    /// Its frames.
    pub frames: Vec<Frame>,
    /// The report.
    pub report: Report,
}

/// Builds and solves a parsed scene; `file` names it in errors and in the report. Without hands
/// there is one static frame; with hands, one frame per distinct keyframe time.
pub fn solve_scene(scene: &Scene, file: &str) -> Result<Solved, PipelineError> {
    let model = Model::build(scene, file)?;
    let (times, frames) = solve_frames(&model).map_err(|source| PipelineError::Sim {
        file: file.to_string(),
        error: Box::new(source),
    })?;
    let reports: Vec<_> = frames
        .iter()
        .zip(&times)
        .enumerate()
        .map(|(i, (f, &t))| frame_report(&model, f, i, t))
        .collect();
    let report = Report {
        scene: file.to_string(),
        model: model_summary(&model),
        warnings: model
            .warnings()
            .into_iter()
            .chain(small_strain_warnings(&model, &frames))
            .chain(keyframe_warnings(&model, &frames))
            .chain(skin_overlap_warnings(&model, &reports))
            .chain(preshape_grip_warnings(&reports))
            .chain(crushed_flesh_warnings(&reports))
            .chain(pressed_inside_out_warnings(&reports))
            .collect(),
        frames: reports,
    };
    Ok(Solved {
        model,
        frames,
        report,
    })
}

/// Reads, builds and solves a scene file.
pub fn solve_scene_file(path: &Path) -> Result<Solved, PipelineError> {
    let scene = Scene::load(path)?;
    solve_scene(&scene, &path.display().to_string())
}

/// Writes `report.json`, one `frame_NNNN.vtu` per frame, `frames.pvd` and `animation.glb` (every
/// frame of every surface in one animated glTF) into `dir` (with hands, also `hand_NNNN.obj`:
/// skin and bones, `bones_NNNN.vtu`, and `skin_NNNN.vtu`: the contact skin with the tactile map),
/// all or nothing.
pub fn write_solved(solved: &Solved, dir: &Path) -> Result<Vec<PathBuf>, PipelineError> {
    write_solved_as(solved, dir, VtuEncoding::default())
}

/// [`write_solved`] with the VTU files' `encoding` (binary, the default, or ASCII).
pub fn write_solved_as(
    solved: &Solved,
    dir: &Path,
    encoding: VtuEncoding,
) -> Result<Vec<PathBuf>, PipelineError> {
    let io = |reason| PipelineError::Output {
        dir: dir.display().to_string(),
        reason,
    };
    let mut out = OutputSet::new(dir).map_err(io)?;
    let json = serde_json::to_string_pretty(&solved.report).expect("report serialises");
    out.write("report.json", json.as_bytes()).map_err(io)?;
    let mut listing = Vec::new();
    for (i, frame) in solved.frames.iter().enumerate() {
        let name = format!("frame_{i:04}.vtu");
        out.write(&name, &frame_vtu(&solved.model, frame, encoding))
            .map_err(io)?;
        listing.push((solved.report.frames[i].time, name));
        if let Some(obj) = frame_obj(&solved.model, frame) {
            out.write(&format!("hand_{i:04}.obj"), obj.as_bytes())
                .map_err(io)?;
        }
        if let Some(vtu) = bones_vtu(&solved.model, frame, encoding) {
            out.write(&format!("bones_{i:04}.vtu"), &vtu).map_err(io)?;
        }
        if let Some(vtu) = skin_vtu(&solved.model, frame, encoding) {
            out.write(&format!("skin_{i:04}.vtu"), &vtu).map_err(io)?;
        }
    }
    out.write("frames.pvd", collection_pvd(&listing).as_bytes())
        .map_err(io)?;
    // Every frame in one animated glTF for Blender and other DCC tools.
    let times: Vec<f64> = solved.report.frames.iter().map(|f| f.time).collect();
    let glb = animation_glb(
        &animated_surfaces(&solved.model, &solved.frames.iter().collect::<Vec<_>>()),
        &times,
    )
    .map_err(|e| io(std::io::Error::other(format!("animation.glb: {e}"))))?;
    out.write("animation.glb", &glb).map_err(io)?;
    out.commit().map_err(io)
}

/// A warning for every grasp keyframe whose preshape already presses the object: the hand is
/// posed into it before any digit closes, and no grip along the synergies is gentler.
fn preshape_grip_warnings(frames: &[FrameReport]) -> Vec<String> {
    let mut out = Vec::new();
    for (i, frame) in frames.iter().enumerate() {
        for (name, hand) in &frame.hands {
            let Some(g) = hand.grasp.as_ref().filter(|g| g.preshape_grip > 0.0) else {
                continue;
            };
            out.push(format!(
                "frame {i}: the preshape \"{}\" of hand \"{name}\" already presses \"{}\" with \
                 {:.3} N before any digit closes (the open hand is posed into it): no grip along \
                 the synergies is gentler, and the grip found ({:.3} N) is not the gentlest that \
                 holds; move the object out of the open hand, or the hand away from it",
                g.preshape, g.object, g.preshape_grip, g.grip,
            ));
        }
    }
    out
}

/// One warning per hand whose flesh some frame crushed past
/// [`CRUSH_WARNING_VOLUME`](crate::state::CRUSH_WARNING_VOLUME) in a part: the frame that
/// crushed the most, its parts over it, and how many frames did.
fn crushed_flesh_warnings(frames: &[FrameReport]) -> Vec<String> {
    let mut worst: BTreeMap<&str, (usize, usize, f64)> = BTreeMap::new();
    for (i, frame) in frames.iter().enumerate() {
        for (name, hand) in &frame.hands {
            let warned = hand.crushed_flesh.warned_parts();
            if warned.is_empty() {
                continue;
            }
            let volume: f64 = warned.iter().map(|(_, v)| v).sum();
            let entry = worst.entry(name).or_insert((i, 0, 0.0));
            entry.1 += 1;
            if volume > entry.2 {
                (entry.0, entry.2) = (i, volume);
            }
        }
    }
    worst
        .into_iter()
        .map(|(name, (i, count, _))| {
            let crushed = &frames[i].hands[name].crushed_flesh;
            let parts: Vec<String> = crushed
                .warned_parts()
                .iter()
                .map(|(p, v)| format!("{p} {:.0} mm³", v * 1e9))
                .collect();
            format!(
                "hand \"{name}\": its flesh is crushed below half its volume in {count} frame{} \
                 (frame {i}: {}; the flesh at its most squeezed {:.2} of its volume{}): the pose or the grip squeezes \
                 more flesh than flesh gives way (a pulp pressed into the palm or onto a stiffer \
                 body, a crease folded flat), and what the bones of those parts feel there \
                 depends on the mesh (from resolution 1 to 1.5 the shipped fist's little \
                 metacarpal moves 7 %: docs/hand.md, \"Self-contact\"); flex \
                 those digits less or press them less deep (the little finger's pulp on the \
                 palm at MCP 88°, PIP 90°, DIP 50° crushes 30 mm³, under the {:.0} mm³ this \
                 warns from)",
                if count == 1 { "" } else { "s" },
                parts.join(", "),
                crushed.smallest_volume_ratio,
                if crushed.smallest_volume_ratio < 0.0 {
                    ", inside out at some points"
                } else {
                    ""
                },
                crate::state::CRUSH_WARNING_VOLUME * 1e9,
            )
        })
        .collect()
}

/// One warning per hand whose flesh a contact's press turned inside out in some frame
/// (`state::pressed_inside_out`): the frame with the point turned the most, where it is, and how
/// many frames did.
fn pressed_inside_out_warnings(frames: &[FrameReport]) -> Vec<String> {
    let mut worst: BTreeMap<&str, (usize, usize, f64)> = BTreeMap::new();
    for (i, frame) in frames.iter().enumerate() {
        for (name, hand) in &frame.hands {
            let Some(turned) = &hand.pressed_inside_out else {
                continue;
            };
            let entry = worst.entry(name).or_insert((i, 0, f64::INFINITY));
            entry.1 += 1;
            if turned.ratio < entry.2 {
                (entry.0, entry.2) = (i, turned.ratio);
            }
        }
    }
    worst
        .into_iter()
        .filter_map(|(name, (i, count, _))| {
            let t = frames[i].hands[name].pressed_inside_out.as_ref()?;
            let [x, y, z] = t.rest_position_mm;
            Some(format!(
                "hand \"{name}\": the press of a contact turns its flesh inside out in {count} \
                 frame{} (frame {i}: {} point{}, the most in the {} — element {} at rest near \
                 [{x:.1}, {y:.1}, {z:.1}] mm, volume ratio {:.2}): the flesh near a contact is \
                 solved linearised about the hand's pose, small strain in the press, and a press \
                 this deep is beyond it — the forces there are not flesh's, which would stiffen \
                 without bound; press the {} less deep (docs/contact.md, \"Flesh pressed inside \
                 out\")",
                if count == 1 { "" } else { "s" },
                t.points,
                if t.points == 1 { "" } else { "s" },
                t.part_named(),
                t.cell,
                t.ratio,
                t.part_named(),
            ))
        })
        .collect()
}

/// A warning for every frame whose hand's skin went into its own flesh, naming the parts and
/// what keeps it out.
fn skin_overlap_warnings(model: &Model, frames: &[FrameReport]) -> Vec<String> {
    let held = model.flexion.self_contact.is_some();
    let mut out = Vec::new();
    for (i, frame) in frames.iter().enumerate() {
        for (name, hand) in &frame.hands {
            let o = &hand.skin_overlap;
            for (other, n) in &o.other_hands {
                out.push(format!(
                    "frame {i}: the skin of hand \"{name}\" is inside hand \"{other}\" at {n} skin \
                     points: the contact is solved between a hand and the other bodies, not \
                     between two hands, so nothing keeps them out of each other and neither \
                     feels the other; pose or place them apart"
                ));
            }
            if o.vertices == 0 {
                continue;
            }
            let parts: Vec<String> = o.parts.iter().map(|(p, n)| format!("{p} {n}")).collect();
            out.push(format!(
                "frame {i}: the skin of hand \"{name}\" is inside its own flesh at {} skin \
                 points ({}): {}; the bones' reactions miss that contact",
                o.vertices,
                parts.join(", "),
                if held {
                    format!(
                        "the self-contact leaves it there (skin folding through the skin within \
                         {:.1} mm of it along the skin, which the flesh between is left to keep \
                         apart; skin the barrier held where a keyframe found it already \
                         through; or the contact steps against other bodies and the linear \
                         tier, which do not carry it: docs/hand.md, \"Self-contact\")",
                        crate::solve::SELF_CONTACT_NEIGHBOURHOOD * 1e3
                    )
                } else {
                    "nothing keeps it out ([solver] self_contact = true keeps the flexion's \
                     skin out of itself, experimental: docs/hand.md)"
                        .to_string()
                }
            ));
        }
    }
    out
}
