//! Small helpers (timing, glTF's axes, numbers in messages) every folder may use.
//! Imports nothing of the crate.

pub mod convergence;
pub mod gltf_axes;
pub mod near;
pub mod number;
pub mod read;
pub mod shown;
pub mod timing;
pub use number::readable;
pub use shown::shown;
