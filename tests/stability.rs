//! Stability at the extremes: each case either converges to a physically sensible result or
//! stops with a clear diagnostic, and never leaves a NaN or an infinity in a displacement, a
//! reaction, a stress or `report.json`. The outcomes are tabulated in docs/stability.md.

use crate::common;

use nalgebra::Vector3;
use prehensile::export::report::{frame_report, model_summary, Report};
use prehensile::fem::hex8::{relative_min_jacobian, scaled_jacobian};
use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::{HandModel, Pose, Side};
use prehensile::headless::{solve_scene, write_solved};
use prehensile::mesh::box_mesh;
use prehensile::model::{FlexionScheme, FlexionSettings, Model};
use prehensile::scene::Scene;
use prehensile::solve::{solve_frames, Flexion};
use prehensile::state::{Frame, HandState};
use serde_json::Value;
use std::path::PathBuf;
use std::sync::OnceLock;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "prehensile-stability-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Every displacement, reaction and stress of `frame` (hands included) is a finite number.
fn assert_finite(frame: &Frame, what: &str) {
    let s = &frame.solution;
    assert!(
        s.displacement
            .iter()
            .chain(&s.reaction)
            .all(|v| v.is_finite()),
        "{what}: displacement or reaction not finite"
    );
    let st = &frame.stress;
    assert!(
        st.gauss
            .iter()
            .flatten()
            .chain(&st.nodal)
            .all(|m| m.iter().all(|v| v.is_finite()))
            && st.cell_von_mises.iter().all(|v| v.is_finite()),
        "{what}: stress not finite"
    );
    for h in &frame.hands {
        assert!(
            h.positions
                .iter()
                .chain(&h.reaction)
                .chain(&h.bone_reactions)
                .all(|p| p.iter().all(|v| v.is_finite()))
                && h.volume.is_finite(),
            "{what}: hand state not finite"
        );
    }
}

/// No null (serde_json's NaN) and no non-finite number anywhere in a report.
fn assert_finite_json(v: &Value, path: &str) {
    match v {
        Value::Null => panic!("{path}: null (a NaN or ∞ in the report)"),
        Value::Number(n) => assert!(n.as_f64().is_some_and(f64::is_finite), "{path}: {n}"),
        Value::Array(a) => a
            .iter()
            .enumerate()
            .for_each(|(i, x)| assert_finite_json(x, &format!("{path}[{i}]"))),
        Value::Object(o) => o
            .iter()
            .for_each(|(k, x)| assert_finite_json(x, &format!("{path}.{k}"))),
        _ => {}
    }
}

fn report_of(model: &Model, frames: &[Frame]) -> Value {
    let report = Report {
        scene: "stability".into(),
        model: model_summary(model),
        warnings: model.warnings(),
        frames: frames
            .iter()
            .enumerate()
            .map(|(i, f)| frame_report(model, f, i, i as f64))
            .collect(),
    };
    serde_json::to_value(&report).unwrap()
}

// ---------------------------------------------------------------------------------------------
// (a) Flesh Poisson ratio from 0 to 0.4999, index PIP 0° → 90°.

/// The simple form at resolution 0.75 (the measurements below are its): the anatomical one's PIP
/// crease falls between the lattice's cells there (docs/hand.md), its volume change +0.013 % …
/// +0.038 % instead, dominated by the crease's cells, not by ν.
const HAND_SCENE: &str = r#"
[[material]]
name = "flesh"
young = 5.0e4
poisson = 0.45
density = 1050.0

[[body]]
name = "hand"
material = "flesh"
shape = { hand = { side = "right", form = "simple", resolution = 0.75 } }

[[keyframe]]
time = 1.0
pose = { "index.pip" = 90.0 }
"#;

#[test]
fn a_flesh_poisson_ratio_towards_one_half_keeps_the_volume_and_locks() {
    let scene = Scene::parse(HAND_SCENE, "poisson.toml").unwrap();
    let mut model = Model::build(&scene, "poisson.toml").unwrap();
    let v0 = model.bodies[0].volume;
    let mut rows = Vec::new();
    for nu in [0.0, 0.3, 0.45, 0.49, 0.499, 0.4999] {
        for m in &mut model.cell_materials {
            m.poisson = nu;
        }
        let (_, frames) = solve_frames(&model).unwrap_or_else(|e| panic!("ν = {nu}: {e}"));
        for f in &frames {
            assert_finite(f, &format!("ν = {nu}"));
        }
        assert_finite_json(&report_of(&model, &frames), "report");
        let h = &frames[1].hands[0];
        let dv = h.volume / v0 - 1.0;
        let largest = h
            .bone_reactions
            .iter()
            .map(|r| r.norm())
            .fold(0.0, f64::max);
        let sum: Vector3<f64> = h.bone_reactions.iter().sum();
        println!(
            "ν = {nu}: volume change {:+.4} %, largest bone reaction {largest:.4} N, sum \
             {:.1e} N, max von Mises {:.0} Pa, {} halvings",
            dv * 100.0,
            sum.norm(),
            frames[1]
                .stress
                .cell_von_mises
                .iter()
                .fold(0.0f64, |a, &b| a.max(b)),
            h.stats.halvings
        );
        assert!(sum.norm() < 1e-8 * largest, "ν = {nu}: reactions balance");
        rows.push((nu, dv, largest));
    }
    // Measured (resolution 0.75, corotated 10° increments): volume change −0.13 %, −0.068 %,
    // −0.012 %, +0.008 %, +0.009 %, +0.002 %; largest bone reaction 1.32, 1.37, 1.60, 1.93,
    // 2.79, 5.35 N. The flesh keeps its volume better as the bulk modulus E / 3(1 − 2ν) grows,
    // until the increments' own error (≈0.01 %) dominates from ν = 0.45 on.
    let dv: Vec<f64> = rows.iter().map(|r| r.1.abs()).collect();
    assert!(dv[0] > dv[1] && dv[1] > dv[2], "volume change {rows:?}");
    assert!(
        dv[3..].iter().all(|&v| v < 1.5e-4),
        "volume change {rows:?}"
    );
    assert!(dv[0] > 10.0 * dv[5], "{rows:?}");
    // Volumetric locking of the fully integrated linear hexahedron: the bones push the nearly
    // incompressible flesh harder and harder as λ = Eν/((1+ν)(1−2ν)) grows, monotonically and
    // without levelling off (×1.9 for the last tenfold λ, 0.499 → 0.4999), 3.3× ν = 0.45 at
    // ν = 0.4999: no NaN, no failed factorization, but a stiffer answer than the material's.
    for w in rows.windows(2) {
        assert!(w[1].2 > w[0].2, "reactions {rows:?}");
    }
    assert!(rows[5].2 > 3.0 * rows[2].2, "locking: {rows:?}");
    assert!(rows[5].2 > 1.5 * rows[4].2, "still growing: {rows:?}");
}

// ---------------------------------------------------------------------------------------------
// (b) The pressurised ball with E = 1e2 Pa and 1e12 Pa.

fn default_ball(young: f64, pressure: f64) -> Scene {
    let mut scene = Scene::load(std::path::Path::new("assets/scenes/default.toml")).unwrap();
    scene.material[0].young = young;
    // The cap pressed by a prescribed displacement would not scale with E: only the table
    // holds the ball, against the air pressure (and gravity).
    scene.constraint.retain(|c| c.name != "finger");
    for l in &mut scene.load {
        l.pressure = Some(pressure);
    }
    scene
}

#[test]
fn b_the_ball_displacement_scales_as_one_over_e_and_a_soft_ball_warns() {
    let soft = solve_scene(&default_ball(1e2, 3e4), "soft.toml").unwrap();
    let hard = solve_scene(&default_ball(1e12, 3e4), "hard.toml").unwrap();
    for s in [&soft, &hard] {
        assert_finite(&s.frames[0], &s.report.scene);
        assert_finite_json(&serde_json::to_value(&s.report).unwrap(), "report");
    }
    let (us, uh) = (
        &soft.frames[0].solution.displacement,
        &hard.frames[0].solution.displacement,
    );
    let largest = uh.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let worst = us
        .iter()
        .zip(uh)
        .map(|(s, h)| (s * 1e-10 - h).abs())
        .fold(0.0, f64::max);
    let (ds, dh) = (
        soft.report.frames[0].max_displacement,
        hard.report.frames[0].max_displacement,
    );
    println!(
        "E = 1e2 Pa: max displacement {ds:.4e} m; E = 1e12 Pa: {dh:.4e} m; ratio {:.6e}; worst \
         dof mismatch {worst:.2e} of {largest:.2e}; warnings {:?}",
        ds / dh,
        soft.report.warnings
    );
    // Linear elasticity: u ∝ 1/E exactly; 1e10 between the two, dof by dof, to round-off.
    assert!(((ds / dh) / 1e10 - 1.0).abs() < 1e-6, "{ds} / {dh}");
    assert!(worst < 1e-6 * largest, "{worst} vs {largest}");
    // The reactions balance the same loads whatever E.
    let (rs, rh) = (
        soft.report.frames[0].constraints["table"].reaction,
        hard.report.frames[0].constraints["table"].reaction,
    );
    for i in 0..3 {
        assert!(
            (rs[i] - rh[i]).abs() < 1e-6 * (1.0 + rh[i].abs()),
            "{rs:?} {rh:?}"
        );
    }
    // E = 1e12: 3.9 nm (sensible: steel is 2e11). E = 1e2 with 30 kPa inside: 39 m of
    // displacement on a 35 mm ball, principal strains of 1.1e3: not physical, and the report
    // says so.
    assert!(dh < 1e-8 && ds > 10.0, "{dh} {ds}");
    assert!(
        hard.report.warnings.is_empty(),
        "{:?}",
        hard.report.warnings
    );
    assert_eq!(soft.report.warnings.len(), 1);
    let w = &soft.report.warnings[0];
    assert!(
        w.contains("body \"ball\"") && w.contains("small-strain"),
        "{w}"
    );
    // Its loads strain it (nothing imposes the displacement): the advised modulus, followed,
    // leaves no warning.
    let factor: f64 = w
        .split("a Young's modulus ")
        .nth(1)
        .and_then(|rest| rest.split('×').next())
        .and_then(|f| f.parse().ok())
        .unwrap_or_else(|| panic!("no modulus advised: {w}"));
    let stiffer = solve_scene(&default_ball(1e2 * factor, 3e4), "stiffer.toml").unwrap();
    assert!(
        stiffer.report.warnings.is_empty(),
        "E = {:.3e}: {:?}",
        1e2 * factor,
        stiffer.report.warnings
    );
}

// ---------------------------------------------------------------------------------------------
// (c) A sliver and an inverted element in a box mesh; (d) a disconnected piece.

fn mesh_scene(name: &str, nodes: &[Vector3<f64>], cells: &[[usize; 8]]) -> Scene {
    let mut text =
        String::from("[[material]]\nname = \"rubber\"\nyoung = 1.0e6\npoisson = 0.3\n\n[[body]]\n");
    text += &format!("name = \"{name}\"\nmaterial = \"rubber\"\n");
    text += "shape = { mesh = { nodes = [";
    text += &nodes
        .iter()
        .map(|p| format!("[{:?}, {:?}, {:?}]", p.x, p.y, p.z))
        .collect::<Vec<_>>()
        .join(", ");
    text += "], cells = [";
    text += &cells
        .iter()
        .map(|c| format!("{c:?}"))
        .collect::<Vec<_>>()
        .join(", ");
    text += "] } }\n";
    text += &format!(
        "[[constraint]]\nname = \"base\"\nbody = \"{name}\"\nwhere = {{ box = {{ min = [-1, -1, \
         -0.001], max = [2, 2, 0.001] }} }}\ndisplacement = [0, 0, 0]\n\n[[constraint]]\nname = \
         \"press\"\nbody = \"{name}\"\nwhere = {{ box = {{ min = [-1, -1, 0.999], max = [2, 2, \
         1.001] }} }}\ndisplacement = {{ z = -0.01 }}\n"
    );
    Scene::parse(&text, "mesh.toml").unwrap()
}

/// The unit cube in 4×4×4 cells with its centre node moved by `t` of the way to the far
/// corner (0.75, 0.75, 0.75) of one of its cells; that cell's index.
fn moved_cube(t: f64) -> (Vec<Vector3<f64>>, Vec<[usize; 8]>, usize) {
    let mut m = box_mesh(Vector3::zeros(), Vector3::repeat(1.0), [4, 4, 4]);
    let near = |p: Vector3<f64>| {
        (0..m.nodes.len())
            .min_by(|&a, &b| (m.nodes[a] - p).norm().total_cmp(&(m.nodes[b] - p).norm()))
            .unwrap()
    };
    let (centre, corner) = (near(Vector3::repeat(0.5)), near(Vector3::repeat(0.75)));
    let cell = (0..m.cells.len())
        .find(|&c| m.cells[c].contains(&centre) && m.cells[c].contains(&corner))
        .unwrap();
    let step = (m.nodes[corner] - m.nodes[centre]) * t;
    m.nodes[centre] += step;
    (m.nodes, m.cells, cell)
}

fn worst_scaled_jacobian(nodes: &[Vector3<f64>], cells: &[[usize; 8]]) -> f64 {
    cells
        .iter()
        .map(|c| scaled_jacobian(&c.map(|n| nodes[n])))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn c_a_sliver_element_solves_correctly_and_an_inverted_one_is_named() {
    // Bisect the move for a worst scaled Jacobian of 1e-3.
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let t = 0.5 * (lo + hi);
        let (n, c, _) = moved_cube(t);
        if worst_scaled_jacobian(&n, &c) > 1e-3 {
            lo = t;
        } else {
            hi = t;
        }
    }
    let (nodes, cells, sliver) = moved_cube(lo);
    let q = worst_scaled_jacobian(&nodes, &cells);
    let rel = relative_min_jacobian(&cells[sliver].map(|n| nodes[n]));
    let regular = {
        let (n, c, _) = moved_cube(0.0);
        solve_scene(&mesh_scene("block", &n, &c), "regular.toml").unwrap()
    };
    let solved = solve_scene(&mesh_scene("block", &nodes, &cells), "sliver.toml").unwrap();
    assert_finite(&solved.frames[0], "sliver");
    let press =
        |s: &prehensile::headless::Solved| s.report.frames[0].constraints["press"].reaction[2];
    let residual = solved.report.frames[0].solver.residual;
    println!(
        "sliver: move {lo:.6}, scaled Jacobian {q:.3e}, det J / size³ {rel:.3e}; press {:.2} N \
         against {:.2} N regular; residual {residual:.1e}",
        press(&solved),
        press(&regular)
    );
    assert!((0.9e-3..1.1e-3).contains(&q), "{q}");
    // One cell of 64 with a flattened corner (its Gauss points keep det J / size³ = 0.047)
    // barely changes the block's stiffness (measured +0.002 %), and the solve stays accurate.
    let change = press(&solved) / press(&regular) - 1.0;
    assert!(change.abs() < 1e-3 && change != 0.0, "{change}");
    assert!(residual < 1e-10, "{residual}");

    // Past the far corner the cell is inside out: refused before solving, naming the body and
    // the element.
    let (nodes, cells, inverted) = moved_cube(1.5);
    assert!(relative_min_jacobian(&cells[inverted].map(|n| nodes[n])) < 0.0);
    let e = solve_scene(&mesh_scene("block", &nodes, &cells), "inverted.toml")
        .err()
        .expect("an inverted element is refused")
        .to_string();
    println!("inverted: {e}");
    assert!(
        e.contains("body \"block\"")
            && e.contains(&format!(
                "element {inverted} is inverted or has zero volume"
            )),
        "{e}"
    );
}

#[test]
fn d_a_disconnected_piece_is_named() {
    let a = box_mesh(Vector3::zeros(), Vector3::repeat(1.0), [1, 1, 1]);
    // A second cube floating beside the first, at half height (the constraints' boxes, at
    // z = 0 and z = 1, miss it).
    let mut nodes = a.nodes.clone();
    nodes.extend(a.nodes.iter().map(|p| p + Vector3::new(3.0, 0.0, 0.5)));
    let mut cells = a.cells.clone();
    cells.extend(a.cells.iter().map(|c| c.map(|n| n + 8)));
    let e = solve_scene(&mesh_scene("two", &nodes, &cells), "two.toml")
        .err()
        .expect("a free piece is refused")
        .to_string();
    println!("{e}");
    assert!(
        e.contains("body \"two\"") && e.contains("piece 2 of 2, 8 nodes"),
        "{e}"
    );
    assert!(e.contains("translation along z"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// (e) Zero pressure.

#[test]
fn e_zero_pressure_gives_exactly_zero_and_a_finite_report() {
    let mut scene = default_ball(2e6, 0.0);
    scene.world.gravity = None;
    let solved = solve_scene(&scene, "zero.toml").unwrap();
    let f = &solved.frames[0];
    assert_finite(f, "zero pressure");
    assert!(f.solution.displacement.iter().all(|&v| v == 0.0));
    assert!(f.solution.reaction.iter().all(|&v| v == 0.0));
    assert!(f.stress.cell_von_mises.iter().all(|&v| v == 0.0));
    let r = &solved.report.frames[0];
    assert_eq!(
        (r.max_displacement, r.max_von_mises, r.solver.residual),
        (0.0, 0.0, 0.0)
    );
    // The written files hold no NaN either.
    let dir = scratch("zero");
    write_solved(&solved, &dir).unwrap();
    let text = std::fs::read_to_string(dir.join("report.json")).unwrap();
    assert_finite_json(&serde_json::from_str(&text).unwrap(), "report.json");
    let vtu = common::vtu::text(&dir.join("frame_0000.vtu"));
    assert!(
        !vtu.contains("NaN") && !vtu.contains("inf"),
        "VTU holds a non-finite value"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------
// (f) Flexion in one 45° increment.

fn hand() -> &'static HandModel {
    static HAND: OnceLock<HandModel> = OnceLock::new();
    HAND.get_or_init(|| HandModel::new(Side::Right, 1.0).unwrap())
}

fn flex_pip_90(step: f64) -> HandState {
    let hand = hand();
    let flesh = Material {
        young: 5.0e4,
        poisson: 0.45,
        density: 1050.0,
    };
    let mut stepper = Flexion::new(
        hand,
        "hand",
        vec![flesh; hand.flesh.mesh.cells.len()],
        FlexionSettings {
            max_step_deg: step,
            scheme: FlexionScheme::UpdatedLagrangian,
            ..Default::default()
        },
        FillOrdering::NestedDissection,
    );
    let mut state = HandState::rest(hand);
    let pose: Pose = [("index.pip".to_string(), 90.0)].into_iter().collect();
    let target = hand.skeleton.apply_pose(&state.angles, &pose).unwrap();
    stepper.move_to(&mut state, &target).unwrap();
    state
}

#[test]
fn f_one_45_degree_increment_is_worse_than_10_degree_ones_and_warns() {
    let hand = hand();
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let reference = flex_pip_90(2.5);
    let mut rows = Vec::new();
    for step in [45.0, 10.0] {
        let s = flex_pip_90(step);
        let gap = s
            .positions
            .iter()
            .zip(&reference.positions)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        let dv = s.flesh_volume(hand) / v0 - 1.0;
        println!(
            "updated Lagrangian, {step}° steps: volume change {:+.3} %, max node gap to 2.5° \
             steps {:.2} mm",
            dv * 100.0,
            gap * 1e3
        );
        rows.push((dv, gap));
    }
    // Measured (resolution 1): 45° steps: +1.70 %, 5.1 mm; 10° steps: +0.49 %, 1.3 mm. Each
    // increment's spurious strain grows as θ², so the keyframe's error grows about as θ
    // (first order): 3.5× the volume error and 4× the gap for 4.5× the step.
    let ((dv45, gap45), (dv10, gap10)) = (rows[0], rows[1]);
    assert!(dv45 > 3.0 * dv10 && dv10 > 0.0, "{rows:?}");
    assert!(gap45 > 3.5 * gap10, "{rows:?}");

    // The scene warns (report and CLI); 10° does not.
    let text = |step: f64| {
        format!(
            "[solver]\nmax_step_deg = {step}\nflexion = \"updated_lagrangian\"\n{}",
            HAND_SCENE.replace("resolution = 0.75", "resolution = 0.5")
        )
    };
    let scene = |step: f64| Scene::parse(&text(step), "step.toml").unwrap();
    let warned = Model::build(&scene(45.0), "step.toml").unwrap();
    assert_eq!(warned.warnings().len(), 1);
    assert!(
        warned.warnings()[0].contains("solver.max_step_deg = 45"),
        "{:?}",
        warned.warnings()
    );
    assert!(Model::build(&scene(10.0), "step.toml")
        .unwrap()
        .warnings()
        .is_empty());
    let dir = scratch("step");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("step.toml");
    std::fs::write(&file, text(45.0)).unwrap();
    let out = common::solve_cli(&file, &dir.join("out"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: solver.max_step_deg = 45"),
        "{stderr}"
    );
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/report.json")).unwrap())
            .unwrap();
    assert_finite_json(&report, "report.json");
    let w = report["warnings"].as_array().unwrap();
    assert!(
        w[0].as_str().unwrap().contains("max_step_deg = 45"),
        "{w:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------------------------
// (f) The finger press on a ball too soft for its air: the error names the strain, and its
// advice removes it.

/// `finger-press-ball.toml` with the ball's Young's modulus `young`.
fn soft_press(young: f64) -> Scene {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    let mut scene = Scene::parse(&text, "press.toml").unwrap();
    let rubber = scene
        .material
        .iter_mut()
        .find(|m| m.name == "rubber")
        .unwrap();
    rubber.young = young;
    scene
}

#[test]
fn f_a_grasp_on_a_ball_its_air_overinflates_is_told_as_that_strain_with_advice_that_works() {
    use prehensile::solve::SimError;
    // E = 1e4 Pa against 30 kPa of air: the table cannot hold the ball the air blows up (the
    // static frame's contact with the table fails); E = 1e5 Pa: contact with the finger turns
    // an element of the ball inside out. Either way the cause is the static frame's strain.
    for young in [1e4, 1e5] {
        let scene = soft_press(young);
        let model = Model::build(&scene, "press.toml").unwrap();
        let error = solve_frames(&model).unwrap_err();
        let message = error.to_string();
        println!("E = {young:.0e} Pa: {message}");
        let SimError::BeyondSmallStrain {
            body,
            strain,
            factor,
            cause,
            ..
        } = error
        else {
            panic!("{message}");
        };
        assert_eq!(body, "ball");
        assert!(strain > 1.0 && (factor - strain / 0.1).abs() < 1e-12 * factor);
        assert!(message.contains("Young's modulus ≥"), "{message}");
        // The cause is told without advice of its own: the ball has its supports (telling it
        // to get some, as the bare cause did, is advice that does not work).
        assert!(!message.contains("give it supports"), "{message}");
        let cause = cause.to_string();
        let what = cause
            .split(" — ")
            .next()
            .unwrap()
            .split("; the body")
            .next()
            .unwrap();
        assert!(message.contains(what), "{what} not in {message}");
        // The advice: E times the factor (rounded up by 1 %) — the ball's air alone then
        // strains it 10 % / 1.01 (linear elasticity scales exactly), the static frame on its
        // table under the 20 % warning, and no error blames the strain.
        let advised = soft_press(young * factor * 1.01);
        let model = Model::build(&advised, "advised.toml").unwrap();
        let still = prehensile::solve::solve_static(
            &model,
            &mut prehensile::fem::solve::PartitionedSolver::new(model.ordering),
        )
        .unwrap();
        let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
        let now = prehensile::state::largest_strains(&model, &still)[ball].unwrap();
        println!(
            "advised E = {:.3e} Pa: static strain {now:.4}",
            young * factor * 1.01
        );
        assert!(now <= prehensile::state::STRAIN_WARNING, "{now}");
        // The strain is mended; whatever the solve meets then is not blamed on it.
        if let Err(e) = solve_frames(&model) {
            assert!(!matches!(e, SimError::BeyondSmallStrain { .. }), "{e}");
            println!("then: {e}");
        }
    }
}
