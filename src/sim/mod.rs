//! The model built from a scene (immutable: mesh, materials, constraints, loads) and the solves
//! that produce the state: the static solve of a frame, and the incremental flexion of a hand.

mod flexion;
mod flexion_nonlinear;
mod grasp;
mod linear_tier;
mod model;
mod motion;
pub mod outcome;
pub mod proximity;
mod select;
mod stabilize;
mod statics;
mod statics_nonlinear;
mod tactile;
mod tier;
mod validity;

pub use flexion::{
    CancelCheck, FleshMethod, FleshRegion, Flexion, FlexionScheme, FlexionSettings, HandState,
    KeyframeStats,
};
pub use flexion_nonlinear::flesh_internal_forces;
pub use grasp::{frame_with_hands, solve_grasp};
pub use linear_tier::LinearTier;
pub use model::{BodyModel, ConstraintModel, KeyframeModel, LoadModel, Model, ProbeModel};
pub use motion::{compose, hand_frame, set_far_parts, solve_frames, still_frame};
pub use statics::{solve_static, Frame, HandFrame, SimError};
pub use tactile::contact_pressure;
pub use tier::STEP_WARNING_DEG;
pub use validity::{largest_strains, small_strain_warnings, STRAIN_WARNING};
