//! The paper's iteration converges only for objects softer than the flesh under them. On a
//! stiff ball its first iterate overruns a bone's threshold while the displacements are still
//! changing by metres: that is no grasp, so the solve stops with an error that says so (the
//! command exits non-zero) instead of writing the iterate — and the method it advises solves it.

use prehensile::headless::solve_scene;
use prehensile::scene::Scene;

fn finger_press(young: &str, method: &str) -> Scene {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml")
        .unwrap()
        .replace("young = 2.0e6", &format!("young = {young}"))
        .replace("contact = \"lagrange\"", &format!("contact = \"{method}\""));
    assert!(text.contains(&format!("young = {young}")) && text.contains(method));
    Scene::parse(&text, "stiff.toml").unwrap()
}

#[test]
fn the_papers_iteration_on_a_stiff_ball_stops_and_the_advice_works() {
    let err = match solve_scene(&finger_press("2.0e9", "paper"), "stiff.toml") {
        Ok(s) => panic!(
            "an unconverged iterate was returned: largest displacement {} m",
            s.report.frames.last().unwrap().max_displacement
        ),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("before it converged"), "{err}");
    assert!(err.contains("contact = \"lagrange\""), "{err}");
    // The advice: the exact method solves the same press, every frame within the contact's
    // penetration limit and displacements of millimetres, not metres.
    let solved = solve_scene(&finger_press("2.0e9", "lagrange"), "stiff.toml").unwrap();
    let limit = solved.model.contact.penetration_limit();
    for f in &solved.frames {
        if let Some(c) = &f.contact {
            assert!(c.max_penetration <= limit, "{}", c.max_penetration);
        }
        let largest = f
            .solution
            .displacement
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(largest.is_finite() && largest < 0.1, "{largest} m");
    }
}
