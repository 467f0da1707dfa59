//! How deep points lie inside closed bodies: each body's surface split into its closed pieces,
//! a winding-number tree over each, and the distance to the piece's surface for a point inside.
//! Made once for many questions where the points move and the bodies do not (a hand's skin
//! skinned to the poses along a keyframe, `proximity.rs`); the contact step's check of the skin
//! it leaves inside a body asks once (`grasp.rs`).

use crate::contact::{connected_pieces, ContactSurface, WindingTree};
use nalgebra::Vector3;
use rayon::prelude::*;

/// The node of `nodes` deepest inside one of the closed `objects` at `positions` (node, the
/// object's body, depth), among those deeper than `beyond`.
pub(super) fn deepest_inside(
    objects: &[ContactSurface],
    nodes: &[usize],
    positions: &[Vector3<f64>],
    beyond: f64,
) -> Option<(usize, usize, f64)> {
    Insides::new(objects, positions).deepest(nodes, positions, beyond)
}

/// The closed pieces of some bodies' surfaces, each with its winding-number tree, and each
/// body's box: what tells how deep a point lies inside them, made once for many questions
/// about points that move while the bodies do not.
pub(super) struct Insides {
    /// Per body: the body, its box, its pieces (triangles and tree).
    bodies: Vec<BodyInside>,
}

struct BodyInside {
    body: usize,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    pieces: Vec<(Vec<[usize; 3]>, WindingTree)>,
}

impl Insides {
    /// The closed `objects` at `positions` (their nodes there; other entries are not read).
    pub(super) fn new(objects: &[ContactSurface], positions: &[Vector3<f64>]) -> Insides {
        let bodies = objects
            .iter()
            .map(|s| {
                let pieces = connected_pieces(&s.triangles)
                    .into_iter()
                    .map(|piece| {
                        let tree = WindingTree::new(&piece, positions);
                        (piece, tree)
                    })
                    .collect();
                let corners = s.triangles.iter().flatten().map(|&n| positions[n]);
                let lo = corners
                    .clone()
                    .fold(Vector3::repeat(f64::INFINITY), |m, p| m.inf(&p));
                let hi = corners.fold(Vector3::repeat(f64::NEG_INFINITY), |m, p| m.sup(&p));
                BodyInside {
                    body: s.body,
                    lo,
                    hi,
                    pieces,
                }
            })
            .collect();
        Insides { bodies }
    }

    /// The node of `nodes` (at `positions`, the bodies' nodes where [`Insides::new`] had them)
    /// deepest inside one of the bodies (node, body, depth), among those deeper than `beyond`.
    pub(super) fn deepest(
        &self,
        nodes: &[usize],
        positions: &[Vector3<f64>],
        beyond: f64,
    ) -> Option<(usize, usize, f64)> {
        let mut deepest: Option<(usize, usize, f64)> = None;
        for b in &self.bodies {
            let (lo, hi) = (b.lo, b.hi);
            // Each node on its own, in parallel (a winding number sums over the whole piece).
            let depths: Vec<(usize, f64)> = nodes
                .par_iter()
                .filter_map(|&n| {
                    let p = positions[n];
                    if (0..3).any(|a| p[a] < lo[a] || p[a] > hi[a]) {
                        return None;
                    }
                    // Inside a piece of the surface (for a shell: within its outer surface, or
                    // in its cavity, having passed the wall): how far from that piece's
                    // surface. Within `beyond` of it, the contact's (or, when only the object's
                    // nodes are checked, the discretisation's); deeper, never found — also a
                    // node deep in a thin wall next to its far side, which is near a facet but
                    // not the piece's it is inside.
                    let depth = b
                        .pieces
                        .iter()
                        .filter(|(_, tree)| tree.inside(&p))
                        .map(|(piece, _)| {
                            piece
                                .iter()
                                .filter_map(|t| {
                                    crate::contact::project_on_triangle(
                                        &p,
                                        &t.map(|m| positions[m]),
                                    )
                                })
                                .map(|q| q.distance)
                                .fold(f64::INFINITY, f64::min)
                        })
                        .fold(0.0, f64::max);
                    Some((n, depth))
                })
                .collect();
            // The deepest, the first of equals in the nodes' order.
            for (n, depth) in depths {
                if depth > beyond && deepest.is_none_or(|d| depth > d.2) {
                    deepest = Some((n, b.body, depth));
                }
            }
        }
        deepest
    }
}
