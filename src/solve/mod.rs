//! The one keyframe driver and what it runs (flexion per tier, statics, contact); its workspace.
//! May import model, state, the kernels and util.

mod anticipate;
mod compose;
mod corotated;
mod crossing;
mod detection;
mod driver;
mod error;
mod far_strain;
mod flexion;
mod flexion_barrier;
mod flexion_nonlinear;
mod frame_stress;
mod gas;
mod gentle_grip;
mod grasp;
mod hyperelastic_objects;
mod insides;
mod iterated_steps;
mod knot_memo;
mod let_go;
mod linear_factor;
mod objects_factor;
mod paper_roles;
mod path;
mod prepare;
mod preview;
pub mod proximity;
mod region;
mod self_contact;
pub(crate) use self_contact::NEIGHBOURHOOD as SELF_CONTACT_NEIGHBOURHOOD;
mod stabilize;
mod statics;
mod statics_nonlinear;
mod step_control;
mod untouched;

pub use driver::{solve_frames, Posed, PosedHand, Workspace, CONTACT_CORRECTION, CONTACT_STEP_DEG};
pub use error::SimError;
pub use flexion::{CancelCheck, Flexion, FlexionCaches};
pub use flexion_nonlinear::flesh_internal_forces;
pub use frame_stress::complete as complete_stress;
pub use linear_factor::LinearFactor;
pub use preview::skinned_preview;
pub use statics::solve_static;
