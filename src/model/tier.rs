//! `[solver] tier`: speed against accuracy for the hands in one key, mapped onto the flexion
//! settings, and the warnings the chosen settings deserve.

use super::flexion_settings::{FleshMethod, FlexionScheme, FlexionSettings};
use crate::scene::{FleshMethodName, FlexionSchemeName, SolverSettings, TierName};

/// How the hands' flesh is solved, fastest first: the one tier of the solver, the viewer and the
/// benches, resolved from `[solver]`'s `tier`, `flesh` and `flexion` keys ([`Tier::of`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tier {
    /// Geometric skinning only (the fast path, no mechanics).
    Skinning,
    /// Linear elasticity on the rest geometry: one factorization, one solve per pose.
    Linear,
    /// The paper's linear increments on the updated geometry (updated Lagrangian).
    Incremental,
    /// Corotated linear increments (the default).
    Corotational,
    /// Neo-Hookean increments solved to equilibrium by Newton (large strain, ν → ½).
    Nonlinear,
}

impl Tier {
    /// Every tier, fastest first.
    pub const ALL: [Tier; 5] = [
        Tier::Skinning,
        Tier::Linear,
        Tier::Incremental,
        Tier::Corotational,
        Tier::Nonlinear,
    ];

    /// The tier `[solver]` asks for: `tier` when given, else what `flesh` and `flexion` imply.
    pub fn of(s: &SolverSettings) -> Tier {
        match (s.tier, s.flesh, s.flexion) {
            (Some(TierName::Skinning), _, _) | (None, Some(FleshMethodName::Skinning), _) => {
                Tier::Skinning
            }
            (Some(TierName::Linear), _, _) | (None, _, Some(FlexionSchemeName::Linear)) => {
                Tier::Linear
            }
            (Some(TierName::Incremental), _, _)
            | (None, _, Some(FlexionSchemeName::UpdatedLagrangian)) => Tier::Incremental,
            (Some(TierName::Nonlinear), _, _) | (None, _, Some(FlexionSchemeName::Nonlinear)) => {
                Tier::Nonlinear
            }
            _ => Tier::Corotational,
        }
    }

    /// The scene's `[solver] tier` value.
    pub fn scene_name(self) -> TierName {
        match self {
            Tier::Skinning => TierName::Skinning,
            Tier::Linear => TierName::Linear,
            Tier::Incremental => TierName::Incremental,
            Tier::Corotational => TierName::Corotational,
            Tier::Nonlinear => TierName::Nonlinear,
        }
    }

    /// Writes this tier into `s`: `tier`, with `flesh` and `flexion` agreeing with it.
    pub fn write(self, s: &mut SolverSettings) {
        s.tier = Some(self.scene_name());
        match self {
            Tier::Skinning => s.flesh = Some(FleshMethodName::Skinning),
            Tier::Linear | Tier::Incremental | Tier::Corotational | Tier::Nonlinear => {
                s.flesh = Some(FleshMethodName::Fem);
                s.flexion = Some(match self {
                    Tier::Linear => FlexionSchemeName::Linear,
                    Tier::Incremental => FlexionSchemeName::UpdatedLagrangian,
                    Tier::Nonlinear => FlexionSchemeName::Nonlinear,
                    _ => FlexionSchemeName::Corotational,
                });
            }
        }
    }
}

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
    if let Some(f) = s.flesh.map(FleshMethod::from) {
        if f != method {
            return Err(contradiction("flesh", name(f), name(method)));
        }
    }
    if let (Some(f), Some(want)) = (s.flexion.map(FlexionScheme::from), scheme) {
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
    // The nonlinear increments keep the skin out of itself by a barrier in their energy.
    let kept = incremental
        || (flexion.scheme == FlexionScheme::Nonlinear
            && flexion.methods.contains(&FleshMethod::Fem));
    if has_hand && flexion.self_contact.is_some() && !kept {
        out.push(
            "solver.self_contact = true: the skin's self-contact is solved in the corotational, \
             the paper's and the nonlinear increments only; this tier's flesh may still pass \
             through itself"
                .to_string(),
        );
    }
    out
}

/// With `tier = "nonlinear"`, a scene with a hand and another body: in the frames where the hand
/// touches the body, the body is Neo-Hookean (`solve::hyperelastic_objects`) but the flesh near
/// the contact is linearised about the pose flexion gave it (`super::grasp`).
pub(super) fn nonlinear_contact_warning(
    nonlinear: bool,
    has_hand: bool,
    has_object: bool,
) -> Option<String> {
    (nonlinear && has_hand && has_object).then(|| {
        "solver.tier = \"nonlinear\": the hands flex by nonlinear increments and the other \
         bodies are Neo-Hookean, also where a hand touches them, but in those frames the flesh \
         near the contact is linearised about the pose its flexion reached (see \
         docs/contact.md)"
            .to_string()
    })
}
