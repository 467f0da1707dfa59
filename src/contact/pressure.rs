//! The tactile map: contact pressure at the surface nodes, the nodal normal contact force (on
//! both sides of a contact: the node, and the facet's nodes by their shares h_i) divided by the
//! node's share of the boundary facets' area (a quarter of each quad it belongs to).

use super::point::ContactPoint;
use crate::mesh::Facet;
use nalgebra::Vector3;

/// Contact pressure at every node (0 where there is no contact), Pa.
pub fn nodal_pressure(
    nodes: &[Vector3<f64>],
    facets: &[Facet],
    contacts: &[ContactPoint],
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
    for c in contacts {
        for (n, f) in c.nodal_normal_forces() {
            if area[n] > 0.0 {
                pressure[n] += f / area[n];
            }
        }
    }
    pressure
}
