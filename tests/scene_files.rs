//! Scene files and the `solve` command: the documented example works as written, bad input is
//! refused with an error naming the file and the field, and nothing is left in `--out`.

use crate::common;

use prehensile::headless::{solve_scene, solve_scene_file};
use prehensile::model::Model;
use prehensile::scene::Scene;
use serde_json::Value;
use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_prehensile"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("prehensile-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn v3(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    ]
}

#[test]
fn the_documented_block_press_scene_solves_and_writes_report_and_vtu() {
    let dir = scratch("block");
    let out = dir.join("out");
    let status = bin()
        .args(["solve", "assets/scenes/block-press.toml", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let frame = &report["frames"][0];
    let base = v3(&frame["constraints"]["base"]["reaction"]);
    let press = v3(&frame["constraints"]["press"]["reaction"]);
    // No other load: the two supports balance each other to round-off.
    for i in 0..3 {
        assert!(
            (base[i] + press[i]).abs() < 1e-9 * press[2].abs(),
            "axis {i}: {base:?} {press:?}"
        );
    }
    // Pressing 1 % on a 1 m² face of E = 1 MPa needs at least the uniaxial-stress force E·ε·A.
    assert!(
        press[2] < -1.0e4 && press[2] > -1.2e4,
        "press reaction {}",
        press[2]
    );
    // The centre node sits on both symmetry planes: it moves along z only, by less than the top.
    let centre = v3(&frame["probes"]["centre"]["displacement"]);
    assert!(
        centre[0].abs() < 1e-12 && centre[1].abs() < 1e-12,
        "{centre:?}"
    );
    assert!(centre[2] < -0.004 && centre[2] > -0.006, "{centre:?}");
    assert!(frame["solver"]["residual"].as_f64().unwrap() < 1e-10);
    for key in ["assembly", "factorization", "solve"] {
        assert!(
            frame["solver"]["timings_ms"][key].as_f64().unwrap() >= 0.0,
            "{key}"
        );
    }
    let vtu = common::vtu::text(&out.join("frame_0000.vtu"));
    assert!(vtu.contains(r#"NumberOfPoints="1331" NumberOfCells="1000""#));
    for name in ["displacement", "von_mises", "material_id"] {
        assert!(vtu.contains(&format!("Name=\"{name}\"")), "{name}");
    }
    assert!(!vtu.to_lowercase().contains("nan") && !vtu.contains("inf"));
    assert!(out.join("frames.pvd").exists());
    // No staging folder is left behind: the four files and the manifest of what was written.
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            ".prehensile-output",
            "animation.glb",
            "frame_0000.vtu",
            "frames.pvd",
            "report.json"
        ]
    );
}

#[test]
fn every_example_scene_solves_in_balance() {
    for entry in std::fs::read_dir("assets/scenes").unwrap() {
        let path = entry.unwrap().path();
        let solved = solve_scene_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // Every keyframe reaches its pose (a bone's threshold may end one: a result, not a
        // failure) and its contact settles there.
        assert_eq!(
            prehensile::headless::unsolved(&solved),
            None,
            "{}",
            path.display()
        );
        // Every frame balances: the loads against the supports, the bones and the obstacles
        // (the contact between hand and object is internal to the scene). To 1e-9 of the
        // forces without contact; with it, 1e-6: the contact's multipliers are solved through a
        // Schur complement, round-off over the stiffness contrast of the bodies (measured
        // 2026-11-29: 2e-11 … 8e-11 N of 1.17 N on the rubber balls, 1.2e-6 N of 2.56 N with
        // the ceramic bowl, E = 1e11 Pa against the flesh's 5e4).
        for (i, f) in solved.report.frames.iter().enumerate() {
            let tolerance = if solved.frames[i].contact.is_some() {
                1e-6
            } else {
                1e-9
            };
            let scale: f64 = f
                .equilibrium
                .reactions
                .iter()
                .chain(&f.equilibrium.applied)
                .map(|v| v.abs())
                .sum::<f64>()
                .max(1.0);
            let worst = f
                .equilibrium
                .imbalance
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()));
            println!(
                "{} frame {i}: imbalance {worst:.2e} N of {scale:.3e}",
                path.display()
            );
            assert!(
                worst < tolerance * scale,
                "{} frame {i}: {:?}",
                path.display(),
                f.equilibrium
            );
        }
    }
}

const GOOD: &str = r#"
[[material]]
name = "rubber"
young = 1.0e6
poisson = 0.3
density = 1100.0

[[body]]
name = "block"
material = "rubber"
shape = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], cells = [2, 2, 2] } }

[[constraint]]
name = "base"
body = "block"
where = { face = "z-" }
displacement = [0.0, 0.0, 0.0]
"#;

/// Runs `solve` on `text` and returns stderr, checking the exit code and that `--out` stays empty.
fn refused(name: &str, text: &str) -> String {
    let dir = scratch(name);
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let result = common::solve_cli(&scene, &out);
    assert!(!result.status.success(), "{name} was accepted");
    assert!(!out.exists(), "{name}: output folder was created");
    let err = String::from_utf8_lossy(&result.stderr).to_string();
    assert!(
        err.contains(&scene.display().to_string()),
        "{name}: error does not name the file: {err}"
    );
    err
}

fn expect(name: &str, text: &str, needles: &[&str]) {
    let err = refused(name, text);
    for n in needles {
        assert!(err.contains(n), "{name}: expected {n:?} in: {err}");
    }
}

#[test]
fn malformed_toml_names_line_and_column() {
    expect(
        "malformed",
        &GOOD.replace("young = 1.0e6", "young = = 1.0e6"),
        &[":4:9:", "extra `=`"],
    );
    expect(
        "typo",
        &GOOD.replace("young = 1.0e6", "youngs = 1.0e6"),
        &["youngs", ":4:", "unknown field"],
    );
}

#[test]
fn unknown_names_are_refused() {
    expect(
        "unknown-material",
        &GOOD.replace("material = \"rubber\"", "material = \"rubbr\""),
        &[
            "body \"block\" (body[0]).material",
            "no material named \"rubbr\"",
            "rubber",
        ],
    );
    expect(
        "unknown-body",
        &GOOD.replace("body = \"block\"", "body = \"blok\""),
        &[
            "constraint \"base\" (constraint[0]).body",
            "no body named \"blok\"",
        ],
    );
}

#[test]
fn inadmissible_materials_are_refused() {
    expect(
        "young",
        &GOOD.replace("young = 1.0e6", "young = 0.0"),
        &["material \"rubber\" (material[0])", "young"],
    );
    expect(
        "poisson",
        &GOOD.replace("poisson = 0.3", "poisson = 0.5"),
        &["material \"rubber\" (material[0])", "poisson"],
    );
    expect(
        "poisson-low",
        &GOOD.replace("poisson = 0.3", "poisson = -1.0"),
        &["poisson"],
    );
}

#[test]
fn zero_cells_and_empty_selections_are_refused() {
    expect(
        "cells",
        &GOOD.replace("cells = [2, 2, 2]", "cells = [2, 0, 2]"),
        &["body \"block\" (body[0]).shape", "cells"],
    );
    expect(
        "empty-selection",
        &GOOD.replace(
            "where = { face = \"z-\" }",
            "where = { box = { min = [5.0, 5.0, 5.0], max = [6.0, 6.0, 6.0] } }",
        ),
        &[
            "constraint \"base\" (constraint[0]).where",
            "selects no node",
        ],
    );
    expect(
        "bad-face",
        &GOOD.replace("face = \"z-\"", "face = \"w-\""),
        &["where", "not a box face"],
    );
}

#[test]
fn inverted_and_flat_elements_are_named() {
    let inverted = GOOD.replace(
        "shape = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], cells = [2, 2, 2] } }",
        "shape = { mesh = { nodes = [[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]], \
         cells = [[4,5,6,7,0,1,2,3]] } }",
    );
    expect(
        "inverted",
        &inverted,
        &[
            "body \"block\" (body[0]).shape",
            "element 0 is inverted or has zero volume",
        ],
    );
    let flat = inverted
        .replace(
            "[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,1],[1,0,1],[1,1,1],[0,1,1]]",
            "[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0,0,0],[1,0,0],[1,1,0],[0,1,0]]",
        )
        .replace("[[4,5,6,7,0,1,2,3]]", "[[0,1,2,3,4,5,6,7]]");
    expect("flat", &flat, &["element 0 is inverted or has zero volume"]);
}

#[test]
fn a_body_free_to_move_rigidly_is_named() {
    let free = GOOD.replace(
        "displacement = [0.0, 0.0, 0.0]",
        "displacement = { z = 0.0 }",
    );
    expect(
        "rigid",
        &free,
        &[
            "body \"block\" (body[0])",
            "free to move rigidly",
            "translation along x",
            "translation along y",
            "rotation about z",
        ],
    );
    let two = format!(
        "{GOOD}\n[[body]]\nname = \"loose\"\nmaterial = \"rubber\"\nshape = {{ sphere = {{ center = [3, 0, 0], radius = 0.5, cells = 2 }} }}\n"
    );
    expect(
        "rigid-second-body",
        &two,
        &["body \"loose\" (body[1])", "free to move rigidly"],
    );
}

#[test]
fn loads_need_exactly_one_kind_and_pressure_needs_facets() {
    let both = format!("{GOOD}\n[[load]]\nbody = \"block\"\nwhere = {{ face = \"z+\" }}\npressure = 1.0\nforce = [0, 0, 1]\n");
    expect(
        "both",
        &both,
        &["load \"load[0]\" (load[0])", "exactly one"],
    );
    let point = format!(
        "{GOOD}\n[[load]]\nbody = \"block\"\nwhere = {{ point = [1, 1, 1] }}\npressure = 1.0\n"
    );
    expect(
        "pressure-point",
        &point,
        &["load[0]", "where", "no boundary facet"],
    );
}

#[test]
fn conflicting_prescriptions_are_refused() {
    let conflict = format!(
        "{GOOD}\n[[constraint]]\nname = \"lift\"\nbody = \"block\"\nwhere = {{ box = {{ min = [0, 0, 0], max = [1, 1, 0] }} }}\ndisplacement = {{ z = 0.1 }}\n"
    );
    expect(
        "conflict",
        &conflict,
        &[
            "constraint \"lift\" (constraint[1]).displacement",
            "already prescribed along z by constraint \"base\"",
        ],
    );
}

#[test]
fn a_missing_scene_file_is_a_clear_error() {
    let result = bin()
        .args(["solve", "no/such/scene.toml", "--out"])
        .arg(scratch("missing").join("out"))
        .output()
        .unwrap();
    assert!(!result.status.success());
    let err = String::from_utf8_lossy(&result.stderr);
    assert!(
        err.contains("no/such/scene.toml") && err.contains("cannot read"),
        "{err}"
    );
}

#[test]
fn the_built_in_default_scene_is_the_hand_and_ball_and_solves() {
    // Without a subcommand the viewer opens on it (tests/viewer_window.rs); here it is solved.
    assert_eq!(
        prehensile::scene::DEFAULT_SCENE,
        std::fs::read_to_string("assets/scenes/hand-and-ball.toml").unwrap()
    );
    let dir = scratch("built-in");
    let out = dir.join("out");
    let result = bin()
        .args(["solve", "assets/scenes/hand-and-ball.toml", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let text = String::from_utf8_lossy(&result.stdout);
    assert!(
        text.contains("constraint support") && text.contains("hand hand"),
        "{text}"
    );
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    // The initial pose and two keyframes; the hand and the ball do not touch.
    assert_eq!(report["frames"].as_array().unwrap().len(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `GOOD` with a `[[load]]` of `name` (a `name = "…"` line, or "" for none) on box face `face`.
fn with_loads(loads: &[(&str, &str, &str)]) -> String {
    let mut text = GOOD.to_string();
    for (name, face, kind) in loads {
        text += &format!(
            "\n[[load]]\n{name}body = \"block\"\nwhere = {{ face = \"{face}\" }}\n{kind}\n"
        );
    }
    text
}

/// Two loads of one name: `report.json` keys `frames[].loads` by name, and one was silently
/// dropped from it (hostile-input probe, 2026-12-04). Refused as duplicate constraints are,
/// also where a name given is an unnamed load's `load[i]`; loads of distinct names are all
/// reported.
#[test]
fn loads_of_one_name_are_refused_and_every_load_is_reported() {
    let pressure = ("x+", "pressure = 100.0");
    let force = ("x-", "force = [0.0, 0.0, 5.0]");
    let err = refused(
        "duplicate-load",
        &with_loads(&[
            ("name = \"p\"\n", pressure.0, pressure.1),
            ("name = \"p\"\n", force.0, force.1),
        ]),
    );
    assert!(
        err.contains(
            "duplicate-load.toml: load \"p\" (load[1]): a load of this name is defined twice \
             (load[0] has it)"
        ),
        "{err}"
    );
    let err = refused(
        "duplicate-default-load-name",
        &with_loads(&[
            ("name = \"load[1]\"\n", pressure.0, pressure.1),
            ("", force.0, force.1),
        ]),
    );
    assert!(
        err.contains("load \"load[1]\" (load[1]): a load of this name is defined twice"),
        "{err}"
    );

    let text = with_loads(&[
        ("name = \"p\"\n", pressure.0, pressure.1),
        ("name = \"q\"\n", force.0, force.1),
        ("", "y+", "force = [0.0, 1.0, 0.0]"),
    ]);
    let solved = solve_scene(&Scene::parse(&text, "loads.toml").unwrap(), "loads.toml").unwrap();
    let loads = &solved.report.frames[0].loads;
    assert_eq!(
        loads.keys().map(String::as_str).collect::<Vec<_>>(),
        ["load[2]", "p", "q"]
    );
    // 100 Pa on the 1 m² face x+, against its outward normal.
    assert!((loads["p"][0] + 100.0).abs() < 1e-9, "{loads:?}");
    assert_eq!(loads["q"], [0.0, 0.0, 5.0]);
    assert_eq!(loads["load[2]"], [0.0, 1.0, 0.0]);
}

/// An obstacle named as a material made `[[friction]] between` ambiguous; a friction pair of
/// two obstacles (rigid, fixed: they never touch) was accepted and used nowhere. Both refused,
/// naming the fields.
#[test]
fn an_obstacle_named_as_a_material_and_friction_between_obstacles_are_refused() {
    let obstacle = |name: &str, z: f64| {
        format!(
            "\n[[obstacle]]\nname = \"{name}\"\n\
             shape = {{ plane = {{ point = [0.0, 0.0, {z}], normal = [0.0, 0.0, 1.0] }} }}\n"
        )
    };
    let err = refused(
        "obstacle-named-as-material",
        &format!("{GOOD}{}", obstacle("rubber", -0.5)),
    );
    assert!(
        err.contains(
            "obstacle-named-as-material.toml: obstacle \"rubber\" (obstacle[0]).name: is also \
             the name of material \"rubber\" (material[0]).name, and [[friction]] between = \
             [...] names materials and obstacles alike: give the obstacle a name of its own"
        ),
        "{err}"
    );
    let err = refused(
        "friction-between-obstacles",
        &format!(
            "{GOOD}{}{}\n[[friction]]\nbetween = [\"table\", \"shelf\"]\nmu = 0.5\n",
            obstacle("table", -0.5),
            obstacle("shelf", -0.6)
        ),
    );
    assert!(
        err.contains(
            "friction-between-obstacles.toml: friction[0].between: \"table\" and \"shelf\" are \
             both obstacles, which never touch each other: a friction pair names two \
             materials, or a material and an obstacle"
        ),
        "{err}"
    );
    // A material and an obstacle remain a pair.
    let text = format!(
        "{GOOD}{}\n[[friction]]\nbetween = [\"rubber\", \"table\"]\nmu = 0.5\n",
        obstacle("table", -0.5)
    );
    let scene = Scene::parse(&text, "pair.toml").unwrap();
    assert!(Model::build(&scene, "pair.toml").is_ok());
}

/// A reference of 500 kB holding ESC and NUL was echoed raw and whole into the error (hostile-
/// input probe, 2026-12-04): it is echoed escaped and cut at 60 characters; and a name holding a
/// control character is refused, for every kind of named entry.
#[test]
fn names_are_echoed_escaped_and_short_and_control_characters_in_names_are_refused() {
    let long = format!("\\u001b[31m\\u0000{}", "ß".repeat(250_000));
    let err = refused(
        "long-reference",
        &GOOD.replace("material = \"rubber\"", &format!("material = \"{long}\"")),
    );
    // `\u{1b}[31m\0` is 12 characters as echoed: 48 more, then "…".
    let echoed = format!("\\u{{1b}}[31m\\0{}…", "ß".repeat(48));
    assert!(
        err.contains(&format!(
            "long-reference.toml: body \"block\" (body[0]).material: no material named \
             \"{echoed}\" (defined: rubber)"
        )),
        "{err}"
    );
    assert!(err.len() < 1000, "{} bytes", err.len());
    assert!(!err.contains(['\u{1b}', '\0']), "{err:?}");

    let probe = "\n[[probe]]\nname = \"tip\\u0007\"\nbody = \"block\"\npoint = [1.0, 1.0, 1.0]\n";
    let load = "\n[[load]]\nname = \"air\\u0000\"\nbody = \"block\"\nwhere = { face = \"z+\" }\npressure = 1.0\n";
    let obstacle = "\n[[obstacle]]\nname = \"table\\r\"\nshape = { plane = { point = [0.0, 0.0, -1.0], normal = [0.0, 0.0, 1.0] } }\n";
    let camera = "\n[[camera]]\nname = \"\\u001b]0;title\\u0007\"\neye = [3.0, 3.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n";
    let cases = [
        (
            "material-control",
            GOOD.replace("name = \"rubber\"", "name = \"rub\\u001bber\""),
            "material \"rub\\u{1b}ber\" (material[0]): the name holds a control character \
             (\\u{1b}): a material's name is plain text on one line",
        ),
        (
            "body-control",
            GOOD.replace("name = \"block\"", "name = \"blo\\u0000ck\""),
            "body \"blo\\0ck\" (body[0]): the name holds a control character (\\0): a body's \
             name",
        ),
        (
            "constraint-control",
            GOOD.replace("name = \"base\"", "name = \"ba\\nse\""),
            "constraint \"ba\\nse\" (constraint[0]): the name holds a control character (\\n)",
        ),
        (
            "load-control",
            format!("{GOOD}{load}"),
            "load \"air\\0\" (load[0]): the name holds a control character (\\0)",
        ),
        (
            "obstacle-control",
            format!("{GOOD}{obstacle}"),
            "obstacle \"table\\r\" (obstacle[0]): the name holds a control character (\\r)",
        ),
        (
            "probe-control",
            format!("{GOOD}{probe}"),
            "probe \"tip\\u{7}\" (probe[0]): the name holds a control character (\\u{7})",
        ),
        (
            "camera-control",
            format!("{GOOD}{camera}"),
            "camera \"\\u{1b}]0;title\\u{7}\" (camera[0]): the name holds a control character \
             (\\u{1b})",
        ),
    ];
    for (name, text, needle) in cases {
        let err = refused(name, &text);
        assert!(
            err.contains(needle),
            "{name}: expected {needle:?} in {err:?}"
        );
        assert!(
            !err.contains(['\u{1b}', '\0', '\u{7}', '\r']),
            "{name}: {err:?}"
        );
    }
}

/// The warnings of `GOOD` (a box, no hand) with `[solver]` keys `solver`.
fn warnings_of(solver: &str) -> Vec<String> {
    let text = format!("[solver]\n{solver}\n{GOOD}");
    let scene = Scene::parse(&text, "warn.toml").unwrap();
    Model::build(&scene, "warn.toml").unwrap().warnings()
}

/// `[solver]` keys with no effect on the scene were accepted silently (hostile-input probe,
/// 2026-12-04): a hand's keys in a scene without a hand, `element` on the nonlinear tier, and
/// `contact_pairs` with the paper's iteration, which checks both ways whatever it says. Each is
/// warned of, in `report.json`'s warnings; keys that do act are not.
#[test]
fn solver_keys_without_effect_are_warned_of() {
    assert_eq!(
        warnings_of("self_contact = true"),
        [
            "solver.self_contact = true: has no effect, the scene has no hand (it keeps a hand's \
             skin from passing through itself)"
        ]
    );
    assert_eq!(
        warnings_of("flesh_digits = { little = \"skinning\" }"),
        [
            "solver.flesh_digits: has no effect, the scene has no hand (it sets how each part of \
             a hand's flesh follows its bones)"
        ]
    );
    assert_eq!(
        warnings_of("tier = \"corotational\"\nmax_step_deg = 5.0"),
        [
            "solver.tier = \"corotational\": has no effect, the scene has no hand (it sets how \
             a hand's flesh is solved; the bodies get the linear static solve, or Newton's \
             with tier = \"nonlinear\")",
            "solver.max_step_deg: has no effect, the scene has no hand (it sets the largest \
             joint rotation of a hand's flexion increment)"
        ]
    );
    assert_eq!(
        warnings_of("tier = \"nonlinear\"\nelement = \"incompatible_modes\""),
        [
            "solver.element = \"incompatible_modes\": has no effect, solver.tier = \"nonlinear\" \
             solves the bodies by Newton on its own Neo-Hookean hexahedron (solver.volumetric); \
             `element` is the element of the linear static solve"
        ]
    );
    let paper = "solver.contact_pairs = \"object_nodes\": has no effect on the contact solve, \
                 the paper's iteration (solver.contact = \"paper\") checks contact both ways \
                 whatever contact_pairs says; it only chooses the pairs the report's \
                 max_penetration is measured over. Remove it, or solve with contact = \
                 \"lagrange\", whose pairs it chooses";
    assert_eq!(
        warnings_of("contact = \"paper\"\ncontact_pairs = \"object_nodes\""),
        [paper]
    );
    // The probe's scene (/work/scratch/probe/cases/contra.toml): each ignored key once.
    let contra = warnings_of(
        "contact = \"paper\"\ncontact_pairs = \"object_nodes\"\nelement = \
         \"incompatible_modes\"\ntier = \"nonlinear\"\nvolumetric = \"full\"\n\
         flesh_digits = { little = \"skinning\" }",
    );
    assert_eq!(contra.len(), 3, "{contra:#?}");
    assert!(contra[0].starts_with("solver.flesh_digits: has no effect"));
    assert!(contra[1].starts_with("solver.element = \"incompatible_modes\": has no effect"));
    assert_eq!(contra[2], paper);

    // Keys that act are not warned of: the element of the linear static solve, the paper's own
    // pairs, the exact method's pairs, the nonlinear and linear tiers of the bodies.
    for acting in [
        "element = \"incompatible_modes\"",
        "contact = \"paper\"\ncontact_pairs = \"both\"",
        "contact_pairs = \"object_nodes\"",
        "tier = \"nonlinear\"",
        "tier = \"linear\"",
        "self_contact = false",
    ] {
        assert_eq!(warnings_of(acting), Vec::<String>::new(), "{acting}");
    }
}

/// With a hand, its keys act (no warning); a scene of hands alone has no linear static solve
/// for `element` to choose the element of.
#[test]
fn hand_keys_act_with_a_hand_and_element_does_not_without_other_bodies() {
    let hand = "[[material]]\nname = \"flesh\"\nyoung = 5.0e4\npoisson = 0.45\n\n\
                [[body]]\nname = \"hand\"\nmaterial = \"flesh\"\n\
                shape = { hand = { side = \"right\", resolution = 0.5 } }\n";
    let warnings = |solver: &str| {
        let text = format!("[solver]\n{solver}\n{hand}");
        let scene = Scene::parse(&text, "hand.toml").unwrap();
        Model::build(&scene, "hand.toml").unwrap().warnings()
    };
    assert_eq!(
        warnings(
            "self_contact = true\nflesh_digits = { little = \"skinning\" }\nmax_step_deg = 5.0"
        ),
        Vec::<String>::new()
    );
    assert_eq!(
        warnings("element = \"incompatible_modes\""),
        [
            "solver.element = \"incompatible_modes\": has no effect, the scene has no body other \
             than hands, and `element` is the element of the other bodies' linear static solve (a \
             hand's flexion always uses hex8)"
        ]
    );
}
