//! What the report says of a contact that did not fully settle: the Lagrange active set cut at
//! its iteration cap keeps its last settled set (every contact pushing, within the penetration
//! limit) and says so, in `contact.at_iteration_cap` and in a warning; with the default cap the
//! shipped finger press settles and says nothing of it.

use prehensile::headless::solve_scene;
use prehensile::scene::Scene;

fn solved_with(extra: &str) -> prehensile::headless::Solved {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    let text = text.replace(
        "contact = \"lagrange\"",
        &format!("contact = \"lagrange\"\n{extra}"),
    );
    let scene = Scene::parse(&text, "press.toml").unwrap();
    solve_scene(&scene, "press.toml").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn an_active_set_kept_at_the_iteration_cap_is_flagged() {
    let capped = solved_with("contact_max_iterations = 3");
    let limit = capped.model.contact.penetration_limit();
    let mut flagged = 0;
    for (i, frame) in capped.frames.iter().enumerate() {
        let c = frame.contact.as_ref().expect("the finger presses the ball");
        let warned = capped.report.warnings.iter().any(|w| {
            w.starts_with(&format!("frame {i}: ")) && w.contains("active set still changed")
        });
        assert_eq!(warned, c.at_iteration_cap, "frame {i}");
        assert_eq!(
            capped.report.frames[i]
                .contact
                .as_ref()
                .unwrap()
                .at_iteration_cap,
            c.at_iteration_cap
        );
        if c.at_iteration_cap {
            flagged += 1;
            assert!(c.iterations <= 3, "{} iterations", c.iterations);
            assert!(c.max_penetration <= limit);
            assert!(c.contacts.iter().all(|p| p.force > 0.0));
        }
    }
    assert!(flagged > 0, "three iterations do not settle the press");
    let free = solved_with("");
    for (i, frame) in free.frames.iter().enumerate() {
        let c = frame.contact.as_ref().unwrap();
        assert!(
            !c.at_iteration_cap,
            "frame {i}: {} iterations",
            c.iterations
        );
    }
}
