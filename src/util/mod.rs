//! Small helpers every folder may use; imports nothing of the crate.

pub mod timing;
