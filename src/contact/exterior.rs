//! The part of a body's boundary that skin can meet from outside: the pieces of its surface
//! that enclose its material, not those that line a cavity inside it. A hollow ball's boundary
//! is two closed pieces, its outer sphere and the wall of its cavity (whose outward normals,
//! out of the rubber, point to the centre); a finger pressing the ball meets the outer one only.
//! Held against the cavity's wall too, a skin point pushed past the middle of a thin wall is
//! nearest the cavity's side and leaves by it, into the cavity: the press then goes through the
//! wall however small its steps.

use nalgebra::Vector3;
use std::collections::HashMap;

/// The quads of `quads` (outward, as a body's boundary facets) in the closed pieces whose
/// signed volume at `positions` is positive: the outer surfaces, without the walls of the
/// cavities. All of them when none encloses a positive volume (an open or inverted surface is
/// left as given).
pub fn exterior_quads(quads: &[[usize; 4]], positions: &[Vector3<f64>]) -> Vec<[usize; 4]> {
    let mut parent: HashMap<usize, usize> = HashMap::new();
    fn root(parent: &mut HashMap<usize, usize>, n: usize) -> usize {
        let mut r = *parent.entry(n).or_insert(n);
        while parent[&r] != r {
            r = parent[&r];
        }
        parent.insert(n, r);
        r
    }
    for q in quads {
        let r0 = root(&mut parent, q[0]);
        for &n in &q[1..] {
            let r = root(&mut parent, n);
            if r != r0 {
                parent.insert(r, r0);
            }
        }
    }
    let piece: Vec<usize> = quads.iter().map(|q| root(&mut parent, q[0])).collect();
    // Each piece's volume about one of its own nodes (its root), so that a small body far from
    // the origin keeps its sign through round-off.
    let mut volume: HashMap<usize, f64> = HashMap::new();
    for (q, &r) in quads.iter().zip(&piece) {
        let o = positions[r];
        let [a, b, c, d] = q.map(|n| positions[n] - o);
        *volume.entry(r).or_insert(0.0) += (a.dot(&b.cross(&c)) + a.dot(&c.cross(&d))) / 6.0;
    }
    let kept: Vec<[usize; 4]> = quads
        .iter()
        .zip(&piece)
        .filter(|(_, r)| volume[r] > 0.0)
        .map(|(q, _)| *q)
        .collect();
    if kept.is_empty() {
        quads.to_vec()
    } else {
        kept
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{boundary_facets, box_mesh, shell_mesh};

    /// A hollow box (a 3×3×3 block without its centre cell): its boundary is the outer cube
    /// (54 faces, +27 volume units) and the cavity's wall (6 faces, −1): the outer cube only.
    #[test]
    fn a_hollow_block_keeps_its_outer_surface_and_not_its_cavity_wall() {
        let mut mesh = box_mesh(Vector3::zeros(), Vector3::repeat(3.0), [3, 3, 3]);
        let centre = (0..mesh.cells.len())
            .find(|&c| {
                let x: Vector3<f64> = mesh.cells[c]
                    .iter()
                    .map(|&n| mesh.nodes[n])
                    .sum::<Vector3<f64>>()
                    / 8.0;
                (x - Vector3::repeat(1.5)).norm() < 1e-9
            })
            .unwrap();
        mesh.cells.remove(centre);
        let quads: Vec<[usize; 4]> = boundary_facets(&mesh).iter().map(|f| f.nodes).collect();
        assert_eq!(quads.len(), 60);
        let outer = exterior_quads(&quads, &mesh.nodes);
        assert_eq!(outer.len(), 54);
        let inner_node = |n: usize| (mesh.nodes[n] - Vector3::repeat(1.5)).amax() < 0.5 + 1e-9;
        assert!(outer.iter().flatten().all(|&n| !inner_node(n)));
        // A hollow ball far from the origin (a 35 mm shell 1 km away): its outer sphere, every
        // kept node at the outer radius.
        let centre = Vector3::new(1000.0, -1000.0, 500.0);
        let shell = shell_mesh(centre, 0.031, 0.035, 6, 2);
        let quads: Vec<[usize; 4]> = boundary_facets(&shell).iter().map(|f| f.nodes).collect();
        let outer = exterior_quads(&quads, &shell.nodes);
        assert!(!outer.is_empty() && outer.len() < quads.len());
        for n in outer.iter().flatten() {
            let r = (shell.nodes[*n] - centre).norm();
            assert!((r - 0.035).abs() < 1e-9, "{r}");
        }
        // A solid block: all of it.
        let solid = box_mesh(Vector3::zeros(), Vector3::repeat(1.0), [2, 2, 2]);
        let all: Vec<[usize; 4]> = boundary_facets(&solid).iter().map(|f| f.nodes).collect();
        assert_eq!(exterior_quads(&all, &solid.nodes).len(), all.len());
    }
}
