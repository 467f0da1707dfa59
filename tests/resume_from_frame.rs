//! The viewer goes on from the frame it shows (`Posed::of_frame`). A frame in contact holds the
//! flesh's positions and reactions with the contact's share in them; going on from it must take
//! that share off (the next contact step adds it again), or the bones would feel the contact
//! twice. Solving the same pose again from the shown frame gives the same frame: the keyframe
//! was corrected at its pose until its contact force changed by less than
//! `CONTACT_CORRECTION` per correction, and the pose again is more such corrections.

use crate::common;

use nalgebra::Vector3;
use prehensile::headless::solve_scene;
use prehensile::scene::Scene;
use prehensile::solve::proximity::posed_deeper_than;
use prehensile::solve::{Posed, Workspace, CONTACT_CORRECTION};
use prehensile::state::KeyframeStats;

/// The shipped finger press, solved.
fn finger_press() -> prehensile::headless::Solved {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    let scene = Scene::parse(&text, "press.toml").unwrap();
    solve_scene(&scene, "press.toml").unwrap()
}

#[test]
fn the_same_pose_again_from_a_frame_in_contact_gives_the_same_forces() {
    let solved = finger_press();
    let (model, shown) = (&solved.model, solved.frames.last().unwrap());
    let contact = shown.contact.as_ref().expect("the finger presses the ball");
    let grip: f64 = contact.contacts.iter().map(|c| c.force).sum();
    assert!(grip > 1.0, "{grip} N");
    let mut workspace = Workspace::new(model).unwrap();
    let mut posed = Posed::of_frame(model, shown);
    let targets: Vec<(usize, Vec<f64>)> = shown
        .hands
        .iter()
        .map(|h| (h.body, h.angles.clone()))
        .collect();
    let again = workspace
        .move_hands(model, &mut posed, &targets, None)
        .unwrap();
    let regrip = again.contact.as_ref().unwrap().normal_force();
    // Counted twice, the contact would double the grip and the bones' share of it. The
    // corrections stop when the force changes by less than CONTACT_CORRECTION per correction;
    // they converge slowly (the ball's air follows its wall's stretch, and the contact's extent
    // moves by a point or two each time), and the pose again is some more of them: within ten
    // times that (measured 0.14 % on the grip, 0.68 % on the bones' sum, 0.54 % of the largest
    // displacement).
    let tolerance = 10.0 * CONTACT_CORRECTION;
    let bones =
        |f: &prehensile::state::Frame| -> Vector3<f64> { f.hands[0].contact_force.iter().sum() };
    let (felt, refelt) = (bones(shown), bones(&again));
    let off = (regrip - grip).abs() / grip;
    let bones_off = (felt - refelt).norm() / felt.norm();
    let largest = |u: &[f64]| u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let moved = shown
        .solution
        .displacement
        .iter()
        .zip(&again.solution.displacement)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / largest(&shown.solution.displacement);
    println!(
        "grip {grip:.4} N, again {regrip:.4} N ({:.3} %); contact on the bones {:.4} N, again \
         {:.4} N ({:.3} %); displacements differ by {:.2e} of max |u|",
        100.0 * off,
        felt.norm(),
        refelt.norm(),
        100.0 * bones_off,
        moved
    );
    assert!(
        felt.norm() > 0.5 * grip,
        "{felt:?} N on the bones of {grip} N"
    );
    assert!(off < tolerance, "{regrip} vs {grip} N");
    assert!(bones_off < tolerance, "{refelt:?} vs {felt:?} N");
    assert!(moved < tolerance, "{moved}");
}

/// Corrections at the pose are for the hands' contact: a keyframe that ends in it is corrected
/// (at most six times, and where the last still changed the force the frame says by how much);
/// one whose hand has let go, the ball left on its table alone, is not (it was, once per
/// keyframe, while the corrections measured the table's force with the hand's).
#[test]
fn only_the_hands_contact_is_corrected_at_the_pose() {
    let solved = finger_press();
    let (model, shown) = (&solved.model, solved.frames.last().unwrap());
    let stats = &shown.hands[0].stats;
    // Six at most, or twelve while each changes the force less than the one before.
    assert!(
        (1..=12).contains(&stats.pose_corrections),
        "{} corrections",
        stats.pose_corrections
    );
    assert!(stats.contact_steps >= stats.pose_corrections);
    if let Some(change) = stats.unsettled_at_pose {
        assert!(change > CONTACT_CORRECTION && stats.pose_corrections >= 6);
    }
    for (i, frame) in solved.frames.iter().enumerate() {
        let unsettled = frame.hands[0].stats.unsettled_at_pose;
        println!(
            "frame {i}: {} corrections, unsettled {unsettled:?}",
            frame.hands[0].stats.pose_corrections
        );
        let warned = solved.report.warnings.iter().any(|w| {
            w.starts_with(&format!("frame {i}: ")) && w.contains("corrections at the pose")
        });
        let over = unsettled.is_some_and(|c| c > KeyframeStats::UNSETTLED_WARNING);
        assert_eq!(warned, over, "frame {i}");
    }
    // The finger lifted off: the ball stays on its table (contact with the obstacle only).
    let mut workspace = Workspace::new(model).unwrap();
    let mut posed = Posed::of_frame(model, shown);
    let hand = model.bodies[shown.hands[0].body].hand.as_deref().unwrap();
    let mut angles = shown.hands[0].angles.clone();
    let mcp = hand
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == "index.mcp.flex")
        .unwrap();
    angles[mcp] = 0.0;
    let lifted = workspace
        .move_hands(
            model,
            &mut posed,
            &[(shown.hands[0].body, angles.clone())],
            None,
        )
        .unwrap();
    // The frame keeps the table's contact (here without force: the ball is held at its base).
    let contact = lifted.contact.as_ref().expect("the table's contact");
    assert!(
        contact.contacts.iter().all(|c| c.obstacle().is_some()),
        "only the table may touch"
    );
    // Let go, the ball is solved as if the finger had never touched it (one contact step from
    // the bodies at rest, counted as a correction at the pose): where a fresh workspace moving
    // the hand from rest to the lifted pose puts it.
    assert!(lifted.hands[0].stats.pose_corrections <= 1);
    let mut fresh = Workspace::new(model).unwrap();
    let never = fresh
        .move_hands(
            model,
            &mut Posed::rest(model),
            &[(shown.hands[0].body, angles.clone())],
            None,
        )
        .unwrap();
    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    let (u0, u) = (&never.solution.displacement, &lifted.solution.displacement);
    let dofs = || {
        model.bodies[ball]
            .nodes
            .clone()
            .flat_map(|n| 3 * n..3 * n + 3)
    };
    let size = dofs().map(|i| u0[i].abs()).fold(0.0, f64::max);
    let off = dofs().map(|i| (u[i] - u0[i]).abs()).fold(0.0, f64::max);
    let pressed = dofs()
        .map(|i| (shown.solution.displacement[i] - u0[i]).abs())
        .fold(0.0, f64::max);
    println!("ball: {off:.3e} m off the untouched frame (the press moved it {pressed:.3e} m, its largest {size:.3e} m)");
    assert!(pressed > 1e-4, "the press moves the ball {pressed} m");
    assert!(off <= 1e-6 * pressed, "{off} m off the untouched frame");
}

/// The Power grasp's pose puts the thumb's skin about 18 mm into the ball at rest, deeper than
/// contact searches (10 mm): from rest that keyframe goes in contact steps along the motion. A
/// two-degree move of the thumb on from the solved grasp (the animator nudging a slider) is
/// measured against the ball and the flesh where the grasp left them, and is solved in one
/// contact step from there (before, it was measured against the ball at rest and went in two
/// steps): the thumb presses a little harder, nothing passes into the ball, the pose is reached.
#[test]
fn a_small_move_on_from_a_deep_grasp_is_one_contact_step() {
    let (solved, ip) = common::power_grasp_and_thumb_ip();
    let (model, shown) = (&solved.model, solved.frames.last().unwrap());
    let grip = shown.contact.as_ref().unwrap().normal_force();
    let h = &shown.hands[0];
    let mut target = h.angles.clone();
    target[ip] += 2.0;
    let mut posed = Posed::of_frame(model, shown);
    let state = &posed.hands[0].state;
    let depth = model.contact.search_depth;
    assert!(
        posed_deeper_than(model, h.body, state, &target, depth, None),
        "against the ball at rest the pose is deeper than the search"
    );
    assert!(
        !posed_deeper_than(
            model,
            h.body,
            state,
            &target,
            depth,
            posed.contact.as_deref()
        ),
        "against the grasp's ball the two degrees are not"
    );
    let mut workspace = Workspace::new(model).unwrap();
    let moved = workspace
        .move_hands(model, &mut posed, &[(h.body, target.clone())], None)
        .unwrap();
    let stats = &moved.hands[0].stats;
    println!(
        "{} contact steps, {} corrections, {} redone",
        stats.contact_steps, stats.pose_corrections, stats.contact_retries
    );
    assert_eq!(stats.contact_steps - stats.pose_corrections, 1);
    assert_eq!(stats.contact_retries, 0);
    assert_eq!(moved.hands[0].angles, target);
    let contact = moved.contact.as_ref().unwrap();
    assert!(
        contact.max_penetration <= model.contact.tolerance,
        "{} m",
        contact.max_penetration
    );
    let regrip = contact.normal_force();
    println!("grip {grip:.4} N -> {regrip:.4} N");
    assert!(regrip > grip && regrip < 1.5 * grip, "{grip} -> {regrip}");
}
