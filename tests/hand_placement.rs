//! The built-in hand placed in the scene (`placement = { translation, rotation }`): built in its
//! own frame, then moved rigidly. Elasticity is objective, so a placed hand flexed as the
//! unplaced one is the same solution moved: every flesh node at R·p + t, every bone reaction
//! turned by R, the flesh volume unchanged.

use nalgebra::{Rotation3, Vector3};
use prehensile::headless::solve_scene;
use prehensile::scene::Scene;

/// A scene of flesh and the hands `(name, shape options)` given, then `rest` appended.
fn hands(hands: &[(&str, String)], rest: &str) -> String {
    let mut text = "[[material]]\nname = \"flesh\"\nyoung = 5.0e4\npoisson = 0.45\n".to_string();
    for (name, options) in hands {
        text += &format!(
            "\n[[body]]\nname = \"{name}\"\nmaterial = \"flesh\"\nshape = {{ hand = {{ {options} }} }}\n"
        );
    }
    text + rest
}

/// One left hand (`placement` appended to its options), flexed in one keyframe.
fn scene(placement: &str) -> String {
    hands(
        &[("hand", format!("side = \"left\", resolution = 0.75{placement}"))],
        "\n[[keyframe]]\ntime = 1.0\npose = { \"index.pip\" = 60.0, \"middle.mcp.flex\" = 30.0, \"thumb.cmc.abd\" = 30.0 }\n",
    )
}

/// `text` solved as the command line does.
fn solve(text: &str) -> prehensile::headless::Solved {
    let scene = Scene::parse(text, "placed.toml").unwrap();
    solve_scene(&scene, "placed.toml").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_placed_hand_is_the_same_solution_moved() {
    let at_origin = solve(&scene(""));
    let (t, angles) = ([0.12, -0.3, 0.05], [30.0_f64, -45.0, 120.0]);
    let placed = solve(&scene(&format!(
        ", placement = {{ translation = {t:?}, rotation = {angles:?} }}"
    )));
    let [rx, ry, rz] = angles.map(f64::to_radians);
    let r = Rotation3::from_euler_angles(rx, ry, rz);
    let t = Vector3::from(t);
    assert_eq!(at_origin.frames.len(), 2);
    for (i, (a, b)) in at_origin.frames.iter().zip(&placed.frames).enumerate() {
        let (a, b) = (&a.hands[0], &b.hands[0]);
        let mut worst: f64 = 0.0;
        for (p, q) in a.positions.iter().zip(&b.positions) {
            worst = worst.max((r * p + t - q).norm());
        }
        assert!(worst < 1e-9, "a flesh node is {worst} m off R·p + t");
        let largest = a
            .bone_reactions
            .iter()
            .map(|f| f.norm())
            .fold(0.0, f64::max);
        assert!(
            i == 0 || largest > 0.01,
            "the flexion loads the bones: {largest} N"
        );
        for (f, g) in a.bone_reactions.iter().zip(&b.bone_reactions) {
            assert!(
                (r * f - g).norm() <= 1e-6 * largest,
                "bone reaction {g} against R·{f}"
            );
        }
        assert!((a.volume - b.volume).abs() <= 1e-9 * a.volume);
    }
}

#[test]
fn a_built_in_hand_is_sized_by_size_not_by_a_placements_scale() {
    let text = scene(", placement = { scale = 2.0 }");
    let scene = Scene::parse(&text, "placed.toml").unwrap();
    let e = solve_scene(&scene, "placed.toml").err().expect("refused");
    let e = format!("{e}");
    assert!(
        e.contains("shape.hand.placement") && e.contains("sized by `size`"),
        "{e}"
    );
}

/// Two hands: the contact is solved between a hand and the other bodies, not between hands, so
/// the report counts the skin of each inside the other and warns. A hand moved 4 mm dorsally
/// has its palmar skin inside its twin, which has its dorsal skin inside it (the skin of the
/// sides runs along the other's and may count or not); one 0.5 m away is in none.
#[test]
fn two_hands_inside_each_other_are_counted_and_warned_of() {
    let text = |at: [f64; 3]| {
        let options = "side = \"right\", resolution = 0.5";
        hands(
            &[
                ("one", options.to_string()),
                (
                    "two",
                    format!("{options}, placement = {{ translation = {at:?} }}"),
                ),
            ],
            "",
        )
    };
    let near = solve(&text([0.0, 0.0, 0.004]));
    let skin = near.model.bodies[0]
        .hand
        .as_deref()
        .unwrap()
        .contact_skin
        .vertex_count();
    let hands = &near.report.frames[0].hands;
    let (one, two) = (
        hands["one"].skin_overlap.other_hands["two"],
        hands["two"].skin_overlap.other_hands["one"],
    );
    println!("{one} and {two} of {skin} skin points");
    assert!(one > skin / 4 && two > skin / 4, "{one}, {two} of {skin}");
    assert!(
        one + two < skin,
        "{one}, {two} of {skin}: skin inside on both sides"
    );
    assert!(!hands["one"].skin_overlap.other_hands.contains_key("one"));
    let warned = |w: &String| {
        w.contains(&format!(
            "hand \"one\" is inside hand \"two\" at {one} skin points"
        ))
    };
    assert!(
        near.report.warnings.iter().any(warned),
        "{:?}",
        near.report.warnings
    );

    let far = solve(&text([0.0, 0.5, 0.0]));
    for hand in far.report.frames[0].hands.values() {
        assert!(hand.skin_overlap.other_hands.is_empty());
    }
    assert!(!far
        .report
        .warnings
        .iter()
        .any(|w| w.contains("is inside hand")));
}
