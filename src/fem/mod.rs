//! Kernel: elements, materials, loads, assembly, the partitioned solve (6)–(8), Newton.
//! May import the mesh kernel and util only.
//!
//! The finite element core: the 8-node hexahedron (standard, or with incompatible modes),
//! isotropic linear elastic materials, loads, sparse assembly of the stiffness K of equation (5),
//! the partitioned solve of equations (6)–(8), and the nonlinear tier: a Neo-Hookean total
//! Lagrangian hexahedron solved by Newton–Raphson with load stepping.

pub mod added_energy;
pub mod assembly;
pub(crate) mod blocks;
pub mod cavity;
pub mod crush_barrier;
pub mod definite;
pub mod elastic_energy;
pub mod forward;
pub mod geometric;
pub mod hex8;
pub mod hex8_hyperelastic;
pub mod hyperelastic;
pub mod hyperelastic_body;
pub mod incompatible;
pub mod kept_elements;
pub mod loads;
pub mod material;
pub mod memory;
pub mod negative_curvature;
pub mod newton;
pub mod ordering;
pub mod partition;
pub mod quadratic_body;
pub mod rigid;
pub mod solve;
pub mod stress;

pub use assembly::{ElementKind, Stiffness, StiffnessPattern};
pub use hex8_hyperelastic::Volumetric;
pub use material::Material;
pub use newton::{solve_nonlinear, NewtonSettings, NonlinearError, NonlinearSolution};
pub use partition::DofPartition;
pub use solve::{PartitionedSolver, Solution, SolveError, SolveStats};
