//! The solver variants the bench compares: a tier of `[solver] tier`, the element of the linear
//! static solve (`[solver] element`), and the largest increment of the incremental tiers
//! (`[solver] max_step_deg`). A variant is applied to a scene through those keys only.

use super::ProblemId;
use crate::scene::{ElementName, Scene, TierName};

/// The hand tiers, fastest first.
pub const HAND_TIERS: [TierName; 5] = [
    TierName::Skinning,
    TierName::Linear,
    TierName::Incremental,
    TierName::Corotational,
    TierName::Nonlinear,
];

/// A tier with its options.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// `[solver] tier`.
    pub tier: TierName,
    /// `[solver] element` (the linear static solve only).
    pub element: ElementName,
    /// `[solver] max_step_deg` when the bench sets it.
    pub step_deg: Option<f64>,
}

impl Variant {
    /// A variant with hex8 and the scene's step.
    pub fn new(tier: TierName) -> Variant {
        Variant {
            tier,
            element: ElementName::Hex8,
            step_deg: None,
        }
    }

    /// The tier's scene name.
    pub fn tier_name(&self) -> String {
        crate::scene::spelling(&self.tier)
    }

    /// Label in tables and on the plot, e.g. `linear · incompatible modes`, `corotational 10°`.
    pub fn label(&self) -> String {
        let mut s = self.tier_name();
        if self.element == ElementName::IncompatibleModes {
            s += " · incompatible modes";
        }
        if let Some(step) = self.step_deg {
            s += &format!(" {step}°");
        }
        s
    }

    /// Sets the scene's `[solver]` keys: `tier`, `element`, `max_step_deg`.
    pub fn apply(&self, scene: &mut Scene) {
        scene.solver.tier = Some(self.tier);
        scene.solver.element = Some(self.element);
        // The tier key alone decides: a scene's own flesh / flexion keys would contradict it.
        scene.solver.flesh = None;
        scene.solver.flexion = None;
        if let Some(step) = self.step_deg {
            scene.solver.max_step_deg = Some(step);
        }
    }

    /// Why the variant cannot apply to `problem`, by the definition of the tiers (the solver
    /// is asked about everything else).
    pub fn not_applicable(&self, problem: ProblemId) -> Option<String> {
        let hand = problem.is_hand();
        match self.tier {
            TierName::Skinning if !hand => Some(
                "geometry only: skinning moves flesh with bones; a body without bones gets no \
                 mechanics and no stress"
                    .into(),
            ),
            TierName::Incremental | TierName::Corotational if !hand => Some(
                "a scheme of hand flexion increments; a scene without a hand gets the linear \
                 static solve"
                    .into(),
            ),
            _ if hand && self.element != ElementName::Hex8 => {
                Some("hand flexion increments and the grasp's contact solve use hex8 only".into())
            }
            TierName::Nonlinear if self.element != ElementName::Hex8 => Some(
                "the nonlinear tier has its own hexahedron (mean dilatation); `element` selects \
                 the element of the linear solve"
                    .into(),
            ),
            _ => None,
        }
    }
}

/// The variants run on `problem`, fastest tier first: every tier, each element kind for the
/// static problems, each step of `steps` for the incremental tiers of the hand problems.
/// Variants that do not apply are listed too (their rows say why).
pub fn variants(problem: ProblemId, steps: &[f64]) -> Vec<Variant> {
    let mut out = Vec::new();
    for tier in HAND_TIERS {
        let stepped = matches!(tier, TierName::Incremental | TierName::Corotational);
        if problem.is_hand() {
            if stepped {
                out.extend(steps.iter().map(|&s| Variant {
                    step_deg: Some(s),
                    ..Variant::new(tier)
                }));
            } else {
                // Skinning and the linear tier have no increments; the nonlinear tier keeps
                // the scene's step (10°).
                out.push(Variant::new(tier));
            }
        } else {
            out.push(Variant::new(tier));
            if tier == TierName::Linear {
                out.push(Variant {
                    element: ElementName::IncompatibleModes,
                    ..Variant::new(tier)
                });
            }
        }
    }
    out
}

/// The hand tiers that may give a hand problem's reference, most exact first.
pub fn reference_candidates(step: f64) -> Vec<Variant> {
    [TierName::Nonlinear, TierName::Corotational]
        .into_iter()
        .map(|tier| Variant {
            step_deg: Some(step),
            ..Variant::new(tier)
        })
        .collect()
}
