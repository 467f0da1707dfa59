//! The contact's pairing kept from one contact step to the next at a pose (issue 15). A contact
//! point near an edge of the other body's surface is about as near to two facets; from one
//! correction at the pose to the next it can be paired with either, and the fixed-point map of
//! the corrections is discontinuous there: the force jumps and the corrections do not settle
//! (the finger press at hand resolution 0.5, MCP 23.5°: 1.96 % after six). A step without
//! motion to follow (a correction, a keyframe in one step from a frame in contact) therefore
//! keeps each point on the facet the last step held it on, as long as the point's projection
//! on that facet's plane stays within the facet; a point that left it is paired anew by the
//! nearest-facet search. (Kept past the facet's edges, the pairing pushes the point where it
//! would have slid onto the next facet: the grip then lands 15 % higher.)

use crate::contact::{Crossing, Master};
use nalgebra::Vector3;

/// The pairs of `last` whose point projects within its facet at `positions` (every contact
/// point and node), each with the barycentric weights of that projection.
pub(super) fn kept_pairs(last: &[Crossing], positions: &[Vector3<f64>]) -> Vec<Crossing> {
    last.iter()
        .filter_map(|c| {
            let weights = plane_weights(&positions[c.node], &c.nodes.map(|m| positions[m]))?;
            weights
                .iter()
                .all(|&w| w >= 0.0)
                .then_some(Crossing { weights, ..*c })
        })
        .collect()
}

/// The pairs a contact solve held: each point on a facet with its weights; `surface_of` gives
/// the index of the surface of a body (`None`: a body without a surface in this step).
pub(super) fn held_pairs<'a>(
    contacts: impl Iterator<Item = (usize, &'a Master)>,
    surface_of: impl Fn(usize) -> Option<usize>,
) -> Vec<Crossing> {
    contacts
        .filter_map(|(node, master)| match master {
            Master::Facet {
                body,
                nodes,
                weights,
            } => Some(Crossing {
                node,
                surface: surface_of(*body)?,
                nodes: *nodes,
                weights: *weights,
            }),
            Master::Obstacle(_) => None,
        })
        .collect()
}

/// Barycentric weights of the projection of `x` on the plane of triangle `p`; `None` for a
/// flat triangle.
fn plane_weights(x: &Vector3<f64>, p: &[Vector3<f64>; 3]) -> Option<[f64; 3]> {
    let (e1, e2, d) = (p[1] - p[0], p[2] - p[0], x - p[0]);
    let (a, b, c) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
    let det = a * c - b * b;
    if det <= f64::EPSILON * a * c || !det.is_finite() {
        return None;
    }
    let (d1, d2) = (d.dot(&e1), d.dot(&e2));
    let v = (c * d1 - b * d2) / det;
    let w = (a * d2 - b * d1) / det;
    Some([1.0 - v - w, v, w])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn crossing(node: usize) -> Crossing {
        Crossing {
            node,
            surface: 0,
            nodes: [0, 1, 2],
            weights: [1.0 / 3.0; 3],
        }
    }

    /// A point above the facet keeps its pair, with the weights of where it projects now; one
    /// that moved past an edge is paired anew (dropped here).
    #[test]
    fn a_pair_is_kept_while_its_point_projects_within_its_facet() {
        let positions = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.25, 0.5, -0.01),
            Vector3::new(0.8, 0.5, 0.02),
        ];
        let kept = kept_pairs(&[crossing(3), crossing(4)], &positions);
        assert_eq!(kept.len(), 1);
        assert_eq!(kept[0].node, 3);
        let w = kept[0].weights;
        assert!((w[0] - 0.25).abs() < 1e-12 && (w[1] - 0.25).abs() < 1e-12);
        assert!((w[2] - 0.5).abs() < 1e-12);
    }
}
