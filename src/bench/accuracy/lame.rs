//! (b) Lamé's thick-walled sphere: inner radius 50 mm, outer 100 mm, E = 1 MPa, ν = 0.3, an
//! inner pressure of 1 kPa (the cavity's wall strains by about 0.1 %, so the small-strain
//! solution holds to far below the discretisation errors measured), rigid motions held by
//! tangential constraints at three poles (the scene of `tests/analytic.rs`). Meshed as a cubed
//! sphere of n × n quads per face and n/2 layers. The error is the largest relative error of
//! the radial displacement over all nodes against
//! u(r) = p a³/[E(b³−a³)]·[(1−2ν) r + (1+ν) b³/(2r²)].

use super::{Column, Solved, Unit};
use crate::scene::Scene;

/// Inner and outer radius (m), pressure (Pa), Young's modulus (Pa), Poisson ratio.
const SPHERE: (f64, f64, f64, f64, f64) = (0.05, 0.1, 1.0e3, 1.0e6, 0.3);

/// The largest radial error, and the largest tangential displacement relative to u(a).
pub const COLUMNS: &[Column] = &[
    Column {
        name: "largest radial error",
        unit: Unit::Percent,
    },
    Column {
        name: "largest tangential / u(a)",
        unit: Unit::Percent,
    },
];

/// Layers through the wall for `cells` quads along a cube face's edge.
pub fn layers(cells: f64) -> usize {
    ((cells / 2.0).round() as usize).max(1)
}

/// Lamé's radial displacement at radius `r`, m.
pub fn lame(r: f64) -> f64 {
    let (a, b, p, e, nu) = SPHERE;
    p * a.powi(3) / (e * (b.powi(3) - a.powi(3)))
        * ((1.0 - 2.0 * nu) * r + (1.0 + nu) * b.powi(3) / (2.0 * r * r))
}

/// The scene with `cells` quads along each cube face's edge.
pub fn scene(cells: usize) -> Scene {
    let (a, b, p, e, nu) = SPHERE;
    let layers = layers(cells as f64);
    let text = format!(
        r#"
[[material]]
name = "m"
young = {e:e}
poisson = {nu}
[[body]]
name = "sphere"
material = "m"
shape = {{ shell = {{ center = [0, 0, 0], inner_radius = {a}, outer_radius = {b}, cells = {cells}, layers = {layers} }} }}
[[load]]
body = "sphere"
where = {{ surface = "inner" }}
pressure = {p:e}
[[constraint]]
name = "px"
body = "sphere"
where = {{ point = [{b}, 0, 0] }}
displacement = {{ y = 0, z = 0 }}
[[constraint]]
name = "py"
body = "sphere"
where = {{ point = [0, {b}, 0] }}
displacement = {{ x = 0, z = 0 }}
[[constraint]]
name = "pz"
body = "sphere"
where = {{ point = [0, 0, {b}] }}
displacement = {{ x = 0, y = 0 }}
"#
    );
    Scene::parse(&text, "lame").expect("the Lamé scene parses")
}

/// The errors of a solved sphere.
pub fn measure(solved: &Solved) -> Result<Vec<f64>, String> {
    let sol = &solved.frames[0].solution;
    let inner = lame(SPHERE.0);
    let mut radial: f64 = 0.0;
    let mut tangential: f64 = 0.0;
    for (n, x) in solved.model.mesh.nodes.iter().enumerate() {
        let r = x.norm();
        let u = sol.node_displacement(n);
        let ur = u.dot(&(x / r));
        radial = radial.max((ur / lame(r) - 1.0).abs());
        tangential = tangential.max((u - x / r * ur).norm() / inner);
    }
    Ok(vec![radial, tangential])
}
