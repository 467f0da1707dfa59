//! Every `prehensile bench` command: each file measures one thing and prints a Markdown table.
//! May import every stage below the front-ends (and the viewer's state, for `bench viewer`).

pub mod accuracy;
pub mod contact;
pub mod elements;
pub mod hand;
pub mod region;
pub mod render;
pub mod solver;
pub mod viewer;
