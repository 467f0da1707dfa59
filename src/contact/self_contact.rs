//! Self-contact of one surface: the hand's skin folding onto itself — the two sides of a flexion
//! crease, phalanx against phalanx ("we consider the third phalanx unable to interpenetrate the
//! second and first phalanges", the paper's finger flexing), fingertip against palm, finger
//! against finger.
//!
//! A point of a surface never meets the facets of its own neighbourhood: those with a corner
//! within `radius` of it along the surface at rest (geodesic distance over the surface's edges)
//! and none farther than [`SPAN`] radii, and those with a corner where it is (a seam's twin),
//! which the flesh between them keeps in place (a point always lies on its neighbouring facets,
//! and on a curved skin slightly behind or in front of them). Along the surface, not straight:
//! two fingers side by side are near each other, but far apart over the web between them, and
//! may meet. The neighbourhood's reach is bounded by a length of the surface, not of its mesh:
//! a facet with a corner inside the radius but reaching beyond [`SPAN`] radii is not the point's
//! own (on facets with edges over half a radius the neighbourhood may therefore fall short of
//! the radius). Until 2026-12-07 any facet with a corner inside was, and a neighbourhood reached
//! the radius plus a facet: on a coarse skin, 4.5 – 5.4 mm facets around a 6.4 mm radius, skin
//! 10 – 11 mm apart at rest passed through itself unseen.
//!
//! Beyond it, over a step, a point meets a facet it **passed through** — its straight path
//! against the facet's corners' straight paths went from the facet's front to its back
//! ([`super::passes_through`], continuous collision) — or one it **lay on** where the step
//! started (facing it, over it, behind its plane by no more than the contact's penetration
//! limit: held there by the step before). Skin that lies behind the plane of a facet across the
//! air of a fold (the two sides of a crease, a fingertip beside the palm) has passed through
//! nothing and is not held; skin that went through another side is held, however the two faced
//! where the step started. Nothing needs guessing from the normals: the far side of a finger is
//! never passed through from the front unless its flesh is crushed through.
//!
//! (Until 2026-12-02 a point met the nearest facet it lay behind whose normal opposed its own by
//! more than 105° where the step started, [`OPPOSED`]; that guess missed skin already through a
//! facet that faced it at 104° and held skin behind facets it had never crossed — the full fist
//! stopped at little PIP 50.7°. It remains the prediction of where the skin will meet itself
//! over a keyframe by skinning alone, [`OwnNeighbourhood::meets`], where there is no path.)
//!
//! Everything else — skin that was apart, or side by side, at rest — is an ordinary pair of the
//! contact problem ([`super::SurfacePair`] with its slaves on the surface they meet), solved by
//! the same methods as contact between bodies.

use super::along_surface::SurfaceEdges;
use super::bounds::Bounds;
use super::surface::{project_on_triangle, Projection};
use super::swept::passes_through;
use nalgebra::Vector3;
use rayon::prelude::*;

/// The skin's normals at a point and at a facet it may meet are at least this far from
/// parallel: their dot product below −cos 105°, ≈ −0.26 (skin folding onto itself meets
/// face to face; skin around a convex finger is at most 90° apart).
pub const OPPOSED: f64 = -0.26;

/// A facet of a point's own neighbourhood lies wholly within this many neighbourhood radii of
/// it along the surface (see the module's text).
pub const SPAN: f64 = 1.5;

/// Which facets of its own surface a point may not meet (see the module's text).
#[derive(Clone, Debug)]
pub struct OwnNeighbourhood {
    /// Rest position of every contact index (nodes, then embedded points), m.
    rest: Vec<Vector3<f64>>,
    /// A facet with a corner nearer than this to the point at rest, along the surface, and none
    /// farther than [`SPAN`] times it, is its neighbourhood, m.
    radius: f64,
    /// Each contact index's surroundings: the surface's points within [`SPAN`] radii along it,
    /// each with how near, sorted by point (empty off the surface).
    near: Vec<Vec<(u32, Along)>>,
    /// A point behind a facet at rest by more than `behind`, nearer than `reach`, is the same
    /// flesh seen from its other side, m.
    behind: f64,
    /// See `behind`, m.
    reach: f64,
    /// A point behind a facet's plane by no more than this where a step started, facing it and
    /// over it, lay on it (held there by the step before), m.
    touching: f64,
}

impl OwnNeighbourhood {
    /// The neighbourhoods on the surface `triangles` (contact indices) at the rest positions
    /// `rest` (one per contact index): points within `radius` along the surface, their facets
    /// wholly within [`SPAN`] radii, and their seam twins'; for the
    /// prediction by skinning, points behind a facet by more than `behind` within `reach`; a
    /// point touched a facet where a step started if it lay behind it by no more than
    /// `touching` (m).
    pub fn new(
        rest: Vec<Vector3<f64>>,
        triangles: &[[usize; 3]],
        radius: f64,
        (behind, reach): (f64, f64),
        touching: f64,
    ) -> Self {
        assert!(
            radius >= 0.0 && behind >= 0.0 && reach >= 0.0 && touching >= 0.0,
            "a neighbourhood's radius, behind, reach and touching are ≥ 0"
        );
        let near = geodesic_neighbourhoods(&rest, triangles, radius);
        OwnNeighbourhood {
            rest,
            radius,
            near,
            behind,
            reach,
            touching,
        }
    }

    /// Whether a point whose projection on a facet is `q` lies over the facet: its offset along
    /// the facet from its nearest point there (from the foot of its normal, 0 inside the facet)
    /// within a quarter of the neighbourhood's radius.
    fn over(&self, q: &Projection) -> bool {
        let along = (q.distance * q.distance - q.gap * q.gap).max(0.0).sqrt();
        along <= self.beside()
    }

    /// Whether the point at `point` may meet the facet with corners `corners` (current
    /// positions): the facet faces it where the step started (`normal`: the point's outward
    /// normal there, `start`: the facet's corners there; [`OPPOSED`]) and it lies over the
    /// facet now (its offset along the facet from its nearest point there within a quarter of
    /// the neighbourhood's radius) nearer than the radius (deeper, it is not skin that met skin
    /// over a step but the far side of a fold).
    pub fn meets(
        &self,
        (point, normal): (&Vector3<f64>, &Vector3<f64>),
        start: &[Vector3<f64>; 3],
        corners: &[Vector3<f64>; 3],
    ) -> bool {
        let facet_normal = (start[1] - start[0]).cross(&(start[2] - start[0]));
        let Some(facet_normal) = facet_normal.try_normalize(0.0) else {
            return false;
        };
        if facet_normal.dot(normal) >= OPPOSED {
            return false;
        }
        match project_on_triangle(point, corners) {
            Some(q) => self.over(&q) && q.distance < self.radius,
            None => false,
        }
    }

    /// Whether the point `point` moving from `from` to `to` over a step (its outward normal
    /// where the step started: `normal`) meets the facet `facet` (contact indices) whose
    /// corners moved from `start` to `now`: it passed through the facet, or lay on it where the
    /// step started but not already at rest (skin that merely touches at rest, as where the
    /// digits' skins meet at the webs, does not lock; see the module's text). Its own
    /// neighbourhood is [`Self::excludes`]'s.
    pub fn met_over_step(
        &self,
        (point, facet): (usize, &[usize; 3]),
        (from, to, normal): (&Vector3<f64>, &Vector3<f64>, &Vector3<f64>),
        start: &[Vector3<f64>; 3],
        now: &[Vector3<f64>; 3],
    ) -> bool {
        if passes_through([from, to], start, now).is_some() {
            return true;
        }
        self.lay_on(from, normal, start) && {
            let at_rest = project_on_triangle(&self.rest[point], &facet.map(|c| self.rest[c]));
            !at_rest.is_some_and(|q| q.gap.abs() <= self.touching && self.over(&q))
        }
    }

    /// How far beside a point's path over a step a facet it meets may lie where the step
    /// started (m): it lay on it, behind it by no more than `touching`, beside it by no more
    /// than a quarter of the radius ([`Self::met_over_step`]).
    pub fn reach_beside_path(&self) -> f64 {
        self.touching + self.beside()
    }

    /// How far past a facet's edge a point may lie and still lie over it ([`Self::over`]): a
    /// quarter of the neighbourhood's radius, m.
    fn beside(&self) -> f64 {
        0.25 * self.radius
    }

    /// Whether the point at `point` (outward normal `normal`) lay on the facet `corners`:
    /// facing it, behind its plane by no more than `touching`, and over it (as
    /// [`Self::over`]: a point held on a facet may have slid a little past its edge).
    fn lay_on(
        &self,
        point: &Vector3<f64>,
        normal: &Vector3<f64>,
        corners: &[Vector3<f64>; 3],
    ) -> bool {
        // Farther from the facet's box than it may lie behind and beside it: not on it.
        if !Bounds::of(corners)
            .grown(self.reach_beside_path())
            .holds(point)
        {
            return false;
        }
        let Some(q) = project_on_triangle(point, corners) else {
            return false;
        };
        q.normal.dot(normal) < OPPOSED && q.gap <= 0.0 && q.gap >= -self.touching && self.over(&q)
    }

    /// How near `to` lies to `from` along the surface at rest; `None` beyond [`SPAN`] radii.
    fn along(&self, from: usize, to: usize) -> Option<Along> {
        if from == to {
            return Some(Along::Joined);
        }
        let near = &self.near[from];
        let to = u32::try_from(to).ok()?;
        near.binary_search_by_key(&to, |e| e.0)
            .ok()
            .map(|i| near[i].1)
    }

    /// Whether the facet with corners `facet` (contact indices) is `point`'s own: one of its
    /// facets or of its seam twin's, or a facet with a corner within the radius along the
    /// surface and every corner within [`SPAN`] radii.
    pub fn excludes(&self, point: usize, facet: &[usize; 3]) -> bool {
        let along = facet.map(|c| self.along(point, c));
        along.contains(&Some(Along::Joined))
            || (along.iter().all(Option::is_some) && along.contains(&Some(Along::Inside)))
    }

    /// Whether the edges `a` and `b` (contact indices of their ends) are the same flesh: they
    /// share an end (or its seam twin), or an end of one lies within the radius of an end of
    /// the other along the surface and every end of each within [`SPAN`] radii of an end of the
    /// other.
    pub fn excludes_edge(&self, a: &[usize; 2], b: &[usize; 2]) -> bool {
        // How near each end of `a` (rows) lies to each end of `b` (columns).
        let along = a.map(|p| b.map(|c| self.along(p, c)));
        let any = |near: Along| along.iter().flatten().any(|n| *n == Some(near));
        let rows = along.iter().all(|row| row.iter().any(Option::is_some));
        let columns = (0..2).all(|j| along.iter().any(|row| row[j].is_some()));
        any(Along::Joined) || (any(Along::Inside) && rows && columns)
    }

    /// Whether `point` lies behind the facet `facet` at rest within reach — by more than
    /// `behind`, or at all where it lies over it: the far side of the same flesh, which a
    /// prediction without a path (skinning from rest to a keyframe's end) must not take for
    /// skin meeting skin (at rest nothing is in contact).
    pub fn behind_at_rest(&self, point: usize, facet: &[usize; 3]) -> bool {
        let corners = facet.map(|c| self.rest[c]);
        match project_on_triangle(&self.rest[point], &corners) {
            Some(q) => {
                q.distance < self.reach && (q.gap < -self.behind || (self.over(&q) && q.gap < 0.0))
            }
            // A flat facet at rest: nothing to say about it.
            None => false,
        }
    }
}

/// How near a point lies to another along the surface at rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Along {
    /// The same point, or its twin across a seam (coinciding, joined at no length).
    Joined,
    /// Within the neighbourhood's radius.
    Inside,
    /// Beyond the radius, within [`SPAN`] radii.
    Spanned,
}

/// For every point of the surface `triangles` at `positions`, the points within [`SPAN`] times
/// `radius` of it along the surface's edges (points that coincide joined), each with how near
/// it lies, sorted by point; empty for a point off the surface.
fn geodesic_neighbourhoods(
    positions: &[Vector3<f64>],
    triangles: &[[usize; 3]],
    radius: f64,
) -> Vec<Vec<(u32, Along)>> {
    assert!(
        u32::try_from(positions.len()).is_ok(),
        "a self-contact surface has fewer than 2³² points"
    );
    let edges = SurfaceEdges::new(positions, triangles);
    (0..positions.len())
        .into_par_iter()
        .map(|start| {
            if !edges.on_surface(start) {
                return Vec::new();
            }
            let mut near: Vec<(u32, Along)> = edges
                .within(&[start], SPAN * radius)
                .into_iter()
                .map(|(p, d)| {
                    let along = if d <= 0.0 {
                        Along::Joined
                    } else if d < radius {
                        Along::Inside
                    } else {
                        Along::Spanned
                    };
                    (p as u32, along)
                })
                .collect();
            near.sort_unstable_by_key(|e| e.0);
            near
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of 1 mm squares along x at height `z` mm, facing up or down: its vertices
    /// (appended to `rest`) and triangles.
    fn strip(rest: &mut Vec<Vector3<f64>>, z: f64, up: bool) -> Vec<[usize; 3]> {
        let first = rest.len();
        for i in 0..=10 {
            for j in 0..=1 {
                rest.push(Vector3::new(i as f64, j as f64, z) * 1e-3);
            }
        }
        let v = |i: usize, j: usize| first + 2 * i + j;
        (0..10)
            .flat_map(|i| {
                let (a, b, c, d) = (v(i, 0), v(i + 1, 0), v(i + 1, 1), v(i, 1));
                if up {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, c, b], [a, d, c]]
                }
            })
            .collect()
    }

    /// A skin strip facing up at z = 0; above it, 2 mm away, another facing down (a finger side
    /// by side, near in space, far along the skin); below, 4 mm down, the strip's own underside
    /// (facing down: the far side of the same flesh).
    #[test]
    fn excludes_the_neighbourhood_along_the_skin_and_the_far_side_only() {
        let mut rest = Vec::new();
        let top = strip(&mut rest, 0.0, true);
        let above = strip(&mut rest, 2.0, false);
        let under = strip(&mut rest, -4.0, false);
        let triangles: Vec<[usize; 3]> = [&top[..], &above[..], &under[..]].concat();
        let n = OwnNeighbourhood::new(rest.clone(), &triangles, 0.0025, (0.001, 0.01), 0.0);
        let point = 0; // (0, 0, 0) on the top strip
                       // Its own facets and those within 2.5 mm along the skin.
        assert!(n.excludes(point, &top[0]));
        assert!(n.excludes(point, &top[2]));
        // Farther along the same skin, about in its plane: may meet it (the other side of a
        // crease, once folded).
        assert!(!n.excludes(point, &top[16]));
        // The strip above: 2 mm away in space, far along the skin, in front: may meet it.
        assert!(!n.excludes(point, &above[0]));
        // The underside, 4 mm behind, within reach: not its neighbourhood along the skin, but
        // the far side of the same flesh at rest.
        assert!(!n.excludes(point, &under[0]));
        assert!(n.behind_at_rest(point, &under[0]));
        assert!(!n.behind_at_rest(point, &above[0]));
        let short = OwnNeighbourhood::new(rest.clone(), &triangles, 0.0025, (0.001, 0.003), 0.0);
        assert!(!short.behind_at_rest(point, &under[0]));
        // Deeper behind than `behind` only: a point 0.5 mm below the top's plane, far along it.
        let mut sunk = rest.clone();
        sunk[point].z = -0.0005;
        let strict = OwnNeighbourhood::new(sunk.clone(), &triangles, 0.0025, (0.0004, 0.04), 0.0);
        assert!(strict.behind_at_rest(point, &top[16]));
        let lenient = OwnNeighbourhood::new(sunk, &triangles, 0.0025, (0.001, 0.04), 0.0);
        assert!(!lenient.behind_at_rest(point, &top[16]));
    }

    /// A neighbourhood reaches 1.5 radii at most, not its radius plus a facet: on a strip whose
    /// facets are large against the radius (1 mm squares halved along 1.41 mm diagonals; radius
    /// 2.2 mm, 1.5 radii 3.3 mm), a facet with a corner inside the radius and one beyond 1.5
    /// radii along the skin is not the point's own; nor is an edge with an end beyond 1.5 radii
    /// of both ends of the other. (Along the strip's edges from (0,0): (i,0) lies i mm away,
    /// (0,1) 1 mm, (i,1) i + 0.41 mm for i ≥ 1.)
    #[test]
    fn a_neighbourhood_reaches_no_facet_beyond_its_span() {
        let mut rest = Vec::new();
        let top = strip(&mut rest, 0.0, true);
        let n = OwnNeighbourhood::new(rest.clone(), &top, 0.0022, (0.001, 0.01), 0.0);
        let v = |i: usize, j: usize| 2 * i + j;
        let point = v(0, 0);
        // Corners 1, 2.41 and 1.41 mm away: wholly within 1.5 radii.
        assert_eq!(top[3], [v(1, 0), v(2, 1), v(1, 1)]);
        assert!(n.excludes(point, &top[3]));
        // Corners 2, 3 and 3.41 mm away: one inside the radius, one beyond 1.5 radii.
        assert_eq!(top[4], [v(2, 0), v(3, 0), v(3, 1)]);
        assert!(!n.excludes(point, &top[4]));
        // Its nearest corner 3 mm away, beyond the radius.
        assert!(!n.excludes(point, &top[6]));
        // Edges: (0,0)–(0,1) against (2,0)–(3,1): (2,0) 2 mm from (0,0); (3,1) 3.41 mm from
        // (0,0) but 3 mm from (0,1): own. Against (3,0)–(4,0): nearest ends 3 mm apart: not.
        assert!(n.excludes_edge(&[v(0, 0), v(0, 1)], &[v(2, 0), v(3, 1)]));
        assert!(!n.excludes_edge(&[v(0, 0), v(0, 1)], &[v(3, 0), v(4, 0)]));
        // Radius 1.5 mm (1.5 radii 2.25 mm): (0,0)–(1,0) against (2,0)–(3,1): (2,0) 1 mm from
        // (1,0), but (3,1) 3.41 and 2.41 mm from (0,0) and (1,0): not own. Against (1,1)–(2,1):
        // (2,1) 2.41 mm from (0,0) but 1.41 mm from (1,0): own.
        let coarse = OwnNeighbourhood::new(rest, &top, 0.0015, (0.001, 0.01), 0.0);
        assert!(!coarse.excludes_edge(&[v(0, 0), v(1, 0)], &[v(2, 0), v(3, 1)]));
        assert!(coarse.excludes_edge(&[v(0, 0), v(1, 0)], &[v(1, 1), v(2, 1)]));
    }

    /// A skin split along a seam (its vertices duplicated, as where the lattice splits a node
    /// between two digits) is one skin: the facet across the seam is the point's neighbourhood.
    #[test]
    fn a_seam_of_coincident_vertices_joins_the_neighbourhood() {
        let mut rest = Vec::new();
        let left = strip(&mut rest, 0.0, true);
        let mut right = strip(&mut rest, 0.0, true);
        // Move the second strip to continue the first along x: its first column on the first
        // strip's last one, the vertices coinciding but not shared.
        let shift = Vector3::new(10e-3, 0.0, 0.0);
        for p in rest.iter_mut().skip(22) {
            *p += shift;
        }
        right.retain(|t| t.iter().all(|&v| v >= 22));
        let triangles: Vec<[usize; 3]> = [&left[..], &right[..]].concat();
        let n = OwnNeighbourhood::new(rest.clone(), &triangles, 0.0025, (0.001, 0.01), 0.0);
        // Vertex 20 is (10, 0, 0) on the first strip; the second strip's first facets touch it.
        assert!(n.excludes(20, &right[0]));
        assert!(n.excludes(18, &right[0]));
        // Farther than 2.5 mm along the joined skin: not excluded.
        assert!(!n.excludes(14, &right[4]));
        // Across the seam the skin is one even where its facets are large against the radius:
        // at 0.5 mm (1.5 radii 0.75 mm) the twin's facet, corners 0, 1 and 1.41 mm from vertex
        // 20, and the twin's diagonal are still its own.
        let small = OwnNeighbourhood::new(rest, &triangles, 0.0005, (0.001, 0.01), 0.0);
        assert_eq!(right[0], [22, 24, 25]);
        assert!(small.excludes(20, &right[0]));
        assert!(small.excludes_edge(&[20, 21], &[22, 25]));
        assert!(!small.excludes(18, &right[0]));
    }

    /// Vertices, and the triangles of a lower and an upper strip.
    type Strips = (Vec<Vector3<f64>>, Vec<[usize; 3]>, Vec<[usize; 3]>);

    /// A strip facing up at z = 0 and one facing down 2 mm above it (`top`, `above`), their
    /// vertices, and their neighbourhoods (radius 4 mm, touching within `touching`).
    fn facing_strips(touching: f64) -> (Strips, OwnNeighbourhood) {
        let mut rest = Vec::new();
        let top = strip(&mut rest, 0.0, true);
        let above = strip(&mut rest, 2.0, false);
        let triangles = [&top[..], &above[..]].concat();
        let n = OwnNeighbourhood::new(rest.clone(), &triangles, 0.004, (0.001, 0.01), touching);
        ((rest, top, above), n)
    }

    /// Whether a point meets a facet: facing it (normals more than 105° apart) and over it.
    #[test]
    fn meets_only_a_facet_that_faces_it_and_that_it_lies_over() {
        let ((rest, top, above), n) = facing_strips(0.0);
        let corners = |t: [usize; 3]| t.map(|c| rest[c]);
        let up = Vector3::z();
        // A point of the top strip 0.3 mm into the strip above, under its first facet.
        let p = Vector3::new(0.7e-3, 0.2e-3, 2.3e-3);
        assert!(n.meets((&p, &up), &corners(above[0]), &corners(above[0])));
        // The same point does not meet a facet 5 mm along (beside it, not over it)…
        assert!(!n.meets((&p, &up), &corners(above[10]), &corners(above[10])));
        // …nor a facet that faced the same way where the step started.
        assert!(!n.meets((&p, &up), &corners(top[0]), &corners(above[0])));
        // A point 5 mm past the facet (deeper than the radius) is not skin that met skin.
        let deep = Vector3::new(0.7e-3, 0.2e-3, 7.0e-3);
        assert!(!n.meets((&deep, &up), &corners(above[0]), &corners(above[0])));
    }

    /// Over a step: a point meets a facet of its own skin it passed through (whatever the
    /// facing where the step started), or one it lay on; not one it lies behind across the air
    /// of a fold without having passed through it.
    #[test]
    fn over_a_step_a_point_meets_what_it_passed_through_or_lay_on() {
        let ((rest, top, above), n) = facing_strips(1e-4);
        let corners = |t: [usize; 3]| t.map(|c| rest[c]);
        let up = Vector3::z();
        let facet = corners(above[0]);
        // From 0.2 mm below the strip above to 0.3 mm into it: passed through.
        let from = Vector3::new(0.7e-3, 0.2e-3, 1.8e-3);
        let to = Vector3::new(0.7e-3, 0.2e-3, 2.3e-3);
        assert!(n.met_over_step((0, &above[0]), (&from, &to, &up), &facet, &facet));
        // The same path with the point's normal at 90° to the facet's (a facing test would have
        // left it): passed through all the same.
        let sideways = Vector3::x();
        assert!(n.met_over_step((0, &above[0]), (&from, &to, &sideways), &facet, &facet));
        // Already 0.3 mm behind where the step started, going deeper: behind its plane by more
        // than `touching` (0.1 mm), it passed through nothing over this step.
        let deep = Vector3::new(0.7e-3, 0.2e-3, 2.3e-3);
        let deeper = Vector3::new(0.7e-3, 0.2e-3, 2.5e-3);
        assert!(!n.met_over_step((0, &above[0]), (&deep, &deeper, &up), &facet, &facet));
        // Lying on it (0.05 mm behind, held there by the step before): met.
        let on = Vector3::new(0.7e-3, 0.2e-3, 2.05e-3);
        assert!(n.met_over_step((0, &above[0]), (&on, &deeper, &up), &facet, &facet));
        // …unless it does not face it.
        assert!(!n.met_over_step((0, &above[0]), (&on, &deeper, &sideways), &facet, &facet));
        // Stopping short of it: not met.
        let short = Vector3::new(0.7e-3, 0.2e-3, 1.95e-3);
        assert!(!n.met_over_step((0, &above[0]), (&from, &short, &up), &facet, &facet));
        // Skin that touched the facet already at rest (0.05 mm behind it, as where the digits'
        // skins meet at the webs) does not lock there; passing through it still counts.
        let mut touching = rest.clone();
        touching[0] = on;
        let t = OwnNeighbourhood::new(
            touching,
            &[&top[..], &above[..]].concat(),
            0.004,
            (0.001, 0.01),
            1e-4,
        );
        assert!(!t.met_over_step((0, &above[0]), (&on, &deeper, &up), &facet, &facet));
        assert!(t.met_over_step((0, &above[0]), (&from, &to, &up), &facet, &facet));
    }
}
