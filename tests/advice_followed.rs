//! Every piece of advice printed is one that works (issue 19): for each piece of advice below, a
//! scene that triggers it is solved (or rendered) as a user runs it, the advice's text and the
//! exit code are asserted, then exactly what the advice says is applied, reading the value it
//! names from the message where it names one, and the case is asserted to be fixed: exit code
//! 0, and the warning or error gone. The items are numbered as in the second advice audit:
//!
//! - 10: a skin point deeper than the contact searches, "raise solver.contact_search to X mm or
//!   more", both as a failed correction at the pose (a warning) and as a motion that stops
//!   (exit 2);
//! - 18: the linear tier turning flesh inside out, "use tier \"corotational\" or
//!   \"incremental\"";
//! - 29: the stiffness pattern above `[solver] max_memory`, "or raise `[solver] max_memory`";
//! - 32: a motion the contact cannot follow (exit 2) with its active set capped below the
//!   default, "raise solver.contact_max_iterations (it is below its default, 50)";
//! - 34: the pressure overlay of a scene without contact, "(use stress, displacement or
//!   forces)";
//! - 43: the strain of a hand's press above 20 %, "or pose the grasp less deep".

use crate::common;

use common::solve_cli;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// A fresh, empty folder for case `name` under the system's temporary folder.
fn fresh(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "prehensile-advice-followed-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// One `prehensile solve` run: its exit code, its stderr and its output folder.
struct Run {
    code: Option<i32>,
    stderr: String,
    out: PathBuf,
}

impl Run {
    /// The warnings printed (each `warning: …` line, without the prefix).
    fn warnings(&self) -> Vec<&str> {
        self.stderr
            .lines()
            .filter_map(|l| l.strip_prefix("warning: "))
            .collect()
    }

    /// The report the run wrote (`report.json`).
    fn report(&self) -> serde_json::Value {
        let text = std::fs::read_to_string(self.out.join("report.json"))
            .unwrap_or_else(|e| panic!("no report.json in {}: {e}", self.out.display()));
        serde_json::from_str(&text).unwrap()
    }

    /// The magnitude of the contact force between the ball and the hand in the last frame (N).
    fn last_press(&self) -> f64 {
        let report = self.report();
        let frame = report["frames"].as_array().unwrap().last().unwrap().clone();
        let force = &frame["contact"]["bodies"]["ball/hand"]["force"];
        (0..3)
            .map(|i| force[i].as_f64().unwrap_or(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}

/// Writes `text` as `name.toml` in a fresh folder and solves it, `prehensile solve FILE --out
/// DIR`, as a user runs it; prints the warnings and errors it gave.
fn solve(name: &str, text: &str) -> Run {
    let dir = fresh(name);
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let start = Instant::now();
    let output = solve_cli(&scene, &out);
    let run = Run {
        code: output.status.code(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        out,
    };
    println!(
        "--- {name}: exit {:?} in {:.1} s",
        run.code,
        start.elapsed().as_secs_f64()
    );
    for line in run.stderr.lines() {
        if line.starts_with("warning: ") || line.starts_with("error: ") {
            println!("{line}");
        }
    }
    run
}

/// The number in `text` between `before` and the next `after`.
fn number_between(text: &str, before: &str, after: &str) -> f64 {
    let rest = text
        .split_once(before)
        .unwrap_or_else(|| panic!("no {before:?} in: {text}"))
        .1;
    let number = rest
        .split_once(after)
        .unwrap_or_else(|| panic!("no {after:?} after {before:?} in: {text}"))
        .0;
    number
        .trim()
        .parse()
        .unwrap_or_else(|e| panic!("{number:?} after {before:?} is not a number ({e}): {text}"))
}

/// The finger press of the audit (assets/scenes/finger-press-ball.toml's setting): the index
/// finger, posed at MCP 20°, presses a pressurised rubber shell held on a table, the MCP flexed
/// further by the keyframes (one a second).
struct FingerPress<'a> {
    /// The hand's lattice resolution.
    resolution: f64,
    /// Lines of `[solver]` beyond `max_step_deg = 10` and `contact = "lagrange"`.
    solver: &'a str,
    /// The table as an obstacle (a plane under the ball) besides the ball's support.
    table: bool,
    /// The keyframes' index.mcp.flex (°).
    keyframes: &'a [f64],
}

impl Default for FingerPress<'_> {
    fn default() -> Self {
        FingerPress {
            resolution: 0.5,
            solver: "",
            table: true,
            keyframes: &[21.0, 30.0],
        }
    }
}

impl FingerPress<'_> {
    fn scene(&self) -> String {
        let mut text = SCENE_FINGER_PRESS
            .replace("@RESOLUTION@", &format!("{:?}", self.resolution))
            .replace("@SOLVER@", self.solver);
        if self.table {
            text.push_str(
                "\n[[obstacle]]\nname = \"table\"\n\
                 shape = { plane = { point = [0.0, 0.0, -0.105], normal = [0.0, 0.0, 1.0] } }\n",
            );
        }
        for (i, mcp) in self.keyframes.iter().enumerate() {
            text.push_str(&format!(
                "\n[[keyframe]]\ntime = {:?}\npose = {{ \"index.mcp.flex\" = {mcp:?} }}\n",
                (i + 1) as f64
            ));
        }
        text
    }
}

/// The audit's finger-press scenes (td_s30_*.toml, cap2.toml) without their table obstacle and
/// keyframes, which [`FingerPress`] adds. The simple hand's, on which each advice's trigger was
/// made to fail one precise way: on the anatomical form at resolution 0.5 the press to MCP 23.5°
/// with a 0.5 mm search does not fail its correction, and its pulp's coarse tip leaves a skin
/// point inside the flesh at MCP 21–30° (measured 2026-12-03; docs/hand.md, "Forms").
const SCENE_FINGER_PRESS: &str = r#"
[world]
gravity = [0.0, 0.0, -9.81]

[solver]
max_step_deg = 10.0
contact = "lagrange"
@SOLVER@

[[material]]
name = "flesh"
young = 5.0e4        # Pa: soft tissue of the finger pulp
poisson = 0.45
density = 1050.0

[[material]]
name = "rubber"
young = 2.0e6        # Pa
poisson = 0.4
density = 1100.0

[[body]]
name = "hand"
material = "flesh"
shape = { hand = { side = "right", form = "simple", resolution = @RESOLUTION@ } }
pose = { "index.mcp.flex" = 20.0, "middle.mcp.flex" = -10.0, "ring.mcp.flex" = -10.0, "little.mcp.flex" = -10.0 }

[[body]]
name = "ball"
material = "rubber"
shape = { shell = { center = [0.160, 0.030, -0.070], inner_radius = 0.031, outer_radius = 0.035, cells = 12, layers = 2 } }

[[load]]
name = "air"
body = "ball"
where = { surface = "inner" }
pressure = 3.0e4     # Pa above ambient

[[constraint]]
name = "table"
body = "ball"
where = { box = { min = [0.150, 0.020, -0.106], max = [0.170, 0.040, -0.1035] } }
displacement = [0.0, 0.0, 0.0]
"#;

/// The advice of a skin point left deeper than the contact searches: the search depth (mm) it
/// names, parsed from the first message that gives it.
fn contact_search_advised(run: &Run) -> f64 {
    number_between(
        &run.stderr,
        "raise solver.contact_search to ",
        " mm or more",
    )
}

/// Item 10, as a failed correction at the pose (a warning, and exit 2: the contact could not
/// be solved at the pose, the frames written): "it went deeper than the
/// contact searches (0.5 mm): raise solver.contact_search to X mm or more". Solved again with
/// `contact_search` at the X printed, the correction holds. (The audit's press to MCP 30° did
/// not serve until 2026-11-26: skin was also met by the ball's cavity wall, which pulled it
/// through the 4 mm wall whatever the search depth; since skin meets the outer surface only,
/// the press reaches MCP 30° at the default search with no failed correction. Pressed to
/// 23.5° at 0.5 mm, the correction fails and the advice mends it.)
#[test]
fn a_skin_point_deeper_than_the_search_in_a_correction_is_mended_by_the_search_advised() {
    let press = |search: &str| {
        FingerPress {
            solver: &format!("contact_search = {search}"),
            keyframes: &[21.0, 23.5],
            ..FingerPress::default()
        }
        .scene()
    };
    let trigger = solve("search-warning", &press("0.0005"));
    assert_eq!(trigger.code, Some(2), "{}", trigger.stderr);
    let failed: Vec<&str> = trigger
        .warnings()
        .into_iter()
        .filter(|w| w.contains("a correction at the pose of hand \"hand\" failed"))
        .collect();
    assert_eq!(failed.len(), 1, "{}", trigger.stderr);
    assert!(
        failed[0].contains("it went deeper than the contact searches (0.5 mm)"),
        "{}",
        failed[0]
    );
    let x = number_between(failed[0], "raise solver.contact_search to ", " mm or more");
    assert!(x > 0.5, "{x} mm advised, the search is 0.5 mm already");

    // The advice, as printed: the search depth at X mm.
    let followed = solve("search-warning-followed", &press(&format!("{x}e-3")));
    assert_eq!(followed.code, Some(0), "{}", followed.stderr);
    let left: Vec<&str> = followed
        .warnings()
        .into_iter()
        .filter(|w| w.contains("correction") || w.contains("contact_search"))
        .collect();
    assert!(left.is_empty(), "raised to {x} mm: {left:#?}");
    // Still a press: the finger holds the ball where it was posed.
    let press = followed.last_press();
    assert!(press > 1.0, "{press} N");
}

/// Item 10, as a motion that stops (exit 2): the hand's move to its rest pose with a 0.4 mm
/// search depth stops, "raise solver.contact_search to X mm or more"; with X mm the scene
/// solves.
#[test]
fn a_skin_point_deeper_than_the_search_in_a_motion_is_mended_by_the_search_advised() {
    let pose = |search: &str| {
        FingerPress {
            solver: &format!("contact_search = {search}"),
            keyframes: &[],
            ..FingerPress::default()
        }
        .scene()
    };
    let trigger = solve("search-stop", &pose("0.0004"));
    assert_eq!(trigger.code, Some(2), "{}", trigger.stderr);
    assert!(
        trigger
            .stderr
            .contains("the scene was not solved to its poses"),
        "{}",
        trigger.stderr
    );
    assert!(
        trigger
            .stderr
            .contains("it went deeper than the contact searches (0.4 mm)"),
        "{}",
        trigger.stderr
    );
    // Frame 0 has no keyframe: the motion is the body's `pose`.
    assert!(
        trigger
            .stderr
            .contains("of its motion from rest to its `pose`")
            && trigger
                .stderr
                .contains("report.json gives the pose reached"),
        "{}",
        trigger.stderr
    );
    let x = contact_search_advised(&trigger);
    assert!(x > 0.4, "{x} mm advised, the search is 0.4 mm already");

    let followed = solve("search-stop-followed", &pose(&format!("{x}e-3")));
    assert_eq!(followed.code, Some(0), "{}", followed.stderr);
    assert!(
        !followed.stderr.contains("contact_search")
            && !followed.stderr.contains("stopped at")
            && !followed.stderr.contains("correction"),
        "raised to {x} mm: {}",
        followed.stderr
    );
}

/// Item 18: the linear tier turns a flesh cell inside out as the finger curls, "use tier
/// \"corotational\" or \"incremental\""; on each tier named the scene solves.
#[test]
fn flesh_the_linear_tier_inverts_solves_on_each_tier_advised() {
    let curl = |tier: &str| {
        format!(
            r#"
[solver]
tier = "{tier}"

[[material]]
name = "flesh"
young = 5.0e4
poisson = 0.45
density = 1050.0

[[body]]
name = "hand"
material = "flesh"
shape = {{ hand = {{ side = "right", resolution = 0.5 }} }}

[[keyframe]]
time = 1.0
pose = {{ "index.pip" = 100.0, "index.mcp.flex" = 80.0 }}
"#
        )
    };
    let trigger = solve("linear", &curl("linear"));
    assert_eq!(trigger.code, Some(1), "{}", trigger.stderr);
    assert!(trigger.stderr.contains("inside out"), "{}", trigger.stderr);
    let advice = trigger
        .stderr
        .split_once("use tier ")
        .unwrap_or_else(|| panic!("no tier advised: {}", trigger.stderr))
        .1
        .lines()
        .next()
        .unwrap();
    assert_eq!(advice, r#""corotational" or "incremental""#);
    // The tiers named: every other piece between quotes.
    let tiers: Vec<&str> = advice.split('"').skip(1).step_by(2).collect();
    assert_eq!(tiers, ["corotational", "incremental"]);

    for tier in tiers {
        let followed = solve(&format!("linear-{tier}"), &curl(tier));
        assert_eq!(followed.code, Some(0), "tier {tier}: {}", followed.stderr);
        assert!(
            !followed.stderr.contains("inside out"),
            "tier {tier}: {}",
            followed.stderr
        );
    }
}

/// Item 29: a box whose stiffness pattern needs more than `[solver] max_memory` is refused at
/// the model's build, "… or raise `[solver] max_memory` where the machine has the memory"; with
/// the budget raised (to 1 GB, which any machine running the tests has) it solves. (The audit's
/// 30³ box at 100 MB took 11 s once raised; a 10³ box at 5 MB is refused by the same check.)
#[test]
fn a_pattern_above_max_memory_solves_with_max_memory_raised() {
    let cube = |memory: &str| {
        format!(
            r#"
[solver]
max_memory = "{memory}"

[[material]]
name = "rubber"
young = 1e6
poisson = 0.3
density = 1100.0

[[body]]
name = "bar"
material = "rubber"
shape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], cells = [10, 10, 10] }} }}

[[constraint]]
name = "root"
body = "bar"
where = {{ face = "x-" }}
displacement = [0.0, 0.0, 0.0]

[[load]]
name = "tip"
body = "bar"
where = {{ face = "x+" }}
force = [0.0, 0.0, -1.0]
"#
        )
    };
    let trigger = solve("pattern", &cube("5 MB"));
    assert_eq!(trigger.code, Some(1), "{}", trigger.stderr);
    // The pattern's refusal (at the build, before the factor's).
    for part in [
        "body \"bar\" (body[0])",
        "to build",
        "for the stiffness matrix alone",
        "([solver] max_memory)",
        "or raise `[solver] max_memory` where the machine has the memory",
    ] {
        assert!(
            trigger.stderr.contains(part),
            "{part:?}: {}",
            trigger.stderr
        );
    }
    assert!(!trigger.out.join("report.json").exists());

    let followed = solve("pattern-raised", &cube("1 GB"));
    assert_eq!(followed.code, Some(0), "{}", followed.stderr);
    assert!(
        !followed.stderr.contains("max_memory"),
        "{}",
        followed.stderr
    );
    assert!(followed.out.join("report.json").is_file());
}

/// Item 32: a press whose contact, capped at 2 active-set iterations, cannot follow its
/// keyframe exits with code 2, "hand \"hand\" stopped at NN % of its keyframe's motion: … the
/// active set was still changing at the cap: raise solver.contact_max_iterations (it is below
/// its default, 50)". With the cap at its default the press solves, at resolution 0.5 where two
/// iterations stop it. (At 0.75 they stopped it too until the corrections at the pose were
/// relaxed, 2026-11-27: the motion now reaches its pose there and the correction the cap stops
/// is warned of with the same advice; at 1.0 two iterations are enough for this press.) (The message used to end "a keyframe at the pose reached solves": true at 0.75,
/// where the keyframe put at the share reached, MCP 26.89°, solved; at 0.5 the keyframe at 25.18°
/// stopped again at 75 % of its motion, at 1.0 the keyframe at 29.36° at 94 %. It was dropped.)
#[test]
fn a_contact_capped_below_its_default_solves_with_the_cap_raised() {
    let (from, to) = (21.0, 30.0);
    let resolution = 0.5;
    let press = |solver: &'static str| {
        FingerPress {
            resolution,
            solver,
            keyframes: &[from, to],
            ..FingerPress::default()
        }
        .scene()
    };
    let trigger = solve(
        &format!("capped-{resolution}"),
        &press("contact_max_iterations = 2"),
    );
    assert_eq!(trigger.code, Some(2), "{}", trigger.stderr);
    let error = trigger
        .stderr
        .lines()
        .find(|l| l.starts_with("error: "))
        .unwrap_or_else(|| panic!("no error: {}", trigger.stderr));
    let advice = "raise solver.contact_max_iterations (it is below its default, 50)";
    // The cap stops the motion short of its pose, or (since the contact normal is smoothed,
    // 2026-11-27: the motion reaches its pose) a correction at the pose; either says why.
    let stopped = error.contains("the scene was not solved to its poses")
        && error.contains("hand \"hand\" stopped at ")
        && error.contains(advice)
        && error.ends_with("report.json gives the pose reached");
    let corrected = error.contains("a correction at the pose failed")
        && trigger.warnings().iter().any(|w| {
            w.contains("a correction at the pose of hand \"hand\" failed") && w.contains(advice)
        });
    assert!(stopped || corrected, "{}", trigger.stderr);

    let followed = solve(&format!("capped-{resolution}-followed"), &press(""));
    assert_eq!(followed.code, Some(0), "{}", followed.stderr);
    assert!(
        !followed.stderr.contains("stopped at"),
        "{}",
        followed.stderr
    );
    let report = followed.report();
    let last = report["frames"].as_array().unwrap().last().unwrap();
    let mcp = last["hands"]["hand"]["pose"]["index.mcp.flex"]
        .as_f64()
        .unwrap();
    assert!((mcp - to).abs() < 1e-9, "{mcp}° for {to}°");
}

/// `prehensile render` in the crate's folder.
fn render(args: &[&str], out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg("render")
        .args(args)
        .args(["--width", "64", "--height", "48", "--out"])
        .arg(out)
        .output()
        .expect("the prehensile binary runs")
}

/// Item 34: the pressure overlay of a scene without contact is refused, "(use stress,
/// displacement or forces)"; each overlay named renders.
#[test]
fn each_overlay_advised_for_a_scene_without_contact_renders() {
    let dir = fresh("overlay");
    let scene = "assets/scenes/default.toml";
    let refused = render(&[scene, "--overlay", "pressure"], &dir.join("pressure.png"));
    let stderr = String::from_utf8_lossy(&refused.stderr);
    println!("{stderr}");
    assert_eq!(refused.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no contact in this scene"), "{stderr}");
    assert!(!dir.join("pressure.png").exists());
    let advice = stderr
        .split_once("(use ")
        .and_then(|(_, rest)| rest.split_once(')'))
        .unwrap_or_else(|| panic!("no overlay advised: {stderr}"))
        .0;
    assert_eq!(advice, "stress, displacement or forces");
    let overlays: Vec<&str> = advice.split(", ").flat_map(|o| o.split(" or ")).collect();
    assert_eq!(overlays, ["stress", "displacement", "forces"]);

    for overlay in overlays {
        let png = dir.join(format!("{overlay}.png"));
        let drawn = render(&[scene, "--overlay", overlay], &png);
        let stderr = String::from_utf8_lossy(&drawn.stderr);
        assert_eq!(drawn.status.code(), Some(0), "{overlay}: {stderr}");
        let image = image::open(&png).unwrap();
        assert_eq!((image.width(), image.height()), (64, 48), "{overlay}");
    }
}

/// Item 43: the finger pressed to MCP 30° strains the ball beyond 20 %, "… (the hands press it
/// that far …: pose the grasp less deep …)" (the nonlinear tier is no longer advised for a
/// pressurised ball, whose contact it does not settle); posed less deep, to MCP 23°, the strain warning is gone while the finger still
/// presses the ball.
#[test]
fn a_grasp_posed_less_deep_is_not_warned_of_its_strain() {
    let press = |mcp: f64| {
        FingerPress {
            keyframes: &[21.0, mcp],
            ..FingerPress::default()
        }
        .scene()
    };
    let strain = |run: &Run| -> Vec<String> {
        run.warnings()
            .into_iter()
            .filter(|w| w.contains("principal strain"))
            .map(str::to_string)
            .collect()
    };
    let trigger = solve("strain", &press(30.0));
    assert_eq!(trigger.code, Some(0), "{}", trigger.stderr);
    let warned = strain(&trigger);
    assert_eq!(warned.len(), 1, "{}", trigger.stderr);
    assert!(warned[0].starts_with("body \"ball\""), "{}", warned[0]);
    assert!(
        warned[0].contains("the hands press it that far"),
        "{}",
        warned[0]
    );
    // The ball is pressurised: the nonlinear tier's contact would not settle on it, so only
    // the pose is advised.
    assert!(
        warned[0].contains(": pose the grasp less deep") && !warned[0].contains("tier = "),
        "{}",
        warned[0]
    );

    let followed = solve("strain-less-deep", &press(23.0));
    assert_eq!(followed.code, Some(0), "{}", followed.stderr);
    assert!(strain(&followed).is_empty(), "{}", followed.stderr);
    // Less deep, still a press: more than at the first keyframe (3 N at MCP 21°).
    let pressed = followed.last_press();
    assert!(pressed > 4.0, "{pressed} N");
    // What it still says: the ball's press crushes the coarse pulp of this hand (resolution 0.5)
    // — 229 mm³ of the index's flesh below half its volume, some of it inside out (measured
    // 2026-12-06; 38 mm³ at MCP 21°), which the contact's press turned so — and those warnings'
    // advice, to press less deep, followed to the first keyframe's MCP 21°, leaves no warning at
    // all.
    let others: Vec<&str> = followed
        .warnings()
        .into_iter()
        .filter(|w| !w.contains("principal strain"))
        .collect();
    assert_eq!(others.len(), 2, "{}", followed.stderr);
    assert!(
        others[0].contains("crushed below half its volume")
            && others[0].contains("(frame 2: index ")
            && others[0].contains("press them less deep"),
        "{}",
        others[0]
    );
    assert!(
        others[1]
            .contains("the press of a contact turns its flesh inside out in 1 frame (frame 2: ")
            && others[1].contains(", the most in the index finger — element ")
            && others[1].contains("press the index finger less deep"),
        "{}",
        others[1]
    );
    let gentler = FingerPress {
        keyframes: &[21.0],
        ..FingerPress::default()
    };
    let gentler = solve("crush-less-deep", &gentler.scene());
    assert_eq!(gentler.code, Some(0), "{}", gentler.stderr);
    assert!(gentler.warnings().is_empty(), "{}", gentler.stderr);
    assert!(gentler.last_press() > 1.0, "{} N", gentler.last_press());
}

/// A press deeper than the flesh near a contact follows, linearised about the hand's pose: the
/// finger press at resolution 1 to MCP 21° then 23° turns a pad cell to −2.4 of its volume
/// under 5.6 N (measured 2026-12-06), the same at every step size (the contact displacement is
/// linear in the press). The frames are written, and a warning names the flesh turned inside
/// out; its advice, to press less deep, followed (the press to 20.5°, where the same pad cell
/// keeps 6 % of its volume): no such warning, still a press.
#[test]
fn a_press_that_turns_flesh_inside_out_is_warned_of_and_a_shallower_one_is_not() {
    let deep = FingerPress {
        resolution: 1.0,
        keyframes: &[21.0, 23.0],
        ..FingerPress::default()
    };
    let run = solve("inside-out", &deep.scene());
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let turned: Vec<&str> = run
        .warnings()
        .into_iter()
        .filter(|w| w.contains("turns its flesh inside out"))
        .collect();
    assert_eq!(turned.len(), 1, "{}", run.stderr);
    assert!(
        turned[0].starts_with("hand \"hand\": the press of a contact turns its flesh inside out in 2 frames (frame 2: ")
            && turned[0].contains(", the most in the index finger — element ")
            && turned[0].contains("volume ratio -2.")
            && turned[0].contains("press the index finger less deep"),
        "{}",
        turned[0]
    );
    let report = run.report();
    let at = |f: usize| report["frames"][f]["hands"]["hand"].clone();
    // The scene's pose (MCP 20°) presses without turning any flesh; 21° and 23° do, the deeper
    // the more, and the report's smallest volume ratio is the pressed point's.
    assert!(at(0)["pressed_inside_out"].is_null());
    let ratio = |f: usize| at(f)["pressed_inside_out"]["ratio"].as_f64().unwrap();
    assert!(
        ratio(1) < 0.0 && ratio(2) < ratio(1),
        "{} {}",
        ratio(1),
        ratio(2)
    );
    assert_eq!(
        ratio(2),
        at(2)["crushed_flesh"]["smallest_volume_ratio"]
            .as_f64()
            .unwrap()
    );
    assert_eq!(at(2)["pressed_inside_out"]["part"], "index");

    let followed = FingerPress {
        resolution: 1.0,
        keyframes: &[20.5],
        ..FingerPress::default()
    };
    let followed = solve("inside-out-less-deep", &followed.scene());
    assert_eq!(followed.code, Some(0), "{}", followed.stderr);
    assert!(
        !followed.stderr.contains("inside out"),
        "{}",
        followed.stderr
    );
    // Still a press, harder than at the scene's pose (MCP 20°: 1.8 N).
    let pressed = followed.last_press();
    assert!(pressed > 2.0, "{pressed} N");
}
