//! The skinning tier (geometry only) on the default scene: skinning folds flesh at the palmar
//! crease; frames without contact still solve (skinned flesh bears no stress, and nothing is
//! NaN), and a frame with contact says that contact needs an FEM tier.
//!
//! The scene's hand in its simple form: skinning folds its flesh at the palmar crease by the
//! first keyframe, which the contact step must refuse. The anatomical form's skinned flesh does
//! not fold there (measured 2026-12-02: the keyframe solves), so it cannot show the refusal.

use prehensile::headless::solve_scene;
use prehensile::scene::{Scene, TierName};

fn scene(keys: usize) -> Scene {
    let mut scene = Scene::load(std::path::Path::new("assets/scenes/hand-and-ball.toml")).unwrap();
    scene.solver.tier = Some(TierName::Skinning);
    scene.keyframe.truncate(keys);
    for body in &mut scene.body {
        if let prehensile::scene::Shape::Hand { form, .. } = &mut body.shape {
            *form = Some("simple".into());
        }
    }
    scene
}

#[test]
fn skinned_frames_without_contact_solve_with_no_stress_in_the_flesh() {
    // The initial pose: the fingers curled 10–15°, farther from the ball than contact searches.
    let solved = solve_scene(&scene(0), "skinning").unwrap();
    assert_eq!(solved.frames.len(), 1);
    let hand = &solved.model.bodies[0];
    assert!(hand.hand.is_some());
    for f in &solved.frames {
        assert!(f.contact.is_none());
        assert!(f.solution.displacement.iter().all(|u| u.is_finite()));
        // The skinned flesh: no stress; the ball: its pressure's.
        let flesh = f.stress.cell_von_mises[hand.cells.clone()]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let ball = f.stress.cell_von_mises[solved.model.bodies[1].cells.clone()]
            .iter()
            .fold(0.0f64, |m, v| m.max(*v));
        assert_eq!(flesh, 0.0);
        assert!(ball > 1e3 && ball.is_finite(), "{ball}");
        // No mechanics: no bone reaction.
        assert!(f.hands[0].bone_reactions.iter().all(|r| r.norm() == 0.0));
    }
}

#[test]
fn a_skinned_hand_touching_the_ball_asks_for_an_fem_tier() {
    // The first key curls the fingers to within the contact search of the ball.
    let err = match solve_scene(&scene(1), "skinning.toml") {
        Ok(_) => panic!("contact with folded skinned flesh must not solve"),
        Err(e) => e.to_string(),
    };
    println!("{err}");
    assert!(err.contains("skinning folded flesh element"), "{err}");
    assert!(err.contains("use an FEM tier"), "{err}");
    // The advice followed: each FEM tier it names solves the same keyframe, to its pose.
    for (name, tier) in [
        ("corotational", TierName::Corotational),
        ("incremental", TierName::Incremental),
        ("nonlinear", TierName::Nonlinear),
    ] {
        assert!(err.contains(&format!("\"{name}\"")), "{err}");
        let mut fixed = scene(1);
        fixed.solver.tier = Some(tier);
        let solved = solve_scene(&fixed, "fem.toml").unwrap_or_else(|e| panic!("{name}: {e}"));
        let frame = solved.frames.last().unwrap();
        assert!(frame.hands[0].stats.stopped_short.is_none(), "{name}");
        assert!(
            frame.solution.displacement.iter().all(|u| u.is_finite()),
            "{name}"
        );
    }
}
