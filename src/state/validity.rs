//! Whether a solved frame stays where small-strain linear elasticity holds.
//!
//! The static bodies are solved with the linear strain ε = sym(∇u) on the undeformed geometry,
//! valid while the strain is small. Above [`STRAIN_WARNING`] (largest principal strain at a
//! Gauss point, dimensionless) the result is outside the theory: for a soft body under a large
//! load the displacement scales as 1/E without bound, where a real body would stiffen.

use super::Frame;
use crate::fem::hex8::{gauss_biot_strains, gauss_strains};
use crate::model::Model;
use nalgebra::Vector3;

/// Largest principal strain accepted without a warning (dimensionless, 20 %; the built-in
/// scenes reach 10 % at their pressed caps).
pub const STRAIN_WARNING: f64 = 0.2;

/// The largest |principal strain| (rotation-free in a contact frame of a corotated tier) at the
/// Gauss points of each non-hand body in `frame`, by body index (hands follow their own tiers and are skipped: `None`). NaN if any is NaN.
pub fn largest_strains(model: &Model, frame: &Frame) -> Vec<Option<f64>> {
    let u = &frame.solution.displacement;
    // In contact, a corotated tier turns the bodies: their strain is the rotation-free one.
    let turned = frame.contact.is_some() && model.corotates_objects();
    model
        .bodies
        .iter()
        .map(|body| {
            body.hand.is_none().then(|| {
                let mut worst = 0.0f64;
                for c in body.cells.clone() {
                    let cell = &model.mesh.cells[c];
                    let disp = cell.map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]));
                    let coords = model.mesh.cell_coords(c);
                    let strains = if turned {
                        gauss_biot_strains(&coords, &disp)
                    } else {
                        gauss_strains(&coords, &disp)
                    };
                    let Ok(strains) = strains else {
                        continue;
                    };
                    for e in strains {
                        let largest = e.symmetric_eigenvalues().amax();
                        if largest.is_nan() {
                            return f64::NAN;
                        }
                        worst = worst.max(largest);
                    }
                }
                worst
            })
        })
        .collect()
}

/// `x` rounded up to three significant digits, printed without trailing zeros ("11200",
/// "2.86").
fn rounded_up(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return format!("{x}");
    }
    let digits = 2 - x.log10().floor().clamp(-300.0, 300.0) as i32;
    let scale = 10f64.powi(digits);
    let up = (x * scale).ceil() / scale;
    format!("{up:.*}", digits.max(0) as usize)
}

/// What imposes the deformation of body `b` in `frame`, if its obstacles or its prescribed
/// displacements do: obstacles overlapping it at rest by, or supports moving it by, at least
/// half its largest displacement there ("the obstacles \"top\", \"bottom\" (which start 24.0
/// mm inside it)", "its prescribed displacements (up to 5.0 mm)").
fn imposed_squeeze(model: &Model, frame: &Frame, b: usize) -> Option<String> {
    let body = &model.bodies[b];
    let u = &frame.solution.displacement;
    let moved = body
        .nodes
        .clone()
        .map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]).norm())
        .fold(0.0f64, f64::max);
    let mut names = Vec::new();
    let mut overlap = 0.0f64;
    for (name, obstacle) in &model.obstacles {
        let deepest = body
            .nodes
            .clone()
            .map(|n| -obstacle.nearest(&model.mesh.nodes[n]).0)
            .fold(0.0f64, f64::max);
        if deepest >= 0.5 * moved && deepest > 0.0 {
            names.push(format!("\"{name}\""));
            overlap = overlap.max(deepest);
        }
    }
    if !names.is_empty() {
        let what = if names.len() == 1 {
            "obstacle"
        } else {
            "obstacles"
        };
        return Some(format!(
            "the {what} {} (which start {:.1} mm inside it)",
            names.join(", "),
            overlap * 1e3
        ));
    }
    let imposed = (3 * body.nodes.start..3 * body.nodes.end)
        .filter(|&d| model.partition.prescribed[d])
        .map(|d| model.prescribed[d].abs())
        .fold(0.0f64, f64::max);
    (imposed > 0.0 && imposed >= 0.5 * moved).then(|| {
        format!(
            "its prescribed displacements (up to {:.1} mm)",
            imposed * 1e3
        )
    })
}

/// Whether a hand's skin touches body `b` in `frame` (a contact with a node of each).
fn pressed_by_a_hand(model: &Model, frame: &Frame, b: usize) -> bool {
    let Some(contact) = frame.contact.as_ref() else {
        return false;
    };
    let body_of = |n: usize| model.body_of_node(n);
    contact.contacts.iter().any(|c| {
        c.terms.iter().any(|&(n, _)| body_of(n) == b)
            && c.terms
                .iter()
                .any(|&(n, _)| model.bodies[body_of(n)].hand.is_some())
    })
}

/// One warning per body, for the frame where its strain is largest, when that strain exceeds
/// [`STRAIN_WARNING`] — with the cause: the hands pressing it there beyond what its static
/// frame strains it (the grasp: its advice is the nonlinear tier, whose Neo-Hookean bodies
/// hold at finite strain, or a less deep pose; for a pressurised body only the pose, the
/// nonlinear tier's contact not settling on it), or its loads and material. None in the
/// nonlinear tier: its bodies are Neo-Hookean, valid at finite strain.
pub fn small_strain_warnings(model: &Model, frames: &[Frame]) -> Vec<String> {
    if model.nonlinear_statics {
        return Vec::new();
    }
    let strains: Vec<Vec<Option<f64>>> = frames.iter().map(|f| largest_strains(model, f)).collect();
    // The static frame's: what the loads alone do.
    let still = strains.first().cloned().unwrap_or_default();
    let mut worst: Vec<Option<(usize, f64)>> = vec![None; model.bodies.len()];
    for (i, frame) in strains.into_iter().enumerate() {
        for (b, s) in frame.into_iter().enumerate() {
            if let Some(s) = s {
                if worst[b].is_none_or(|(_, w)| s > w || s.is_nan()) {
                    worst[b] = Some((i, s));
                }
            }
        }
    }
    worst
        .iter()
        .enumerate()
        .filter_map(|(b, w)| {
            let (i, s) = (*w)?;
            (s > STRAIN_WARNING || s.is_nan()).then(|| {
                let unloaded = still
                    .get(b)
                    .copied()
                    .flatten()
                    .is_some_and(|s0| s0 <= STRAIN_WARNING);
                let pressurised = model
                    .loads
                    .iter()
                    .any(|l| l.body == b && l.pressure.is_some());
                let pressed = unloaded && pressed_by_a_hand(model, &frames[i], b);
                let cause = if pressed && pressurised {
                    // The nonlinear tier's corrections at a pose do not settle on a body its
                    // air presses (its tangent lacks the air's load stiffness, docs/contact.md):
                    // that advice would end unsettled, exit 2.
                    "the hands press it that far (its loads alone strain it less): pose the \
                     grasp less deep (the nonlinear tier, valid at finite strain, does not yet \
                     settle its contact with a pressurised body: its forces would be uncertain \
                     by several per cent)"
                        .to_string()
                } else if pressed {
                    "the hands press it that far (its loads alone strain it less): solve the \
                     scene with [solver] tier = \"nonlinear\", whose bodies are Neo-Hookean, \
                     valid at finite strain, or pose the grasp less deep"
                        .to_string()
                } else if let Some(imposed) = imposed_squeeze(model, &frames[i], b) {
                    // A stiffer material strains as much under an imposed displacement.
                    format!(
                        "{imposed} squeeze it that far, whatever its stiffness: solve the \
                         scene with [solver] tier = \"nonlinear\", whose bodies are \
                         Neo-Hookean, valid at finite strain, or squeeze it less"
                    )
                } else {
                    let factor = rounded_up(s / (0.5 * STRAIN_WARNING));
                    format!(
                        "too soft a material or too large a load: a Young's modulus {factor}× \
                         higher, or loads {factor}× smaller, keep it within half the limit"
                    )
                };
                format!(
                    "body \"{}\": principal strain up to {s:.3e} (frame {i}), above \
                     {STRAIN_WARNING}: outside small-strain linear elasticity, whose \
                     displacements grow as 1/E without bound; the result is not physical \
                     ({cause})",
                    model.bodies[b].name
                )
            })
        })
        .collect()
}
