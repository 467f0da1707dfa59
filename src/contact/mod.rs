//! Contact. Today: deformable bodies against rigid obstacles (a table plane, a rigid sphere),
//! frictionless, enforced exactly at convergence by an active set of Lagrange multipliers solved
//! through a Schur complement that reuses the stiffness factorization.

mod lagrange;
mod obstacle;
mod pressure;

pub use lagrange::{
    solve_with_obstacles, ContactError, ContactPoint, ContactResult, ContactSettings,
};
pub use obstacle::Obstacle;
pub use pressure::nodal_pressure;
