//! Hands in scene files: keyframes, bone constraints, per-keyframe bone reactions in the report,
//! the OBJ/VTU exports, and clear errors for bad poses.

use prehensile::headless::{solve_scene, write_solved};
use prehensile::scene::Scene;

const HAND: &str = r#"
[[material]]
name = "flesh"
young = 5.0e4
poisson = 0.45
[[body]]
name = "hand"
material = "flesh"
shape = { hand = { side = "right", resolution = 0.75 } }
"#;

fn error_of(extra: &str) -> String {
    let text = format!("{HAND}{extra}");
    let scene = match Scene::parse(&text, "bad.toml") {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    match solve_scene(&scene, "bad.toml") {
        Ok(_) => panic!("accepted: {extra}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_finger_flexion_scene_reports_every_keyframe_and_exports_the_hand() {
    let solved =
        prehensile::headless::solve_scene_file("assets/scenes/finger-flexion.toml".as_ref())
            .unwrap();
    assert_eq!(solved.model.cameras[0].name, "finger");
    let times: Vec<f64> = solved.report.frames.iter().map(|f| f.time).collect();
    assert_eq!(times, [0.0, 0.5, 1.0, 1.5]);
    let increments: Vec<usize> = solved
        .report
        .frames
        .iter()
        .map(|f| f.hands["hand"].motion.increments)
        .collect();
    // 45° in ≤ 10° steps: 5; 45° more: 5; the DIP's 40°: 4.
    assert_eq!(increments, [0, 5, 5, 4]);
    for f in &solved.report.frames[1..] {
        let h = &f.hands["hand"];
        assert_eq!(h.pose["index.pip"], if f.time < 1.0 { 45.0 } else { 90.0 });
        let largest = h.bones.values().map(|b| b.magnitude).fold(0.0, f64::max);
        let sum = h
            .bone_reaction_sum
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        assert!(
            largest > 0.5,
            "a flexed finger loads its bones: {largest} N"
        );
        assert!(sum < 1e-10 * largest, "bone reactions balance: {sum} N");
        assert!(h.volume_change.abs() < 0.01);
        // Bones of the fingers that did not move carry (almost) nothing.
        assert!(h.bones["little.distal"].magnitude < 1e-6 * largest);
        // The constraint naming a bone reports the reaction of that bone's nodes.
        let c = f.constraints["index middle phalanx"].reaction;
        assert!(c.iter().map(|x| x * x).sum::<f64>().sqrt() > 0.1 * largest);
    }
    // Flexing the DIP loads the distal phalanx more (before, it only held the flesh at the edge
    // of the PIP's FEM region).
    let distal = |k: usize| solved.report.frames[k].hands["hand"].bones["index.distal"].magnitude;
    assert!(
        distal(3) > 1.3 * distal(2),
        "{} then {}",
        distal(2),
        distal(3)
    );

    let dir = std::env::temp_dir().join(format!("prehensile-hand-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let written = write_solved(&solved, &dir).unwrap();
    let names: Vec<String> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for n in [
        "hand_0003.obj",
        "bones_0003.vtu",
        "frame_0003.vtu",
        "report.json",
        "animation.glb",
    ] {
        assert!(names.iter().any(|x| x == n), "{n} missing from {names:?}");
    }
    let obj = std::fs::read_to_string(dir.join("hand_0003.obj")).unwrap();
    assert!(obj.contains("o hand_skin") && obj.contains("o hand_index.distal"));
    let hand = solved.model.bodies[0].hand.as_ref().unwrap();
    let vertices = obj.lines().filter(|l| l.starts_with("v ")).count();
    let bone_vertices: usize = hand
        .skeleton
        .bones
        .iter()
        .map(|b| prehensile::hand::bone_surface(b).0.len())
        .sum();
    assert_eq!(vertices, hand.skin.vertex_count() + bone_vertices);
    assert!(!obj.contains("NaN"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_poses_and_hand_constraints_are_refused_with_the_field_named() {
    let e = error_of("[[keyframe]]\ntime = 1.0\npose = { \"index.pipp\" = 10 }\n");
    assert!(
        e.contains("bad.toml: keyframe[0].pose: there is no joint \"index.pipp\""),
        "{e}"
    );
    // A joint name of 100 000 characters with an escape sequence: echoed escaped and cut.
    let long = format!("{}\\u001b[31m", "x".repeat(100_000));
    let e = error_of(&format!(
        "[[keyframe]]\ntime = 1.0\npose = {{ \"{long}\" = 10 }}\n"
    ));
    assert!(
        e.contains(&format!("there is no joint \"{}…\"", "x".repeat(60))) && e.len() < 2_000,
        "{} bytes: {}",
        e.len(),
        &e[..e.len().min(300)]
    );
    assert!(!e.contains('\u{1b}'));
    let e = error_of("[[keyframe]]\ntime = 1.0\npose = { \"index.pip\" = 150 }\n");
    assert!(e.contains("outside its range 0° … 110°"), "{e}");
    let e = error_of(
        "[[keyframe]]\ntime = 1.0\npose = { \"index.pip\" = 10 }\n\
         [[keyframe]]\ntime = 0.5\npose = { \"index.pip\" = 20 }\n",
    );
    assert!(
        e.contains("keyframe[1].time") && e.contains("time order"),
        "{e}"
    );
    let e = error_of(
        "[[constraint]]\nname = \"c\"\nbody = \"hand\"\nwhere = { bone = \"index.distall\" }\n\
         displacement = [0, 0, 0]\n",
    );
    assert!(
        e.contains("there is no bone \"index.distall\"") && e.contains("index.distal,"),
        "{e}"
    );
    let e = error_of(
        "[[constraint]]\nname = \"c\"\nbody = \"hand\"\nwhere = { box = { min = [0, 0, 0], \
         max = [1, 1, 1] } }\ndisplacement = [0, 0, 0]\n",
    );
    assert!(e.contains("a hand moves with its skeleton"), "{e}");
    let text = HAND.replace("resolution = 0.75", "resolution = 9");
    let e = solve_scene(&Scene::parse(&text, "bad.toml").unwrap(), "bad.toml")
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("shape.hand") && e.contains("between 0.5 and 4"),
        "{e}"
    );
    let e =
        error_of("[[camera]]\nname = \"c\"\neye = [1, 0, 0]\ntarget = [0, 0, 0]\nfov_deg = 200\n");
    assert!(e.contains("camera \"c\" (camera[0]).fov_deg"), "{e}");
    let e = error_of("[solver]\nflesh_digits = { pinky = \"skinning\" }\n");
    assert!(e.contains("solver.flesh_digits.pinky"), "{e}");
}
