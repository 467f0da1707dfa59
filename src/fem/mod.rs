//! The finite element core: the 8-node hexahedron, isotropic linear elastic materials, loads,
//! sparse assembly of the stiffness K of equation (5), and the partitioned solve of
//! equations (6)–(8).

pub mod assembly;
pub mod hex8;
pub mod loads;
pub mod material;
pub mod memory;
pub mod ordering;
pub mod partition;
pub mod rigid;
pub mod solve;
pub mod stress;

pub use assembly::{Stiffness, StiffnessPattern};
pub use material::Material;
pub use partition::DofPartition;
pub use solve::{PartitionedSolver, Solution, SolveError, SolveStats};
