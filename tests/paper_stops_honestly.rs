//! The paper's iteration converges only for objects softer than the flesh under them. On a
//! stiff ball its first iterate overruns a bone's threshold while the displacements are still
//! changing by metres: that is no grasp, so the solve stops with an error that says so (the
//! command exits non-zero) instead of writing the iterate — and the method it advises solves it.

mod common;

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

/// The paper's iteration inside the contact steps along a motion: on the five-digit grasp of a
/// ball stiffer than the flesh (E = 2 MPa against 50 kPa) it cannot follow the closing hand.
/// That is the method's failure, not the grasp's limit: the command exits non-zero, writes no
/// frame, and its advice (the exact method) solves the same motion to the pose.
#[test]
fn the_papers_iteration_along_a_motion_fails_with_exit_code_and_the_advice_works() {
    let text = std::fs::read_to_string("assets/scenes/hand-grasp-ball.toml")
        .unwrap()
        .replace("resolution = 1.0", "resolution = 0.75");
    assert!(text.contains("resolution = 0.75"));
    let paper = text.replace("contact = \"lagrange\"", "contact = \"paper\"");
    assert!(paper.contains("contact = \"paper\""));
    let dir = std::env::temp_dir().join(format!("paper-motion-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("paper.toml");
    std::fs::write(&scene, &paper).unwrap();
    let out = dir.join("out");
    let run = common::solve_cli(&scene, &out);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success(),
        "exit 0 on a failed iteration: {stderr}"
    );
    assert!(
        stderr.contains("could not follow the motion beyond"),
        "{stderr}"
    );
    assert!(stderr.contains("contact = \"lagrange\""), "{stderr}");
    // Nothing half-written: no report and no frame.
    assert!(!out.join("report.json").exists());
    assert!(!out.join("frames.pvd").exists());
    // The advice: the exact method reaches the grasp pose with the fingers in contact.
    let solved = solve_scene(&Scene::parse(&text, "grasp.toml").unwrap(), "grasp.toml").unwrap();
    let last = solved.frames.last().unwrap();
    let contact = last.contact.as_ref().expect("the grasp touches the ball");
    assert!(contact.max_penetration <= solved.model.contact.penetration_limit());
    for h in &last.hands {
        assert!(
            h.stats.stopped_short.is_none(),
            "the exact method stopped short: {:?}",
            h.stats.stopped_short
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
