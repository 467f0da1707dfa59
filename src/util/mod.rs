//! Small helpers (timing) every folder may use.
//! Imports nothing of the crate.

pub mod timing;
