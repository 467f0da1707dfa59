//! The display skin moved by the contact skin: each display vertex is the Catmull–Clark
//! subdivision of the contact skin's vertices (the control net the display skin was subdivided
//! from, each vertex where its cell puts it) plus its rest offset from that subdivision, turned
//! with its control quad's frame at its site.
//!
//! Why: the contact holds the contact skin's vertices out of every object (issue 15, item 5); a
//! display vertex embedded in its own flesh cell follows that cell's trilinear field, which
//! under a hard press (a ball 100 times stiffer than rubber squeezing the pad's cells by 10 mm)
//! extrapolates far from the held points — the display skin went 1.43 mm into such a ball
//! between contact points held to 10⁻⁸ m. The subdivision weights are positive and sum to one,
//! so the display skin lies on a smooth surface through what the contact holds: 0.49 mm into
//! that ball; on the default scene's presets 0.29 mm (Pinch, from 0.57) and 0.47 mm (Power
//! grasp, from 0.50) into the rubber ball (measured 2026-12-02; what is left is the display
//! skin lying outward of the contact skin's points, docs/hand.md). At rest the display skin is
//! where it was, to round-off, and it moves rigidly with the flesh (tests/hand.rs).

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// Points as fixed combinations of flesh nodes (CSR): the contact skin's vertices.
#[derive(Clone, Debug, Default)]
pub(super) struct Combinations {
    /// Start of each point's terms, one more than points.
    pub offsets: Vec<u32>,
    /// (node, weight) of every point, in order.
    pub terms: Vec<(u32, f64)>,
}

impl Combinations {
    /// The points at node positions `nodes`.
    fn at(&self, nodes: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        (0..self.offsets.len() - 1)
            .into_par_iter()
            .map(|v| {
                let (a, b) = (self.offsets[v] as usize, self.offsets[v + 1] as usize);
                self.terms[a..b]
                    .iter()
                    .map(|&(n, w)| nodes[n as usize] * w)
                    .sum()
            })
            .collect()
    }
}

/// Each display vertex's control quad and bilinear coordinates there.
pub(super) type Sites = Vec<(u32, [f64; 2])>;

/// What the display skin needs to follow the contact skin.
#[derive(Clone, Debug, Default)]
pub(super) struct Follow {
    /// The contact skin's vertices (the control net's, in the order the subdivision numbers
    /// them) over the flesh nodes.
    control: Combinations,
    /// Each subdivision level's vertices over the level before's (the first over the contact
    /// skin's vertices, the last giving the display vertices).
    levels: Vec<Combinations>,
    /// The control net's quads, over the contact skin's vertices.
    control_quads: Vec<[u32; 4]>,
    /// Where each display vertex's frame is taken: its control quad and bilinear coordinates
    /// there, or where the quad has no area at rest, the centre of one that has around it
    /// ([`frame_sites`]).
    site: Sites,
    /// Each display vertex's rest offset from the subdivided surface, in its frame at rest
    /// (the control quad's two directions at its site, orthonormalised, and their normal).
    offset: Vec<Vector3<f64>>,
}

impl Follow {
    /// The display skin (its vertices `at_rest` with the flesh nodes at rest `rest`, each
    /// at `site` on a quad of `control_quads`) following the contact skin `control`, each
    /// display vertex the contact skin's vertices subdivided by `levels` plus its offset from
    /// that at rest.
    pub(super) fn new(
        (control, levels): (Combinations, Vec<Combinations>),
        (control_quads, site): (Vec<[u32; 4]>, Sites),
        (at_rest, rest): (&[Vector3<f64>], &[Vector3<f64>]),
    ) -> Follow {
        let points = control.at(rest);
        let site = frame_sites(&control_quads, site, &points);
        let mut follow = Follow {
            control,
            levels,
            control_quads,
            site,
            offset: Vec::new(),
        };
        let base = follow.subdivided(&points);
        let frames = follow.frames(&points);
        follow.offset = at_rest
            .iter()
            .zip(&base)
            .zip(&frames)
            .map(|((p, b), f)| f.transpose() * (p - b))
            .collect();
        follow
    }

    /// The display vertices' subdivided positions from the contact skin's vertices at `points`.
    fn subdivided(&self, points: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        self.levels
            .iter()
            .fold(points.to_vec(), |coarser, level| level.at(&coarser))
    }

    /// Each display vertex's frame ([`frame_at`] its frame site) with the contact skin's
    /// vertices at `points`; the identity where that has no area.
    fn frames(&self, points: &[Vector3<f64>]) -> Vec<Matrix3<f64>> {
        self.site
            .par_iter()
            .map(|&(q, uv)| {
                let corners = self.control_quads[q as usize].map(|i| points[i as usize]);
                frame_at(&corners, uv).unwrap_or_else(Matrix3::identity)
            })
            .collect()
    }

    /// The display skin's vertices at flesh node positions `nodes`.
    pub(super) fn positions(&self, nodes: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        let points = self.control.at(nodes);
        let base = self.subdivided(&points);
        let frames = self.frames(&points);
        base.iter()
            .zip(&frames)
            .zip(&self.offset)
            .map(|((b, f), o)| b + f * o)
            .collect()
    }
}

/// The frame of the bilinear quad `corners` at (u, v), columns: the u direction, the v
/// direction made orthogonal to it, their normal; `None` where the quad has no area there.
fn frame_at(corners: &[Vector3<f64>; 4], [u, v]: [f64; 2]) -> Option<Matrix3<f64>> {
    let [a, b, c, d] = corners;
    let du = (b - a) * (1.0 - v) + (c - d) * v;
    let dv = (d - a) * (1.0 - u) + (c - b) * u;
    let normal = du.cross(&dv);
    // Relative to the quad's size: a sliver's normal is noise.
    if normal.norm() <= 1e-6 * du.norm_squared().max(dv.norm_squared()) {
        return None;
    }
    let t = du.normalize();
    let n = normal.normalize();
    Some(Matrix3::from_columns(&[t, n.cross(&t), n]))
}

/// Where each display vertex's frame is taken, from its `site` on its control quad (of `quads`,
/// over the contact skin's vertices at rest `points`): there, else at that quad's centre, else
/// at the centre of a quad sharing a corner with it (the split skin's seams collapse a few
/// quads where digits meet: 104 display vertices of the built-in hand at resolution 1).
fn frame_sites(quads: &[[u32; 4]], site: Sites, points: &[Vector3<f64>]) -> Vec<(u32, [f64; 2])> {
    let corners = |q: u32| quads[q as usize].map(|i| points[i as usize]);
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    for (q, quad) in quads.iter().enumerate() {
        for &v in quad {
            around[v as usize].push(q as u32);
        }
    }
    const CENTRE: [f64; 2] = [0.5, 0.5];
    site.into_iter()
        .map(|(q, uv)| {
            if frame_at(&corners(q), uv).is_some() {
                return (q, uv);
            }
            if frame_at(&corners(q), CENTRE).is_some() {
                return (q, CENTRE);
            }
            quads[q as usize]
                .iter()
                .flat_map(|&v| &around[v as usize])
                .find(|&&o| frame_at(&corners(o), CENTRE).is_some())
                .map_or((q, uv), |&o| (o, CENTRE))
        })
        .collect()
}
