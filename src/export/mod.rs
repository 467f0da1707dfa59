//! Output files from a model and its frames: the JSON report, VTU, OBJ, glTF, PNG, atomic writing.
//! May import model, state, the kernels and util.
//!
//! Output files: the JSON report, VTU meshes for ParaView, OBJ hand surfaces and the animated
//! glTF for Blender, the built-in hand as a rigged glTF, PNG images, and atomic writing of an
//! output folder.

pub mod glb;
pub mod gltf_animation;
pub mod hand_geometry;
pub mod hand_rig;
pub mod output;
pub mod png;
pub mod report;
pub mod rig_mesh;
pub mod vtu;
pub mod vtu_grid;
