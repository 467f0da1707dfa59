//! Modelling only what a scene requires: which digits of a hand (the thumb, each finger) stay
//! far from every body they could touch over a keyframe. Flexion solves their
//! flesh by FEM only when they come within `near_contact` of another body
//! (`FlexionSettings::near_contact`); farther, their flesh follows the bones by skinning
//! (`Flexion::set_far_parts`), and the FEM effort goes where contact is.
//!
//! A part is near when, at any increment of the keyframe (the joint angles interpolated as
//! flexion interpolates them), a node of its outer skin, moved by skinning, lies within the
//! distance of another body's boundary (at rest, as the contact step takes it) or inside it.
//! A scene without another body has nothing to be near: every part is solved as set.
//!
//! Skinning is only taken where it stays sound: a far part whose skinned flesh would crush a
//! cell (det J at a Gauss point falling below [`CRUSH_RATIO`] of its value now, as at the
//! palmar crease of a deep flexion) is solved by FEM all the same.

use super::insides::Insides;
use crate::contact::{connected_pieces, ContactSurface, WindingTree};
use crate::fem::hex8::relative_min_jacobian;
use crate::model::FleshMethod;
use crate::model::Model;
use crate::state::HandState;
use nalgebra::Vector3;

/// A far part is skinned only if no cell's smallest det J at a Gauss point falls below this
/// fraction of its value at the start of the keyframe.
pub const CRUSH_RATIO: f64 = 0.2;

/// Parts of a hand: 0 the palm, 1 the thumb … 5 the little finger (`cell_digit` + 1).
pub const PARTS: usize = 6;

/// For hand body `body` moving from `state` to the joint angles `target` (degrees): which
/// parts stay farther than `distance` (m) from every other body of the model over the
/// keyframe. All `false` when the model has no other body.
pub fn far_parts(
    model: &Model,
    body: usize,
    state: &HandState,
    target: &[f64],
    distance: f64,
) -> [bool; PARTS] {
    let objects: Vec<usize> = (0..model.bodies.len())
        .filter(|&b| model.bodies[b].hand.is_none())
        .collect();
    if objects.is_empty() {
        return [false; PARTS];
    }
    let hand = model.bodies[body]
        .hand
        .as_deref()
        .expect("far_parts of a hand body");
    let flesh = &hand.flesh;
    let rest = &model.mesh.nodes;
    let surfaces: Vec<ContactSurface> = objects
        .iter()
        .map(|&b| ContactSurface::from_quads(b, &model.bodies[b].exterior, rest))
        .collect();
    let pieces: Vec<Vec<WindingTree>> = surfaces
        .iter()
        .map(|s| {
            connected_pieces(&s.triangles)
                .iter()
                .map(|piece| WindingTree::new(piece, rest))
                .collect()
        })
        .collect();
    let hierarchies: Vec<_> = surfaces
        .iter()
        .map(|s| s.hierarchy(rest, distance))
        .collect();
    let boxes: Vec<(Vector3<f64>, Vector3<f64>)> = objects
        .iter()
        .map(|&b| {
            model.bodies[b].nodes.clone().fold(
                (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
                |(lo, hi), n| (lo.inf(&rest[n]), hi.sup(&rest[n])),
            )
        })
        .collect();
    let within = |x: &Vector3<f64>, j: usize, margin: f64| {
        let (lo, hi) = boxes[j];
        let m = Vector3::repeat(margin);
        (x - (lo - m)).min() >= 0.0 && ((hi + m) - x).min() >= 0.0
    };
    // Within `distance` of a body's surface.
    let close = |x: &Vector3<f64>| {
        (0..objects.len()).any(|j| {
            within(x, j, distance)
                && hierarchies[j]
                    .project(x, rest, None, |_| false)
                    .is_some_and(|p| p.gap < distance)
        })
    };
    // Inside a body (in a closed piece of its surface: a shell's cavity too, behind its
    // wall), by winding numbers.
    let inside = |x: &Vector3<f64>| {
        (0..objects.len())
            .any(|j| within(x, j, 0.0) && pieces[j].iter().any(|piece| piece.inside(x)))
    };

    // The outer skin quads, each with its part, and their nodes.
    let quads: Vec<([usize; 4], usize)> = flesh
        .skin_quads
        .iter()
        .zip(&flesh.skin_cells)
        .zip(&flesh.skin_outer)
        .filter(|(_, &outer)| outer)
        .map(|((q, &c), _)| (*q, flesh.cell_digit[c].map_or(0, |d| d + 1)))
        .collect();
    let mut skin: Vec<usize> = quads.iter().flat_map(|(q, _)| *q).collect();
    skin.sort_unstable();
    skin.dedup();

    // The sweep: the joint angles interpolated as flexion interpolates them, sampled so that
    // no skin node moves more than half the distance between samples (a fingertip cannot
    // jump over a thin shell and its margins). The skin moves along arcs, whose chords the
    // end-to-end displacement bounds from below; over 90° an arc is 1.11× its chord.
    let skin_at = |f: f64, out: &mut Vec<Vector3<f64>>| {
        let angles = angles_between(&state.angles, target, f);
        let motion = state.motion_to(&hand.skeleton.transforms(&angles));
        hand.weights.apply(
            model.flexion.blend,
            &motion,
            &state.positions,
            skin.iter().copied(),
            out,
        );
    };
    let mut moved = state.positions.clone();
    skin_at(1.0, &mut moved);
    let travel = skin
        .iter()
        .map(|&n| (moved[n] - state.positions[n]).norm())
        .fold(0.0, f64::max);
    let steps = ((2.5 * travel / distance).ceil() as usize).clamp(1, 1000);
    // A node is inside or outside a body for as long as it does not come within `distance`
    // of its surface, which the sampling cannot step over: the (costly) inside test is needed
    // at the start only. Nodes whose parts are all near already are not tested again.
    let mut node_parts = vec![0u8; flesh.mesh.nodes.len()];
    for (q, part) in &quads {
        for &n in q {
            node_parts[n] |= 1 << part;
        }
    }
    // The palm holds every finger's MCP joint: its flesh next to a finger near contact
    // belongs to that finger's joint, so the palm is always solved as set.
    let mut near: u8 = 1;
    for i in 0..=steps {
        skin_at(i as f64 / steps as f64, &mut moved);
        for &n in &skin {
            if node_parts[n] & !near == 0 {
                continue;
            }
            let x = &moved[n];
            if close(x) || (i == 0 && inside(x)) {
                near |= node_parts[n];
            }
        }
        if near == (1 << PARTS) - 1 {
            break;
        }
    }
    let mut far = [false; PARTS];
    for (p, f) in far.iter_mut().enumerate() {
        *f = near & (1 << p) == 0;
    }
    if far.iter().any(|&f| f) {
        let crushed = crushed_by_skinning(model, hand, state, target);
        for (f, c) in far.iter_mut().zip(crushed) {
            *f &= !c;
        }
    }
    far
}

/// Which parts skinning alone would crush on the way from `state` to `target`: a cell of the
/// part solved by FEM (as `[solver] flesh` says) whose smallest det J at a Gauss point falls
/// below [`CRUSH_RATIO`] of its value in `state`.
pub(super) fn crushed_by_skinning(
    model: &Model,
    hand: &crate::hand::HandModel,
    state: &HandState,
    target: &[f64],
) -> [bool; PARTS] {
    let flesh = &hand.flesh;
    let skinned = skinned_to(model, hand, state, target, 0..flesh.mesh.nodes.len());
    let mut crushed = [false; PARTS];
    for (c, cell) in flesh.mesh.cells.iter().enumerate() {
        let part = flesh.cell_digit[c].map_or(0, |d| d + 1);
        if crushed[part] || model.flexion.methods[part] != FleshMethod::Fem {
            continue;
        }
        let now = relative_min_jacobian(&cell.map(|n| state.positions[n]));
        let then = relative_min_jacobian(&cell.map(|n| skinned[n]));
        if then < CRUSH_RATIO * now {
            crushed[part] = true;
        }
    }
    crushed
}

/// Whether the skin of hand body `body` (its contact skin, the smooth skin), moved by skinning
/// from `state` to the joint angles `target`, lies deeper than `depth` (m) inside another body
/// (by winding numbers): what a keyframe solved in one step would have to resolve at once. The
/// bodies and the flesh are where `carried` (the displacements the last contact step left, over
/// every dof: the other bodies' from rest, the flesh's over its flexed pose) puts them, so that a
/// small motion on from a grasp is measured by what it adds, not by how deep the grasp's pose
/// already is in the bodies at rest; at rest without it.
pub fn posed_deeper_than(
    model: &Model,
    body: usize,
    state: &HandState,
    target: &[f64],
    depth: f64,
    carried: Option<&[f64]>,
) -> bool {
    SkinProbe::new(model, body, state, carried).deeper_than(target, depth)
}

/// Whether the skin of hand body `body`, moved by skinning from `state` towards the joint
/// angles `target` along the keyframe (the angles interpolated linearly), lies deeper than
/// `depth` (m) inside another body at its end or at one of the `samples − 1` poses evenly
/// between (the bodies and the flesh where `carried` puts them, as [`posed_deeper_than`]): a
/// keyframe whose skin goes through a body on the way, whatever its end. Sampled as the contact
/// steps along a motion are (one sample a step), so that a finger swung through a ball and out
/// of it within one keyframe is not taken for a motion that touches nothing. The end is looked
/// at first; the bodies' surfaces are made once for all the poses.
pub fn deeper_on_the_way(
    model: &Model,
    body: usize,
    state: &HandState,
    target: &[f64],
    (depth, samples): (f64, usize),
    carried: Option<&[f64]>,
) -> bool {
    let probe = SkinProbe::new(model, body, state, carried);
    probe.deeper_than(target, depth)
        || (1..samples).any(|k| {
            let f = k as f64 / samples as f64;
            probe.deeper_than(&angles_between(&state.angles, target, f), depth)
        })
}

/// The joint angles a fraction `f` of the way from `from` to `to` (interpolated linearly, as
/// flexion interpolates a keyframe's).
fn angles_between(from: &[f64], to: &[f64], f: f64) -> Vec<f64> {
    from.iter().zip(to).map(|(a, b)| a + f * (b - a)).collect()
}

/// A hand's contact skin moved by skinning, asked how deep it lies in the other bodies: the
/// bodies' closed surfaces made once (they do not move while the hand's pose is varied).
struct SkinProbe<'a> {
    model: &'a Model,
    body: usize,
    state: &'a HandState,
    carried: Option<&'a [f64]>,
    /// The contact skin's points' terms' flesh nodes (hand-local), sorted.
    nodes: Vec<usize>,
    /// The model's nodes where `carried` puts them.
    positions: Vec<Vector3<f64>>,
    insides: Insides,
}

impl<'a> SkinProbe<'a> {
    fn new(
        model: &'a Model,
        body: usize,
        state: &'a HandState,
        carried: Option<&'a [f64]>,
    ) -> SkinProbe<'a> {
        let hand = model.bodies[body]
            .hand
            .as_deref()
            .expect("a skin probe of a hand body");
        let skin = &hand.contact_skin;
        let mut nodes: Vec<usize> = (0..skin.vertex_count())
            .flat_map(|v| skin.terms(v).map(|t| t.0))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        let mut positions = model.mesh.nodes.clone();
        if let Some(u) = carried {
            for (n, p) in positions.iter_mut().enumerate() {
                *p += Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
            }
        }
        let objects: Vec<ContactSurface> = (0..model.bodies.len())
            .filter(|&o| model.bodies[o].hand.is_none())
            .map(|o| {
                ContactSurface::from_quads_split_at(
                    o,
                    &model.bodies[o].exterior,
                    &model.mesh.nodes,
                    &positions,
                )
            })
            .collect();
        let insides = Insides::new(&objects, &positions);
        SkinProbe {
            model,
            body,
            state,
            carried,
            nodes,
            positions,
            insides,
        }
    }

    /// Whether the skin moved by skinning to the joint angles `target` lies deeper than `depth`
    /// inside another body.
    fn deeper_than(&self, target: &[f64], depth: f64) -> bool {
        let b = &self.model.bodies[self.body];
        let hand = b.hand.as_deref().expect("a hand body");
        let skin = &hand.contact_skin;
        let mut moved = skinned_to(
            self.model,
            hand,
            self.state,
            target,
            self.nodes.iter().copied(),
        );
        if let Some(u) = self.carried {
            for (i, p) in moved.iter_mut().enumerate() {
                let n = b.nodes.start + i;
                *p += Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
            }
        }
        // The skin's points numbered after the model's nodes.
        let mut positions = self.positions.clone();
        positions.extend(skin.positions(&moved));
        let points: Vec<usize> = (self.model.mesh.node_count()..positions.len()).collect();
        self.insides.deepest(&points, &positions, depth).is_some()
    }
}

/// The flesh of `hand` in `state` with the nodes `nodes` moved by skinning to the joint angles
/// `target` (the others where `state` has them).
fn skinned_to(
    model: &Model,
    hand: &crate::hand::HandModel,
    state: &HandState,
    target: &[f64],
    nodes: impl Iterator<Item = usize>,
) -> Vec<Vector3<f64>> {
    let motion = state.motion_to(&hand.skeleton.transforms(target));
    let mut moved = state.positions.clone();
    hand.weights.apply(
        model.flexion.blend,
        &motion,
        &state.positions,
        nodes,
        &mut moved,
    );
    moved
}
