//! Output files: the JSON report, VTU meshes for ParaView, PNG images, and atomic writing of an
//! output folder.

pub mod output;
pub mod png;
pub mod report;
pub mod vtu;
