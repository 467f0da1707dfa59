//! Self-contact of one surface: the hand's skin folding onto itself — the two sides of a flexion
//! crease, phalanx against phalanx ("we consider the third phalanx unable to interpenetrate the
//! second and first phalanges", the paper's finger flexing), fingertip against palm, finger
//! against finger.
//!
//! A point of a surface may meet a facet of the same surface unless, on the rest geometry,
//!
//! - a corner of the facet is within `radius` of the point along the surface (geodesic distance
//!   over the surface's edges): its own neighbourhood, which the flesh between them keeps in
//!   place (a point always lies on its neighbouring facets, and on a curved skin slightly behind
//!   or in front of them). Along the surface, not straight: two fingers side by side are near
//!   each other, but far apart over the web between them, and may meet; or
//! - the point lies behind the facet (on its inner side) nearer than `reach`, by more than
//!   `behind` or at all where it lies over the facet (see below): the same piece of flesh seen
//!   from its other side (the far side of a finger, the nail behind the pulp), which the point
//!   can only reach through the flesh. Skin that lies
//!   about in the facet's plane at rest (the two sides of a crease, along the finger) may meet
//!   it; a point far away (the fingertip, seen from the palm) too, whichever side of the
//!   facet's plane it lies.
//!
//! and, on the current geometry, a point meets only a facet that faces it — the facet's normal
//! and the point's own more than [`OPPOSED`] apart, as skin meeting skin is — and that it lies
//! over: its nearest point on the facet (nearly) the foot of its normal. On a convex finger every
//! skin point lies behind the plane of the skin around the finger from it, and beside the skin
//! farther along: neither is a contact.
//!
//! Everything else — skin that was apart, or side by side, at rest — is an ordinary pair of the
//! contact problem ([`super::SurfacePair`] with its slaves on the surface they meet), solved by
//! the same methods as contact between bodies.

use super::along_surface::SurfaceEdges;
use super::surface::{project_on_triangle, Projection};
use nalgebra::Vector3;

/// The skin's normals at a point and at a facet it may meet are at least this far from
/// parallel: their dot product below −cos 105°, ≈ −0.26 (skin folding onto itself meets
/// face to face; skin around a convex finger is at most 90° apart).
pub const OPPOSED: f64 = -0.26;

/// Which facets of its own surface a point may not meet (see the module's text).
#[derive(Clone, Debug)]
pub struct OwnNeighbourhood {
    /// Rest position of every contact index (nodes, then embedded points), m.
    rest: Vec<Vector3<f64>>,
    /// A facet with a corner nearer than this to the point at rest, along the surface, is its
    /// neighbourhood, m.
    radius: f64,
    /// Each contact index's neighbourhood: the surface's points within `radius` along it,
    /// sorted (empty off the surface).
    near: Vec<Vec<usize>>,
    /// A point behind a facet at rest by more than `behind`, nearer than `reach`, is the same
    /// flesh seen from its other side, m.
    behind: f64,
    /// See `behind`, m.
    reach: f64,
}

impl OwnNeighbourhood {
    /// The neighbourhoods on the surface `triangles` (contact indices) at the rest positions
    /// `rest` (one per contact index): points within `radius` along the surface, and points
    /// behind a facet by more than `behind` within `reach` (m).
    pub fn new(
        rest: Vec<Vector3<f64>>,
        triangles: &[[usize; 3]],
        radius: f64,
        (behind, reach): (f64, f64),
    ) -> Self {
        assert!(
            radius >= 0.0 && behind >= 0.0 && reach >= 0.0,
            "a neighbourhood's radius, behind and reach are ≥ 0"
        );
        let near = geodesic_neighbourhoods(&rest, triangles, radius);
        OwnNeighbourhood {
            rest,
            radius,
            near,
            behind,
            reach,
        }
    }

    /// Whether a point whose projection on a facet is `q` lies over the facet: its offset along
    /// the facet from its nearest point there (from the foot of its normal, 0 inside the facet)
    /// within a quarter of the neighbourhood's radius.
    fn over(&self, q: &Projection) -> bool {
        let along = (q.distance * q.distance - q.gap * q.gap).max(0.0).sqrt();
        along <= 0.25 * self.radius
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

    /// Whether `point` may not meet the facet with corners `facet` (contact indices).
    pub fn excludes(&self, point: usize, facet: &[usize; 3]) -> bool {
        let p = self.rest[point];
        if facet.contains(&point) {
            return true;
        }
        let near = &self.near[point];
        if facet.iter().any(|c| near.binary_search(c).is_ok()) {
            return true;
        }
        let corners = facet.map(|c| self.rest[c]);
        match project_on_triangle(&p, &corners) {
            // Behind the facet at rest, within reach — by more than `behind`, or at all where
            // the point lies over it: the far side of the same flesh (at rest nothing is in
            // contact).
            Some(q) => {
                q.distance < self.reach && (q.gap < -self.behind || (self.over(&q) && q.gap < 0.0))
            }
            // A flat facet at rest: nothing to say about it.
            None => false,
        }
    }
}

/// For every point of the surface `triangles` at `positions`, the points within `radius` of it
/// along the surface's edges (points that coincide joined), sorted; empty for a point off the
/// surface.
fn geodesic_neighbourhoods(
    positions: &[Vector3<f64>],
    triangles: &[[usize; 3]],
    radius: f64,
) -> Vec<Vec<usize>> {
    let edges = SurfaceEdges::new(positions, triangles);
    (0..positions.len())
        .map(|start| {
            if !edges.on_surface(start) {
                return Vec::new();
            }
            let mut near: Vec<usize> = edges.within(&[start], radius).into_keys().collect();
            near.sort_unstable();
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
        let n = OwnNeighbourhood::new(rest.clone(), &triangles, 0.0025, (0.001, 0.01));
        let point = 0; // (0, 0, 0) on the top strip
                       // Its own facets and those within 2.5 mm along the skin.
        assert!(n.excludes(point, &top[0]));
        assert!(n.excludes(point, &top[2]));
        // Farther along the same skin, about in its plane: may meet it (the other side of a
        // crease, once folded).
        assert!(!n.excludes(point, &top[16]));
        // The strip above: 2 mm away in space, far along the skin, in front: may meet it.
        assert!(!n.excludes(point, &above[0]));
        // The underside, 4 mm behind, within reach: the far side of the same flesh.
        assert!(n.excludes(point, &under[0]));
        let short = OwnNeighbourhood::new(rest.clone(), &triangles, 0.0025, (0.001, 0.003));
        assert!(!short.excludes(point, &under[0]));
        // Deeper behind than `behind` only: a point 0.5 mm below the top's plane, far along it.
        let mut sunk = rest.clone();
        sunk[point].z = -0.0005;
        let strict = OwnNeighbourhood::new(sunk.clone(), &triangles, 0.0025, (0.0004, 0.04));
        assert!(strict.excludes(point, &top[16]));
        let lenient = OwnNeighbourhood::new(sunk, &triangles, 0.0025, (0.001, 0.04));
        assert!(!lenient.excludes(point, &top[16]));
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
        let n = OwnNeighbourhood::new(rest.clone(), &triangles, 0.0025, (0.001, 0.01));
        // Vertex 20 is (10, 0, 0) on the first strip; the second strip's first facets touch it.
        assert!(n.excludes(20, &right[0]));
        assert!(n.excludes(18, &right[0]));
        // Farther than 2.5 mm along the joined skin: not excluded.
        assert!(!n.excludes(14, &right[4]));
    }

    /// Whether a point meets a facet: facing it (normals more than 105° apart) and over it.
    #[test]
    fn meets_only_a_facet_that_faces_it_and_that_it_lies_over() {
        let mut rest = Vec::new();
        let top = strip(&mut rest, 0.0, true);
        let above = strip(&mut rest, 2.0, false);
        let n = OwnNeighbourhood::new(
            rest.clone(),
            &[&top[..], &above[..]].concat(),
            0.004,
            (0.001, 0.01),
        );
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
}
