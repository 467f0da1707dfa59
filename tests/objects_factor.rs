//! A contact step's other bodies factored apart from the flesh near the contact (issue 20,
//! src/solve/objects_factor.rs): no cell joins a hand to an object, so K11 is block diagonal;
//! the objects' block is assembled and factored beside the detection and kept by the step's
//! solve, and only the flesh region's block is factored after the detection. A ball that stays
//! linear (the linear tier: its K does not turn) keeps its factor from step to step for the
//! whole session. The blocks' factors solve as one factorization of the whole does, to round-off
//! (unit tests: src/fem/blocks.rs); here, the finger press's contact forces balance between hand
//! and ball, and grow as the finger presses further.

use prehensile::headless::solve_scene;
use prehensile::scene::Scene;

/// The finger press (`assets/scenes/finger-press-ball.toml`: MCP 21° then 21.5°) with `solver`
/// lines added.
fn finger_press(solver: &str) -> Scene {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    let text = text.replacen("[solver]\n", &format!("[solver]\n{solver}\n"), 1);
    Scene::parse(&text, "press.toml").unwrap()
}

#[test]
fn a_linear_ball_keeps_its_factor_and_a_corotated_one_is_factored_beside_the_detection() {
    for (solver, kept) in [("tier = \"linear\"", true), ("", false)] {
        let solved = solve_scene(&finger_press(solver), "press.toml").unwrap();
        let frames = &solved.frames[1..];
        assert_eq!(frames.len(), 2);
        let mut forces = Vec::new();
        for (k, frame) in frames.iter().enumerate() {
            let contact = frame.contact.as_ref().expect("in contact");
            let stats = &frame.solution.stats;
            // Two blocks, the ball's and the flesh region's; the ball's factor kept by the step
            // (the flesh's too where a correction at the pose solves the same region again).
            println!(
                "{solver:?} keyframe {}: {} blocks, {} kept",
                k + 1,
                stats.blocks,
                stats.blocks_reused
            );
            assert!(
                stats.blocks == 2 && stats.blocks_reused >= 1,
                "{solver:?} keyframe {}",
                k + 1
            );
            // The linear ball's values never change: made once, kept at every later step (each
            // keyframe's last step is a correction after at least one other step). The corotated
            // ball turns with what each step carries: made beside each detection.
            assert_eq!(contact.objects_kept, Some(kept), "{solver:?}");
            assert!(contact.times.beside > 0.0);
            let force = contact.normal_force();
            assert!(force > 0.5, "{solver:?}: {force} N");
            // Action and reaction: what the contacts push on the hand's nodes is what they push
            // on the ball's, opposite.
            let hand = &frame.hands[0];
            let on_hand: f64 = hand.contact_force.iter().map(|f| f.z).sum();
            let on_ball: f64 = contact
                .contacts
                .iter()
                .flat_map(|c| c.nodal_forces())
                .filter(|(n, _)| !solved.model.bodies[hand.body].nodes.contains(n))
                .map(|(_, f)| f.z)
                .sum();
            assert!(
                (on_hand + on_ball).abs() <= 1e-9 * force,
                "{solver:?}: {on_hand} N on the hand, {on_ball} N on the ball"
            );
            forces.push(force);
        }
        // Pressed further, pressed harder.
        assert!(forces[1] > forces[0], "{solver:?}: {forces:?}");
        println!("{solver:?}: {forces:?} N");
    }
}
