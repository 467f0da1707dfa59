//! The integration tests, one binary: every file of `tests/` is a module of it, so the test
//! threads share the whole suite (a long test runs beside the others instead of alone at the
//! end of its own binary) and the crate links once. Run one file's tests with its module's
//! name as the filter: `cargo test --release --test suite let_go::`.

mod common;

mod accuracy;
mod advice_followed;
mod analytic;
mod architecture;
mod bench_cli;
mod contact;
mod contact_drag;
mod contact_report;
mod deformable_contact;
mod embedded_contact;
mod exports;
mod far_from_contact;
mod fist_refinement;
mod friction_grasp;
mod fuzz_scenes;
mod gas_cavity;
mod gentle_grip;
mod graded_balls;
mod grasp_extremes;
mod grasp_presets;
mod grip_convergence;
mod hand;
mod hand_form;
mod hand_import;
mod hand_placement;
mod hand_rig_export;
mod hand_scene;
mod hand_size;
mod hardening;
mod hertz_refined;
mod independent_reference;
mod let_go;
mod linear_tier;
mod malformed_scenes;
mod neo_hookean_objects;
mod nonlinear;
mod nonlinear_hand;
mod objects_factor;
mod pad_refinement;
mod paper_along_motion;
mod patch_test;
mod pinch;
mod region;
mod release;
mod render_cli;
mod render_snapshots;
mod resume_from_frame;
mod scene_files;
mod self_contact;
mod skinning_tier;
mod soft_ball_press;
mod solver;
mod stability;
mod viewer_grasp;
mod viewer_presets;
mod viewer_ui;
mod viewer_window;
mod volumetric_key;
