//! Self-contact in the flexion increments (issue 16): the hand's smooth skin may not pass through
//! itself — the two sides of a flexion crease, phalanx against phalanx, fingertip against palm,
//! finger against finger.
//!
//! The region's skin points (the contact skin's vertices embedded in its cells) and facets beyond
//! a point's own neighbourhood (`contact::OwnNeighbourhood`) are kept apart by a barrier in the
//! energy each increment lowers (`contact::SelfBarrier`: point–facet and edge–edge pairs) — the
//! nonlinear tier's Newton (`flexion_nonlinear`) and the linear increments' (`flexion_barrier`).
//! The press is internal to the hand: it pushes flesh against flesh, and where it reaches a bone
//! node it goes into its reaction (equation (8)), so the bones feel the fold. Here: the region's
//! skin, the barrier over it, and where a keyframe's skin will meet itself (the region grows
//! there).

use super::region::SubProblem;
use crate::contact::{ContactSettings, ContactSurface, EmbeddedPoints, OwnNeighbourhood};
use crate::hand::{Blend, HandModel, BASE_SPACING};
use nalgebra::{Isometry3, Vector3};
use std::sync::Arc;

/// The skin of a keyframe's FEM region as a contact surface on the region's own nodes.
pub(super) struct OwnSkin {
    /// The skin points kept (every term in the region), over the region's local nodes.
    embedded: EmbeddedPoints,
    /// The contact-skin vertex of each point kept, in the order of their contact indices.
    vertices: Vec<usize>,
    /// Skin quads with all four corners kept, in contact indices.
    quads: Vec<[usize; 4]>,
    /// Which facets each point may not meet.
    own: Arc<OwnNeighbourhood>,
}

/// The neighbourhood radius of the self-contact, m: skin points nearer than this along the skin
/// at rest are kept apart by the flesh between them, not by contact. A length of the hand, not
/// of its mesh (two base lattice spacings, 6.4 mm), so that refining the mesh refines the same
/// contact problem: at two spacings of a resolution-1.5 lattice (4.3 mm) the dorsal skin over
/// the PIP's knuckle met itself at 30° of flexion and crushed a cell.
pub(crate) const NEIGHBOURHOOD: f64 = 2.0 * BASE_SPACING;

/// Skin lying behind a facet at rest by more than this is the same flesh seen from behind, m
/// (one base lattice spacing): skin about in the facet's plane (the other side of a crease,
/// along the finger) may meet it. Read only by the prediction of where the skin will meet
/// itself ([`near_itself`]: skinning from rest, no path to follow); the increments follow each
/// point's path.
const BEHIND: f64 = BASE_SPACING;

impl OwnSkin {
    /// The skin of `sub`'s region of `hand`, or `None` when it has no facet.
    pub(super) fn new(
        hand: &HandModel,
        sub: &SubProblem,
        settings: &ContactSettings,
    ) -> Option<OwnSkin> {
        let skin = &hand.contact_skin;
        let mut local = vec![usize::MAX; hand.flesh.mesh.nodes.len()];
        for (i, &n) in sub.nodes.iter().enumerate() {
            local[n] = i;
        }
        let mut embedded = EmbeddedPoints::none(sub.nodes.len());
        let mut index = vec![usize::MAX; skin.vertex_count()];
        let mut vertices = Vec::new();
        for (v, slot) in index.iter_mut().enumerate() {
            let terms: Vec<(usize, f64)> = skin.terms(v).map(|(n, w)| (local[n], w)).collect();
            if terms.iter().all(|t| t.0 != usize::MAX) {
                *slot = embedded.push(terms);
                vertices.push(v);
            }
        }
        let quads: Vec<[usize; 4]> = skin
            .quads
            .iter()
            .map(|q| q.map(|v| index[v as usize]))
            .filter(|q| q.iter().all(|&i| i != usize::MAX))
            .collect();
        if quads.is_empty() {
            return None;
        }
        let rest = embedded.extend(&sub.mesh.nodes);
        // The same flesh seen from behind: within twice the depth the contact searches (as in
        // `near_itself`).
        let behind = (BEHIND, 2.0 * settings.search_depth);
        let triangles = ContactSurface::from_quads(0, &quads, &rest).triangles;
        // A point held by the step before lies within the penetration limit behind its facet.
        let touching = 2.0 * settings.penetration_limit();
        let own = OwnNeighbourhood::new(rest, &triangles, NEIGHBOURHOOD, behind, touching);
        Some(OwnSkin {
            embedded,
            vertices,
            quads,
            own: Arc::new(own),
        })
    }
}

/// The reach d̂ of the barrier that keeps the skin out of itself (`contact::SelfBarrier`), m: skin pressed on skin stops at most this far apart, and skin
/// nearer than this to its own at rest (beyond its neighbourhood) is left free. A length of the
/// hand, not of its mesh. At 0.5 mm (a fifth of the skin's facets at resolution 1) the crease's
/// edges passed through its facets between vertices held apart (51 triangle pairs crossing,
/// unweighted barrier), at 0.75 mm 14, at 1 mm none.
pub(crate) const BARRIER_REACH: f64 = 1.0e-3;

/// The barrier's stiffness per area of skin where skin is half its reach from skin, as a
/// multiple of the flesh's Young modulus over [`BASE_SPACING`] (the stiffness per area of a
/// lattice cell's layer of that flesh, Pa/m). Softer, the skin comes nearer itself and its
/// edges, which the barrier does not see, pass through facets (index PIP 110°, nonlinear tier,
/// resolution 1: 4 triangle pairs of the crease crossing at 2 and 4, none at 8 and 16; the
/// largest bone reaction 2.86, 2.90, 2.91, 2.92 N).
const BARRIER_STIFFNESS: f64 = 8.0;

/// κ of the barrier (N/m⁵: its energy is κ·A·b, A a point's area, b on squared distances) in
/// flesh of Young modulus `young` (Pa): its stiffness per area along the distance d at
/// d = d̂/2, κ·(4d²·b″ + 2b′), is [`BARRIER_STIFFNESS`] · young / [`BASE_SPACING`].
pub(crate) fn barrier_kappa(young: f64) -> f64 {
    let (d, reach2) = (0.5 * BARRIER_REACH, BARRIER_REACH * BARRIER_REACH);
    let (_, b1, b2) = crate::contact::barrier(d * d, reach2);
    let per_kappa = 4.0 * d * d * b2 + 2.0 * b1;
    BARRIER_STIFFNESS * young / BASE_SPACING / per_kappa
}

impl OwnSkin {
    /// The region's skin kept out of itself by a barrier of stiffness `kappa` (N/m⁵), over the
    /// region's nodes at rest (the displacements it takes are from there): every point against
    /// every facet beyond its neighbourhood; pairs within the barrier's reach at rest, or
    /// within a tenth of it at `start` (the keyframe's start: skin a keyframe solved without
    /// the barrier brought onto its own), are left out. (Skin already through its own where a
    /// keyframe starts, farther than that, is held where it is.)
    pub(super) fn barrier(
        &self,
        rest: &[Vector3<f64>],
        kappa: f64,
        start: &[f64],
    ) -> crate::contact::SelfBarrier {
        let positions = self.embedded.extend(rest);
        let triangles = ContactSurface::from_quads(0, &self.quads, &positions).triangles;
        let first = self.embedded.first();
        // Each point's share of the skin's area at rest: a quarter of each quad around it.
        let mut area = vec![0.0; positions.len()];
        for q in &self.quads {
            let [a, b, c, d] = q.map(|v| positions[v]);
            let quad = 0.5 * ((b - a).cross(&(c - a)).norm() + (c - a).cross(&(d - a)).norm());
            for &v in q {
                area[v] += 0.25 * quad;
            }
        }
        let points = (first..first + self.embedded.len())
            .map(|p| (p, area[p]))
            .collect();
        let mut barrier = crate::contact::SelfBarrier::new(
            self.embedded.clone(),
            rest.to_vec(),
            (triangles, points),
            self.own.clone(),
            (BARRIER_REACH, kappa),
            &vec![0.0; 3 * rest.len()],
        );
        barrier.leave_out_within(start, 0.1 * BARRIER_REACH);
        barrier
    }

    /// Sets the barrier's forces at `u` on the region's skin vertices in `press` (N, one per
    /// vertex of the hand's contact skin, `vertices` of them; empty while nothing presses),
    /// leaving the other vertices' as they were (pressed in a keyframe before, outside this
    /// region); returns the pairs held and the points' total force.
    pub(super) fn set_press(
        &self,
        barrier: &crate::contact::SelfBarrier,
        u: &[f64],
        (press, vertices): (&mut Vec<f64>, usize),
    ) -> (usize, f64) {
        let (at, count, total) = barrier.forces(u);
        let first = self.embedded.first();
        let mut out = std::mem::take(press);
        out.resize(vertices, 0.0);
        for &v in &self.vertices {
            out[v] = 0.0;
        }
        for (i, f) in at.into_iter().enumerate().skip(first) {
            out[self.vertices[i - first]] += f;
        }
        if out.iter().any(|&f| f != 0.0) {
            *press = out;
        }
        (count, total)
    }
}

/// Whether the rigid motion `m` leaves everything where it was (to round-off).
pub(super) fn still(m: &Isometry3<f64>) -> bool {
    m.translation.vector.norm() < 1e-12 && m.rotation.angle() < 1e-12
}

/// The bones grouped by their rigid `motion`: each bone's class, bones moving alike (to
/// round-off, [`still`] relative to each other) in the same one, numbered as first met.
pub(super) fn motion_classes(motion: &[Isometry3<f64>]) -> Vec<usize> {
    let mut class = vec![0usize; motion.len()];
    let mut reps: Vec<usize> = Vec::new();
    for b in 0..motion.len() {
        let same = reps
            .iter()
            .position(|&r| still(&(motion[r].inverse() * motion[b])));
        class[b] = same.unwrap_or_else(|| {
            reps.push(b);
            reps.len() - 1
        });
    }
    class
}

/// How near its own skin (m) a skin point must come at a keyframe's end, predicted by
/// skinning, for the local flexion region to grow around it.
const MEETING: f64 = 0.003;

/// Where `hand`'s skin will meet itself over a keyframe: the positions in `now` (the flesh where
/// the keyframe starts) of the skin points, and of the corners of the facets they face, that
/// come within [`MEETING`] of their own skin (the pairs the increments' self-contact, solved
/// with `settings`, would consider) when the flesh follows the bones to `transforms` (rest →
/// the keyframe's end) by skinning from rest — pairs of which some skin moves over the keyframe
/// (`motion`: each bone's from the keyframe's start to its end). The flexion's local region grows
/// around them: the press of skin on skin must fall on flesh the increments solve, not on the
/// region's prescribed edge, where nothing can give. Skin that met itself in a keyframe before
/// and does not move in this one (the fingers of a fist while the thumb folds over them) is left
/// where it is: solved again, its contact would be found afresh from every increment's start and
/// chase itself (the thumb folding over a four-fingers' fist stopped at its third increment on
/// the fingers' creases, the fingers not moving).
pub(super) fn near_itself(
    hand: &HandModel,
    blend: Blend,
    (transforms, motion): (&[Isometry3<f64>], &[Isometry3<f64>]),
    now: &[Vector3<f64>],
    settings: &ContactSettings,
) -> Vec<Vector3<f64>> {
    let bone_moves: Vec<bool> = motion.iter().map(|m| !still(m)).collect();
    let skin_moves = |v: usize| {
        hand.contact_skin
            .terms(v)
            .any(|(n, _)| hand.weights.weights[n].iter().any(|&(b, _)| bone_moves[b]))
    };
    let margin = MEETING.min(settings.search_depth);
    let skin = &hand.contact_skin;
    let rest = &hand.flesh.mesh.nodes;
    let mut predicted = rest.clone();
    hand.weights
        .apply(blend, transforms, rest, 0..rest.len(), &mut predicted);
    let end = skin.positions(&predicted);
    let now = skin.positions(now);
    let quads: Vec<[usize; 4]> = skin.quads.iter().map(|q| q.map(|v| v as usize)).collect();
    let surface = ContactSurface::from_quads(0, &quads, &end);
    let behind = (BEHIND, 2.0 * settings.search_depth);
    let own = OwnNeighbourhood::new(
        skin.positions(rest),
        &surface.triangles,
        NEIGHBOURHOOD,
        behind,
        0.0,
    );
    let normals = surface.reference_normals();
    let bvh = surface.hierarchy(&end, margin);
    let mut out = Vec::new();
    for v in 0..skin.vertex_count() {
        let Some(normal) = normals.get(&v) else {
            continue;
        };
        let skip = |t: &[usize; 3]| {
            let corners = t.map(|c| end[c]);
            own.excludes(v, t)
                || own.behind_at_rest(v, t)
                || !own.meets((&end[v], normal), &corners, &corners)
        };
        if let Some(p) = bvh.project(&end[v], &end, Some(normal), skip) {
            if p.gap < margin && (skin_moves(v) || p.nodes.iter().any(|&c| skin_moves(c))) {
                out.push(now[v]);
                out.extend(p.nodes.map(|c| now[c]));
            }
        }
    }
    out
}
