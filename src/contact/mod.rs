//! Kernel: contact detection and projection, the paper's iteration, the exact methods, friction.
//! May import the mesh and fem kernels and util only.
//!
//! Contact: deformable bodies against rigid obstacles (a table plane, a rigid sphere) and against
//! each other (node to facet, both ways), by the paper's repel–prescribe–release iteration or by
//! an active set of Lagrange multipliers solved through a Schur complement that reuses the
//! stiffness factorization, with Coulomb friction; the tactile map; and whether a grip's forces hold an object (`hold.rs`).

mod along_surface;
mod barrier;
mod bounds;
mod coulomb;
#[cfg(test)]
mod differences;
mod edge_edge;
mod edge_pairs;
mod embedded;
mod exterior;
mod hold;
mod lagrange;
mod obstacle;
mod paper;
mod patch;
mod point;
mod pressure;
mod problem;
mod quasi_newton;
mod row;
mod self_barrier;
mod self_contact;
mod surface;
mod swept;
mod winding;

pub use along_surface::SurfaceEdges;
pub use barrier::{
    barrier, pair_barrier, point_triangle_derivatives, point_triangle_distance2, project_psd,
    PairBarrier, PointTriangle,
};
pub use bounds::Bounds;
pub use edge_edge::{
    edge_edge_derivatives, edge_edge_distance2, edge_edge_mollifier, edge_edge_mollifier_threshold,
    edge_pair_barrier, EdgeMollifier,
};
pub use embedded::EmbeddedPoints;
pub use exterior::exterior_quads;
pub use hold::{hold_margin, GripContact, HoldMargin, MAX_MARGIN};
pub use lagrange::{solve_lagrange, solve_with_obstacles, RUNAWAY};
pub use obstacle::Obstacle;
pub use paper::solve_paper;
pub use patch::patch_pressure;
pub use point::{
    held_nodes, transferred_forces, Adhesion, ContactError, ContactMethod, ContactPoint,
    ContactResult, ContactSettings, ContactSummary, ContactTimes, Master, PairSides, Relaxation,
    DEFAULT_MAX_ITERATIONS,
};
pub use pressure::{nodal_pressure, nodal_pressure_with};
pub use problem::{ContactProblem, Crossing, FrictionLaw, StopCheck, SurfacePair};
pub use self_barrier::SelfBarrier;
pub use self_contact::OwnNeighbourhood;
pub use surface::{connected_pieces, project_on_triangle, ContactSurface, Projection, SurfaceBvh};
pub use swept::{edges_cross, passes_through};
pub use winding::{vertices_inside_itself, winding_number_of, WindingTree};
