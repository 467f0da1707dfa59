//! The model built from a scene (immutable: mesh, materials, constraints, loads) and the static
//! solve of one frame, which produces the state (displacements, stresses, reactions).

mod model;
mod select;
mod statics;

pub use model::{BodyModel, ConstraintModel, LoadModel, Model, ProbeModel};
pub use statics::{solve_static, Frame, SimError};
