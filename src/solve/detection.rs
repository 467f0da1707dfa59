//! What a contact step sees before it solves: where the skin and the other bodies are, which
//! skin points and object nodes are near each other (the pairs of the contact problem), the
//! skin that went into a body over the step's flexion, and the flesh solved with the contact —
//! or that nothing touches (the frame composed, not solved).

use super::compose::compose;
use super::crossing::crossings;
use super::error::SimError;
use super::untouched::UntouchedStep;
use crate::contact::{
    Bounds, ContactSummary, ContactSurface, Crossing, EmbeddedPoints, SurfaceBvh, SurfacePair,
};
use crate::fem::DofPartition;
use crate::model::Model;
use crate::state::{Frame, HandFrame};
use crate::util::near::NearPoints;
use crate::util::timing::ms;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::ops::Range;
use std::time::Instant;

/// Skin closer than this to an object (m) seeds the flesh region solved with the contact.
const SEED_GAP: f64 = 0.002;

/// Where a contact step goes on from: the displacements the last step left over every dof, and
/// each hand's flexed skin before this step's flexion (see `solve_grasp`, src/solve/grasp.rs).
pub type StepStart<'a> = (Option<&'a [f64]>, Option<&'a [Vec<Vector3<f64>>]>);

/// What the detection found where skin and bodies are near.
pub(super) struct Detected {
    /// Reference positions: the objects at rest, the hands as posed.
    pub x: Vec<Vector3<f64>>,
    /// Where the contact is detected and linearised: the reference moved by what is carried.
    pub x_now_nodes: Vec<Vector3<f64>>,
    /// And the skin's points embedded in the flesh after the nodes.
    pub x_now: Vec<Vector3<f64>>,
    pub embedded: EmbeddedPoints,
    /// Each hand's skin points.
    pub skin_points: Vec<Range<usize>>,
    /// The hands' skins, then the objects' surfaces.
    pub surfaces: Vec<ContactSurface>,
    pub pairs: Vec<SurfacePair>,
    /// Skin points within the search of an object, sorted.
    pub near_skin: Vec<usize>,
    /// Skin that went into a body over this step's flexion.
    pub crossed: Vec<Crossing>,
    /// The objects' free dofs and the flesh near the contact.
    pub partition: DofPartition,
    pub region_cells: usize,
}

/// What a contact step's detection ends with.
pub(super) enum Detection {
    /// No hand near another body.
    Apart,
    /// Near, but nothing touches nor can: the frame composed.
    Untouched(Frame),
    Near(Detected),
}

/// The detection of a contact step of `hands` from `carried` (with the skin `previous` before
/// the step's flexion), `untouched` the static frame where a step that touches nothing may be
/// left unsolved, `step` the bodies' own step from it (src/solve/untouched.rs); `t_all` when
/// the contact step started.
pub(super) fn detect(
    model: &Model,
    hands: &[HandFrame],
    (carried_given, previous): StepStart<'_>,
    (untouched, step): (Option<&Frame>, Option<&UntouchedStep>),
    t_all: Instant,
) -> Result<Detection, SimError> {
    let settings = &model.contact;
    let margin = settings.search_depth;
    let objects: Vec<usize> = (0..model.bodies.len())
        .filter(|&b| model.bodies[b].hand.is_none())
        .collect();
    // Reference positions: the objects at rest, the hands as posed.
    let mut x = model.mesh.nodes.clone();
    for h in hands {
        let body = &model.bodies[h.body];
        x[body.nodes.clone()].copy_from_slice(&h.positions);
    }
    // Where the contact is detected and linearised: the reference moved by what is carried.
    let zero = vec![0.0; 3 * model.mesh.node_count()];
    let carried = carried_given.unwrap_or(&zero);
    let x_now_nodes: Vec<Vector3<f64>> = x
        .iter()
        .enumerate()
        .map(|(n, p)| p + Vector3::new(carried[3 * n], carried[3 * n + 1], carried[3 * n + 2]))
        .collect();
    // The hands' contact surface is their smooth skin (item 4): its vertices, embedded in the
    // flesh cells, are contact points numbered after the mesh's nodes.
    let mut embedded = EmbeddedPoints::none(model.mesh.node_count());
    let mut skin_points: Vec<std::ops::Range<usize>> = Vec::new();
    let mut surfaces: Vec<ContactSurface> = Vec::new();
    let mut skin_quads: Vec<Vec<[usize; 4]>> = Vec::new();
    for h in hands {
        let body = &model.bodies[h.body];
        let hand = body.hand.as_deref().expect("a hand body");
        let skin = &hand.contact_skin;
        let start = embedded.first() + embedded.len();
        for v in 0..skin.vertex_count() {
            embedded.push(skin.terms(v).map(|(n, w)| (n + body.nodes.start, w)));
        }
        skin_points.push(start..start + skin.vertex_count());
        skin_quads.push(
            skin.quads
                .iter()
                .map(|q| q.map(|v| start + v as usize))
                .collect(),
        );
    }
    let x_now = embedded.extend(&x_now_nodes);
    // Each quad split along its diagonal at rest, the same in every step.
    let x_rest = embedded.extend(&model.mesh.nodes);
    for (h, quads) in hands.iter().zip(&skin_quads) {
        surfaces.push(ContactSurface::from_quads_split_at(
            h.body, quads, &x_rest, &x_now,
        ));
    }
    for &b in &objects {
        surfaces.push(ContactSurface::from_quads_split_at(
            b,
            &model.bodies[b].exterior,
            &x_rest,
            &x_now,
        ));
    }
    // Which skin nodes are near which object, and the object nodes near the skin.
    let mut pairs: Vec<SurfacePair> = Vec::new();
    let mut near_skin: Vec<usize> = Vec::new();
    let mut seeds: Vec<usize> = Vec::new();
    // The smallest gap between skin and an object within the search, either way.
    let mut closest = f64::INFINITY;
    // Where the objects' surfaces are: skin facets not within the search of that box hold no
    // object node (the skin's hierarchy is built over the others only).
    let objects_nodes: Vec<Vec<usize>> =
        surfaces[hands.len()..].iter().map(|s| s.nodes()).collect();
    let object_points: Vec<&Vector3<f64>> =
        objects_nodes.iter().flatten().map(|&n| &x_now[n]).collect();
    let objects_box = (!object_points.is_empty()).then(|| Bounds::of(object_points));
    for (i, _) in hands.iter().enumerate() {
        let skin_nodes = surfaces[i].nodes();
        let skin_bvh = match &objects_box {
            Some(b) => surfaces[i].hierarchy_meeting(&x_now, margin, b),
            None => surfaces[i].hierarchy(&x_now, margin),
        };
        for (j, &b) in objects.iter().enumerate() {
            let s = hands.len() + j;
            let object_nodes = objects_nodes[j].clone();
            let object_bvh = surfaces[s].hierarchy(&x_now, margin);
            // (The gap to the nearest facet; where it is in front of that facet's plane but
            // in a pit at its edge or corner, the gap behind the facet around it — looked
            // for only where a step that touches nothing may be left unsolved.)
            let signed = |bvh: &SurfaceBvh, x: &Vector3<f64>| {
                bvh.project(x, &x_now, None, |_| false).map(|p| {
                    let behind = (untouched.is_some() && p.gap >= 0.0)
                        .then(|| bvh.behind_feature(x, &x_now, &p, |_| false))
                        .flatten();
                    (p.gap, behind.map_or(p.gap, |b| b.gap.min(p.gap)))
                })
            };
            // (Point by point, on every thread: a drag's first frame waits for it.)
            let found: Vec<(usize, f64, f64)> = skin_nodes
                .par_iter()
                .filter_map(|&n| {
                    signed(&object_bvh, &x_now[n]).map(|(gap, inside)| (n, gap, inside))
                })
                .collect();
            closest = found.iter().fold(closest, |c, g| c.min(g.2));
            let skin_near: Vec<usize> =
                found.iter().filter(|g| g.1 < margin).map(|g| g.0).collect();
            // The flesh solved with the contact grows from the skin that touches (or nearly).
            seeds.extend(found.iter().filter(|g| g.1 < SEED_GAP).map(|g| g.0));
            let object_found: Vec<(usize, f64, f64)> = object_nodes
                .par_iter()
                .filter_map(|&n| signed(&skin_bvh, &x_now[n]).map(|(gap, inside)| (n, gap, inside)))
                .collect();
            closest = object_found.iter().fold(closest, |c, g| c.min(g.2));
            let object_near: Vec<usize> = object_found
                .iter()
                .filter(|g| g.1 < margin)
                .map(|g| g.0)
                .collect();
            if skin_near.is_empty() && object_near.is_empty() {
                continue;
            }
            debug_assert_eq!(surfaces[s].body, b);
            near_skin.extend(&skin_near);
            // The paper's direction first: object nodes repelled from the skin.
            pairs.push(SurfacePair {
                slaves: object_nodes,
                surface: i,
                primary: true,
                slave_surface: Some(s),
                own: None,
            });
            pairs.push(SurfacePair {
                slaves: skin_near,
                surface: s,
                primary: false,
                slave_surface: Some(i),
                own: None,
            });
        }
    }
    if pairs.is_empty() {
        return Ok(Detection::Apart);
    }
    near_skin.sort_unstable();
    near_skin.dedup();
    // Skin that went into a body over this step's flexion: held where it went through.
    let crossed = match previous {
        Some(previous) => {
            let mut from = x_now_nodes.clone();
            for (h, before) in hands.iter().zip(previous) {
                let start = model.bodies[h.body].nodes.start;
                for (i, p) in before.iter().enumerate() {
                    let n = start + i;
                    from[n] =
                        p + Vector3::new(carried[3 * n], carried[3 * n + 1], carried[3 * n + 2]);
                }
            }
            let from = embedded.extend(&from);
            crossings(
                &surfaces,
                hands.len(),
                &near_skin,
                (&from, &x_now),
                settings.tolerance,
                settings.search_depth,
            )
        }
        None => Vec::new(),
    };
    // Nothing touches, nor can the bodies' loads bring them into touch (every gap wider than
    // the farthest they move an object's node from where detection sees it): a contact frame
    // without contacts. From rest, the bodies move to the static frame; from the static frame,
    // by the step they take there alone (src/solve/untouched.rs) where it is known, else they
    // are taken to stay in it (bounded by their motion from rest).
    let step = carried_given.and(step);
    if let Some(still) = untouched {
        let reach = step.map_or_else(|| objects_moved(model, still), |s| s.motion);
        if crossed.is_empty() && closest > reach + settings.tolerance {
            let mut frame = compose(model, still, hands.to_vec())?;
            if let Some(step) = step {
                super::untouched::apply(model, step, &mut frame);
            }
            let skin_points = hands
                .iter()
                .zip(&skin_points)
                .map(|(h, r)| (h.body, r.start))
                .collect();
            frame.contact = Some(ContactSummary::without_contacts(
                settings.method,
                skin_points,
                ms(t_all),
            ));
            return Ok(Detection::Untouched(frame));
        }
    }

    // The flesh solved with the contact: cells within `contact_region` of a near skin node,
    // of digits solved by FEM; free nodes are those of such cells only, not on a bone.
    let radius = model.contact_region;
    let mut free_node = vec![false; model.mesh.node_count()];
    let mut region_cells = 0;
    for (h, points) in hands.iter().zip(&skin_points) {
        let body = &model.bodies[h.body];
        let hand = body.hand.as_deref().expect("a hand body");
        let flesh = &hand.flesh;
        let near: Vec<Vector3<f64>> = seeds
            .iter()
            .filter(|&&n| points.contains(&n))
            .map(|&n| x_now[n])
            .collect();
        if near.is_empty() {
            continue;
        }
        let near = NearPoints::new(&near, radius);
        // (Cell by cell on every thread, then counted in order.)
        let within: Vec<bool> = (0..flesh.mesh.cells.len())
            .into_par_iter()
            .map(|c| {
                let cell = &flesh.mesh.cells[c];
                let method = model.flexion.methods[flesh.cell_digit[c].map_or(0, |d| d + 1)];
                method == crate::model::FleshMethod::Fem
                    && near.any_within(
                        &(cell.iter().map(|&n| h.positions[n]).sum::<Vector3<f64>>() / 8.0),
                    )
            })
            .collect();
        let mut in_region = vec![0usize; flesh.mesh.nodes.len()];
        let mut incident = vec![0usize; flesh.mesh.nodes.len()];
        for (cell, &inside) in flesh.mesh.cells.iter().zip(&within) {
            for &n in cell {
                incident[n] += 1;
            }
            if inside {
                region_cells += 1;
                for &n in cell {
                    in_region[n] += 1;
                }
            }
        }
        for n in 0..flesh.mesh.nodes.len() {
            if in_region[n] > 0 && in_region[n] == incident[n] && flesh.node_bone[n].is_none() {
                free_node[body.nodes.start + n] = true;
            }
        }
    }
    let mut mask = model.partition.prescribed.clone();
    for (n, &f) in free_node.iter().enumerate() {
        if f {
            for a in 0..3 {
                mask[3 * n + a] = false;
            }
        }
    }
    let partition = DofPartition::new(mask);

    Ok(Detection::Near(Detected {
        x,
        x_now_nodes,
        x_now,
        embedded,
        skin_points,
        surfaces,
        pairs,
        near_skin,
        crossed,
        partition,
        region_cells,
    }))
}

/// The farthest any node of a body other than the hands is moved in the static frame `still`, m.
fn objects_moved(model: &Model, still: &Frame) -> f64 {
    let u = &still.solution.displacement;
    model
        .bodies
        .iter()
        .filter(|b| b.hand.is_none())
        .flat_map(|b| b.nodes.clone())
        .map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]).norm())
        .fold(0.0, f64::max)
}
