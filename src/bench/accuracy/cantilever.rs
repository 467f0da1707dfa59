//! (a) The cantilever of `docs/validation.md` as a scene: 8 × 1 × 1 m, E = 1 MPa, ν = 0.3,
//! clamped at x = 0, 1 N along −z shared by the nodes of the free end, meshed with 8k × k × k
//! hexahedra. The error is that of the mean tip deflection against Timoshenko's beam
//! (δ = PL³/3EI + PL/κGA); δ/L = 2.5·10⁻⁴, so the small-strain solution is exact to far below
//! the errors measured, for the linear and the nonlinear tiers alike.

use super::{Column, Solved, Unit};
use crate::bench::elements::{timoshenko_tip, BEAM, TIP_FORCE};
use crate::scene::Scene;

/// Poisson ratio of the beam.
const POISSON: f64 = 0.3;

/// |tip / Timoshenko − 1|, then the signed value.
pub const COLUMNS: &[Column] = &[
    Column {
        name: "tip deflection error",
        unit: Unit::Percent,
    },
    Column {
        name: "tip / Timoshenko − 1",
        unit: Unit::SignedPercent,
    },
];

/// The scene with `k` elements through the thickness.
pub fn scene(k: usize) -> Scene {
    let (l, h, young) = BEAM;
    let text = format!(
        r#"
[[material]]
name = "m"
young = {young:e}
poisson = {POISSON}
[[body]]
name = "beam"
material = "m"
shape = {{ box = {{ min = [0, 0, 0], max = [{l:e}, {h:e}, {h:e}], cells = [{}, {k}, {k}] }} }}
[[constraint]]
name = "clamp"
body = "beam"
where = {{ face = "x-" }}
displacement = [0, 0, 0]
[[load]]
name = "tip"
body = "beam"
where = {{ face = "x+" }}
force = [0, 0, {:e}]
"#,
        8 * k,
        -TIP_FORCE
    );
    Scene::parse(&text, "cantilever").expect("the cantilever scene parses")
}

/// The tip error of a solved cantilever.
pub fn measure(solved: &Solved) -> Result<Vec<f64>, String> {
    let (l, _, _) = BEAM;
    let mesh = &solved.model.mesh;
    let u = &solved.frames[0].solution.displacement;
    let end: Vec<usize> = (0..mesh.node_count())
        .filter(|&n| (mesh.nodes[n].x - l).abs() < 1e-9 * l)
        .collect();
    if end.is_empty() {
        return Err("no node at the free end".into());
    }
    let tip = end.iter().map(|&n| u[3 * n + 2]).sum::<f64>() / end.len() as f64;
    let signed = tip / timoshenko_tip(POISSON, TIP_FORCE) - 1.0;
    Ok(vec![signed.abs(), signed])
}
