//! Nested refinement of the flesh mesh: every cell split into n × n × n by its own trilinear map.
//!
//! A finer lattice ([`super::lattice`]) cuts the hand anew: which cells are flesh, which are joint
//! space, which nodes follow which bone, all change with the spacing, so that a bone reaction
//! measured on lattices of resolution 1, 1.5 and 2 compares three hands, not three meshes of one
//! (docs/hand.md, "Why the shipped mean rises"). Split instead, the cells of one lattice keep its
//! hand: the same joint spaces, the same flesh between the digits, the bones holding the same
//! faces, the very same domain — what is refined is the finite element space alone, the setting
//! in which a finite element solution converges at a rate.
//!
//! What a split mesh holds by its parent's:
//! - a node at a parent node keeps its attachment;
//! - a node inside a parent face whose four nodes follow one group of bones (they move as one
//!   body), or on an edge of such a face, or inside a parent cell all of whose nodes do, follows
//!   the bone of its nearest parent node; a node on a parent edge alone that joins two attached
//!   nodes does not (a line held in three dimensions holds nothing in the limit: its reaction
//!   would fall away with the spacing);
//! - every new node stays where its parent cell's map puts it, on the skin and on the bones too:
//!   the split cells fill their parent exactly. (Moved onto the skin's shape and the bones', as
//!   far as the cells kept their quality, they changed the domain with every split — the parents'
//!   nodes the lattice had held back for quality went on too — and on two of six lattices the
//!   index's reaction then converged at an observed order of 0.2 to 0.4 instead of about 1:
//!   docs/hand.md, "Nested refinement". The skin's and the bones' surfaces are the lattice's,
//!   to its spacing's accuracy; a finer `resolution` approaches them.)
//! - each skin quadrilateral becomes n² of the cells along it, the display skin's control net is
//!   split alike (bilinearly), each of its quadrilaterals tied to its parent's cell (by that
//!   cell's first child), through which the skins are embedded (`embed::embed_split`).

use super::lattice::{rigid_groups, FleshMesh, CORNERS};
use super::skeleton::Skeleton;
use crate::mesh::{Mesh, HEX_FACES};
use nalgebra::Vector3;
use std::collections::HashMap;

/// The most splits of an edge a mesh may be refined by.
pub const MAX_SUBDIVISIONS: usize = 4;

/// A point of a parent entity, named by its parent nodes and their weights' numerators (over n³
/// in a cell, n² on a display quad), sorted by node: the same key from every cell sharing it.
type Key = [(u32, u32); 8];

fn key_of(terms: impl Iterator<Item = (usize, u32)>) -> Key {
    let mut key = [(u32::MAX, 0u32); 8];
    let mut len = 0;
    for (node, w) in terms {
        if w == 0 {
            continue;
        }
        let node = node as u32;
        match key[..len].iter_mut().find(|e| e.0 == node) {
            Some(e) => e.1 += w,
            None => {
                key[len] = (node, w);
                len += 1;
            }
        }
    }
    key[..len].sort_unstable();
    key
}

fn terms(key: &Key) -> impl Iterator<Item = (usize, u32)> + '_ {
    key.iter()
        .take_while(|e| e.0 != u32::MAX)
        .map(|&(n, w)| (n as usize, w))
}

/// The point of `key` over `points` (weights over `denominator`), summed in the key's order so
/// that every cell sharing it places it alike.
fn place(key: &Key, points: &[Vector3<f64>], denominator: u32) -> Vector3<f64> {
    terms(key).fold(Vector3::zeros(), |p, (n, w)| {
        p + points[n] * (w as f64 / denominator as f64)
    })
}

/// Node registry: one node per key.
struct Registry {
    index: HashMap<Key, u32>,
    keys: Vec<Key>,
}

impl Registry {
    fn new() -> Registry {
        Registry {
            index: HashMap::new(),
            keys: Vec::new(),
        }
    }

    fn id(&mut self, key: Key) -> usize {
        let next = self.keys.len() as u32;
        let id = *self.index.entry(key).or_insert(next);
        if id == next {
            self.keys.push(key);
        }
        id as usize
    }
}

/// The local point (i, j, k) of 0..=n of a cell: its key over the cell's nodes.
fn cell_point(cell: &[usize; 8], n: usize, [i, j, k]: [usize; 3]) -> Key {
    let w = |a: usize, t: usize| if a == 1 { t } else { n - t } as u32;
    key_of(
        CORNERS
            .iter()
            .zip(cell)
            .map(|(&[a, b, c], &node)| (node, w(a, i) * w(b, j) * w(c, k))),
    )
}

/// The children of a cell along its face `f` ([`HEX_FACES`]: −ξ, +ξ, −η, +η, −ζ, +ζ), as local
/// offsets (i, j, k) in 0..n.
fn along_face(f: usize, n: usize) -> impl Iterator<Item = [usize; 3]> {
    let (axis, side) = (f / 2, if f.is_multiple_of(2) { 0 } else { n - 1 });
    (0..n * n).map(move |s| {
        let (u, v) = (s % n, s / n);
        match axis {
            0 => [side, u, v],
            1 => [u, side, v],
            _ => [u, v, side],
        }
    })
}

/// `flesh` (meshed around the bones of `skeleton`) with every cell split into `n` × `n` × `n`
/// (module doc); `n` = 1 gives it back unchanged.
pub fn subdivide(flesh: FleshMesh, n: usize, skeleton: &Skeleton) -> FleshMesh {
    assert!(
        (1..=MAX_SUBDIVISIONS).contains(&n),
        "subdivisions {n} outside 1 ..= {MAX_SUBDIVISIONS}"
    );
    if n == 1 {
        return flesh;
    }
    let flesh = &flesh;
    let parent = &flesh.mesh;
    let group = rigid_groups(skeleton);
    let same_group = |nodes: &mut dyn Iterator<Item = usize>| -> bool {
        let mut groups = nodes.map(|p| flesh.node_bone[p].map(|b| group[b]));
        match groups.next() {
            Some(Some(first)) => groups.all(|g| g == Some(first)),
            _ => false,
        }
    };
    // Parent edges on a held face (a face whose four nodes move as one body).
    let mut held_edges: std::collections::HashSet<(usize, usize)> = Default::default();
    for cell in &parent.cells {
        for face in HEX_FACES {
            let q = face.map(|l| cell[l]);
            if same_group(&mut q.iter().copied()) {
                for e in 0..4 {
                    let (a, b) = (q[e], q[(e + 1) % 4]);
                    held_edges.insert((a.min(b), a.max(b)));
                }
            }
        }
    }

    // Nodes and cells.
    let n3 = (n * n * n) as u32;
    let mut registry = Registry::new();
    let mut cells = Vec::with_capacity(parent.cells.len() * n * n * n);
    let mut cell_digit = Vec::with_capacity(cells.capacity());
    for (c, cell) in parent.cells.iter().enumerate() {
        let mut local = vec![0usize; (n + 1) * (n + 1) * (n + 1)];
        for k in 0..=n {
            for j in 0..=n {
                for i in 0..=n {
                    local[i + (n + 1) * (j + (n + 1) * k)] =
                        registry.id(cell_point(cell, n, [i, j, k]));
                }
            }
        }
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    cells.push(CORNERS.map(|[a, b, cc]| {
                        local[(i + a) + (n + 1) * ((j + b) + (n + 1) * (k + cc))]
                    }));
                    cell_digit.push(flesh.cell_digit[c]);
                }
            }
        }
    }
    let child = |c: usize, [i, j, k]: [usize; 3]| c * n * n * n + i + n * (j + n * k);
    // Where the parent's trilinear map puts them (the parents' nodes where they were).
    let nodes: Vec<Vector3<f64>> = registry
        .keys
        .iter()
        .map(|key| place(key, &parent.nodes, n3))
        .collect();

    // Attachments.
    let node_bone: Vec<Option<usize>> = registry
        .keys
        .iter()
        .map(|key| {
            let parents: Vec<usize> = terms(key).map(|(p, _)| p).collect();
            // The parent node of the largest weight, the first of equals (the bones of one group
            // move alike; this only names the one that feels the force).
            let nearest = terms(key)
                .fold(None, |best: Option<(usize, u32)>, (p, w)| match best {
                    Some((_, bw)) if bw >= w => best,
                    _ => Some((p, w)),
                })
                .map(|(p, _)| p)?;
            let held = match parents.len() {
                1 => return flesh.node_bone[parents[0]],
                2 => held_edges.contains(&(parents[0], parents[1])),
                _ => same_group(&mut parents.iter().copied()),
            };
            if held {
                flesh.node_bone[nearest]
            } else {
                None
            }
        })
        .collect();

    // Skin quadrilaterals: the children's faces along each parent one.
    let face_of =
        |c: usize, q: &[usize; 4]| (0..6).find(|&f| HEX_FACES[f].map(|l| parent.cells[c][l]) == *q);
    let mut skin_quads = Vec::new();
    let mut skin_cells = Vec::new();
    let mut skin_outer = Vec::new();
    for ((q, &c), &outer) in flesh
        .skin_quads
        .iter()
        .zip(&flesh.skin_cells)
        .zip(&flesh.skin_outer)
    {
        let f = face_of(c, q).expect("a skin quadrilateral is a face of its cell");
        for offset in along_face(f, n) {
            let fc = child(c, offset);
            skin_quads.push(HEX_FACES[f].map(|l| cells[fc][l]));
            skin_cells.push(fc);
            skin_outer.push(outer);
        }
    }

    // The display skin's control net, split bilinearly, each quadrilateral tied to its parent's
    // cell by that cell's first child (the skins are embedded through the parent:
    // `embed::embed_split`).
    let n2 = (n * n) as u32;
    let mut vertices = Registry::new();
    let mut display_quads = Vec::new();
    let mut display_cells = Vec::new();
    for (q, &host) in flesh.display_quads.iter().zip(&flesh.display_cells) {
        let m = n as u32;
        let mut at = |s: u32, t: u32| {
            vertices.id(key_of(
                [
                    (q[0], (m - s) * (m - t)),
                    (q[1], s * (m - t)),
                    (q[2], s * t),
                    (q[3], (m - s) * t),
                ]
                .into_iter(),
            ))
        };
        for t in 0..m {
            for s in 0..m {
                display_quads.push([at(s, t), at(s + 1, t), at(s + 1, t + 1), at(s, t + 1)]);
                display_cells.push(child(host, [0, 0, 0]));
            }
        }
    }
    let display_vertices = vertices
        .keys
        .iter()
        .map(|key| place(key, &flesh.display_vertices, n2))
        .collect();

    FleshMesh {
        mesh: Mesh { nodes, cells },
        node_bone,
        cell_digit,
        skin_quads,
        skin_cells,
        skin_outer,
        display_quads,
        display_vertices,
        display_cells,
        spacing: flesh.spacing / n as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::hex8::{cell_volume, scaled_jacobian};
    use crate::hand::{mesh_flesh, Side};
    use crate::mesh::boundary_facets;

    fn volume(mesh: &Mesh) -> f64 {
        mesh.cells
            .iter()
            .map(|c| cell_volume(&c.map(|n| mesh.nodes[n])))
            .sum()
    }

    /// Split in two and in three, the resolution-0.75 hand keeps its hand: n³ cells for one,
    /// n² skin quads for one, the parent nodes where they were and held as they were, every
    /// face of the flesh either skin or held by one bone all over, and the very same volume (the
    /// children fill their parent exactly).
    #[test]
    fn a_split_hand_is_the_lattice_s_hand_with_finer_cells() {
        let skeleton = Skeleton::new(Side::Right);
        let skin = crate::hand::SkinShape::new(Side::Right);
        let parent = mesh_flesh(&skeleton, &skin, 0.75).unwrap();
        let groups = rigid_groups(&skeleton);
        let mut at: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        let key = |p: &Vector3<f64>| [p.x, p.y, p.z].map(|c| (c * 1e9).round() as i64);
        for n in [2, 3] {
            let split = subdivide(parent.clone(), n, &skeleton);
            assert_eq!(split.mesh.cells.len(), n * n * n * parent.mesh.cells.len());
            assert_eq!(split.skin_quads.len(), n * n * parent.skin_quads.len());
            assert_eq!(split.spacing, parent.spacing / n as f64);
            at.clear();
            for (v, p) in split.mesh.nodes.iter().enumerate() {
                at.entry(key(p)).or_default().push(v);
            }
            for (p, x) in parent.mesh.nodes.iter().enumerate() {
                let held_alike = at.get(&key(x)).is_some_and(|vs| {
                    vs.iter()
                        .any(|&v| split.node_bone[v] == parent.node_bone[p])
                });
                assert!(held_alike, "split {n}: parent node {p} at {x:?} lost");
            }
            // The flesh's faces: skin, or a bone's.
            let skin_faces: std::collections::HashSet<[usize; 4]> = split
                .skin_quads
                .iter()
                .map(|q| {
                    let mut q = *q;
                    q.sort_unstable();
                    q
                })
                .collect();
            let facets = boundary_facets(&split.mesh);
            let loose = facets
                .iter()
                .filter(|f| {
                    let mut key = f.nodes;
                    key.sort_unstable();
                    let group = |v: usize| split.node_bone[v].map(|b| groups[b]);
                    !skin_faces.contains(&key)
                        && (group(f.nodes[0]).is_none()
                            || f.nodes.iter().any(|&v| group(v) != group(f.nodes[0])))
                })
                .count();
            assert_eq!(
                loose,
                0,
                "split {n}: {loose} of {} faces of the flesh are neither skin nor held by a bone",
                facets.len()
            );
            for (c, cell) in split.mesh.cells.iter().enumerate() {
                let q = scaled_jacobian(&cell.map(|v| split.mesh.nodes[v]));
                assert!(q > 0.0, "split {n}, cell {c}: scaled Jacobian {q}");
            }
            let (v0, v1) = (volume(&parent.mesh), volume(&split.mesh));
            assert!(
                ((v1 - v0) / v0).abs() < 1e-12,
                "split {n}: volume {v0:.12e} → {v1:.12e} m³"
            );
        }
        // One split gives the mesh back.
        assert_eq!(
            subdivide(parent.clone(), 1, &skeleton).mesh.nodes,
            parent.mesh.nodes
        );
    }

    /// A point the parents share gets one node, whichever cell names it; the weights sum to the
    /// denominator.
    #[test]
    fn a_shared_point_is_one_key() {
        let a = [0, 1, 2, 3, 4, 5, 6, 7];
        // The cell beside it along +ξ shares nodes 1, 2, 6, 5 as its 0, 3, 7, 4.
        let b = [1, 8, 9, 2, 5, 10, 11, 6];
        for n in 2..=4 {
            for j in 0..=n {
                for k in 0..=n {
                    assert_eq!(cell_point(&a, n, [n, j, k]), cell_point(&b, n, [0, j, k]));
                }
            }
            let total: u32 = terms(&cell_point(&a, n, [1, 1, 1])).map(|t| t.1).sum();
            assert_eq!(total, (n * n * n) as u32);
        }
    }
}
