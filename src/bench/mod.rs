//! Every `prehensile bench` command: each file measures one thing and prints a table.
//! May import every stage, kernel and front-end but cli.

pub mod accuracy;
pub mod contact;
pub mod elements;
pub mod flexion_refinement;
pub mod gentle;
pub mod grasp;
pub mod hand;
pub mod region;
pub mod render;
pub mod self_contact;
pub mod solver;
pub mod viewer;
pub mod viewer_contact;
