//! The tactile map: contact pressure at the surface nodes, the nodal normal contact force (on
//! both sides of a contact: the node, and the facet's nodes by their shares h_i) divided by the
//! node's share of the boundary facets' area (a quarter of each quad it belongs to). A contact
//! point embedded in a cell (the smooth skin's) gives its force to the cell's surface nodes, in
//! proportion to their weights.

use super::point::ContactPoint;
use crate::mesh::Facet;
use nalgebra::Vector3;

/// Contact pressure at every node (0 where there is no contact), Pa.
pub fn nodal_pressure(
    nodes: &[Vector3<f64>],
    facets: &[Facet],
    contacts: &[ContactPoint],
) -> Vec<f64> {
    nodal_pressure_with(nodes, facets, contacts, &[])
}

/// [`nodal_pressure`] with more normal forces: each `(terms, force)` of `more` pressing `force`
/// (N) on the nodes of `terms` (node, weight), shared as a contact's side is.
pub fn nodal_pressure_with(
    nodes: &[Vector3<f64>],
    facets: &[Facet],
    contacts: &[ContactPoint],
    more: &[(Vec<(usize, f64)>, f64)],
) -> Vec<f64> {
    let mut area = vec![0.0; nodes.len()];
    for f in facets {
        let p = f.nodes.map(|n| nodes[n]);
        let a = 0.5 * ((p[2] - p[0]).cross(&(p[3] - p[1]))).norm();
        let mut distinct = f.nodes.to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        for &n in &distinct {
            area[n] += a / distinct.len() as f64;
        }
    }
    let mut pressure = vec![0.0; nodes.len()];
    // A side's share of a normal force over its nodes on the surface.
    let mut press = |side: &[(usize, f64)], force: f64| {
        let on_surface = |&&(n, w): &&(usize, f64)| area[n] > 0.0 && w != 0.0;
        let total: f64 = side.iter().filter(on_surface).map(|t| t.1.abs()).sum();
        if total > 0.0 {
            for &(n, w) in side.iter().filter(on_surface) {
                pressure[n] += force * w.abs() / total / area[n];
            }
        }
    };
    for c in contacts {
        let (slave, master) = c.terms.split_at(c.slave_terms);
        press(slave, c.force);
        press(master, c.force);
    }
    for (terms, force) in more {
        press(terms, *force);
    }
    pressure
}
