//! Small helpers (timing, glTF's axes) every folder may use.
//! Imports nothing of the crate.

pub mod gltf_axes;
pub mod timing;
