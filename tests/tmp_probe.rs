use prehensile::hand::{HandModel, Side};
use prehensile::contact::ContactSurface;
#[test]
fn probe() {
    let h = HandModel::new(Side::Right, 1.0).unwrap();
    let x = &h.flesh.mesh.nodes;
    let s = ContactSurface::from_quads(0, &h.flesh.skin_quads, x);
    let v: f64 = s.triangles.iter().map(|t| x[t[0]].dot(&x[t[1]].cross(&x[t[2]])) / 6.0).sum();
    println!("signed volume {v}");
    let m = prehensile::mesh::shell_mesh(nalgebra::Vector3::zeros(), 0.031, 0.035, 12, 2);
    let f = prehensile::mesh::boundary_facets(&m);
    let q: Vec<[usize;4]> = f.iter().map(|f| f.nodes).collect();
    let s = ContactSurface::from_quads(0, &q, &m.nodes);
    let v: f64 = s.triangles.iter().map(|t| m.nodes[t[0]].dot(&m.nodes[t[1]].cross(&m.nodes[t[2]])) / 6.0).sum();
    println!("shell signed volume {v} expected {}", 4.0/3.0*std::f64::consts::PI*(0.035f64.powi(3)-0.031f64.powi(3)));
}
