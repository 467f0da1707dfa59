//! The Solver and Display panels' models: the solver tier and its settings (written into the
//! scene's `[solver]` table and hand bodies), and how frames are drawn.

pub use crate::model::Tier;
use crate::present::{Overlay, VisualOptions};
use crate::scene::{ContactMethodName, FarFromContact, HandSizeDef, Scene, Shape};

/// The label of `tier` in the Solver panel.
pub fn tier_label(tier: Tier) -> &'static str {
    match tier {
        Tier::Skinning => "skinning",
        Tier::Linear => "linear (rest geometry, factored once)",
        Tier::Incremental => "incremental (updated Lagrangian)",
        Tier::Corotational => "corotational",
        Tier::Nonlinear => "nonlinear (Neo-Hookean, Newton)",
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
    /// Every cell of the hands' lattices split into n × n × n (`subdivisions` of their shape;
    /// 1, the lattice as it is, when absent): the same hand with finer elements.
    pub subdivisions: usize,
    /// The built-in hands' size (`size` of their shape); the built-in hand's own when `None`.
    pub hand_size: Option<HandSizeDef>,
    /// The built-in hands' form (`form` of their shape): `"simple"` or `"anatomical"`.
    pub hand_form: crate::hand::HandForm,
    /// Contact method between hands and objects.
    pub contact: ContactMethodName,
    /// Fingers far from every object follow their bones by skinning (`[solver]
    /// far_from_contact = "skinning"`, the default) rather than being solved.
    pub skin_far_fingers: bool,
    /// The skin kept out of itself (`[solver] self_contact`): a crease's two sides, a fingertip
    /// on the palm, fingers side by side.
    pub self_contact: bool,
}

impl SolverParams {
    /// The settings of `scene`.
    pub fn from_scene(scene: &Scene) -> Self {
        let s = &scene.solver;
        let tier = Tier::of(s);
        let resolution = scene
            .body
            .iter()
            .find_map(|b| match b.shape {
                Shape::Hand { resolution, .. } => Some(resolution),
                _ => None,
            })
            .unwrap_or(1.0);
        let subdivisions = scene
            .body
            .iter()
            .find_map(|b| match b.shape {
                Shape::Hand { subdivisions, .. } => Some(subdivisions.unwrap_or(1)),
                _ => None,
            })
            .unwrap_or(1);
        let hand_size = scene.body.iter().find_map(|b| match &b.shape {
            Shape::Hand {
                gltf: None, size, ..
            } => Some(size.clone()),
            _ => None,
        });
        let hand_form = scene
            .body
            .iter()
            .find_map(|b| match &b.shape {
                Shape::Hand {
                    gltf: None, form, ..
                } => form.as_deref().and_then(crate::hand::HandForm::from_name),
                _ => None,
            })
            .unwrap_or_default();
        SolverParams {
            tier,
            tolerance: 1e-8,
            max_step_deg: s.max_step_deg.unwrap_or(10.0),
            resolution,
            subdivisions,
            hand_size: hand_size.flatten(),
            hand_form,
            contact: s.contact.unwrap_or_default(),
            skin_far_fingers: s.far_from_contact != Some(FarFromContact::Solve),
            self_contact: s.self_contact.unwrap_or(false),
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
        // Written only when changed: a scene's own key (or its absence) stays as it was.
        if s.self_contact.unwrap_or(false) != self.self_contact {
            s.self_contact = Some(self.self_contact);
        }
        // `tier` is written with `flesh` and `flexion` agreeing with it.
        self.tier.write(s);
        for b in &mut scene.body {
            if let Shape::Hand {
                resolution,
                subdivisions,
                gltf,
                size,
                form,
                ..
            } = &mut b.shape
            {
                *resolution = self.resolution;
                // Every hand takes the slider's value, as its resolution; the key is written only
                // where it differs (its absence is 1), so an unsplit scene keeps none.
                if subdivisions.unwrap_or(1) != self.subdivisions {
                    *subdivisions = Some(self.subdivisions);
                }
                if gltf.is_none() {
                    size.clone_from(&self.hand_size);
                    // Written only when it differs from the scene's (its absence is the default form,
                    // anatomical).
                    let now = form.as_deref().and_then(crate::hand::HandForm::from_name);
                    if now.unwrap_or_default() != self.hand_form {
                        *form = Some(self.hand_form.name().to_string());
                    }
                }
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
