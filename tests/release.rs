//! Release: the hand closes on the ball of the built-in default scene (the viewer's Pinch
//! preset, reached in contact steps) and opens again to the scene's pose. Contact is linear
//! elastic and frictionless, so once the skin has left the ball nothing remembers the grasp:
//! the ball returns to its static frame within 1e-6 of what the grasp moved it, and the flesh is
//! where the same motion leaves it with the ball out of reach, within 1e-6 of what the grasp
//! moved it.

use prehensile::app::pose::Preset;
use prehensile::hand::{Side, Skeleton};
use prehensile::headless::solve_scene;
use prehensile::scene::{Scene, DEFAULT_SCENE};

/// `angles` as a TOML pose table.
fn pose(skeleton: &Skeleton, angles: &[f64]) -> String {
    let entries: Vec<String> = skeleton
        .dofs
        .iter()
        .zip(angles)
        .map(|(d, a)| format!("\"{}\" = {a}", d.name))
        .collect();
    format!("{{ {} }}", entries.join(", "))
}

/// The largest distance between a node of `body` displaced by `a` and by `b`, m.
fn farthest(model: &prehensile::model::Model, body: usize, a: &[f64], b: &[f64]) -> f64 {
    model.bodies[body]
        .nodes
        .clone()
        .map(|n| {
            (0..3)
                .map(|k| (a[3 * n + k] - b[3 * n + k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

#[test]
fn opening_the_hand_returns_ball_and_flesh_to_rest() {
    let skeleton = Skeleton::new(Side::Right);
    let base = &DEFAULT_SCENE[..DEFAULT_SCENE.find("[[keyframe]]").unwrap()];
    let scene0 = Scene::parse(base, "default.toml").unwrap();
    // The scene's own pose, as angles of every dof.
    let mut open = skeleton.rest_angles();
    for (name, value) in scene0.body[0].pose.iter().flatten() {
        let d = skeleton.dofs.iter().position(|d| &d.name == name).unwrap();
        open[d] = *value;
    }
    let closed = Preset::Pinch.angles(&skeleton);
    // Every digit solved by FEM (none skinned for being far from the ball), so that the motion
    // without the ball flexes the same flesh.
    let base = base.replacen("[solver]\n", "[solver]\nfar_from_contact = \"solve\"\n", 1);
    let keyframes = format!(
        "[[keyframe]]\ntime = 1.0\npose = {}\n[[keyframe]]\ntime = 2.0\npose = {}\n",
        pose(&skeleton, &closed),
        pose(&skeleton, &open)
    );
    let text = format!("{base}{keyframes}");
    let scene = Scene::parse(&text, "release.toml").unwrap();
    let solved = solve_scene(&scene, "release.toml").unwrap_or_else(|e| panic!("{e}"));
    // The same motion with the ball and its support a metre away: the flesh never touches.
    let away = text
        .replacen("center = [0.065,", "center = [1.065,", 1)
        .replacen("min = [0.055,", "min = [1.055,", 1)
        .replacen("max = [0.075,", "max = [1.075,", 1);
    assert_ne!(away, text, "the default scene's ball moved");
    let untouched = solve_scene(&Scene::parse(&away, "away.toml").unwrap(), "away.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(untouched.frames.iter().all(|f| f.contact.is_none()));
    let model = &solved.model;
    let [rest, grasp, released] = &solved.frames[..] else {
        panic!("three frames, got {}", solved.frames.len())
    };
    let touching =
        |f: &prehensile::state::Frame| f.contact.as_ref().map_or(0, |c| c.contacts.len());
    assert_eq!(touching(rest), 0, "the scene's pose does not touch");
    let grip = grasp.contact.as_ref().expect("the pinch touches the ball");
    assert!(!grip.contacts.is_empty());
    assert_eq!(touching(released), 0, "the open hand touches nothing");

    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    let hand = model.bodies.iter().position(|b| b.hand.is_some()).unwrap();
    // How far each body's nodes are from where they were at rest, and how far the grasp took
    // them: the largest of each.
    let largest = |a: &[f64], b: &[f64], body: usize| farthest(model, body, a, b);
    let (u0, u1, u2) = (
        &rest.solution.displacement,
        &grasp.solution.displacement,
        &released.solution.displacement,
    );
    // The ball: back to its static frame.
    let moved = largest(u1, u0, ball);
    let left = largest(u2, u0, ball);
    println!("ball: the grasp moved it {moved:.3e} m, {left:.3e} m left after release");
    assert!(moved > 1e-4, "the grasp moves the ball");
    assert!(
        left <= 1e-6 * moved,
        "ball: {left:e} m from its static frame after release (the grasp moved it {moved:e} m)"
    );
    // The flesh keeps nothing of the contact: it is where the same motion leaves it untouched.
    // (Not where it was at rest: the incremental corotational flexion there and back is not
    // exactly reversible, with or without the ball.)
    let away = |i: usize| &untouched.frames[i].solution.displacement;
    // What the contact moved the flesh by, in the grasp: from where the motion alone takes it.
    let hand_moved = largest(u1, away(1), hand);
    let hand_left = largest(u2, away(2), hand);
    println!(
        "flesh: the contact moved it {hand_moved:.3e} m; released, {hand_left:.3e} m from the \
         motion without the ball ({:.3e} m from its first frame)",
        largest(u2, u0, hand)
    );
    assert!(hand_moved > 1e-4, "the contact moves the flesh");
    assert!(
        hand_left <= 1e-6 * hand_moved,
        "the released flesh is {hand_left:e} m from the untouched motion's (the grasp moved it \
         {hand_moved:e} m)"
    );
}

/// The shipped five-digit ball grasp (Figure 4) closed, then opened back to the scene's own
/// pose and further to every joint at 0°: the open fingers stay near the ball (within the
/// contact's search, so those frames are contact solves), yet the ball is back in its static
/// frame within 1e-6 of what the grasp moved it. Before 2026-11-27 the opening's last step,
/// linearised about the squeezed, turned ball, left it tilted by 1.5° and 2.6° with its top
/// 3 mm off (found by a user's scene, with the open frames differing from each other).
#[test]
fn opening_the_five_digit_grasp_returns_the_ball_to_its_static_frame() {
    let asset = std::fs::read_to_string("assets/scenes/hand-grasp-ball.toml").unwrap();
    let at = asset.find("[[keyframe]]").unwrap();
    let (head, keys) = asset.split_at(at);
    let keys = &keys[..keys.find("[[camera]]").unwrap_or(keys.len())];
    let scene0 = Scene::parse(head, "grasp.toml").unwrap();
    let hand = scene0.body.iter().find(|b| b.pose.is_some()).unwrap();
    let open = hand.pose.as_ref().unwrap();
    let table = |angles: &mut dyn Iterator<Item = (String, f64)>| {
        let entries: Vec<String> = angles.map(|(n, a)| format!("\"{n}\" = {a}")).collect();
        format!("{{ {} }}", entries.join(", "))
    };
    let back = table(&mut open.iter().map(|(n, a)| (n.clone(), *a)));
    let flat = table(&mut open.keys().map(|n| (n.clone(), 0.0)));
    let text = format!(
        "{head}{keys}\n[[keyframe]]\ntime = 2.0\npose = {back}\n\n[[keyframe]]\ntime = 3.0\npose = {flat}\n"
    );
    let scene = Scene::parse(&text, "release-grasp.toml").unwrap();
    let solved = solve_scene(&scene, "release-grasp.toml").unwrap_or_else(|e| panic!("{e}"));
    let model = &solved.model;
    let [rest, grasp, back, flat] = &solved.frames[..] else {
        panic!("four frames, got {}", solved.frames.len())
    };
    let hands_force = |f: &prehensile::state::Frame| {
        f.hands
            .iter()
            .flat_map(|h| h.contact_force.iter())
            .map(|v| v.norm())
            .sum::<f64>()
    };
    assert!(hands_force(grasp) > 1.0, "{} N", hands_force(grasp));
    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    let largest = |a: &[f64], b: &[f64]| farthest(model, ball, a, b);
    let u0 = &rest.solution.displacement;
    let moved = largest(&grasp.solution.displacement, u0);
    assert!(moved > 1e-4, "the grasp moves the ball {moved} m");
    for (name, frame) in [("back to the scene's pose", back), ("flat", flat)] {
        assert_eq!(hands_force(frame), 0.0, "{name}: the open hand presses");
        let left = largest(&frame.solution.displacement, u0);
        println!("{name}: the grasp moved the ball {moved:.3e} m, {left:.3e} m left");
        assert!(
            left <= 1e-6 * moved,
            "{name}: {left:e} m left of {moved:e} m"
        );
    }
}
