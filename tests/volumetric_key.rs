//! `[solver] volumetric`: the nonlinear tier's Neo-Hookean law with mean dilatation (default)
//! or full 2×2×2 integration of the volumetric energy, on a nearly incompressible block pressed
//! 5 % between a fixed base and a plate that lets it spread: full integration locks.

use prehensile::headless::solve_scene;
use prehensile::scene::Scene;

fn press_force(poisson: f64, volumetric: &str) -> f64 {
    let text = format!(
        r#"
[solver]
tier = "nonlinear"
volumetric = "{volumetric}"

[[material]]
name = "rubber"
young = 1.0e6
poisson = {poisson}

[[body]]
name = "block"
material = "rubber"
shape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [0.1, 0.1, 0.1], cells = [4, 4, 4] }} }}

[[constraint]]
name = "base"
body = "block"
where = {{ face = "z-" }}
displacement = [0.0, 0.0, 0.0]

[[constraint]]
name = "press"
body = "block"
where = {{ face = "z+" }}
displacement = {{ z = -0.005 }}
"#
    );
    let scene = Scene::parse(&text, "volumetric test").unwrap();
    let solved = solve_scene(&scene, "volumetric test").unwrap();
    let f = solved.report.frames[0].constraints["press"].reaction[2];
    assert!(f.is_finite());
    -f
}

#[test]
fn full_integration_locks_and_mean_dilatation_does_not() {
    let mut rows = Vec::new();
    for nu in [0.3, 0.49, 0.4999] {
        let (md, full) = (press_force(nu, "mean_dilatation"), press_force(nu, "full"));
        println!("ν = {nu}: mean dilatation {md:.1} N, full {full:.1} N");
        rows.push((md, full));
    }
    // Both press back.
    assert!(rows.iter().all(|r| r.0 > 0.0 && r.1 > 0.0));
    // Mean dilatation: the force tends to the incompressible limit (ν 0.49 → 0.4999 changes it
    // by under 10 %); fully integrated, a 4-cell hex8 block locks: the force keeps growing.
    assert!(rows[2].0 < 1.1 * rows[1].0, "{rows:?}");
    assert!(rows[2].1 > 2.0 * rows[2].0, "{rows:?}");
    // At ν = 0.3 the two integrations differ little.
    assert!((rows[0].1 - rows[0].0).abs() < 0.1 * rows[0].0, "{rows:?}");
}

#[test]
fn a_bad_volumetric_value_names_the_key() {
    let text = r#"
[solver]
volumetric = "reduced"

[[material]]
name = "rubber"
young = 1.0e6
poisson = 0.3

[[body]]
name = "block"
material = "rubber"
shape = { box = { min = [0.0, 0.0, 0.0], max = [0.1, 0.1, 0.1], cells = [2, 2, 2] } }
"#;
    let err = Scene::parse(text, "bad.toml").unwrap_err().to_string();
    println!("{err}");
    // The file, the line of the key and the accepted values.
    assert!(
        err.contains("bad.toml:3") && err.contains("mean_dilatation"),
        "{err}"
    );
}
