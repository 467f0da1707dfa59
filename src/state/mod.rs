//! State: what a solve produces — frames, hand states, keyframe statistics, bone overloads — and
//! what is derived from them (tactile map, strain checks). Imports the model and the kernels.

mod frame;
mod hand;
pub mod outcome;
mod tactile;
mod validity;

pub use frame::{Frame, HandFrame};
pub use hand::{HandState, KeyframeStats};
pub use tactile::contact_pressure;
pub use validity::{largest_strains, small_strain_warnings, STRAIN_WARNING};
