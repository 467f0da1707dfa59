//! Skin that went into another body during a contact step's flexion (issue 15, item 5). A step's
//! flexion moves fingertip skin by millimetres before contact is detected on the moved
//! geometry; past the middle of a thin part of a body, the facet nearest to a skin node is the
//! far side's and it looks outside (a shell's cavity wall is not met by skin, `BodyModel::exterior`,
//! but a solid body's thin parts remain). Its straight path from where the last step left it
//! tells which facet it went through: the contact holds it there.
//! A node that was already just inside (held by the contact within its tolerance) and went
//! deeper is held against the facet nearest to where it was.

use crate::contact::{connected_pieces, ContactSurface, Crossing, WindingTree};
use nalgebra::Vector3;
use rayon::prelude::*;
use std::collections::HashSet;
use std::sync::OnceLock;

/// The nodes of `nodes` whose straight path from `from` to `to` (positions over every node; the
/// other bodies where they are, the same in both) entered a closed piece of one of the surfaces
/// `surfaces[first..]` and whose nearest facet at `to` does not hold them (it is the far side's,
/// or sees them outside, or no more than `tolerance` inside): each with the facet its path
/// crossed first (`Crossing::surface` indexes `surfaces`); the nearest facet is sought within
/// `search` (the contact's search depth).
pub(super) fn crossings(
    surfaces: &[ContactSurface],
    first: usize,
    nodes: &[usize],
    (from, to): (&[Vector3<f64>], &[Vector3<f64>]),
    tolerance: f64,
    search: f64,
) -> Vec<Crossing> {
    let mut out = Vec::new();
    for (s, surface) in surfaces.iter().enumerate().skip(first) {
        let bvh = surface.hierarchy(to, search);
        for piece in connected_pieces(&surface.triangles) {
            let corners = piece.iter().flatten().map(|&n| to[n]);
            let lo = corners
                .clone()
                .fold(Vector3::repeat(f64::INFINITY), |m, p| m.inf(&p));
            let hi = corners.fold(Vector3::repeat(f64::NEG_INFINITY), |m, p| m.sup(&p));
            let within = |p: &Vector3<f64>| (p - lo).min() >= 0.0 && (hi - p).min() >= 0.0;
            let in_piece: OnceLock<HashSet<[usize; 3]>> = OnceLock::new();
            let winding = WindingTree::new(&piece, to);
            // Each node on its own (in parallel, kept in the nodes' order).
            let of_node = |n: usize| -> Option<Crossing> {
                if !within(&to[n]) || !winding.inside(&to[n]) {
                    return None;
                }
                // A node already inside where the step started (the contact held it there,
                // within its tolerance) went deeper: the facet nearest to where it was is the
                // one that held it. Otherwise, the facet its path went through.
                let (nodes, weights) = if winding.inside(&from[n]) {
                    let set = in_piece.get_or_init(|| piece.iter().copied().collect());
                    bvh.project(&from[n], to, None, |t| !set.contains(t))
                        .filter(|p| p.gap <= 0.0)
                        .map(|p| (p.nodes, p.weights))
                } else {
                    first_hit(&from[n], &to[n], &piece, to)
                }?;
                // Where the nearest facet faces the way the node came in and sees it inside,
                // it holds it as well (a shallow entry): no crossing needed. Past the middle
                // of a thin wall or body, the nearest facet is the far side's.
                let [p0, p1, p2] = nodes.map(|m| to[m]);
                let crossed = (p1 - p0).cross(&(p2 - p0)).normalize();
                let held = bvh
                    .project(&to[n], to, None, |_| false)
                    .is_some_and(|p| p.gap < -tolerance && p.normal.dot(&crossed) > 0.8);
                (!held).then_some(Crossing {
                    node: n,
                    surface: s,
                    nodes,
                    weights,
                })
            };
            let left: Vec<usize> = nodes
                .iter()
                .copied()
                .filter(|&n| out.iter().all(|c: &Crossing| c.node != n))
                .collect();
            let found: Vec<Option<Crossing>> = left.par_iter().map(|&n| of_node(n)).collect();
            out.extend(found.into_iter().flatten());
        }
    }
    out
}

/// The triangle of `triangles` that the segment a → b enters first (against its outward normal),
/// and the barycentric weights of the point where it does (Möller–Trumbore).
fn first_hit(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    triangles: &[[usize; 3]],
    positions: &[Vector3<f64>],
) -> Option<([usize; 3], [f64; 3])> {
    let d = b - a;
    let mut best: Option<(f64, [usize; 3], [f64; 3])> = None;
    for t in triangles {
        let [p0, p1, p2] = t.map(|n| positions[n]);
        let (e1, e2) = (p1 - p0, p2 - p0);
        if e1.cross(&e2).dot(&d) >= 0.0 {
            continue;
        }
        let h = d.cross(&e2);
        let det = e1.dot(&h);
        if det.abs() < 1e-30 {
            continue;
        }
        let s = a - p0;
        let u = s.dot(&h) / det;
        let q = s.cross(&e1);
        let v = d.dot(&q) / det;
        let along = e2.dot(&q) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 || !(0.0..=1.0).contains(&along) {
            continue;
        }
        if best.is_none_or(|(t0, _, _)| along < t0) {
            best = Some((along, *t, [1.0 - u - v, u, v]));
        }
    }
    best.map(|(_, t, w)| (t, w))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's surface (outward triangles from its quads) and its corner positions.
    fn unit_cube() -> (Vec<[usize; 4]>, Vec<Vector3<f64>>) {
        let mesh = crate::mesh::box_mesh(Vector3::zeros(), Vector3::repeat(1.0), [1, 1, 1]);
        let quads = crate::mesh::boundary_facets(&mesh)
            .iter()
            .map(|f| f.nodes)
            .collect();
        (quads, mesh.nodes)
    }

    /// The crossings of the cube's surface by one node moving `from` → `to`.
    fn crossings_of(from: Vector3<f64>, to: Vector3<f64>) -> (Vec<Crossing>, Vec<Vector3<f64>>) {
        let (quads, mut positions) = unit_cube();
        let node = positions.len();
        positions.push(from);
        let mut moved = positions.clone();
        moved[node] = to;
        let surface = ContactSurface::from_quads(0, &quads, &positions);
        let found = crossings(&[surface], 0, &[node], (&positions, &moved), 1e-3, 1.0);
        (found, moved)
    }

    /// Where the one crossing found holds its node.
    fn held_at(found: &[Crossing], positions: &[Vector3<f64>]) -> Vector3<f64> {
        assert_eq!(found.len(), 1, "{found:?}");
        let c = found[0];
        (0..3).map(|i| positions[c.nodes[i]] * c.weights[i]).sum()
    }

    /// A node already just inside the top (held there by the contact) that goes on past the
    /// middle of the cube, where the bottom is nearer: held against the top, at the point
    /// nearest to where it was.
    #[test]
    fn a_node_already_inside_that_goes_deeper_is_held_where_it_was() {
        let from = Vector3::new(0.3, 0.6, 0.999);
        let (found, moved) = crossings_of(from, Vector3::new(0.35, 0.6, 0.3));
        let point = held_at(&found, &moved);
        assert!(
            (point - Vector3::new(0.3, 0.6, 1.0)).norm() < 1e-12,
            "{point}"
        );
        // Going only a little deeper, the top still holds it: no crossing needed.
        assert!(crossings_of(from, Vector3::new(0.3, 0.6, 0.8)).0.is_empty());
    }

    /// A node's path into the cube through its top.
    #[test]
    fn a_path_through_the_top_of_a_cube_crosses_the_top() {
        let from = Vector3::new(0.3, 0.6, 1.2);
        let (found, moved) = crossings_of(from, Vector3::new(0.3, 0.6, 0.1));
        let point = held_at(&found, &moved);
        assert!(
            (point - Vector3::new(0.3, 0.6, 1.0)).norm() < 1e-12,
            "{point}"
        );
        // Ending just under the top: its nearest facet holds it, no crossing needed.
        assert!(crossings_of(from, Vector3::new(0.3, 0.6, 0.9)).0.is_empty());
    }
}
