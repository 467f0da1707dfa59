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

/// The palm-down power grasp of the default scene's ball (issue 17): the power synergy's thumb,
/// in wide palmar abduction, wraps the ball from the wrist's side below its equator and opposes
/// the fingertips (src/hand/synergy.rs). Let go of its stand, the ball is held by the hand
/// alone with the margin asked, at the least closing that holds; every bone within its
/// threshold; the grip smaller than those of the firmer closings that hold too; the thumb
/// pushes the ball towards the fingertips, the fingers towards the wrist. Measured
/// (2026-11-30): held at 0.5° past first contact, grip 1.206 N, margin 1.523, drift 1.74 mm.
#[test]
fn the_palm_down_power_grasp_holds_the_ball_let_go_of() {
    let text = scene("grasp = { object = \"ball\", preshape = \"power\" }");
    let scene = Scene::parse(&text, "grasp.toml").unwrap();
    let solved = solve_scene(&scene, "grasp.toml").unwrap_or_else(|e| panic!("{e}"));
    let frame = solved.frames.last().unwrap();
    let hand = &frame.hands[0];
    let g = hand.grasp.clone().unwrap();
    held_at_the_least_closing(&g);
    assert!(g.digits_touching.iter().any(|d| d == "thumb"), "{g:?}");
    assert!(hand.overloads.is_empty(), "{:?}", hand.overloads);
    // Firmer closings that hold too, with a larger grip.
    let firmer: Vec<_> = g
        .search
        .iter()
        .filter(|t| t.closing_deg > g.closing_deg && t.margin >= 1.5)
        .collect();
    assert!(!firmer.is_empty(), "{:?}", g.search);
    for t in firmer {
        assert!(t.grip > g.grip, "{t:?} against the grip found {}", g.grip);
    }
    let drift = g.drift.expect("held: its drift");
    assert!(drift > 1e-5 && drift < 0.01, "drift {drift} m");
    // The ball pushes the thumb back towards the wrist (−x) and the fingers towards their tips.
    let skeleton = &solved.model.bodies[hand.body]
        .hand
        .as_deref()
        .unwrap()
        .skeleton;
    let mut thumb = nalgebra::Vector3::<f64>::zeros();
    let mut fingers = nalgebra::Vector3::<f64>::zeros();
    for (bone, f) in skeleton.bones.iter().zip(&hand.contact_force) {
        match bone.digit {
            Some(0) => thumb += f,
            Some(_) => fingers += f,
            None => {}
        }
    }
    assert!(
        thumb.x < -0.1 * thumb.norm().max(fingers.norm()) && fingers.x > 0.0,
        "on the thumb {thumb:?}, on the fingers {fingers:?}"
    );
    held_by_the_hand_alone(&solved);
    hand_made_grasps_press_harder(&g);
}

/// The gentlest grip `g` against grasps an animator makes by hand (issue 17's test), each
/// judged as posed (`close = false`: solved from rest, let go of, no closing): the pose found,
/// as posed, holds with the grip the search found (within 5 %: reached from rest, not along
/// the closing); the fingers flexed 3° further at every MCP, PIP and DIP, and 6° with the
/// thumb's MCP 5° further, hold too, with a larger grip; the viewer's Power grasp preset
/// presses harder still and does not hold (its thumb, abducted 35° in the palm's plane, pushes
/// the ball towards the wrist and out of the grip), and says so.
fn hand_made_grasps_press_harder(g: &prehensile::state::GraspOutcome) {
    let judged = |pose: &std::collections::BTreeMap<String, f64>| {
        let table: Vec<String> = pose.iter().map(|(j, a)| format!("\"{j}\" = {a}")).collect();
        let text = scene(&format!(
            "grasp = {{ object = \"ball\", preshape = {{ {} }}, close = false }}",
            table.join(", ")
        ));
        let scene = Scene::parse(&text, "hand-made.toml").unwrap();
        let run = solve_scene(&scene, "hand-made.toml").unwrap_or_else(|e| panic!("{e}"));
        let o = run.frames.last().unwrap().hands[0].grasp.clone().unwrap();
        println!(
            "hand-made: held {}, grip {:.3} N, margin {:.3}, drift {:?}, {:?}",
            o.held, o.grip, o.margin, o.drift, o.reason
        );
        assert_eq!(
            (o.trials, o.closing_deg),
            (1, 0.0),
            "judged as posed: {o:?}"
        );
        assert_eq!(o.preshape_grip, o.grip);
        o
    };
    let further = |fingers: f64, thumb_mcp: f64| {
        let mut pose = g.pose.clone();
        for (joint, angle) in pose.iter_mut() {
            let finger = !joint.starts_with("thumb.");
            if finger
                && [".mcp.flex", ".pip", ".dip"]
                    .iter()
                    .any(|j| joint.ends_with(j))
            {
                *angle += fingers;
            }
            if joint == "thumb.mcp" {
                *angle += thumb_mcp;
            }
        }
        pose
    };
    let found = judged(&g.pose);
    assert!(found.held && found.margin >= 1.5, "{found:?}");
    assert!((found.grip - g.grip).abs() <= 0.05 * g.grip, "{found:?}");
    let mut last = g.grip;
    for (fingers, thumb_mcp) in [(3.0, 0.0), (6.0, 5.0)] {
        let h = judged(&further(fingers, thumb_mcp));
        assert!(h.held && h.margin >= 1.5, "{h:?}");
        assert!(h.grip > last, "{h:?}: not firmer than {last} N");
        last = h.grip;
    }
    let skeleton = prehensile::hand::Skeleton::new(prehensile::hand::Side::Right);
    let preset = prehensile::app::pose::Preset::PowerGrasp.angles(&skeleton);
    let preset = skeleton
        .dofs
        .iter()
        .zip(preset)
        .map(|(d, a)| (d.name.clone(), a))
        .collect();
    let viewer = judged(&preset);
    assert!(!viewer.held && viewer.grip > 10.0 * g.grip, "{viewer:?}");
    let reason = viewer.reason.unwrap();
    assert!(
        reason.starts_with("as posed, let go of, the hand does not hold it")
            && reason.contains("close = false"),
        "{reason}"
    );
}

/// The anatomical hand turned palm up (`placement = { rotation = [180, 0, 0] }`) with the ball on
/// the cupped fingers, its stand above it: let go of, the ball settles onto the hand, which holds
/// it. (The ball 3 mm lower than over the simple hand. At the simple hand's own placement the
/// anatomical hand's best margin along the synergies is 1.22, against the 1.5 asked; at six
/// placements about it — x ± 5 mm, y ± 5 mm, z ± 3 mm — it holds, margins 1.52–3.71, this one
/// 2.30 at 4.0° past first contact: the let-go's outcome near the margin asked depends on where
/// the ball sits, measured 2026-12-03.) The search finds the least closing that holds it let go of; the frame shown is the ball
/// held by the hand alone: the contact forces on it (normal and friction) balance its weight
/// (action = reaction, to what the stabilising springs may carry), every contact in its Coulomb
/// cone, nothing through the skin, and the drift is its sinking into the soft flesh.
#[test]
fn a_ball_let_go_of_in_the_upturned_hand_is_held_by_it_alone() {
    let text = scene("grasp = { object = \"ball\", preshape = \"power\" }")
        .replace(
            "resolution = 1.0 }",
            "resolution = 1.0, form = \"anatomical\", placement = { rotation = [180.0, 0.0, 0.0] } }",
        )
        .replace(
            "center = [0.065, 0.0, -0.065]",
            "center = [0.065, 0.0, 0.053]",
        )
        .replace(
            "min = [0.055, -0.01, -0.101], max = [0.075, 0.01, -0.098]",
            "min = [0.055, -0.01, 0.0865], max = [0.075, 0.01, 0.0895]",
        );
    assert!(text.contains("rotation = [180.0") && text.contains("0.0895"));
    let scene = Scene::parse(&text, "grasp.toml").unwrap();
    let solved = solve_scene(&scene, "grasp.toml").unwrap_or_else(|e| panic!("{e}"));
    let frame = solved.frames.last().unwrap();
    let g = frame.hands[0].grasp.clone().unwrap();
    held_at_the_least_closing(&g);
    let drift = g.drift.expect("held: its drift");
    assert!(drift > 1e-5 && drift < 0.01, "drift {drift} m");

    held_by_the_hand_alone(&solved);
}

/// The ball held by the hand alone in the last frame of `solved` (gravity −9.81 m/s² along z,
/// μ = 0.8).
fn held_by_the_hand_alone(solved: &prehensile::headless::Solved) {
    crate::common::held::held_by_the_hand_alone(
        solved,
        "ball",
        nalgebra::Vector3::new(0.0, 0.0, -9.81),
        0.8,
    );
}

/// The grasp held with the margin asked (1.5) at the least closing that holds: every pose of
/// the search closed less did not hold it.
fn held_at_the_least_closing(g: &prehensile::state::GraspOutcome) {
    assert!(g.held, "{:?}", g.reason);
    assert!(g.margin >= 1.5, "margin {}", g.margin);
    for t in &g.search {
        if t.closing_deg < g.closing_deg {
            assert!(
                t.margin < 1.5,
                "{t:?} holds, closed less than {}",
                g.closing_deg
            );
        }
    }
}

/// The gentlest power grip under the hand's refinement (the numbers the product exists for
/// converge): the palm-down grasp searched at hand resolutions 1, 1.25 and 1.5 (the ball's mesh
/// alike) is held at each, at a margin near the one asked (under 2: before the let-go told its
/// floor from sliding out, the search closed on to margins of 2.35–2.60), and the grips found
/// lie within 15 % of one another (measured 2026-11-30: 1.206, 1.354, 1.200 N, margins 1.523,
/// 1.530, 1.533; before, 1.36, 2.50, 4.09 N).
#[test]
fn the_gentlest_power_grip_converges_under_the_hands_refinement() {
    let grips: Vec<f64> = ["1.0", "1.25", "1.5"]
        .iter()
        .map(|r| {
            let text = scene("grasp = { object = \"ball\", preshape = \"power\" }")
                .replace("resolution = 1.0 }", &format!("resolution = {r} }}"));
            assert!(text.contains(&format!("resolution = {r} }}")));
            let scene = Scene::parse(&text, "grasp.toml").unwrap();
            let solved = solve_scene(&scene, "grasp.toml").unwrap_or_else(|e| panic!("{e}"));
            let g = solved.frames.last().unwrap().hands[0]
                .grasp
                .clone()
                .unwrap();
            held_at_the_least_closing(&g);
            assert!(g.margin < 2.0, "resolution {r}: margin {}", g.margin);
            g.grip
        })
        .collect();
    let (least, most) = grips
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(l, m), g| (l.min(*g), m.max(*g)));
    assert!(most <= 1.15 * least, "grips found {grips:?} N");
}
