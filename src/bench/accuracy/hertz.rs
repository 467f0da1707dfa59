//! (c) Hertz contact: an elastic ball (R = 50 mm, E = 100 kPa, ν = 0.3) pressed by 1.5 mm onto
//! the rigid plane z = 0 through its top cap (the problem of `tests/contact.rs`), meshed finer
//! toward the contact: `refine = { toward = [0, 0, 0], size = R/n }` over a base of 12 cells
//! across (n = 32 is the default refinement: no `size`). Hertz's solution is compared at the
//! total force F the solver finds: a = (3FR/4E*)^(1/3), p0 = 3F/(2πa²), E* = E/(1−ν²). The
//! mesh's contact radius comes from the second moment of the nodal contact forces
//! (∫ρ²p dA / F = (2/5)a² for Hertz's pressure); the peak pressure from the tactile map (nodal
//! forces over tributary areas, which under-reads a peak on a coarse mesh).

use super::{Column, Solved, Unit};
use crate::model::DEFAULT_SIZE_OF_RADIUS;
use crate::scene::Scene;
use crate::state::contact_pressure;

/// Radius (m), Young's modulus (Pa), Poisson ratio, the cap's displacement (m).
const BALL: (f64, f64, f64, f64) = (0.05, 1.0e5, 0.3, 0.0015);

/// Contact radius error, signed, peak pressure error (signed), total force.
pub const COLUMNS: &[Column] = &[
    Column {
        name: "contact radius error",
        unit: Unit::Percent,
    },
    Column {
        name: "a / a_Hertz − 1",
        unit: Unit::SignedPercent,
    },
    Column {
        name: "peak pressure / p0_Hertz − 1",
        unit: Unit::SignedPercent,
    },
    Column {
        name: "force (N)",
        unit: Unit::Newton,
    },
];

/// Cells across the ball away from the contact.
pub const BASE_CELLS: usize = 12;

/// The scene with cells of R/`level` at the contact (the default refinement at its level, 32).
pub fn scene(level: usize) -> Scene {
    let (r, e, nu, delta) = BALL;
    let cells = BASE_CELLS;
    let size = if level as f64 * DEFAULT_SIZE_OF_RADIUS == 1.0 {
        String::new()
    } else {
        format!(", size = {:e}", r / level as f64)
    };
    let text = format!(
        r#"
[[material]]
name = "m"
young = {e:e}
poisson = {nu}
[[body]]
name = "ball"
material = "m"
shape = {{ sphere = {{ center = [0, 0, {r}], radius = {r}, cells = {cells}, refine = {{ toward = [0, 0, 0]{size} }} }} }}
[[constraint]]
name = "cap"
body = "ball"
where = {{ box = {{ min = [-1, -1, {cap}], max = [1, 1, 1] }} }}
displacement = [0, 0, {d:e}]
[[obstacle]]
name = "table"
shape = {{ plane = {{ point = [0, 0, 0], normal = [0, 0, 1] }} }}
"#,
        cap = 1.9 * r,
        d = -delta
    );
    Scene::parse(&text, "hertz").expect("the Hertz scene parses")
}

/// The errors of a solved ball.
pub fn measure(solved: &Solved) -> Result<Vec<f64>, String> {
    let (r, e, nu, _) = BALL;
    let frame = &solved.frames[0];
    let contact = frame.contact.as_ref().ok_or("no contact")?;
    let nodes = &solved.model.mesh.nodes;
    let force: f64 = contact.contacts.iter().map(|c| c.force).sum();
    if force <= 0.0 {
        return Err(format!("no compressive contact force ({force} N)"));
    }
    let second = contact
        .contacts
        .iter()
        .map(|c| {
            let p = nodes[c.node];
            c.force * (p.x * p.x + p.y * p.y)
        })
        .sum::<f64>()
        / force;
    let a = (2.5 * second).sqrt();
    let e_star = e / (1.0 - nu * nu);
    let a_hertz = (3.0 * force * r / (4.0 * e_star)).cbrt();
    let p0_hertz = 1.5 * force / (std::f64::consts::PI * a_hertz * a_hertz);
    let peak = contact_pressure(&solved.model, frame)
        .ok_or("no tactile map")?
        .into_iter()
        .fold(0.0, f64::max);
    let ea = a / a_hertz - 1.0;
    Ok(vec![ea.abs(), ea, peak / p0_hertz - 1.0, force])
}
