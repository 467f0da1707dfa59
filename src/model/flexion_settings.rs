//! How the hands' flesh moves: the flexion settings resolved from `[solver]` (method per part,
//! increment scheme, FEM region, skinning blend, volumetric integration, near-contact distance).

use crate::contact::ContactSettings;
use crate::fem::Volumetric;
use crate::hand::Blend;

/// How the flesh of a digit (or of the palm) moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FleshMethod {
    /// Finite elements, incremental updated Lagrangian.
    #[default]
    Fem,
    /// Geometric skinning only.
    Skinning,
}

/// How an increment's stiffness treats the rotation of the flesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FlexionScheme {
    /// The paper's scheme: K assembled on the current geometry, K·ΔU = 0 with the bones'
    /// ΔU prescribed. A finite rotation is not a zero-energy motion of a linear increment, so
    /// flesh that turns with a bone picks up O(θ²) spurious strain per increment.
    UpdatedLagrangian,
    /// The same increments with each element's stiffness turned by the rotation its nodes
    /// follow (from the skinning blend of the bones' incremental motions): K̃ = Σ R K_e Rᵀ,
    /// K̃·y = Σ R K_e x, so that flesh turning with a bone turns without strain.
    #[default]
    Corotational,
    /// No increments: small-strain linear elasticity on the rest geometry, K factored once per
    /// hand and each keyframe one solve with the bones' total displacement from rest prescribed
    /// (`solve::LinearFactor`). Fast, but a finite rotation is strain to it: flesh that turns
    /// with a bone swells.
    Linear,
    /// The same increments, each solved to equilibrium at large strain: Neo-Hookean flesh
    /// (mean dilatation, valid to ν → ½), total Lagrangian on the rest flesh mesh,
    /// Newton–Raphson with a line search (`solve::flexion_nonlinear`). No linearisation error
    /// accumulates over increments.
    Nonlinear,
}

/// Which cells the FEM solves in an increment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FleshRegion {
    /// Every FEM cell of the hand.
    Whole,
    /// The FEM cells whose centre lies within `radius` (m) of a joint that moves.
    Local {
        /// Radius, m.
        radius: f64,
    },
}

/// Settings of the incremental flexion.
#[derive(Clone, Debug)]
pub struct FlexionSettings {
    /// Largest joint rotation per increment, degrees.
    pub max_step_deg: f64,
    /// Region solved by FEM.
    pub region: FleshRegion,
    /// Method of the palm (index 0) and of each digit (1 = thumb … 5 = little).
    pub methods: [FleshMethod; 6],
    /// Skinning blend.
    pub blend: Blend,
    /// Increment scheme.
    pub scheme: FlexionScheme,
    /// Volumetric integration of the Neo-Hookean flesh of [`FlexionScheme::Nonlinear`] (mean
    /// dilatation by default: no volumetric locking; `Full` is the fully integrated hex8,
    /// which at small strain is the element of the other schemes).
    pub volumetric: Volumetric,
    /// In a scene with other bodies, the parts of a hand (palm, thumb, fingers) that stay
    /// farther than this (m) from all of them over a keyframe are not solved by FEM: their
    /// flesh follows the bones by skinning (`solve::proximity`). `None`: every part is solved
    /// as `methods` says.
    pub near_contact: Option<f64>,
    /// Self-contact of the skin in the increments (the contact settings it is solved with), or
    /// `None` (the default) when the skin may pass through itself. Experimental, asked for by
    /// `[solver] self_contact = true`; solved by a barrier in the corotational, the paper's and the
    /// nonlinear increments (docs/hand.md, "Self-contact").
    pub self_contact: Option<ContactSettings>,
}

impl Default for FlexionSettings {
    fn default() -> Self {
        FlexionSettings {
            max_step_deg: 10.0,
            region: FleshRegion::Local { radius: 0.012 },
            methods: [FleshMethod::Fem; 6],
            blend: Blend::DualQuaternion,
            scheme: FlexionScheme::Corotational,
            volumetric: Volumetric::MeanDilatation,
            near_contact: Some(0.01),
            self_contact: None,
        }
    }
}
