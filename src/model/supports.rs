//! Supports: every body held against rigid motion, or floating (held by contact alone).

use super::check::list;
use super::BodyModel;
use crate::fem::rigid::free_rigid_motions;
use crate::mesh::Mesh;
use crate::scene::Scene;

/// Every piece of every body must be held against rigid motion, or (a body with no
/// support at all, in a scene with obstacles or hands) be held by contact: returns the bodies
/// held by contact alone (floating); the error names a body (or piece) free to move rigidly.
pub fn floating_bodies(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
    prescribed_mask: &[bool],
) -> Result<Vec<usize>, (String, String)> {
    let mut floating = Vec::new();
    let (piece, pieces) = mesh.connected_pieces();
    let mut piece_nodes: Vec<Vec<usize>> = vec![Vec::new(); pieces];
    for (n, &p) in piece.iter().enumerate() {
        piece_nodes[p].push(n);
    }
    for (b, body) in bodies.iter().enumerate() {
        let mut body_pieces: Vec<usize> = body.nodes.clone().map(|n| piece[n]).collect();
        body_pieces.sort_unstable();
        body_pieces.dedup();
        for (k, &p) in body_pieces.iter().enumerate() {
            let free = free_rigid_motions(&piece_nodes[p], &mesh.nodes, |d| prescribed_mask[d]);
            let untouched = body
                .nodes
                .clone()
                .all(|n| (0..3).all(|a| !prescribed_mask[3 * n + a]));
            let holders = !scene.obstacle.is_empty() || bodies.iter().any(|o| o.hand.is_some());
            if !free.is_empty()
                && untouched
                && body_pieces.len() == 1
                && holders
                && body.hand.is_none()
            {
                floating.push(b);
                continue;
            }
            if !free.is_empty() {
                let which = if body_pieces.len() > 1 {
                    format!(
                        " (piece {} of {}, {} nodes)",
                        k + 1,
                        body_pieces.len(),
                        piece_nodes[p].len()
                    )
                } else {
                    String::new()
                };
                return Err((
                    format!("body \"{}\" (body[{b}])", super::names::shown(&body.name)),
                    format!(
                        "is free to move rigidly{which}: the constraints leave {} free; \
                         prescribe more displacements on it",
                        list(&free.iter().map(String::as_str).collect::<Vec<_>>())
                    ),
                ));
            }
        }
    }
    Ok(floating)
}
