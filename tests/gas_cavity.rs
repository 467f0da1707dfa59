//! The rubber ball as a sealed gas cavity (`gas = true`): its pressure follows its volume,
//! isothermally (p·V = P0·V0 in absolute pressure), so squeezing raises it and releasing
//! restores the ball (the paper's remark under Figure 3c).

use crate::common;

use common::rel;
use nalgebra::Vector3;
use prehensile::headless::{solve_scene, Solved};
use prehensile::model::Model;
use prehensile::scene::Scene;
use prehensile::solve::solve_frames;
use std::f64::consts::PI;

const AMBIENT: f64 = 101_325.0;

/// A rubber shell (a = 31 mm, b = 35 mm) pressurised to `pressure` and squeezed between two
/// rigid plates `squeeze` (m) inside its outer radius at its poles (z = ±(b − squeeze)).
fn plates_scene(pressure: f64, gas: bool, squeeze: f64) -> String {
    plates_scene_meshed(pressure, gas, squeeze, 8, 2)
}

/// `plates_scene` with `cells` × `cells` quads per face of the cubed sphere and `layers` through
/// the wall.
fn plates_scene_meshed(
    pressure: f64,
    gas: bool,
    squeeze: f64,
    cells: usize,
    layers: usize,
) -> String {
    let z = 0.035 - squeeze;
    format!(
        r#"
[[material]]
name = "rubber"
young = 2.0e6
poisson = 0.4
density = 1100.0
[[body]]
name = "ball"
material = "rubber"
shape = {{ shell = {{ center = [0.0, 0.0, 0.0], inner_radius = 0.031, outer_radius = 0.035, cells = {cells}, layers = {layers} }} }}
[[load]]
name = "air"
body = "ball"
where = {{ surface = "inner" }}
pressure = {pressure:e}
{gas}
[[obstacle]]
name = "bottom"
shape = {{ plane = {{ point = [0.0, 0.0, {bottom:e}], normal = [0.0, 0.0, 1.0] }} }}
[[obstacle]]
name = "top"
shape = {{ plane = {{ point = [0.0, 0.0, {z:e}], normal = [0.0, 0.0, -1.0] }} }}
"#,
        bottom = -z,
        gas = if gas {
            format!("gas = true\nambient = {AMBIENT:e}")
        } else {
            "gas = false".into()
        }
    )
}

fn solve(text: &str) -> Solved {
    let scene = Scene::parse(text, "gas.toml").unwrap();
    solve_scene(&scene, "gas.toml").unwrap()
}

fn largest(u: &[f64]) -> f64 {
    u.iter().fold(0.0, |m, v| m.max(v.abs()))
}

fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// Squeezed between two plates in steps: at every step the solve applied the pressure the gas
/// law gives the cavity's volume (a fixed-pressure solve at that pressure reproduces it), and the
/// pressure and the plates' force rise with the squeeze.
#[test]
fn squeezed_between_plates_the_gas_keeps_p_v_and_its_pressure_rises() {
    let gauge = 3.0e4;
    let p0v0 = |s: &Solved| {
        let c = s.model.gas.as_ref().unwrap();
        (c.rest_gauge + c.ambient) * c.rest_volume
    };
    let mut last_pressure = f64::NEG_INFINITY;
    let mut last_force = 0.0;
    for squeeze in [0.001, 0.002, 0.003, 0.004] {
        let solved = solve(&plates_scene(gauge, true, squeeze));
        let frame = &solved.report.frames[0];
        let cavity = frame.cavity.as_ref().expect("a cavity report");
        let force = frame.contact.as_ref().unwrap().obstacles["bottom"].force[2];
        let law = (cavity.gauge_pressure + AMBIENT) * cavity.volume / p0v0(&solved) - 1.0;
        // The pressure the solve applied: the same plates with that pressure fixed give the same
        // displacements; an error δp in it would move the wall by δp·U_a.
        let fixed = solve(&plates_scene(cavity.gauge_pressure, false, squeeze));
        let (u, v) = (
            &solved.frames[0].solution.displacement,
            &fixed.frames[0].solution.displacement,
        );
        let applied = largest_difference(u, v) / largest(u);
        let fixed_force =
            fixed.report.frames[0].contact.as_ref().unwrap().obstacles["bottom"].force[2];
        println!(
            "squeeze {:.0} mm: gauge {:.1} Pa, volume {:.4e} m³ (rest {:.4e}), p·V/(P0·V0) − 1 = \
             {law:.1e}, fixed-pressure solve differs by {applied:.1e} of max |u|, plate force \
             {force:.3} N (fixed pressure {fixed_force:.3} N)",
            squeeze * 1e3,
            cavity.gauge_pressure,
            cavity.volume,
            cavity.rest_volume
        );
        assert!(law.abs() < 1e-6, "{law}");
        assert!(applied < 1e-6, "{applied}");
        assert!(rel(fixed_force, force) < 1e-6, "{fixed_force} vs {force}");
        assert!(cavity.gauge_pressure > last_pressure + 100.0);
        assert!(force > last_force);
        assert!(frame.cavity.as_ref().unwrap().volume < cavity.rest_volume * 1.2);
        last_pressure = cavity.gauge_pressure;
        last_force = force;
    }
}

/// The plates' force against an independent reference: the same squeeze (2 mm at each pole, the
/// gas inside) meshed ever finer with two elements that converge from opposite sides — the
/// standard hex8, stiff in the wall's bending (shear locking: too large a force), and hex8 with
/// incompatible modes, free of that locking (too small a force on coarse meshes, where its
/// extra modes soften the contact patch). The true force lies between them: each sequence moves
/// towards the other as the mesh is refined, the two finest bracket it within 2 %, and the gas
/// tests' own mesh (8 cells, 2 layers) is stated against that bracket. Measured 2026-11-29 (hex8 /
/// incompatible modes, N): cells 8 — 8.541 / 7.453; 12 — 8.126 / 7.525; 16 — 7.985 / 7.689;
/// 24 — 7.853 / 7.700; hex8 at 32 cells, 8 layers (55 s, 3 GB; not run here): 7.825.
#[test]
fn the_plates_force_is_bracketed_by_two_elements_refined_towards_each_other() {
    let squeeze = 0.002;
    let force = |cells: usize, element: &str| {
        let text = format!(
            "[solver]\nelement = \"{element}\"\n{}",
            plates_scene_meshed(3.0e4, true, squeeze, cells, cells / 4)
        );
        let solved = solve(&text);
        let frame = &solved.report.frames[0];
        let cavity = frame.cavity.as_ref().expect("a cavity report");
        let c = solved.model.gas.as_ref().unwrap();
        let law = (cavity.gauge_pressure + AMBIENT) * cavity.volume
            / ((c.rest_gauge + c.ambient) * c.rest_volume)
            - 1.0;
        assert!(law.abs() < 1e-6, "{law}");
        let f = frame.contact.as_ref().unwrap().obstacles["bottom"].force[2];
        println!("{cells} cells, {} layers, {element}: {f:.4} N", cells / 4);
        f
    };
    let sequence = [8, 16, 24];
    let stiff: Vec<f64> = sequence.iter().map(|&c| force(c, "hex8")).collect();
    let free: Vec<f64> = sequence
        .iter()
        .map(|&c| force(c, "incompatible_modes"))
        .collect();
    for i in 0..sequence.len() {
        // Each mesh: hex8 above, incompatible modes below.
        assert!(stiff[i] > free[i], "{stiff:?} {free:?}");
        if i > 0 {
            // Refinement closes the bracket from both sides, at least as fast as the cell size
            // shrinks (measured: the gap 1.088 → 0.296 → 0.153 N, rates 1.9 and 1.6).
            assert!(
                stiff[i] < stiff[i - 1] && free[i] > free[i - 1],
                "{stiff:?} {free:?}"
            );
            let h = sequence[i - 1] as f64 / sequence[i] as f64;
            let rate = ((stiff[i] - free[i]) / (stiff[i - 1] - free[i - 1])).ln() / h.ln();
            println!("the bracket closes at rate {rate:.2} in the cell size");
            assert!(rate > 1.0, "{rate}: {stiff:?} {free:?}");
        }
    }
    let (upper, lower) = (stiff[2], free[2]);
    let reference = 0.5 * (upper + lower);
    println!(
        "the force is {reference:.3} N ± {:.1} %; the gas tests' mesh (8 cells, 2 layers) reads \
         {:+.1} %",
        50.0 * (upper - lower) / reference,
        100.0 * (stiff[0] / reference - 1.0)
    );
    assert!((upper - lower) / reference < 0.02, "{upper} {lower}");
    // The coarse mesh is stiff by its locking: above the bracket, by less than 15 %.
    assert!(
        stiff[0] > upper && stiff[0] < 1.15 * reference,
        "{}",
        stiff[0]
    );
}

/// Lamé's thick sphere with the outer surface pushed in radially by δ and the gas inside:
/// u(r) = A·r + B/r², σrr(r) = E/(1−2ν)·A − 2E/(1+ν)·B/r³, with u(b) = −δ and σrr(a) = −p, and
/// the gas law (p + p_amb)·(1 + u(a)/a)³ = P0 (the cavity a sphere of radius a + u(a)). Returns
/// (gauge pressure, total inward force on the outer surface −σrr(b)·4πb²). With `gas = false`,
/// p stays at its rest value.
fn lame_press(a: f64, b: f64, e: f64, nu: f64, delta: f64, rest: f64, gas: bool) -> (f64, f64) {
    let at = |p: f64| {
        let (m11, m12, m21, m22) = (
            b,
            1.0 / (b * b),
            e / (1.0 - 2.0 * nu),
            -2.0 * e / (1.0 + nu) / a.powi(3),
        );
        let det = m11 * m22 - m12 * m21;
        let aa = (-delta * m22 + m12 * p) / det;
        let bb = (-m11 * p + m21 * delta) / det;
        let ua = aa * a + bb / (a * a);
        let srr_b = e / (1.0 - 2.0 * nu) * aa - 2.0 * e / (1.0 + nu) * bb / b.powi(3);
        (ua, -srr_b * 4.0 * PI * b * b)
    };
    if !gas {
        return (rest, at(rest).1);
    }
    let (mut lo, mut hi) = (-0.99 * AMBIENT, 1.0e7);
    for _ in 0..200 {
        let p = 0.5 * (lo + hi);
        let law = (p + AMBIENT) * (1.0 + at(p).0 / a).powi(3) - (rest + AMBIENT);
        if law > 0.0 {
            hi = p;
        } else {
            lo = p;
        }
    }
    let p = 0.5 * (lo + hi);
    (p, at(p).1)
}

/// The shell of the press: a = 50 mm, b = 60 mm, E = 1 MPa, ν = 0.3, gas at 10 kPa gauge;
/// `tier`: the `[solver]` table's tier line (or nothing).
fn press_scene(cells: usize, layers: usize, tier: &str) -> String {
    format!(
        r#"
[solver]
{tier}
[[material]]
name = "rubber"
young = 1.0e6
poisson = 0.3
density = 1100.0
[[body]]
name = "ball"
material = "rubber"
shape = {{ shell = {{ center = [0, 0, 0], inner_radius = 0.05, outer_radius = 0.06, cells = {cells}, layers = {layers} }} }}
[[load]]
name = "air"
body = "ball"
where = {{ surface = "inner" }}
pressure = 1.0e4
gas = true
[[constraint]]
name = "press"
body = "ball"
where = {{ surface = "outer" }}
displacement = [0.0, 0.0, 0.0]
"#
    )
}

/// The FEM press: the outer nodes pushed in radially by δ; (gauge pressure, inward force).
fn fem_press(cells: usize, layers: usize, delta: f64) -> (f64, f64) {
    fem_press_on(cells, layers, delta, "")
}

/// [`fem_press`] with the `[solver]` table's `tier` line.
fn fem_press_on(cells: usize, layers: usize, delta: f64, tier: &str) -> (f64, f64) {
    let scene = Scene::parse(&press_scene(cells, layers, tier), "press.toml").unwrap();
    let mut model = Model::build(&scene, "press.toml").unwrap();
    let outer = model.constraints[0].dofs.clone();
    for &d in &outer {
        let x = model.mesh.nodes[d / 3];
        model.prescribed[d] = -delta * x[d % 3] / x.norm();
    }
    let (_, frames) = solve_frames(&model).unwrap();
    let frame = &frames[0];
    let cavity = prehensile::state::cavity_state(&model, frame).unwrap();
    let mut nodes: Vec<usize> = outer.iter().map(|d| d / 3).collect();
    nodes.dedup();
    let mut inward = 0.0;
    for n in nodes {
        let x: Vector3<f64> = model.mesh.nodes[n];
        inward -= frame.solution.reaction_at(n).dot(&(x / x.norm()));
    }
    (cavity.gauge_pressure, inward)
}

/// A sphere pressed uniformly (its outer surface moved in radially by δ) against Lamé's closed
/// form with the gas law: the FEM pressure rise and pressing force converge to it with the mesh,
/// and the gas changes the force by far more than the mesh's error.
#[test]
fn a_sphere_pressed_uniformly_matches_lame_with_the_gas_law() {
    let (a, b, e, nu, delta, rest) = (0.05, 0.06, 1.0e6, 0.3, 5.0e-4, 1.0e4);
    let (p, force) = lame_press(a, b, e, nu, delta, rest, true);
    let (_, fixed_force) = lame_press(a, b, e, nu, delta, rest, false);
    println!(
        "closed form: gauge {p:.1} Pa (rest {rest:.0}), force {force:.2} N; at a fixed pressure \
         {fixed_force:.2} N"
    );
    let mut errors = Vec::new();
    for (cells, layers) in [(6, 2), (12, 4)] {
        let (p_h, f_h) = fem_press(cells, layers, delta);
        let (dp_error, f_error) = (rel(p_h - rest, p - rest), rel(f_h, force));
        println!(
            "cells {cells}, layers {layers}: gauge {p_h:.1} Pa (rise error {:.2} %), force \
             {f_h:.2} N (error {:.2} %)",
            100.0 * dp_error,
            100.0 * f_error
        );
        errors.push((dp_error, f_error));
    }
    // The gas adds a fifth to the force: the comparison can tell it.
    assert!(rel(force, fixed_force) > 0.15);
    let (coarse, fine) = (errors[0], errors[1]);
    assert!(fine.0 < coarse.0 && fine.1 < coarse.1, "{errors:?}");
    assert!(fine.0 < 0.02 && fine.1 < 0.02, "{errors:?}");
}

/// The nonlinear tier (Neo-Hookean wall, the gas's pressure on the wall where it is) pressed
/// uniformly at small strain (δ = 0.5 mm on b = 60 mm) matches Lamé's closed form with the gas
/// law as the linear statics does, and keeps p·V = P0·V0.
#[test]
fn the_nonlinear_tier_pressed_uniformly_matches_lame_with_the_gas_law() {
    let (a, b, e, nu, delta, rest) = (0.05, 0.06, 1.0e6, 0.3, 5.0e-4, 1.0e4);
    let (p, force) = lame_press(a, b, e, nu, delta, rest, true);
    let (p_lin, f_lin) = fem_press(12, 4, delta);
    let (p_h, f_h) = fem_press_on(12, 4, delta, "tier = \"nonlinear\"");
    let (dp_error, f_error) = (rel(p_h - rest, p - rest), rel(f_h, force));
    println!(
        "closed form: gauge {p:.1} Pa, force {force:.2} N; linear statics {p_lin:.1} Pa, \
         {f_lin:.2} N; nonlinear tier {p_h:.1} Pa (rise error {:.2} %), {f_h:.2} N (error {:.2} %)",
        100.0 * dp_error,
        100.0 * f_error
    );
    assert!(dp_error < 0.03 && f_error < 0.03, "{dp_error} {f_error}");
}

/// Squeezed between two plates on the nonlinear tier: in every frame p·V = P0·V0, and the
/// pressure and the plates' force rise with the squeeze. At small strain (300 Pa, squeezed
/// 0.5 mm) the force is the linear statics' with incompatible modes (which, like the tier's
/// mean-dilatation Neo-Hookean hexahedra, does not lock in the thin wall's bending; plain hex8
/// is 16 % stiffer there) within 3 %.
#[test]
fn the_nonlinear_tier_squeezed_between_plates_keeps_p_v() {
    let gauge = 3.0e4;
    let mut last = (f64::NEG_INFINITY, 0.0);
    for squeeze in [0.001, 0.003] {
        let text = format!(
            "[solver]\ntier = \"nonlinear\"\n{}",
            plates_scene(gauge, true, squeeze)
        );
        let solved = solve(&text);
        let frame = &solved.report.frames[0];
        let cavity = frame.cavity.as_ref().expect("a cavity report");
        let force = frame.contact.as_ref().unwrap().obstacles["bottom"].force[2];
        let top = frame.contact.as_ref().unwrap().obstacles["top"].force[2];
        let law = (cavity.gauge_pressure + AMBIENT) * cavity.volume
            / ((gauge + AMBIENT) * cavity.rest_volume)
            - 1.0;
        println!(
            "nonlinear, squeeze {:.0} mm: gauge {:.1} Pa, volume {:.4e} m³, law {law:.1e}, plate \
             force {force:.3} N (top {top:.3} N)",
            squeeze * 1e3,
            cavity.gauge_pressure,
            cavity.volume
        );
        assert!(law.abs() < 1e-6, "{law}");
        assert!(rel(-top, force) < 1e-9, "{top} {force}");
        assert!(cavity.gauge_pressure > last.0 && force > last.1);
        last = (cavity.gauge_pressure, force);
    }
    let small = |solver: &str| {
        let text = format!("[solver]\n{solver}\n{}", plates_scene(300.0, true, 0.0005));
        let solved = solve(&text);
        let frame = &solved.report.frames[0];
        frame.contact.as_ref().unwrap().obstacles["bottom"].force[2]
    };
    let (nonlinear, linear) = (
        small("tier = \"nonlinear\""),
        small("element = \"incompatible_modes\""),
    );
    println!("300 Pa, 0.5 mm: nonlinear {nonlinear:.4} N, incompatible modes {linear:.4} N");
    assert!(rel(nonlinear, linear) < 0.03, "{nonlinear} {linear}");
}

/// The finger of `finger-press-ball.toml` starts clear of the ball (MCP 10°), presses it sealed
/// (`gas = true`) at MCP 21° then 21.5°, and is drawn back to 10°: pressed deeper, the pressure
/// rises and the volume falls; released, the ball and its pressure are back to the unsqueezed
/// state. (Pressed frames are compared with each other: their contact steps put the ball's air
/// on its deformed wall, which the linear static frame does not; docs/contact.md.)
#[test]
fn released_by_the_finger_the_ball_and_its_pressure_come_back() {
    press_and_release("");
}

/// As [`released_by_the_finger_the_ball_and_its_pressure_come_back`] on the nonlinear tier: the
/// contact steps with the Neo-Hookean ball and the gas's pressure on its wall where it is.
#[test]
fn on_the_nonlinear_tier_the_pressed_ball_and_its_pressure_come_back() {
    press_and_release("tier = \"nonlinear\"\n");
}

/// The finger press and release of the sealed ball, with `solver` lines added to `[solver]`.
fn press_and_release(solver: &str) {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml")
        .unwrap()
        .replacen("[solver]\n", &format!("[solver]\n{solver}"), 1)
        .replace(
            "pressure = 3.0e4     # Pa above ambient",
            "pressure = 3.0e4\ngas = true",
        )
        .replace(
            "pose = { \"index.mcp.flex\" = 20.0,",
            "pose = { \"index.mcp.flex\" = 10.0,",
        )
        + "\n[[keyframe]]\ntime = 3.0\npose = { \"index.mcp.flex\" = 10.0 }\n";
    let solved = solve(&text);
    let frames = &solved.report.frames;
    let cavity = |i: usize| frames[i].cavity.as_ref().unwrap();
    let (rest, touched, pressed, released) =
        (cavity(0), cavity(1), cavity(2), cavity(frames.len() - 1));
    let u = |i: usize| &solved.frames[i].solution.displacement;
    let ball = solved.model.bodies[1].nodes.clone();
    let ball_u = |i: usize| u(i)[3 * ball.start..3 * ball.end].to_vec();
    let back = largest_difference(&ball_u(0), &ball_u(frames.len() - 1)) / largest(&ball_u(0));
    println!(
        "gauge pressure: unsqueezed {:.2} Pa, pressed {:.2} Pa then {:.2} Pa, released {:.2} Pa; \
         volume {:.6e} → {:.6e} → {:.6e} → {:.6e} m³; released ball displacements differ by \
         {back:.1e} of max |u|",
        rest.gauge_pressure,
        touched.gauge_pressure,
        pressed.gauge_pressure,
        released.gauge_pressure,
        rest.volume,
        touched.volume,
        pressed.volume,
        released.volume
    );
    // (The finger at 10° may lie within the contact search of the ball: no force then.)
    let force = |i: usize| {
        solved.frames[i]
            .contact
            .as_ref()
            .map_or(0.0, |c| c.normal_force())
    };
    assert!(force(0) < 1e-9 && force(frames.len() - 1) < 1e-9);
    assert!(force(1) > 0.5 && force(2) > force(1));
    assert!(pressed.gauge_pressure > touched.gauge_pressure + 1.0);
    assert!(pressed.volume < touched.volume);
    // The gas law holds in every frame.
    for c in [rest, touched, pressed, released] {
        let (p0v0, pv) = (
            (3.0e4 + c.ambient) * c.rest_volume,
            (c.gauge_pressure + c.ambient) * c.volume,
        );
        assert!(rel(pv, p0v0) < 1e-6, "{c:?}");
    }
    assert!(rel(released.gauge_pressure, rest.gauge_pressure) < 1e-6);
    assert!(rel(released.volume, rest.volume) < 1e-6);
    assert!(back < 1e-6, "{back}");
}

/// `gas = false` (or no `gas` key) is the fixed pressure: the same numbers as before, no cavity
/// in the report.
#[test]
fn without_gas_the_pressure_is_fixed_as_before() {
    let text = std::fs::read_to_string("assets/scenes/default.toml").unwrap();
    let plain = solve(&text);
    let explicit = solve(&text.replace(
        "pressure = 3.0e4     # Pa above ambient",
        "pressure = 3.0e4\ngas = false",
    ));
    assert!(plain.model.gas.is_none() && explicit.model.gas.is_none());
    assert!(plain.report.frames[0].cavity.is_none());
    assert_eq!(
        plain.frames[0].solution.displacement,
        explicit.frames[0].solution.displacement
    );
    // And gas = true changes them (the pressure falls as the ball inflates, and rises as the
    // finger presses it).
    let sealed = solve(&text.replace(
        "pressure = 3.0e4     # Pa above ambient",
        "pressure = 3.0e4\ngas = true",
    ));
    let c = sealed.report.frames[0].cavity.as_ref().unwrap();
    println!(
        "default.toml sealed: gauge {:.1} Pa, volume {:.4e} m³",
        c.gauge_pressure, c.volume
    );
    assert!((c.gauge_pressure - 3.0e4).abs() > 100.0);
}

fn build_error(text: &str) -> String {
    let scene = Scene::parse(text, "bad.toml").unwrap();
    Model::build(&scene, "bad.toml").unwrap_err().to_string()
}

/// Misuse of `gas` and `ambient` is refused, naming the field.
#[test]
fn gas_keys_are_checked() {
    let good = plates_scene(3.0e4, true, 0.001);
    let cases = [
        (
            good.replace("pressure = 3e4", "traction = [0.0, 0.0, 1.0]"),
            "load[0]).gas",
            "needs `pressure`",
        ),
        (
            good.replace(
                "surface = \"inner\"",
                "box = { min = [-1, -1, 0], max = [1, 1, 1] }",
            ),
            "load[0]).where",
            "closed surface",
        ),
        (
            good.replace("gas = true", "gas = false"),
            "load[0]).ambient",
            "gas = true",
        ),
        (
            good.replace("ambient = 1.01325e5", "ambient = -1.0"),
            "load[0]).ambient",
            "> 0",
        ),
        (
            good.replace("pressure = 3e4", "pressure = -2e5"),
            "load[0]).pressure",
            "must be > 0",
        ),
    ];
    for (text, field, words) in cases {
        let e = build_error(&text);
        println!("{e}");
        assert!(e.contains(field) && e.contains(words), "{e}");
    }
    let twice = good.clone()
        + "[[load]]\nbody = \"ball\"\nwhere = { surface = \"inner\" }\npressure = 1.0\ngas = true\n";
    let e = build_error(&twice);
    assert!(
        e.contains("load[1]).gas") && e.contains("one gas cavity"),
        "{e}"
    );
}

/// The cavity kernel on a box: closed, its volume exact, kept by a shear and a translation,
/// scaled by a stretch; an open surface refused.
#[test]
fn a_box_is_closed_and_encloses_its_volume_moved_or_sheared() {
    use prehensile::fem::cavity::{check_closed, enclosed_volume, NotClosed};
    use prehensile::mesh::{boundary_facets, box_mesh};
    let mesh = box_mesh(Vector3::zeros(), Vector3::new(0.2, 0.3, 0.5), [2, 3, 1]);
    let facets = boundary_facets(&mesh);
    check_closed(&facets).unwrap();
    let v = enclosed_volume(&facets, |n| mesh.nodes[n]);
    assert!((v - 0.03).abs() < 1e-15, "{v}");
    let sheared = enclosed_volume(&facets, |n| {
        let p = mesh.nodes[n];
        Vector3::new(p.x + 0.7 * p.z + 1.0, p.y - 2.0, p.z * 1.5)
    });
    assert!((sheared - 0.045).abs() < 1e-14, "{sheared}");
    assert_eq!(
        check_closed(&facets[1..]),
        Err(NotClosed::Open { edges: 4 })
    );
}

/// The coarsest shell (cells = 2, one layer): its facets' centroids lie 12 % inside their
/// nodes' sphere, yet `surface = "inner"` selects only the cavity's 24 facets and `"outer"` only
/// the outside's 24; the gas pushes the wall out (the volume grows, so the pressure falls below
/// its rest value), and p·V = P0·V0 holds.
#[test]
fn the_coarsest_shell_selects_its_own_surfaces_and_its_gas_inflates_it() {
    let text = r#"
[[material]]
name = "rubber"
young = 1.0e6
poisson = 0.3
density = 1100.0
[[body]]
name = "ball"
material = "rubber"
shape = { shell = { center = [0.0, 0.0, 0.0], inner_radius = 0.04, outer_radius = 0.05, cells = 2, layers = 1 } }
[[constraint]]
name = "base"
body = "ball"
where = { box = { min = [-1.0, -1.0, -1.0], max = [1.0, 1.0, -0.03] } }
displacement = [0.0, 0.0, 0.0]
[[load]]
name = "air"
body = "ball"
where = { surface = "inner" }
pressure = 1000.0
gas = true
"#;
    let solved = solve(text);
    let cavity = solved.model.gas.as_ref().unwrap();
    assert_eq!(cavity.facets.len(), 24);
    let nodes = &solved.model.mesh.nodes;
    for f in &cavity.facets {
        for &n in &f.nodes {
            assert!((nodes[n].norm() - 0.04).abs() < 1e-12);
        }
    }
    let report = solved.report.frames[0].cavity.as_ref().unwrap();
    let law = (report.gauge_pressure + AMBIENT) * report.volume
        / ((cavity.rest_gauge + AMBIENT) * cavity.rest_volume)
        - 1.0;
    println!(
        "gauge {:.2} Pa (rest 1000), volume {:.6e} (rest {:.6e}), law {law:.1e}",
        report.gauge_pressure, report.volume, cavity.rest_volume
    );
    assert!(law.abs() < 1e-6, "{law}");
    assert!(report.volume > cavity.rest_volume);
    assert!(report.gauge_pressure < 1000.0 && report.gauge_pressure > 0.0);
    // The outside: the other 24 facets, each node at the outer radius.
    let outer = text.replace(
        "surface = \"inner\" }\npressure = 1000.0\ngas = true",
        "surface = \"outer\" }\npressure = 1000.0",
    );
    let outer = Model::build(&Scene::parse(&outer, "outer.toml").unwrap(), "outer.toml").unwrap();
    let loaded: Vec<usize> = (0..outer.mesh.node_count())
        .filter(|&n| (0..3).any(|i| outer.load_vector[3 * n + i] != 0.0))
        .collect();
    assert!(!loaded.is_empty());
    for n in loaded {
        assert!(
            (outer.mesh.nodes[n].norm() - 0.05).abs() < 1e-12,
            "node {n}"
        );
    }
}

/// Squeezed 24 mm from each side (the plates a third of its diameter apart): the small-strain
/// tiers warn that the obstacles impose it (a stiffer material would strain as much, so no
/// modulus is advised) and advise the nonlinear tier; followed, the nonlinear static frame
/// solves it (its Neo-Hookean wall in compression has an indefinite exact tangent there: those
/// Newton iterations take each element's tangent made definite), keeps p·V = P0·V0, the plates
/// push equally and no node is left beyond either plate.
#[test]
fn a_deep_squeeze_is_told_to_the_nonlinear_tier_which_solves_it() {
    let (gauge, squeeze) = (3.0e4, 0.024);
    let text = plates_scene(gauge, true, squeeze);
    let linear = solve(&text);
    let warning = linear
        .report
        .warnings
        .iter()
        .find(|w| w.contains("principal strain"))
        .expect("a strain warning");
    assert!(
        warning.contains("the obstacles \"bottom\", \"top\" (which start 24.0 mm inside it)")
            && warning.contains("tier = \"nonlinear\"")
            && !warning.contains("too soft"),
        "{warning}"
    );
    let solved = solve(&format!("[solver]\ntier = \"nonlinear\"\n{text}"));
    let frame = &solved.report.frames[0];
    let cavity = frame.cavity.as_ref().expect("a cavity report");
    let law = (cavity.gauge_pressure + AMBIENT) * cavity.volume
        / ((gauge + AMBIENT) * cavity.rest_volume)
        - 1.0;
    let contact = frame.contact.as_ref().unwrap();
    let (bottom, top) = (
        contact.obstacles["bottom"].force[2],
        contact.obstacles["top"].force[2],
    );
    let model = &solved.model;
    let u = &solved.frames[0].solution.displacement;
    let z = 0.035 - squeeze;
    let beyond = (0..model.mesh.node_count())
        .map(|n| (model.mesh.nodes[n].z + u[3 * n + 2]).abs() - z)
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "squeezed {:.0} mm on the nonlinear tier: gauge {:.0} Pa, volume {:.4e} m³ (rest {:.4e}), \
         law {law:.1e}, plates {bottom:.2} / {top:.2} N, {:.2e} m beyond a plate",
        squeeze * 1e3,
        cavity.gauge_pressure,
        cavity.volume,
        cavity.rest_volume,
        beyond
    );
    assert!(law.abs() < 1e-6, "{law}");
    assert!(cavity.gauge_pressure > gauge && cavity.volume < cavity.rest_volume);
    assert!(bottom > 0.0 && rel(-top, bottom) < 1e-9, "{top} {bottom}");
    assert!(beyond <= model.contact.penetration_limit(), "{beyond}");
}
