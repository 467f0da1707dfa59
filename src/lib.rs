//! Prehensile: finite element simulation of object and human skin deformations in a grasping task,
//! after Gourret, Magnenat-Thalmann & Thalmann (1989), "Simulation of Object and Human Skin
//! Deformations in a Grasping Task".
//!
//! The data flow is in the folder names: `scene` → `model` → `solve` (per keyframe) → `state` →
//! `present` / `render` / `export`, with the kernels `mesh`, `fem`, `contact` and `hand` below
//! them all, and the front-ends `cli`, `app`, `headless` and `bench` above (docs/architecture.md).
//!
//! Units are SI everywhere: metres, newtons, pascals, kilograms per cubic metre.
//!
//! ```
//! use prehensile::headless::solve_scene;
//! use prehensile::scene::Scene;
//!
//! // A 1 m rubber cube, clamped below, its top face pulled 1 mm up.
//! let scene = Scene::parse(r#"
//!     [[material]]
//!     name = "rubber"
//!     young = 1.0e6
//!     poisson = 0.3
//!     [[body]]
//!     name = "block"
//!     material = "rubber"
//!     shape = { box = { min = [0, 0, 0], max = [1, 1, 1], cells = [4, 4, 4] } }
//!     [[constraint]]
//!     name = "base"
//!     body = "block"
//!     where = { face = "z-" }
//!     displacement = [0, 0, 0]
//!     [[constraint]]
//!     name = "pull"
//!     body = "block"
//!     where = { face = "z+" }
//!     displacement = { z = 0.001 }
//! "#, "example").unwrap();
//! let solved = solve_scene(&scene, "example").unwrap();
//! let frame = &solved.report.frames[0];
//! // Equation (8): the two supports' reactions balance, and pulling needs at least E·ε·A = 1 kN.
//! let (base, pull) = (frame.constraints["base"].reaction, frame.constraints["pull"].reaction);
//! assert!((base[2] + pull[2]).abs() < 1e-9);
//! assert!(pull[2] > 1.0e3 && pull[2] < 1.2e3);
//! ```

pub mod app;
pub mod bench;
pub mod cli;
pub mod contact;
pub mod export;
pub mod fem;
pub mod hand;
pub mod headless;
pub mod mesh;
pub mod model;
pub mod present;
pub mod render;
pub mod scene;
pub mod solve;
pub mod state;
pub mod util;
