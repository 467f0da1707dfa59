//! `[solver] tier`: speed against accuracy for the hands in one key, mapped onto the flexion
//! settings, and the warnings the chosen settings deserve.

use super::flexion::{FleshMethod, FlexionScheme, FlexionSettings};
use crate::scene::{SolverSettings, TierName};

/// Largest increment, degrees, below which the increments' error stays within the figures of
/// docs/hand.md (updated Lagrangian at 10°: +0.49 % flesh volume, 0.86 mm from 5° steps for
/// an index PIP flexion of 90°).
pub const STEP_WARNING_DEG: f64 = 10.0;

/// What a tier sets: the flesh method of every part, and the flexion scheme (none for
/// skinning, where it only concerns parts that `flesh_digits` sets back to FEM).
fn implied(tier: TierName) -> Result<(FleshMethod, Option<FlexionScheme>), String> {
    Ok(match tier {
        TierName::Skinning => (FleshMethod::Skinning, None),
        TierName::Linear => (FleshMethod::Fem, Some(FlexionScheme::Linear)),
        TierName::Incremental => (FleshMethod::Fem, Some(FlexionScheme::UpdatedLagrangian)),
        TierName::Corotational => (FleshMethod::Fem, Some(FlexionScheme::Corotational)),
        // Hands by nonlinear increments; the static frame of the other bodies by Newton too
        // (`Model::tier`).
        TierName::Nonlinear => (FleshMethod::Fem, Some(FlexionScheme::Nonlinear)),
    })
}

fn name<T: serde::Serialize>(value: T) -> String {
    serde_json::to_value(value)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// Applies `s.tier` to `out` (every part's method and the scheme); `flesh_digits` may still
/// override single parts afterwards. A tier contradicting `flesh` or `flexion` is an error
/// naming both keys: (field, message).
pub(super) fn apply_tier(
    s: &SolverSettings,
    out: &mut FlexionSettings,
) -> Result<(), (String, String)> {
    let Some(tier) = s.tier else { return Ok(()) };
    let (method, scheme) = implied(tier).map_err(|m| ("solver.tier".to_string(), m))?;
    let contradiction = |key: &str, given: String, wants: String| {
        (
            "solver.tier".to_string(),
            format!(
                "solver.tier = \"{}\" contradicts solver.{key} = \"{given}\" (the tier means \
                 {key} = \"{wants}\"); give one of the two keys",
                name(tier)
            ),
        )
    };
    if let Some(f) = s.flesh {
        if f != method {
            return Err(contradiction("flesh", name(f), name(method)));
        }
    }
    if let (Some(f), Some(want)) = (s.flexion, scheme) {
        if f != want {
            return Err(contradiction("flexion", name(f), name(want)));
        }
    }
    out.methods = [method; 6];
    if let Some(scheme) = scheme {
        out.scheme = scheme;
    }
    Ok(())
}

/// Warnings about the flexion settings of a scene whose hands move by FEM increments: an
/// increment above [`STEP_WARNING_DEG`] is one linear step over a large rotation.
pub(super) fn flexion_warnings(flexion: &FlexionSettings, has_hand: bool) -> Vec<String> {
    // The nonlinear increments are each solved to equilibrium: their size is no error.
    let incremental = matches!(
        flexion.scheme,
        FlexionScheme::UpdatedLagrangian | FlexionScheme::Corotational
    ) && flexion.methods.contains(&FleshMethod::Fem);
    let mut out = Vec::new();
    if has_hand && incremental && flexion.max_step_deg > STEP_WARNING_DEG {
        out.push(format!(
            "solver.max_step_deg = {}: increments above {STEP_WARNING_DEG}° are each one linear \
             step over a large rotation; the flexion error grows with the step (index PIP 0° → \
             90°, updated Lagrangian: flesh volume +1.7 % with 45° steps against +0.49 % with \
             10°, nodes 5.1 mm against 1.3 mm from the 2.5° solution; see docs/stability.md)",
            flexion.max_step_deg
        ));
    }
    out
}

/// With `tier = "nonlinear"`, a scene with a hand and another body: the frames where the hand
/// touches the body are solved by the contact step, which stays linear (the object small-strain
/// from rest, the flesh near the contact linearised about its posed state; `super::grasp`).
pub(super) fn nonlinear_contact_warning(
    tier: Option<TierName>,
    has_hand: bool,
    has_object: bool,
) -> Option<String> {
    (tier == Some(TierName::Nonlinear) && has_hand && has_object).then(|| {
        "solver.tier = \"nonlinear\": the hands flex by nonlinear increments and bodies \
         untouched by a hand are solved by Newton, but a frame where a hand touches a body is \
         solved by the linear contact step (the body small-strain from rest, the flesh near the \
         contact linearised about its posed state; see docs/elements.md)"
            .to_string()
    })
}
