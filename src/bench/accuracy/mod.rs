//! `prehensile bench accuracy`: the measured trade between speed and accuracy. Every solver tier
//! (and element option) that applies to a problem is run at three mesh resolutions on
//!
//! - (a) the cantilever of `docs/validation.md`, against Timoshenko's tip deflection;
//! - (b) the thick-walled sphere under internal pressure, against Lamé;
//! - (c) an elastic ball pressed on a rigid plane, against Hertz;
//! - (d) the index finger flexed at the PIP, 0° → 30° and 0° → 90°, against the finest result
//!   of the most exact hand tier available;
//! - (e) the ball grasp of `assets/scenes/hand-grasp-ball.toml`, its contact forces against the
//!   same kind of reference;
//!
//! each through a scene file's `[solver]` keys (`tier`, `element`, `max_step_deg`), so that a
//! tier the scene refuses today (`nonlinear` for hands, `nonlinear` with obstacles) is recorded
//! as not applicable with the solver's own reason and is measured as soon as the solver takes it.
//! The time is the solve of the scene's frames (meshing excluded); the error is the problem's own.

mod cantilever;
mod column;
mod doc;
mod embed;
mod flexion;
mod grasp;
mod hertz;
mod lame;
mod machine;
mod plot;
mod reference;
mod results;
mod run;
mod table;
mod variant;

pub use column::{Column, Unit};
pub use doc::{
    doc_text, merged_text, problem_section, write_atomic, write_doc, GUIDANCE_BEGIN, GUIDANCE_END,
};
pub use embed::Embedding;
pub use machine::Machine;
pub use plot::{plot_png, write_plot};
pub use reference::{find_reference, hand_reference, HandReference, ReferenceInfo};
pub use results::{accuracy_results, problem_rows, Outcome, Results, Row, Settings};
pub use run::{run_scene, RunError, Solved};
pub use table::{problem_table, summary};
pub use variant::{Variant, HAND_TIERS};

use crate::scene::{Scene, TierName};
use std::path::Path;

/// The plot's path as a link from the document: relative to the document's folder when the plot
/// lies under it, else the path as given.
pub fn plot_link(doc: &Path, plot: &Path) -> String {
    let dir = doc.parent().unwrap_or(Path::new(""));
    plot.strip_prefix(dir)
        .unwrap_or(plot)
        .to_string_lossy()
        .replace('\\', "/")
}

/// The problems of the bench.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProblemId {
    /// (a) Cantilever, tip deflection.
    Cantilever,
    /// (b) Thick sphere under internal pressure.
    Lame,
    /// (c) Ball on a rigid plane.
    Hertz,
    /// (d) Index PIP 0° → 30°.
    Flexion30,
    /// (d) Index PIP 0° → 90°.
    Flexion90,
    /// (e) Ball grasp.
    Grasp,
}

impl ProblemId {
    /// All problems, in the order of the document.
    pub const ALL: [ProblemId; 6] = [
        ProblemId::Cantilever,
        ProblemId::Lame,
        ProblemId::Hertz,
        ProblemId::Flexion30,
        ProblemId::Flexion90,
        ProblemId::Grasp,
    ];

    /// Short name used by `--only`.
    pub fn key(self) -> &'static str {
        match self {
            ProblemId::Cantilever => "cantilever",
            ProblemId::Lame => "lame",
            ProblemId::Hertz => "hertz",
            ProblemId::Flexion30 => "flexion30",
            ProblemId::Flexion90 => "flexion90",
            ProblemId::Grasp => "grasp",
        }
    }

    /// The problem of a `--only` name.
    pub fn from_key(key: &str) -> Result<ProblemId, String> {
        ProblemId::ALL
            .into_iter()
            .find(|p| p.key() == key)
            .ok_or_else(|| {
                format!(
                    "unknown problem \"{key}\" (known: {})",
                    ProblemId::ALL.map(|p| p.key()).join(", ")
                )
            })
    }

    /// Heading in the document and on the plot.
    pub fn title(self) -> &'static str {
        match self {
            ProblemId::Cantilever => "(a) cantilever: tip deflection against Timoshenko",
            ProblemId::Lame => "(b) thick sphere under pressure: radial displacement against Lamé",
            ProblemId::Hertz => "(c) ball on a rigid plane: contact radius against Hertz",
            ProblemId::Flexion30 => "(d) index PIP 0° → 30°: flesh against the reference",
            ProblemId::Flexion90 => "(d) index PIP 0° → 90°: flesh against the reference",
            ProblemId::Grasp => "(e) ball grasp: contact force on the hand against the reference",
        }
    }

    /// Caption of the problem's panel on the plot (the bundled font has no arrows).
    pub fn short_title(self) -> &'static str {
        match self {
            ProblemId::Cantilever => "(a) cantilever",
            ProblemId::Lame => "(b) thick sphere, Lamé",
            ProblemId::Hertz => "(c) ball on a plane, Hertz",
            ProblemId::Flexion30 => "(d) index PIP 0° to 30°",
            ProblemId::Flexion90 => "(d) index PIP 0° to 90°",
            ProblemId::Grasp => "(e) ball grasp",
        }
    }

    /// A hand problem (tiers are flexion schemes; error against a computed reference).
    pub fn is_hand(self) -> bool {
        matches!(
            self,
            ProblemId::Flexion30 | ProblemId::Flexion90 | ProblemId::Grasp
        )
    }

    /// The three resolutions (the scene's own parameter: elements through the beam, cells of
    /// the cubed sphere, the ball's cells at the contact as a fraction of its radius, hand
    /// `resolution`).
    pub fn resolutions(self, quick: bool) -> Vec<f64> {
        match (self, quick) {
            (ProblemId::Cantilever, _) => vec![1.0, 2.0, 4.0],
            (ProblemId::Lame, false) => vec![4.0, 8.0, 12.0],
            (ProblemId::Lame, true) => vec![4.0, 6.0, 8.0],
            (ProblemId::Hertz, false) => vec![8.0, 16.0, 32.0],
            (ProblemId::Hertz, true) => vec![4.0, 8.0, 16.0],
            (ProblemId::Flexion30 | ProblemId::Flexion90, false) => vec![0.75, 1.0, 1.25],
            // Contact on the finer hands costs tens of seconds per keyframe.
            (ProblemId::Grasp, false) => vec![0.5, 0.75, 1.0],
            (ProblemId::Flexion30 | ProblemId::Flexion90 | ProblemId::Grasp, true) => {
                vec![0.5, 0.625, 0.75]
            }
        }
    }

    /// How a resolution is written in the tables.
    pub fn resolution_label(self, r: f64) -> String {
        match self {
            ProblemId::Cantilever => {
                let k = r as usize;
                format!("{}×{k}×{k}", 8 * k)
            }
            ProblemId::Lame => format!("{}² × 6, {} layers", r as usize, lame::layers(r)),
            ProblemId::Hertz => format!("R/{} at the contact", r as usize),
            _ => format!("{r}"),
        }
    }

    /// The scene at resolution `r` (before the variant's solver keys).
    pub fn scene(self, r: f64) -> Scene {
        match self {
            ProblemId::Cantilever => cantilever::scene(r as usize),
            ProblemId::Lame => lame::scene(r as usize),
            ProblemId::Hertz => hertz::scene(r as usize),
            ProblemId::Flexion30 => flexion::scene(r, 30.0),
            ProblemId::Flexion90 => flexion::scene(r, 90.0),
            ProblemId::Grasp => grasp::scene(r),
        }
    }

    /// Names of the measures (the first is the error plotted) and how they are written.
    pub fn columns(self) -> &'static [Column] {
        match self {
            ProblemId::Cantilever => cantilever::COLUMNS,
            ProblemId::Lame => lame::COLUMNS,
            ProblemId::Hertz => hertz::COLUMNS,
            ProblemId::Flexion30 | ProblemId::Flexion90 => flexion::COLUMNS,
            ProblemId::Grasp => grasp::COLUMNS,
        }
    }

    /// The measure plotted (an index into [`ProblemId::columns`]).
    pub fn plotted(self) -> usize {
        match self {
            // The largest distance is set by the few nodes next to the joint that two meshes
            // give to different phalanges; the RMS distance weighs the whole flesh.
            ProblemId::Flexion30 | ProblemId::Flexion90 => 1,
            _ => 0,
        }
    }

    /// The measures of a solved scene at resolution `r` (`reference` for the hand problems).
    pub fn measure(
        self,
        solved: &Solved,
        r: f64,
        reference: Option<&HandReference>,
    ) -> Result<Vec<f64>, String> {
        let refs = || {
            let h = reference.ok_or("no reference")?;
            Ok::<_, String>((&h.finest, h.at(r).ok_or("no reference on the same mesh")?))
        };
        let values = match self {
            ProblemId::Cantilever => cantilever::measure(solved),
            ProblemId::Lame => lame::measure(solved),
            ProblemId::Hertz => hertz::measure(solved),
            ProblemId::Flexion30 | ProblemId::Flexion90 => {
                let (finest, same) = refs()?;
                flexion::measure(solved, finest, same)
            }
            ProblemId::Grasp => {
                let (finest, same) = refs()?;
                grasp::measure(solved, finest, same)
            }
        }?;
        match values.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(format!(
                "the measure \"{}\" is not finite ({})",
                self.columns()[i].name,
                values[i]
            )),
            None => Ok(values),
        }
    }

    /// Why a tier that the solver accepts is not this problem's reference, if it is not.
    pub fn not_a_reference(self, variant: &variant::Variant) -> Option<&'static str> {
        match (self, variant.tier) {
            (ProblemId::Grasp, TierName::Nonlinear) => Some(
                "in its contact steps the flesh near the contact is linearised about the pose \
                 its flexion reached (docs/contact.md, limits), so the hand is not at large \
                 strain where the grip is decided",
            ),
            _ => None,
        }
    }

    /// The reference of a hand problem: resolution and largest increment, degrees (finer and
    /// smaller than any row's).
    pub fn reference(self, quick: bool) -> (f64, f64) {
        match (self, quick) {
            (_, true) => (1.0, 5.0),
            // The grip converges under refinement (1.5 to 2: Σ|F| within 0.14 %, each digit
            // carrying a tenth of it within 3.8 %; tests/grip_convergence.rs) and the corotated
            // step barely matters (20° and 10° within 0.03 %): resolution 2 with 10° steps.
            (ProblemId::Grasp, false) => (2.0, 10.0),
            (_, false) => (1.5, 2.5),
        }
    }
}
