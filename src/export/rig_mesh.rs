//! The skin mesh of a rigged hand export: the display (or contact) skin at rest as triangles,
//! optionally opened at the wrist cut as an animator's hand mesh is, with vertex normals and up
//! to four joint weights per vertex.

use crate::hand::anatomy::PALM;
use crate::hand::{DisplaySkin, HandModel};
use nalgebra::Vector3;
use std::collections::HashMap;

/// Distance from the wrist plane within which a vertex lies on the wrist cut, m: round-off (the
/// cut's vertices are on the plane, projected onto the skin's shape). A wider band (0.3 mm)
/// takes in triangles of the rounded rim at some resolutions (0.75) and leaves the boundary
/// pinched, not one loop.
pub const WRIST_TOLERANCE: f64 = 1e-6;

/// Which of the hand's skins is exported.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RigSkin {
    /// The smooth display skin (≈100 000 vertices at resolution 1).
    #[default]
    Display,
    /// The contact skin: the same skin at the flesh lattice's resolution (a small file).
    Contact,
}

/// What a rigged hand export holds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RigOptions {
    /// Leave out the flat wrist cut, leaving one open boundary loop at the wrist.
    pub open_wrist: bool,
    /// The skin exported.
    pub skin: RigSkin,
}

/// The skin as exported, in the hand frame (Z-up, m).
#[derive(Clone, Debug)]
pub struct RigMesh {
    /// The skin vertex each exported vertex is (the unused vertices of an open wrist dropped).
    pub vertices: Vec<usize>,
    /// Rest positions, m.
    pub positions: Vec<Vector3<f64>>,
    /// Unit normals (area-weighted over the exported triangles).
    pub normals: Vec<Vector3<f64>>,
    /// Triangles (outward), exported vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Four joints per vertex (by their index among the rig's joints) and their weights, largest
    /// first, summing to one; unused entries are joint 0 with weight 0.
    pub joints: Vec<[(u8, f64); 4]>,
}

/// The skin of `hand` chosen by `options`.
pub fn chosen_skin<'a>(hand: &'a HandModel, options: &RigOptions) -> &'a DisplaySkin {
    match options.skin {
        RigSkin::Display => &hand.skin,
        RigSkin::Contact => &hand.contact_skin,
    }
}

/// Whether each of `triangles` belongs to the flat wrist cut: the largest piece (by area) of
/// triangles joined by their edges whose three vertices lie within [`WRIST_TOLERANCE`] of the
/// plane x = `PALM.wrist_x`, if it faces −x. Pieces apart from it are folds of the rounded rim
/// onto the plane (three triangles at resolution 0.75 near the thumb's side), not the cut:
/// taken out, each would leave a hole of its own. The cut itself may hold folded slivers facing
/// +x (0.002 mm² at most at 0.75); they go with it.
pub fn wrist_cut(positions: &[Vector3<f64>], triangles: &[[u32; 3]]) -> Vec<bool> {
    let on_plane: Vec<bool> = triangles
        .iter()
        .map(|t| {
            t.iter()
                .all(|&v| (positions[v as usize].x - PALM.wrist_x).abs() <= WRIST_TOLERANCE)
        })
        .collect();
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (k, t) in triangles.iter().enumerate().filter(|(k, _)| on_plane[*k]) {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(k);
        }
    }
    let normal = |k: usize| {
        let p = triangles[k].map(|v| positions[v as usize]);
        (p[1] - p[0]).cross(&(p[2] - p[0]))
    };
    // The pieces, by a flood over shared edges; the largest kept.
    let mut piece = vec![usize::MAX; triangles.len()];
    let mut best: Option<(f64, usize, f64)> = None; // (area, piece, Σ normal·x)
    for seed in (0..triangles.len()).filter(|&k| on_plane[k]) {
        if piece[seed] != usize::MAX {
            continue;
        }
        let (mut area, mut facing) = (0.0, 0.0);
        let mut stack = vec![seed];
        piece[seed] = seed;
        while let Some(k) = stack.pop() {
            let n = normal(k);
            area += n.norm() / 2.0;
            facing += n.x;
            let t = triangles[k];
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                for &other in &by_edge[&(a.min(b), a.max(b))] {
                    if piece[other] == usize::MAX {
                        piece[other] = seed;
                        stack.push(other);
                    }
                }
            }
        }
        if best.is_none_or(|b| area > b.0) {
            best = Some((area, seed, facing));
        }
    }
    let cut = best.filter(|b| b.2 < 0.0).map(|b| b.1);
    piece.iter().map(|&p| Some(p) == cut).collect()
}

/// The skin of `hand` at rest as `options` ask, each vertex weighted to the joints: bone `b`
/// moves joint `bone_joint[b]`. A display vertex's weights are the flesh nodes' skinning weights
/// combined through its embedding terms (negative sums dropped), the four largest kept and
/// normalised.
pub fn rig_mesh(hand: &HandModel, options: &RigOptions, bone_joint: &[usize]) -> RigMesh {
    let skin = chosen_skin(hand, options);
    let all = skin.positions(&hand.flesh.mesh.nodes);
    let mut triangles = skin.triangles();
    if options.open_wrist {
        let cut = wrist_cut(&all, &triangles);
        let mut k = 0;
        triangles.retain(|_| {
            k += 1;
            !cut[k - 1]
        });
    }
    // The vertices the triangles use, numbered in the skin's order.
    let mut local = vec![u32::MAX; all.len()];
    for &v in triangles.iter().flatten() {
        local[v as usize] = 0;
    }
    let vertices: Vec<usize> = (0..all.len()).filter(|&v| local[v] == 0).collect();
    for (i, &v) in vertices.iter().enumerate() {
        local[v] = i as u32;
    }
    let triangles: Vec<[u32; 3]> = triangles
        .iter()
        .map(|t| t.map(|v| local[v as usize]))
        .collect();
    let positions: Vec<Vector3<f64>> = vertices.iter().map(|&v| all[v]).collect();
    let normals = vertex_normals(&positions, &triangles);
    let joint_count = bone_joint.iter().max().map_or(0, |m| m + 1);
    let joints = vertices
        .iter()
        .map(|&v| {
            let mut sum = vec![0.0; joint_count];
            for (node, c) in skin.terms(v) {
                for &(bone, w) in &hand.weights.weights[node] {
                    sum[bone_joint[bone]] += c * w;
                }
            }
            largest_four(&sum)
        })
        .collect();
    RigMesh {
        vertices,
        positions,
        normals,
        triangles,
        joints,
    }
}

/// A joint's share of a vertex below which it is dropped (as the flesh nodes' skinning weights
/// drop theirs): no joint is listed with a weight f32 rounds to zero.
const LEAST_WEIGHT: f64 = 1e-4;

/// Twice the area below which a vertex's triangles give it no normal, m²: the skin has
/// zero-area triangles where lattice nodes split between digits meet at one skin point.
const LEAST_NORMAL: f64 = 1e-12;

/// Unit vertex normals, area-weighted over `triangles`; a vertex whose triangles all have
/// (nearly) zero area takes its neighbours' normals (over the triangles' edges, as far as
/// needed).
fn vertex_normals(positions: &[Vector3<f64>], triangles: &[[u32; 3]]) -> Vec<Vector3<f64>> {
    let mut sums = vec![Vector3::zeros(); positions.len()];
    for t in triangles {
        let p = t.map(|v| positions[v as usize]);
        let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
        for &v in t {
            sums[v as usize] += n;
        }
    }
    let mut normals: Vec<Option<Vector3<f64>>> = sums
        .iter()
        .map(|n| (n.norm() > LEAST_NORMAL).then(|| n.normalize()))
        .collect();
    loop {
        let mut borrowed = vec![Vector3::zeros(); positions.len()];
        for t in triangles {
            for &v in t.iter().filter(|&&v| normals[v as usize].is_none()) {
                for &w in t {
                    borrowed[v as usize] += normals[w as usize].unwrap_or_default();
                }
            }
        }
        let mut filled = false;
        for (n, b) in normals.iter_mut().zip(&borrowed) {
            if n.is_none() && b.norm() > 0.5 {
                *n = Some(b.normalize());
                filled = true;
            }
        }
        if !filled {
            break;
        }
    }
    normals
        .into_iter()
        .map(|n| n.unwrap_or_else(Vector3::x))
        .collect()
}

/// The four largest positive of `weights` (joint, weight), largest first, normalised, those
/// under [`LEAST_WEIGHT`] of the four's sum dropped; unused entries (0, 0).
fn largest_four(weights: &[f64]) -> [(u8, f64); 4] {
    let mut order: Vec<usize> = (0..weights.len()).filter(|&j| weights[j] > 0.0).collect();
    order.sort_by(|&a, &b| weights[b].total_cmp(&weights[a]).then(a.cmp(&b)));
    order.truncate(4);
    let total: f64 = order.iter().map(|&j| weights[j]).sum();
    order.retain(|&j| weights[j] >= LEAST_WEIGHT * total);
    let total: f64 = order.iter().map(|&j| weights[j]).sum();
    let mut out = [(0u8, 0.0); 4];
    for (k, &j) in order.iter().enumerate() {
        out[k] = (j as u8, weights[j] / total);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_four_largest_positive_weights_normalised() {
        let w = [0.1, -0.05, 0.5, 0.2, 0.15, 0.1];
        let four = largest_four(&w);
        assert_eq!(four.map(|e| e.0), [2, 3, 4, 0]);
        let total = 0.5 + 0.2 + 0.15 + 0.1;
        assert!((four[0].1 - 0.5 / total).abs() < 1e-15);
        assert!((four[3].1 - 0.1 / total).abs() < 1e-15);
        assert_eq!(
            largest_four(&[0.0, 1.0]),
            [(1, 1.0), (0, 0.0), (0, 0.0), (0, 0.0)]
        );
    }

    #[test]
    fn a_vertex_whose_triangles_have_no_area_takes_its_neighbours_normal() {
        // A fan about vertex 0 in the plane z = 0, and vertex 4 on the edge 1–2 with a
        // zero-area triangle of its own only.
        let p = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(-1.0, -1.0, 0.0),
            Vector3::new(0.5, 0.5, 0.0),
        ];
        let n = vertex_normals(&p, &[[0, 1, 2], [0, 2, 3], [1, 2, 4]]);
        for v in 0..5 {
            assert!((n[v] - Vector3::z()).norm() < 1e-15, "{v}: {}", n[v]);
        }
    }

    #[test]
    fn the_cut_is_the_largest_piece_on_the_wrist_plane_facing_back() {
        let x = PALM.wrist_x;
        let v = |y: f64, z: f64, dx: f64| Vector3::new(x + dx, y, z);
        let p = [
            // A square facing −x (0–3), a triangle apart on the plane (4–6), a point off it.
            v(0.0, 0.0, 0.0),
            v(0.0, 0.01, 1e-7),
            v(0.01, 0.01, 0.0),
            v(0.01, 0.0, 0.0),
            v(0.05, 0.0, 0.0),
            v(0.051, 0.0, 0.0),
            v(0.05, 0.001, 0.0),
            v(0.0, 0.0, 1e-5),
        ];
        // (0, 1, 2): (p1 − p0) × (p2 − p0) = (−1e-4, …), facing −x.
        let triangles = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [0, 3, 7]];
        assert_eq!(wrist_cut(&p, &triangles), [true, true, false, false]);
        // Facing +x, the largest piece is not a wrist cut.
        let turned = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [0, 3, 7]];
        assert_eq!(wrist_cut(&p, &turned), [false; 4]);
    }
}
