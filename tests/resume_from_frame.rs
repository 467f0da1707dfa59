//! The viewer goes on from the frame it shows (`Posed::of_frame`). A frame in contact holds the
//! flesh's positions and reactions with the contact's share in them; going on from it must take
//! that share off (the next contact step adds it again), or the bones would feel the contact
//! twice. Solving the same pose again from the shown frame gives the same frame.

use nalgebra::Vector3;
use prehensile::headless::solve_scene;
use prehensile::scene::Scene;
use prehensile::solve::{Posed, Workspace};

#[test]
fn the_same_pose_again_from_a_frame_in_contact_gives_the_same_forces() {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    let scene = Scene::parse(&text, "press.toml").unwrap();
    let solved = solve_scene(&scene, "press.toml").unwrap();
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
    assert!((regrip - grip).abs() < 1e-9 * grip, "{regrip} vs {grip} N");
    for (a, b) in shown.hands[0]
        .bone_reactions
        .iter()
        .zip(&again.hands[0].bone_reactions)
    {
        let scale = a.norm().max(1e-3);
        assert!((a - b).norm() < 1e-9 * scale, "{a:?} vs {b:?}");
    }
    let largest = shown
        .solution
        .displacement
        .iter()
        .zip(&again.solution.displacement)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(largest < 1e-12, "{largest} m");
    let total: Vector3<f64> = again.hands[0].bone_reactions.iter().sum();
    println!("grip {grip:.4} N, again {regrip:.4} N, bones' total {total:?} N");
}
