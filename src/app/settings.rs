//! The Solver and Display panels' models: the solver tier and its settings (written into the
//! scene's `[solver]` table and hand bodies), and how frames are drawn.

use crate::scene::{FarFromContact, Scene, Shape, TierName};
use crate::sim::{FleshMethod, FlexionScheme};
use crate::visual::{Overlay, VisualOptions};

/// How the hands' flesh is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tier {
    /// Geometric skinning only (the fast path, no mechanics).
    Skinning,
    /// Linear elasticity on the rest geometry: one factorization, one solve per pose.
    Linear,
    /// The paper's linear increments on the updated geometry.
    UpdatedLagrangian,
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
        Tier::UpdatedLagrangian,
        Tier::Corotational,
        Tier::Nonlinear,
    ];

    /// The label shown in the Solver panel.
    pub fn label(self) -> &'static str {
        match self {
            Tier::Skinning => "skinning",
            Tier::Linear => "linear (rest geometry, factored once)",
            Tier::UpdatedLagrangian => "incremental (updated Lagrangian)",
            Tier::Corotational => "corotational",
            Tier::Nonlinear => "nonlinear (Neo-Hookean, Newton)",
        }
    }

    /// The scene's `[solver] tier` value.
    pub fn scene_name(self) -> TierName {
        match self {
            Tier::Skinning => TierName::Skinning,
            Tier::Linear => TierName::Linear,
            Tier::UpdatedLagrangian => TierName::Incremental,
            Tier::Corotational => TierName::Corotational,
            Tier::Nonlinear => TierName::Nonlinear,
        }
    }
}

/// The Solver panel.
#[derive(Clone, Debug, PartialEq)]
pub struct SolverParams {
    /// The tier.
    pub tier: Tier,
    /// Largest relative residual accepted before the status panel flags a solve.
    pub tolerance: f64,
    /// Largest joint rotation per increment, degrees.
    pub max_step_deg: f64,
    /// Hand mesh resolution (0.5 … 4; 1 is the default 3.2 mm lattice).
    pub resolution: f64,
    /// Contact method between hands and objects.
    pub contact: crate::contact::ContactMethod,
    /// Fingers far from every object follow their bones by skinning (`[solver]
    /// far_from_contact = "skinning"`, the default) rather than being solved.
    pub skin_far_fingers: bool,
}

impl SolverParams {
    /// The settings of `scene`.
    pub fn from_scene(scene: &Scene) -> Self {
        let s = &scene.solver;
        let tier = match (s.tier, s.flesh, s.flexion) {
            (Some(TierName::Skinning), _, _) | (None, Some(FleshMethod::Skinning), _) => {
                Tier::Skinning
            }
            (Some(TierName::Linear), _, _) | (None, _, Some(FlexionScheme::Linear)) => Tier::Linear,
            (Some(TierName::Incremental), _, _)
            | (None, _, Some(FlexionScheme::UpdatedLagrangian)) => Tier::UpdatedLagrangian,
            (Some(TierName::Nonlinear), _, _) | (None, _, Some(FlexionScheme::Nonlinear)) => {
                Tier::Nonlinear
            }
            _ => Tier::Corotational,
        };
        let resolution = scene
            .body
            .iter()
            .find_map(|b| match b.shape {
                Shape::Hand { resolution, .. } => Some(resolution),
                _ => None,
            })
            .unwrap_or(1.0);
        SolverParams {
            tier,
            tolerance: 1e-8,
            max_step_deg: s.max_step_deg.unwrap_or(10.0),
            resolution,
            contact: s.contact.unwrap_or_default(),
            skin_far_fingers: s.far_from_contact != Some(FarFromContact::Solve),
        }
    }

    /// Writes these settings into `scene`.
    pub fn apply(&self, scene: &mut Scene) {
        let s = &mut scene.solver;
        s.max_step_deg = Some(self.max_step_deg);
        s.contact = Some(self.contact);
        s.far_from_contact = Some(if self.skin_far_fingers {
            FarFromContact::Skinning
        } else {
            FarFromContact::Solve
        });
        // `tier` is written with `flesh` and `flexion` agreeing with it.
        s.tier = Some(self.tier.scene_name());
        match self.tier {
            Tier::Skinning => s.flesh = Some(FleshMethod::Skinning),
            Tier::Linear | Tier::UpdatedLagrangian | Tier::Corotational | Tier::Nonlinear => {
                s.flesh = Some(FleshMethod::Fem);
                s.flexion = Some(match self.tier {
                    Tier::Linear => FlexionScheme::Linear,
                    Tier::UpdatedLagrangian => FlexionScheme::UpdatedLagrangian,
                    Tier::Nonlinear => FlexionScheme::Nonlinear,
                    _ => FlexionScheme::Corotational,
                });
            }
        }
        for b in &mut scene.body {
            if let Shape::Hand { resolution, .. } = &mut b.shape {
                *resolution = self.resolution;
            }
        }
    }
}

/// What the Display panel's overlay menu offers.
pub const OVERLAYS: [(Overlay, &str); 5] = [
    (Overlay::Pressure, "contact pressure"),
    (Overlay::Stress, "von Mises stress"),
    (Overlay::Displacement, "displacement"),
    (Overlay::Forces, "forces"),
    (Overlay::None, "none"),
];

/// The Display panel.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplayParams {
    /// Skin opacity (1 opaque).
    pub skin_opacity: f32,
    /// Draw bones (when the skin is translucent).
    pub bones: bool,
    /// Draw the simulation mesh's edges.
    pub wireframe: bool,
    /// The overlay.
    pub overlay: Overlay,
    /// Colour range from the data (`true`) or `fixed`.
    pub auto_range: bool,
    /// The fixed colour range, in the overlay's unit.
    pub fixed_range: [f32; 2],
}

impl Default for DisplayParams {
    fn default() -> Self {
        DisplayParams {
            skin_opacity: 0.6,
            bones: true,
            wireframe: false,
            overlay: Overlay::None,
            auto_range: true,
            fixed_range: [0.0, 1.0e4],
        }
    }
}

impl DisplayParams {
    /// The options the draw list is built with.
    pub fn visual(&self) -> VisualOptions {
        VisualOptions {
            overlay: self.overlay,
            displacement_scale: 1.0,
            wireframe: self.wireframe,
            skin_opacity: self.skin_opacity,
            bones: self.bones,
        }
    }

    /// The colour range to draw with, given the automatic one: never NaN, never empty.
    pub fn range(&self, auto: [f32; 2]) -> [f32; 2] {
        let r = if self.auto_range {
            auto
        } else {
            self.fixed_range
        };
        crate::render::guard_range(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overlay_menu_offers_every_overlay() {
        for o in [
            Overlay::None,
            Overlay::Stress,
            Overlay::Displacement,
            Overlay::Forces,
            Overlay::Pressure,
        ] {
            // A new overlay breaks this match, and so must be added to the list above.
            match o {
                Overlay::None
                | Overlay::Stress
                | Overlay::Displacement
                | Overlay::Forces
                | Overlay::Pressure => {}
            }
            assert!(OVERLAYS.iter().any(|(x, _)| *x == o), "{o:?}");
        }
    }
}
