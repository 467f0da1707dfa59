//! Where a hand's skin has gone into its own flesh: the contact skin's vertices inside the
//! closed skin (`contact::vertices_inside_itself`, by winding number). Without self-contact
//! nothing keeps the skin out of itself — a fist's fingers pass into each other and into the
//! palm, a crease's two sides through each other — and the bones' reactions then miss that
//! contact; the report counts it per part so the animator sees where.

use crate::contact::vertices_inside_itself;
use crate::hand::HandModel;
use nalgebra::Vector3;

/// How far outside its own side a skin vertex is looked at, m: far below the flesh's
/// millimetres, far above rounding.
const OFF_SIDE: f64 = 5e-5;

/// Skin vertices this near each other at rest are one point of the skin, split where the
/// lattice splits a node between two digits, m.
const SAME: f64 = 1e-6;

/// The contact skin's vertices of `hand` inside its flesh with the flesh's nodes at `nodes`,
/// sorted.
pub fn skin_inside_flesh(hand: &HandModel, nodes: &[Vector3<f64>]) -> Vec<usize> {
    let skin = &hand.contact_skin;
    let rest = skin.positions(&hand.flesh.mesh.nodes);
    let positions = skin.positions(nodes);
    let triangles: Vec<[usize; 3]> = skin
        .triangles()
        .into_iter()
        .map(|t| t.map(|v| v as usize))
        .collect();
    let mut inside = vertices_inside_itself(&triangles, &positions, &seams(&rest), OFF_SIDE);
    inside.sort_unstable();
    inside
}

/// For each vertex, the first vertex coinciding with it at `rest` (itself if none).
fn seams(rest: &[Vector3<f64>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..rest.len()).collect();
    order.sort_by(|&a, &b| rest[a].x.total_cmp(&rest[b].x).then(a.cmp(&b)));
    let mut joined: Vec<usize> = (0..rest.len()).collect();
    for (i, &a) in order.iter().enumerate() {
        if joined[a] != a {
            continue;
        }
        for &b in &order[i + 1..] {
            if rest[b].x - rest[a].x > SAME {
                break;
            }
            if (rest[a] - rest[b]).norm() < SAME {
                joined[b] = a;
            }
        }
    }
    joined
}

/// Skin this near, along the skin, to skin inside the flesh at rest is where the skins of
/// neighbouring digits meet (the webs), m: two base lattice spacings, the self-contact's
/// neighbourhood. Measured on the shipped scenes: within 3.2 mm of them, 14–45 vertices of a
/// grasp entered the flesh at the webs as the fingers moved; within 6.4 mm, 0–10 besides the
/// thumb's web and the fingers pressed together (docs/hand.md).
const WEB: f64 = 2.0 * crate::hand::BASE_SPACING;

/// Where the skins of `hand`'s neighbouring digits meet at rest: its contact-skin vertices
/// inside the flesh at rest, and those within [`WEB`] of one along the skin — a flag per
/// vertex. A frame's skin overlap leaves them out.
pub fn skin_met_at_rest(hand: &HandModel) -> Vec<bool> {
    along_skin_within(hand, &skin_inside_flesh(hand, &hand.flesh.mesh.nodes), WEB)
}

/// The contact skin's vertices of `hand` within `radius` along the skin (over its edges,
/// coinciding vertices joined) of one in `sources`: a flag per vertex.
fn along_skin_within(hand: &HandModel, sources: &[usize], radius: f64) -> Vec<bool> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let skin = &hand.contact_skin;
    let rest = skin.positions(&hand.flesh.mesh.nodes);
    let joined = seams(&rest);
    let mut edges: Vec<Vec<(usize, f64)>> = vec![Vec::new(); rest.len()];
    for t in skin.triangles() {
        for i in 0..3 {
            let (a, b) = (joined[t[i] as usize], joined[t[(i + 1) % 3] as usize]);
            let length = (rest[a] - rest[b]).norm();
            edges[a].push((b, length));
            edges[b].push((a, length));
        }
    }
    // Lengths as integer nanometres, for the heap's order.
    let key = |d: f64| Reverse((d * 1e9) as u64);
    let mut best = vec![f64::INFINITY; rest.len()];
    let mut heap = BinaryHeap::new();
    for &s in sources {
        best[joined[s]] = 0.0;
        heap.push((key(0.0), joined[s]));
    }
    while let Some((Reverse(d), n)) = heap.pop() {
        let d = d as f64 * 1e-9;
        if d > best[n] + 1e-12 {
            continue;
        }
        for &(m, length) in &edges[n] {
            let e = d + length;
            if e < radius && e < best[m] {
                best[m] = e;
                heap.push((key(e), m));
            }
        }
    }
    (0..rest.len()).map(|v| best[joined[v]] < radius).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coinciding_vertices_are_joined_to_the_first() {
        let p = |x: f64, y: f64| Vector3::new(x, y, 0.0);
        let rest = vec![
            p(1.0, 0.0),
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 5e-7),
            p(2.0, 0.0),
        ];
        assert_eq!(seams(&rest), vec![0, 1, 0, 0, 4]);
    }
}
