//! A grasp against gravity decided with the object let go of (issue 17): the grip found with
//! the ball on its stand is solved again with the stand gone (`Model::released`), the ball held
//! by nothing but the hand's frictional contacts.

use prehensile::headless::solve_scene;
use prehensile::model::Model;
use prehensile::scene::Scene;

/// The Power-grasp scene (`assets/scenes/hand-power-grasp.toml`: a pressurised ball on a
/// stand beside the default hand), skin on rubber μ = 0.8, its keyframe `keyframe`.
fn scene(keyframe: &str) -> String {
    let s = include_str!("../assets/scenes/hand-power-grasp.toml");
    let s = &s[..s.find("[[keyframe]]").unwrap()];
    format!(
        "{s}[[friction]]\nbetween = [\"flesh\", \"rubber\"]\nmu = 0.8\n\n[[keyframe]]\ntime = 1.0\n\
         {keyframe}\n"
    )
}

/// The released model frees exactly the object: its stand's 66 dofs become free, it floats,
/// obstacles no longer touch it; the hand's prescribed bone dofs and everything else stay.
#[test]
fn the_released_model_frees_the_object_and_nothing_else() {
    let text = scene("grasp = { object = \"ball\" }");
    let scene = Scene::parse(&text, "grasp.toml").unwrap();
    let model = Model::build(&scene, "grasp.toml").unwrap();
    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    let released = model.released(ball);
    let nodes = model.bodies[ball].nodes.clone();
    let in_ball = |d: usize| nodes.contains(&(d / 3));
    let held = |m: &Model, inside: bool| {
        (0..m.partition.prescribed.len())
            .filter(|&d| in_ball(d) == inside && m.partition.prescribed[d])
            .count()
    };
    assert_eq!(
        held(&model, true),
        66,
        "the stand holds 66 dofs of the ball"
    );
    assert_eq!(held(&released, true), 0);
    assert_eq!(held(&released, false), held(&model, false));
    assert!(model.supports(ball) && !released.supports(ball));
    assert!(released.bodies[ball].floating && !model.bodies[ball].floating);
    assert!(released.constraints.iter().all(|c| c.body != ball));
    assert_eq!(
        released.load_vector, model.load_vector,
        "its weight and air stay"
    );
    assert_eq!(
        released.partition.free_count(),
        model.partition.free_count() + 66
    );

    // A block resting on a table: let go of, the table no longer touches it.
    let text = include_str!("../assets/scenes/ball-on-table.toml");
    let scene = Scene::parse(text, "table.toml").unwrap();
    let model = Model::build(&scene, "table.toml").unwrap();
    assert!(!model.obstacles.is_empty());
    let b = model.body_of_node(model.contact_candidates[0]);
    let released = model.released(b);
    let nodes = model.bodies[b].nodes.clone();
    assert!(model.contact_candidates.iter().any(|n| nodes.contains(n)));
    assert!(released
        .contact_candidates
        .iter()
        .all(|n| !nodes.contains(n)));
    assert!(model.supports(b) && !released.supports(b));
}

/// The built-in hand's power grasp pushes the ball towards the wrist (its thumb does not oppose
/// the fingers: docs/hand.md): on its stand the grip's normal forces leave ≈ 9.7 N unbalanced;
/// let go of, the ball slides out of the grip and falls. The grasp is not held, says so with
/// the motion, and reports no drift; the frame shown is the grip on the stand.
#[test]
fn a_grip_whose_forces_do_not_balance_lets_the_ball_fall() {
    let text = scene("grasp = { object = \"ball\", preshape = \"power\" }");
    let scene = Scene::parse(&text, "grasp.toml").unwrap();
    let solved = solve_scene(&scene, "grasp.toml").unwrap_or_else(|e| panic!("{e}"));
    let g = solved.frames.last().unwrap().hands[0]
        .grasp
        .clone()
        .unwrap();
    assert!(!g.held);
    assert_eq!(g.drift, None);
    assert!(g.margin < 1.0, "margin {}", g.margin);
    let reason = g.reason.unwrap();
    assert!(
        reason.contains("let go of, the hand does not hold it"),
        "{reason}"
    );
    assert!(
        reason.contains("out of the grip") || reason.contains("falls"),
        "{reason}"
    );
    // A real grip was let go of (not a hand that never touched): ≈ 11 N at 8° past first
    // contact, the firmest as a rigid body.
    assert!(g.grip > 5.0, "grip {}", g.grip);
}
