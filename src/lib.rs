//! Prehensile: finite element simulation of object and human skin deformations in a grasping task,
//! after Gourret, Magnenat-Thalmann & Thalmann (1989), "Simulation of Object and Human Skin
//! Deformations in a Grasping Task".
//!
//! The solver core (`mesh`, `fem`, `sim`) never depends on a renderer or a UI.
//!
//! Units are SI everywhere: metres, newtons, pascals, kilograms per cubic metre.

pub mod bench;
pub mod export;
pub mod fem;
pub mod mesh;
pub mod pipeline;
pub mod scene;
pub mod sim;
