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
/// hold at finite strain), or its loads and material. None in the nonlinear tier: its bodies
/// are Neo-Hookean, valid at finite strain.
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
                let cause = if unloaded && pressed_by_a_hand(model, &frames[i], b) {
                    "the hands press it that far (its loads alone strain it less): solve the \
                     scene with [solver] tier = \"nonlinear\", whose bodies are Neo-Hookean, \
                     valid at finite strain, or pose the grasp less deep"
                } else {
                    "too soft a material or too large a load"
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
