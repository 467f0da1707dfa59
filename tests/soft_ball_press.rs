//! A soft solid ball pressed far by the index (issue 15: every pose reachable by joint motion
//! converges). The finger closes from touching (MCP 21°) to MCP 45° into a solid rubber ball
//! of E = 100 kPa, 8 cells across, held by a patch at its base above a table: the pad dents the
//! coarse ball into a pit whose facets fold around the fingertip. Two things used to stop the
//! motion there: a skin point held on the facet it went through slid over the facet's edge
//! and was left behind the next, folded, facet (corotational tier: stopped at 60 % of the
//! keyframe); and, on the nonlinear tier, the squeezed ball's exact Neo-Hookean tangent
//! turned indefinite, which was reported as "some part of the model can still move without
//! deforming" (stopped at 40 %).

use crate::common;

use nalgebra::Vector3;
use prehensile::headless::{solve_scene, Solved};
use prehensile::scene::Scene;
use prehensile::state::KeyframeStats;

const SCENE: &str = r#"
[world]
gravity = [0.0, 0.0, -9.81]

[solver]
max_step_deg = 10.0
contact = "lagrange"
TIER

[[material]]
name = "flesh"
young = 5.0e4
poisson = 0.45
density = 1050.0

[[material]]
name = "rubber"
young = 1.0e5
poisson = 0.4
density = 1100.0

[[body]]
name = "hand"
material = "flesh"
shape = { hand = { side = "right", resolution = 0.5 } }
pose = { "index.mcp.flex" = 20.0, "middle.mcp.flex" = -10.0, "ring.mcp.flex" = -10.0, "little.mcp.flex" = -10.0 }

[[body]]
name = "ball"
material = "rubber"
shape = { sphere = { center = [0.160, 0.030, -0.070], radius = 0.035, cells = 8 } }

[[constraint]]
name = "stand"
body = "ball"
where = { box = { min = [0.150, 0.020, -0.106], max = [0.170, 0.040, -0.1035] } }
displacement = [0.0, 0.0, 0.0]

[[obstacle]]
name = "table"
shape = { plane = { point = [0.0, 0.0, -0.105], normal = [0.0, 0.0, 1.0] } }

[[keyframe]]
time = 1.0
pose = { "index.mcp.flex" = 21.0 }

[[keyframe]]
time = 2.0
pose = { "index.mcp.flex" = MCP }
"#;

/// The press to `mcp` degrees on `tier`, solved.
fn press(tier: &str, mcp: f64) -> Solved {
    let text = SCENE
        .replace("TIER", &format!("tier = \"{tier}\""))
        .replace("MCP", &format!("{mcp:.1}"));
    let scene = Scene::parse(&text, "soft-press.toml").unwrap();
    solve_scene(&scene, "soft-press.toml").unwrap_or_else(|e| panic!("{tier}: {e}"))
}

/// Asserts the press reached MCP `mcp` with the contact converged (no contact point inside the
/// ball beyond the limit, by the solver's projections and by winding numbers on the deformed
/// geometry) and returns the force on the pad (N).
fn reached(solved: &Solved, mcp: f64) -> f64 {
    let (first, last) = (&solved.frames[1], solved.frames.last().unwrap());
    let h = &last.hands[0];
    assert!(
        h.stats.stopped_short.is_none(),
        "{:?}",
        h.stats.stopped_short
    );
    let model = &solved.model;
    let skeleton = &model.bodies[0].hand.as_ref().unwrap().skeleton;
    let dof = skeleton
        .dofs
        .iter()
        .position(|d| d.name == "index.mcp.flex")
        .unwrap();
    assert!((h.angles[dof] - mcp).abs() < 1e-9, "MCP {}°", h.angles[dof]);
    let c = last.contact.as_ref().unwrap();
    assert!(
        c.max_penetration <= model.contact.penetration_limit(),
        "{} m",
        c.max_penetration
    );
    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    let (skin_depth, _, contact_depth) = common::skins_depth_inside(model, last, 0, ball);
    assert!(
        contact_depth <= model.contact.penetration_limit(),
        "the contact skin is {} mm inside the ball",
        contact_depth * 1e3
    );
    let press = |frame: &prehensile::state::Frame| frame.contact.as_ref().unwrap().normal_force();
    let imbalance = Vector3::from(solved.report.frames.last().unwrap().equilibrium.imbalance);
    println!(
        "MCP {mcp}°: {:.2} N on the pad (MCP 21°: {:.3} N), {} contact steps ({} redone), contact \
         skin {:.3} mm inside (display skin, finer than the lattice: {:.3} mm), out of balance \
         {:.2e} N",
        press(last),
        press(first),
        h.stats.contact_steps,
        h.stats.contact_retries,
        contact_depth * 1e3,
        skin_depth * 1e3,
        imbalance.norm()
    );
    assert!(imbalance.norm() < 1e-9, "{imbalance:?}");
    // Far deeper than where it touched: the pad presses many times harder.
    assert!(press(last) > 5.0 * press(first));
    press(last)
}

#[test]
fn the_corotational_press_follows_the_pad_into_the_folded_ball() {
    let solved = press("corotational", 45.0);
    reached(&solved, 45.0);
}

#[test]
fn the_nonlinear_press_goes_on_where_the_balls_tangent_turns_indefinite() {
    let solved = press("nonlinear", 38.0);
    reached(&solved, 38.0);
    // Settled at the pose: until 2026-12-06 the steps along the motion (one Newton iteration
    // each) drifted to twice the press, the first correction from there failed, and the frame
    // kept the drifted press (`prehensile solve` exited 2). Now followed again with each step
    // iterated at its own pose (src/solve/iterated_steps.rs).
    let stats = &solved.frames.last().unwrap().hands[0].stats;
    println!(
        "{} contact steps, {} corrections at the pose, {} redone, unsettled {:?}",
        stats.contact_steps, stats.pose_corrections, stats.contact_retries, stats.unsettled_at_pose
    );
    assert!(
        stats.correction_failed.is_none(),
        "{:?}",
        stats.correction_failed
    );
    assert!(
        stats.unsettled_at_pose.unwrap_or(0.0) <= KeyframeStats::UNSETTLED_WARNING,
        "{:?}",
        stats.unsettled_at_pose
    );
    // The same press on the corotational tier (which settles there): the two laws differ at
    // this strain (the contact force on the index measured 12.45 against 13.83 N, 10 %); the
    // drifted frame's was twice the settled one (25.30 N; its distal bone 24.96 against
    // 10.86 N).
    let on_index = |solved: &Solved| {
        solved.report.frames.last().unwrap().hands["hand"].contact["index"].magnitude
    };
    let corotational = press("corotational", 38.0);
    reached(&corotational, 38.0);
    let (nonlinear, corotational) = (on_index(&solved), on_index(&corotational));
    println!("on the index: nonlinear {nonlinear:.3} N, corotational {corotational:.3} N");
    assert!(
        (nonlinear - corotational).abs() < 0.15 * corotational,
        "{nonlinear} against {corotational}"
    );
}

/// The shipped finger press on its hollow ball softened to 1.124 MPa (the modulus the strain
/// advice gives for a 10 kPa ball, tests/stability.rs (f), × 1.01), corotational tier. Its
/// corrections at the pose used to swing from one to the next (frame 1 still changing by 29 %
/// after six, frame 0 by 12 %), and one at the last pose failed with a ball node that would
/// move 0.10 m in one step — the index's distal bone felt 8.6 N at MCP 21°. Relaxed by
/// Aitken's Δ² on the carried state (2026-11-27) every frame settles within the report's
/// warning threshold, nothing is left inside the ball, and the distal bone's reaction agrees
/// with the nonlinear tier's (Neo-Hookean ball, exact tangent) within 15 % at both poses
/// (measured 4.21 / 4.72 N against 4.72 / 5.24 N: the two laws differ at this strain).
#[test]
fn the_soft_hollow_balls_corrections_settle_on_the_corotational_tier() {
    let asset = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    assert!(asset.contains("young = 2.0e6") && asset.contains("contact = \"lagrange\"\n"));
    let soft = asset.replace("young = 2.0e6", "young = 1.124e6");
    let solve = |text: &str| {
        let scene = Scene::parse(text, "soft-hollow.toml").unwrap();
        solve_scene(&scene, "soft-hollow.toml").unwrap()
    };
    let distal = |solved: &Solved| -> Vec<f64> {
        let model = &solved.model;
        let skeleton = &model.bodies[0].hand.as_ref().unwrap().skeleton;
        let bone = skeleton.bone_index("index.distal").unwrap();
        solved.frames[1..]
            .iter()
            .map(|f| f.hands[0].bone_reactions[bone].norm())
            .collect()
    };
    let corotational = solve(&soft);
    let warnings = &corotational.report.warnings;
    assert!(
        !warnings
            .iter()
            .any(|w| w.contains("corrections at the pose") || w.contains("correction at the pose")),
        "{warnings:#?}"
    );
    let model = &corotational.model;
    for (i, frame) in corotational.frames.iter().enumerate() {
        let stats = &frame.hands[0].stats;
        println!(
            "frame {i}: {} corrections, unsettled {:?}",
            stats.pose_corrections, stats.unsettled_at_pose
        );
        assert!(
            stats.correction_failed.is_none(),
            "{:?}",
            stats.correction_failed
        );
        assert!(
            stats.unsettled_at_pose.unwrap_or(0.0)
                <= prehensile::state::KeyframeStats::UNSETTLED_WARNING,
            "frame {i}: {:?}",
            stats.unsettled_at_pose
        );
        let c = frame.contact.as_ref().unwrap();
        assert!(
            c.max_penetration <= model.contact.penetration_limit(),
            "frame {i}: {} m",
            c.max_penetration
        );
    }
    let nonlinear = solve(&soft.replace(
        "contact = \"lagrange\"\n",
        "contact = \"lagrange\"\ntier = \"nonlinear\"\n",
    ));
    let (a, b) = (distal(&corotational), distal(&nonlinear));
    println!("index.distal: corotational {a:?} N, nonlinear {b:?} N");
    for (a, b) in a.iter().zip(&b) {
        assert!((a - b).abs() < 0.15 * b, "{a} N against {b} N");
    }
}
