//! Output files: the JSON report, VTU meshes for ParaView, and atomic writing of an output folder.

pub mod output;
pub mod report;
pub mod vtu;
