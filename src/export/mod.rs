//! Output files from a model and its frames: the JSON report, VTU, OBJ, PNG, atomic writing.
//! May import model, state, the kernels and util.
//!
//! Output files: the JSON report, VTU meshes for ParaView, OBJ hand surfaces for Blender, PNG
//! images, and atomic writing of an output folder.

pub mod gltf_animation;
pub mod hand_geometry;
pub mod output;
pub mod png;
pub mod report;
pub mod vtu;
pub mod vtu_grid;
