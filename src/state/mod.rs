//! What a solve produces: frames, hand states, keyframe statistics, overloads, derived quantities.
//! May import model, the kernels and util.

mod cavity;
mod crushed;
mod finite;
mod frame;
mod grip;
mod hand;
pub mod outcome;
mod tactile;
mod validity;

pub use cavity::{cavity_state, CavityState};
pub use crushed::{
    crushed_flesh, pressed_inside_out, CrushedFlesh, InsideOut, CRUSH_WARNING_VOLUME,
};
pub use finite::{first_non_finite, NonFinite};
pub use frame::{Frame, HandFrame, PendingStress};
pub use grip::{grip, mass_centre, GraspOutcome, Grip, GripTrial};
pub use hand::{blend_forces, HandState, KeyframeStats, StoppedShort, UnsettledMotion};
pub use tactile::{
    contact_pressure, contact_skin_pressure, self_contact_patch_pressure,
    self_contact_skin_pressure, skin_patch_pressure, skin_pressure, tactile_peaks, TactilePeaks,
    TACTILE_PATCH_RADIUS,
};
pub use validity::{largest_strains, small_strain_warnings, STRAIN_WARNING};
