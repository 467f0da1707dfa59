//! The model built from a scene (immutable: mesh, materials, constraints, loads) and the solves
//! that produce the state: the static solve of a frame, and the incremental flexion of a hand.

mod flexion;
mod model;
mod motion;
mod select;
mod statics;
mod statics_nonlinear;
mod tactile;

pub use flexion::{
    CancelCheck, FleshMethod, FleshRegion, Flexion, FlexionScheme, FlexionSettings, HandState,
    KeyframeStats,
};
pub use model::{BodyModel, ConstraintModel, KeyframeModel, LoadModel, Model, ProbeModel};
pub use motion::{compose, hand_frame, solve_frames, still_frame};
pub use statics::{solve_static, Frame, HandFrame, SimError};
pub use tactile::contact_pressure;
