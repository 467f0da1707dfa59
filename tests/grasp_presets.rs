//! The viewer's grasp presets on the built-in default scene, from the hand's pose of the scene:
//! the keyframe's pose puts the skin 18–20 mm into the ball, more than contact linearised at the
//! final pose resolves. The driver then moves the hand in contact steps, each from where the
//! last left the ball and the flesh, and the grasp converges: no penetration left beyond the
//! tolerance, and every body in equilibrium with the contact forces (action = reaction).

use crate::common;

use nalgebra::Vector3;
use prehensile::app::pose::Preset;
use prehensile::bench::grasp::preset_scene;
use prehensile::headless::solve_scene;

fn check_converged_grasp(preset: Preset) {
    check_converged(preset_scene(preset), &format!("{preset:?}"), 0.5);
}

/// The grasp keyframe of `scene` (a hand, a body "ball" on a support "support") converges from
/// a contact-free first frame whose pose drives the flexed flesh `min_depth` of the ball's
/// radius or more into it.
fn check_converged(scene: prehensile::scene::Scene, name: &str, min_depth: f64) {
    let solved = solve_scene(&scene, "grasp.toml").unwrap_or_else(|e| panic!("{name}: {e}"));
    let model = &solved.model;
    // The pose is reached, and the corrections at it settle (what the command line exits
    // non-zero for otherwise).
    assert_eq!(prehensile::headless::unsolved(&solved), None, "{name}");
    let frame = solved.frames.last().unwrap();
    assert!(
        frame.hands[0].stats.stopped_short.is_none(),
        "{name}: stopped short"
    );
    // Every frame leaves the solver with its stresses (a step's are computed only for the frame
    // kept: src/solve/frame_stress.rs), finite, over every node.
    for f in &solved.frames {
        assert_eq!(f.stress_pending, None, "{name}");
        assert_eq!(f.stress.nodal.len(), model.mesh.node_count(), "{name}");
        assert!(f
            .stress
            .nodal
            .iter()
            .all(|s| s.iter().all(|v| v.is_finite())));
    }
    let contact = frame.contact.as_ref().expect("the grasp touches the ball");
    // No interpenetration left beyond what the contact accepts on the moved geometry (its
    // limit, 0.5 mm here); measured 0.1–0.2 µm (2026-11-24), up to 0.12 mm with skin held on
    // the facets it crossed (src/solve/crossing.rs).
    assert!(
        contact.max_penetration <= model.contact.penetration_limit(),
        "{name}: {} m left",
        contact.max_penetration
    );
    let hand = model.bodies.iter().position(|b| b.hand.is_some()).unwrap();
    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    // From a contact-free frame, the pose drives the flexed flesh (the pose without contact)
    // `min_depth` of the ball's radius or more into the ball at rest (measured 2026-11-29: the
    // presets half of it or more — Power grasp 0.51 R, Pinch 0.59 R of R = 35 mm).
    let touching =
        |f: &prehensile::state::Frame| f.contact.as_ref().map_or(0, |c| c.contacts.len());
    assert_eq!(
        touching(&solved.frames[0]),
        0,
        "{name}: the scene's pose touches"
    );
    let rest = &model.mesh.nodes;
    let ball_nodes = model.bodies[ball].nodes.clone();
    let centre =
        ball_nodes.clone().map(|n| rest[n]).sum::<Vector3<f64>>() / ball_nodes.len() as f64;
    let radius = ball_nodes
        .map(|n| (rest[n] - centre).norm())
        .fold(0.0, f64::max);
    let h = &frame.hands[0];
    let depth = h
        .positions
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let flexed = h.contact_displacement.get(i).map_or(*x, |d| x - d);
            radius - (flexed - centre).norm()
        })
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "{name}: the pose drives the flesh {:.2} R into the ball",
        depth / radius
    );
    assert!(
        depth >= min_depth * radius,
        "{name}: {depth} m of R = {radius} m"
    );
    let mut on_hand = Vector3::zeros();
    let mut on_ball = Vector3::zeros();
    for c in &contact.contacts {
        for (n, f) in c.nodal_forces() {
            if model.bodies[hand].nodes.contains(&n) {
                on_hand += f;
            } else if model.bodies[ball].nodes.contains(&n) {
                on_ball += f;
            }
        }
    }
    let grip = on_ball.norm();
    assert!(grip > 0.5, "{name}: grip {grip} N");
    // The contact acts on the smooth skin (issue 15, item 4): the skin the user sees stays out
    // of the ball to within the contact's limit plus as much again for what lies between the
    // contact skin's points (its vertices are held out; the finer display skin between them,
    // and the ball's own corners, are not). Measured 0.57 mm (Pinch) and 0.50 mm (Power grasp),
    // where the lattice's skin nodes, no longer the contact surface, are 1.1 and 1.3 mm in
    // (2026-11-24); 0.29 and 0.47 mm with the display skin moved by the contact skin
    // (2026-12-02, src/hand/skin_follow.rs), and 0.49 mm under a ball 100 times stiffer, where
    // the display skin in its own cells went 1.43 mm in.
    let (skin_depth, lattice_depth) = common::skin_depth_inside(model, frame, hand, ball);
    println!(
        "{name}: display skin {:.3} mm inside the ball, flesh lattice nodes {:.3} mm",
        skin_depth * 1e3,
        lattice_depth * 1e3
    );
    assert!(
        skin_depth <= 2.0 * model.contact.penetration_limit(),
        "{name}: the skin is {} mm inside the ball",
        skin_depth * 1e3
    );
    // And the other way: no node of the ball inside the skin the user sees beyond the same
    // allowance. The contact holds the ball's nodes out of the contact skin, whose points lie
    // inside the display skin by up to 0.4 mm on the pads (docs/hand.md, "Moved by the contact
    // skin"). Measured 0.26 mm (Power grasp) and 0.19 mm (Pinch) on 2026-11-29, 0.53 mm under a
    // ball 100 times stiffer (2026-12-02).
    let ball_depth = common::object_depth_inside_skin(model, frame, hand, ball);
    println!(
        "{name}: the ball's surface nodes {:.3} mm inside the display skin",
        ball_depth * 1e3
    );
    assert!(
        ball_depth <= 2.0 * model.contact.penetration_limit(),
        "{name}: a node of the ball is {} mm inside the skin",
        ball_depth * 1e3
    );
    // The tactile map drawn and exported on the display skin integrates to the contact's
    // normal force (item 4: the map is the contact's, carried from the contact skin's vertices
    // to the finer display skin).
    let hand_model = model.bodies[hand].hand.as_deref().unwrap();
    let pressure = prehensile::state::skin_pressure(model, frame, hand).expect("skin pressure");
    let area = hand_model
        .skin
        .vertex_areas(&hand_model.skin.positions(&frame.hands[0].positions));
    let integral: f64 = pressure.iter().zip(&area).map(|(p, a)| p * a).sum();
    let normal = contact.normal_force();
    println!(
        "{name}: the skin's tactile map integrates to {integral:.4} N of {normal:.4} N ({:+.2} %)",
        100.0 * (integral / normal - 1.0)
    );
    // (Before 2026-11-29 the map was the force over the contact skin's own areas: 6.8 and
    // 7.9 % short on the smoother display skin.)
    assert!(
        (integral - normal).abs() < 1e-9 * normal,
        "{name}: {integral} N of {normal} N"
    );
    // The ball: contact force, its weight and its support's reaction balance (the air pressure
    // on its closed cavity sums to zero).
    let report = &solved.report.frames[solved.frames.len() - 1];
    let support = Vector3::from(report.constraints["support"].reaction);
    let ball_balance = on_ball + model.gravity_total + support;
    assert!(
        ball_balance.norm() < 1e-6 * grip,
        "{name}: ball out of balance by {ball_balance:?} N (grip {grip} N)"
    );
    // The hand: the bones hold the flesh against the contact (equation (8)).
    let bones: Vector3<f64> = frame.hands[0].bone_reactions.iter().sum();
    let hand_balance = bones + on_hand;
    assert!(
        hand_balance.norm() < 1e-6 * grip,
        "{name}: flesh out of balance by {hand_balance:?} N (grip {grip} N)"
    );
    // The keyframe went in contact steps along the motion (the pose is deeper than one step
    // resolves: no one-step attempt), several of them kept within the contact's search before
    // the corrections at the pose (measured 2026-11-28: 4 along the motion — two approaching
    // the ball, two pressing it — and 3 corrections, for either preset).
    let stats = &frame.hands[0].stats;
    assert!(
        stats.contact_steps >= stats.pose_corrections + 3,
        "{name}: {} contact steps of which {} corrections, {} redone",
        stats.contact_steps,
        stats.pose_corrections,
        stats.contact_retries
    );
    // The flexion is solved at its own increments (max_step_deg of the largest joint motion),
    // not once per contact step: the steps between its knots take the flesh carried by the
    // bones (src/solve/path.rs).
    let largest = frame.hands[0]
        .angles
        .iter()
        .zip(&solved.frames[0].hands[0].angles)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let knots = (largest / model.flexion.max_step_deg - 1e-9).ceil() as usize;
    assert_eq!(
        stats.increments_taken,
        knots + stats.halvings,
        "{name}: {largest}° in {} increments",
        stats.increments_taken
    );
    assert!(stats.increments_taken < stats.contact_steps, "{name}");
    println!(
        "{name}: grip {grip:.3} N, {} contacts, {:.2e} m left, {} contact steps ({} redone)",
        contact.contacts.len(),
        contact.max_penetration,
        stats.contact_steps,
        stats.contact_retries
    );
}

#[test]
fn the_power_grasp_preset_converges_on_the_default_scene() {
    check_converged_grasp(Preset::PowerGrasp);
}

#[test]
fn the_pinch_preset_converges_on_the_default_scene() {
    check_converged_grasp(Preset::Pinch);
}

/// The Power grasp scene (`assets/scenes/hand-power-grasp.toml`) with another hand or ball:
/// each converges as the shipped one does (checked 2026-12-02 from the command line: exit 0,
/// 2–8 s each at resolution 1).
#[test]
fn the_power_grasp_converges_on_other_balls_and_hands() {
    const SCENE: &str = include_str!("../assets/scenes/hand-power-grasp.toml");
    const SHELL: &str = "shell = { center = [0.065, 0.0, -0.065], inner_radius = 0.031, outer_radius = 0.035, cells = 12, layers = 2 }";
    const SUPPORT: &str = "min = [0.055, -0.01, -0.101], max = [0.075, 0.01, -0.098]";
    let variants: [(&str, &[(&str, &str)]); 6] = [
        ("left hand", &[("side = \"right\"", "side = \"left\"")]),
        (
            "a smaller ball (R 30 mm)",
            &[
                (SHELL, "shell = { center = [0.065, 0.0, -0.065], inner_radius = 0.026, outer_radius = 0.030, cells = 12, layers = 2 }"),
                (SUPPORT, "min = [0.055, -0.01, -0.0965], max = [0.075, 0.01, -0.0935]"),
            ],
        ),
        (
            "a larger ball (R 40 mm)",
            &[
                (SHELL, "shell = { center = [0.065, 0.0, -0.065], inner_radius = 0.036, outer_radius = 0.040, cells = 12, layers = 2 }"),
                (SUPPORT, "min = [0.055, -0.01, -0.106], max = [0.075, 0.01, -0.103]"),
            ],
        ),
        (
            "a ball 5 mm off",
            &[
                (SHELL, "shell = { center = [0.070, 0.005, -0.065], inner_radius = 0.031, outer_radius = 0.035, cells = 12, layers = 2 }"),
                (SUPPORT, "min = [0.060, -0.005, -0.101], max = [0.080, 0.015, -0.098]"),
            ],
        ),
        ("a ball 100 times stiffer", &[("young = 2.0e6 ", "young = 2.0e8 ")]),
        (
            "the hand at resolution 1.25",
            &[("resolution = 1.0", "resolution = 1.25")],
        ),
    ];
    for (name, edits) in variants {
        let mut text = SCENE.to_string();
        for (from, to) in edits {
            assert!(text.contains(from), "{name}: the scene has no {from}");
            text = text.replace(from, to);
        }
        let scene = prehensile::scene::Scene::parse(&text, name).unwrap();
        check_converged(scene, name, 0.3);
    }
}

/// Weak muscles: every fingertip bone holds at most 0.3 N. Closing into the Power grasp, the
/// keyframe stops at the first contact step after which a bone's reaction overruns its
/// threshold — the paper's "grasp not realisable" — short of the preset's pose, and says so.
#[test]
fn a_power_grasp_beyond_the_muscles_stops_where_a_bone_is_overloaded() {
    let mut scene = preset_scene(Preset::PowerGrasp);
    let hand = scene
        .body
        .iter_mut()
        .find(|b| matches!(b.shape, prehensile::scene::Shape::Hand { .. }))
        .unwrap();
    hand.bone_thresholds = Some(
        ["thumb", "index", "middle", "ring", "little"]
            .iter()
            .map(|d| (format!("{d}.distal"), 0.3))
            .collect(),
    );
    let solved = solve_scene(&scene, "weak.toml").unwrap_or_else(|e| panic!("{e}"));
    let frame = solved.frames.last().unwrap();
    let contact = frame.contact.as_ref().expect("the hand touches the ball");
    assert!(
        contact.stopped_by_threshold,
        "the motion stops by a threshold"
    );
    let h = &frame.hands[0];
    assert!(!h.overloads.is_empty());
    // The overrunning step is halved down to 5°/16: the motion stops close to where the
    // threshold is crossed, not a whole step past it. (Measured: middle.distal 0.384 N,
    // index.distal 0.315 N, ring.distal 0.301 N at 58 % of the motion. The middle's is flexion
    // only, no contact on it: it jumps when the first contact step re-solves the flesh around
    // the contact, which no halving removes — docs/contact.md, limits.)
    for o in &h.overloads {
        assert!(o.reaction > o.threshold && o.threshold == 0.3, "{o:?}");
        assert!(o.reaction < 1.35 * o.threshold, "{o:?}");
    }
    let report = &solved.report.frames[solved.frames.len() - 1].hands["hand"];
    assert!(!report.realisable);
    // Short of the preset's pose: the joint moving most has not reached its angle.
    let skeleton = prehensile::hand::Skeleton::new(prehensile::hand::Side::Right);
    let target = Preset::PowerGrasp.angles(&skeleton);
    let short = target
        .iter()
        .zip(&h.angles)
        .map(|(t, a)| (t - a).abs())
        .fold(0.0, f64::max);
    println!(
        "stopped {short:.1}° short of the pose: {}",
        h.overloads
            .iter()
            .map(|o| format!("{} {:.2} N", o.bone, o.reaction))
            .collect::<Vec<_>>()
            .join(", ")
    );
    assert!(short > 1.0, "{short}°");
}
