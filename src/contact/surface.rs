//! A contact surface: the boundary facets of a body split into triangles (the paper uses
//! triangles for the fingers "because the four surface points are generally not in the same
//! plane"), with a bounding-volume hierarchy (parry3d-f64) over their current positions, and the
//! projection of a point onto the nearest facet: the point C of Figure 5, its barycentric weights
//! h_i (the interpolation functions at C, so that a force R_C is shared as R_i = h_i·R_C) and the
//! facet normal n_F.

use super::bounds::Bounds;
use nalgebra::Vector3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhNode};
use rustc_hash::FxHashMap;

/// Facets around a corner whose normals turn from a facet's by less than this, degrees, are
/// smoothed over in its contact normal ([`ContactSurface::smoothed_normal`]); an edge sharper
/// than it is a crease of the body and stays sharp.
pub const FEATURE_ANGLE_DEG: f64 = 30.0;

/// Triangles over global node indices, outward normals.
#[derive(Clone, Debug)]
pub struct ContactSurface {
    /// The body (model index) the facets belong to.
    pub body: usize,
    /// Triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[usize; 3]>,
    /// Unit normal at every node at the positions the surface was made from (see
    /// [`ContactSurface::node_normals`]).
    reference_normals: FxHashMap<usize, Vector3<f64>>,
    /// The triangles (indices into `triangles`) around each node.
    around: FxHashMap<usize, Vec<usize>>,
}

/// The projection of a point onto a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// The triangle's nodes.
    pub nodes: [usize; 3],
    /// Barycentric weights h_i of the projection point C (sum 1, each ≥ 0).
    pub weights: [f64; 3],
    /// Outward unit normal n_F of the facet.
    pub normal: Vector3<f64>,
    /// Signed gap (x − C)·n_F, m: negative when the point is behind the facet (penetrating).
    pub gap: f64,
    /// Distance |x − C|, m.
    pub distance: f64,
}

impl ContactSurface {
    /// The surface of quadrilaterals `quads` (outward, repeated nodes allowed): each quad split
    /// along its shorter diagonal at `positions`.
    pub fn from_quads(body: usize, quads: &[[usize; 4]], positions: &[Vector3<f64>]) -> Self {
        Self::from_quads_split_at(body, quads, positions, positions)
    }

    /// [`Self::from_quads`] with each quad split along its shorter diagonal at `split` (the
    /// rest geometry, so that a quad folded by the motion keeps its diagonal from step to step:
    /// a point held on one of its triangles is not left behind the other diagonal's), the
    /// surface at `positions`.
    pub fn from_quads_split_at(
        body: usize,
        quads: &[[usize; 4]],
        split: &[Vector3<f64>],
        positions: &[Vector3<f64>],
    ) -> Self {
        let mut triangles = Vec::with_capacity(2 * quads.len());
        for q in quads {
            let mut distinct: Vec<usize> = Vec::with_capacity(4);
            for &n in q {
                if distinct.last() != Some(&n) && distinct.first() != Some(&n) {
                    distinct.push(n);
                }
            }
            match distinct.len() {
                3 => triangles.push([distinct[0], distinct[1], distinct[2]]),
                4 => {
                    let d02 = (split[q[2]] - split[q[0]]).norm();
                    let d13 = (split[q[3]] - split[q[1]]).norm();
                    if d02 <= d13 {
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    } else {
                        triangles.push([q[0], q[1], q[3]]);
                        triangles.push([q[1], q[2], q[3]]);
                    }
                }
                _ => {}
            }
        }
        ContactSurface::new(body, triangles, positions)
    }

    /// The surface of `triangles` (counter-clockwise seen from outside) at `positions`.
    pub fn new(body: usize, triangles: Vec<[usize; 3]>, positions: &[Vector3<f64>]) -> Self {
        let mut around: FxHashMap<usize, Vec<usize>> = FxHashMap::default();
        for (i, t) in triangles.iter().enumerate() {
            for &v in t {
                around.entry(v).or_default().push(i);
            }
        }
        let mut s = ContactSurface {
            body,
            triangles,
            reference_normals: FxHashMap::default(),
            around,
        };
        s.reference_normals = s.node_normals(positions);
        s
    }

    /// The node normals at the positions the surface was made from.
    pub fn reference_normals(&self) -> &FxHashMap<usize, Vector3<f64>> {
        &self.reference_normals
    }

    /// The nodes of the surface, sorted, without repeats.
    pub fn nodes(&self) -> Vec<usize> {
        let mut n: Vec<usize> = self.triangles.iter().flatten().copied().collect();
        n.sort_unstable();
        n.dedup();
        n
    }

    /// Unit normal at every node of the surface (area-weighted mean of its triangles'), at
    /// `positions`.
    pub fn node_normals(&self, positions: &[Vector3<f64>]) -> FxHashMap<usize, Vector3<f64>> {
        let mut out: FxHashMap<usize, Vector3<f64>> = Default::default();
        for t in &self.triangles {
            let n = (positions[t[1]] - positions[t[0]]).cross(&(positions[t[2]] - positions[t[0]]));
            for &v in t {
                *out.entry(v).or_insert_with(Vector3::zeros) += n;
            }
        }
        for n in out.values_mut() {
            let l = n.norm();
            if l > 0.0 {
                *n /= l;
            }
        }
        out
    }

    /// The surface's smoothed outward normal at the point of facet `nodes` with barycentric
    /// weights `weights`, at `positions`: the weights' blend of the facet's corner normals,
    /// each the area-weighted mean of the normals of the triangles around the corner that
    /// turn from this facet's by less than [`FEATURE_ANGLE_DEG`] (a crease or an edge of the
    /// body stays sharp). Across an edge between two facets that meet at a smaller angle, with
    /// every triangle around its two ends within that angle of both (the ball: everywhere), the
    /// normal is continuous — the two facets give the same normal on their shared edge — so a
    /// contact point sliding over it is not pushed along a normal that jumps by the angle
    /// between the facets (a faceted ball's 7.5°): the contact's fixed point at a pose then
    /// exists (Puso and Laursen 2002 smooth the master surface for the same reason). The
    /// facet's own normal where it is flat or alone.
    pub fn smoothed_normal(
        &self,
        nodes: &[usize; 3],
        weights: &[f64; 3],
        positions: &[Vector3<f64>],
    ) -> Option<Vector3<f64>> {
        let area_normal = |t: &[usize; 3]| {
            (positions[t[1]] - positions[t[0]]).cross(&(positions[t[2]] - positions[t[0]]))
        };
        let own = area_normal(nodes).try_normalize(0.0)?;
        let cos_feature = FEATURE_ANGLE_DEG.to_radians().cos();
        let mut blend = Vector3::zeros();
        for (corner, w) in nodes.iter().zip(weights) {
            let mut n = Vector3::zeros();
            for &t in self.around.get(corner).into_iter().flatten() {
                let a = area_normal(&self.triangles[t]);
                let l = a.norm();
                if l > 0.0 && a.dot(&own) >= cos_feature * l {
                    n += a;
                }
            }
            let n = n.try_normalize(0.0).unwrap_or(own);
            blend += n * *w;
        }
        Some(blend.try_normalize(0.0).unwrap_or(own))
    }

    /// A hierarchy over the triangles at `positions`, each box grown by `margin` (m).
    pub fn hierarchy<'a>(&'a self, positions: &'a [Vector3<f64>], margin: f64) -> SurfaceBvh<'a> {
        let boxes = self
            .triangles
            .iter()
            .map(|t| Bounds::of(t.map(|n| &positions[n])).grown(margin));
        SurfaceBvh {
            grown: Some(Grown::of(positions, margin, self.triangles.iter())),
            ..self.over_boxes(boxes)
        }
    }

    /// Its bounding-volume hierarchy over the boxes the facets sweep from `start` to `now`
    /// (each corner moving straight): what a point's path over a step may meet
    /// ([`SurfaceBvh::project_near`]).
    pub fn swept_hierarchy(&self, start: &[Vector3<f64>], now: &[Vector3<f64>]) -> SurfaceBvh<'_> {
        let boxes = self
            .triangles
            .iter()
            .map(|t| Bounds::of(t.iter().flat_map(|&c| [&start[c], &now[c]])));
        self.over_boxes(boxes)
    }

    /// [`Self::hierarchy`] over only the facets whose grown box meets `region`: for every point
    /// inside `region` the same facets (a facet left out could not hold it), built over a few
    /// of a large surface's facets (a hand's skin against the box of the ball it holds: a
    /// drag's every contact step builds it). The tree is another, so facets are met in another
    /// order: where two are equally near (a point over a convex edge), [`SurfaceBvh::project`]
    /// may keep the other one, with its own signed gap.
    pub fn hierarchy_meeting<'a>(
        &'a self,
        positions: &'a [Vector3<f64>],
        margin: f64,
        region: &Bounds,
    ) -> SurfaceBvh<'a> {
        let (facets, boxes): (Vec<usize>, Vec<Aabb>) = self
            .triangles
            .iter()
            .enumerate()
            .map(|(f, t)| (f, Bounds::of(t.map(|n| &positions[n])).grown(margin)))
            .filter(|(_, b)| b.meets(region))
            .map(|(f, b)| (f, b.aabb()))
            .unzip();
        SurfaceBvh {
            surface: self,
            bvh: Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes),
            grown: Some(Grown::of(
                positions,
                margin,
                facets.iter().map(|&f| &self.triangles[f]),
            )),
            facets: Some(facets),
        }
    }

    /// A hierarchy over one box per facet.
    fn over_boxes(&self, boxes: impl Iterator<Item = Bounds>) -> SurfaceBvh<'_> {
        let boxes: Vec<Aabb> = boxes.map(|b| b.aabb()).collect();
        SurfaceBvh {
            surface: self,
            bvh: Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes),
            facets: None,
            grown: None,
        }
    }
}

/// A surface with its bounding-volume hierarchy at one set of positions.
pub struct SurfaceBvh<'a> {
    surface: &'a ContactSurface,
    bvh: Bvh,
    /// The facet of each leaf, where the hierarchy holds only some (`None`: leaf i is facet i).
    facets: Option<Vec<usize>>,
    /// Where every leaf's box is its facet's box grown by one margin, at the positions it was
    /// built from: how near a subtree's facets may lie (`None`: boxes of another kind).
    grown: Option<Grown<'a>>,
}

/// The margin a hierarchy's boxes were grown by, and the positions they were made from
/// (borrowed while the hierarchy lives): a node's box shrunk by the margin holds its facets
/// there.
struct Grown<'a> {
    margin: f64,
    positions: &'a [Vector3<f64>],
    /// The longest edge of a facet held, m.
    longest_edge: f64,
}

impl<'a> Grown<'a> {
    fn of<'t>(
        positions: &'a [Vector3<f64>],
        margin: f64,
        facets: impl Iterator<Item = &'t [usize; 3]>,
    ) -> Grown<'a> {
        let longest_edge = facets
            .flat_map(|t| (0..3).map(move |i| (t[i], t[(i + 1) % 3])))
            .map(|(a, b)| (positions[a] - positions[b]).norm())
            .fold(0.0, f64::max);
        Grown {
            margin,
            positions,
            longest_edge,
        }
    }

    /// The distance from `x` to `node`'s box shrunk by the margin: no facet under it is nearer.
    fn distance(&self, node: &BvhNode, x: &Vector3<f64>) -> f64 {
        let (lo, hi) = (node.mins(), node.maxs());
        (0..3)
            .map(|i| {
                let (a, b) = (lo[i] + self.margin, hi[i] - self.margin);
                (a - x[i]).max(x[i] - b).max(0.0).powi(2)
            })
            .sum::<f64>()
            .sqrt()
    }
}

impl SurfaceBvh<'_> {
    /// The facet (an index into the surface's triangles) of a leaf.
    fn facet(&self, leaf: u32) -> usize {
        self.facets
            .as_ref()
            .map_or(leaf as usize, |f| f[leaf as usize])
    }

    /// The nearest facet to `x` among those whose grown box contains `x`, unless `skip` says
    /// the facet must be ignored (e.g. it contains the point's own node); between equally near
    /// facets, the one whose normal is most opposed to `prefer` (the point's own normal).
    pub fn project(
        &self,
        x: &Vector3<f64>,
        positions: &[Vector3<f64>],
        prefer: Option<&Vector3<f64>>,
        skip: impl Fn(&[usize; 3]) -> bool,
    ) -> Option<Projection> {
        // How near the nearest facet lies, found first (nearer subtrees first: a few facets);
        // then the facets no farther than that, met in the hierarchy's order as every facet
        // was (a subtree whose facets all lie farther is left: none of them could be nearer,
        // nor tie) — the same facet as a search of all of them.
        let within = self.nearest_distance(x, positions, &skip)?;
        let mut best: Option<Projection> = None;
        self.for_each_facet(x, positions, skip, within, |p, proj| {
            if nearer(&proj, best.as_ref(), (p[1] - p[0]).norm(), prefer) {
                best = Some(proj);
            }
        });
        best
    }

    /// As [`Self::project`], over the facets whose box meets the box `near` instead of
    /// those whose box contains `x` (a hierarchy of swept boxes, [`ContactSurface::swept_hierarchy`],
    /// and a point's path: the facets it may have met over the step).
    pub fn project_near(
        &self,
        x: &Vector3<f64>,
        near: &Bounds,
        positions: &[Vector3<f64>],
        prefer: Option<&Vector3<f64>>,
        skip: impl Fn(&[usize; 3]) -> bool,
    ) -> Option<Projection> {
        let query = near.aabb();
        let mut best: Option<Projection> = None;
        self.for_each_facet_in(&query, x, positions, skip, |p, proj| {
            if nearer(&proj, best.as_ref(), (p[1] - p[0]).norm(), prefer) {
                best = Some(proj);
            }
        });
        best
    }

    /// The facets (indices into the surface's triangles) whose box meets `query`.
    pub fn facets_meeting(&self, query: &Bounds) -> Vec<usize> {
        self.facets_meeting_iter(query).collect()
    }

    /// [`Self::facets_meeting`], one at a time (nothing allocated).
    pub fn facets_meeting_iter(&self, query: &Bounds) -> impl Iterator<Item = usize> + '_ {
        let query = BvhNode::leaf(query.aabb(), 0);
        self.bvh
            .leaves(move |node: &BvhNode| node.intersects(&query))
            .map(|leaf| self.facet(leaf))
    }

    /// The distance from `x` to the nearest facet whose grown box holds it and that `skip`
    /// leaves (`None`: there is none); infinite where the boxes are not grown at `positions`.
    fn nearest_distance(
        &self,
        x: &Vector3<f64>,
        positions: &[Vector3<f64>],
        skip: &impl Fn(&[usize; 3]) -> bool,
    ) -> Option<f64> {
        let Some(grown) = self.grown_at(positions) else {
            return Some(f64::INFINITY);
        };
        let query = BvhNode::leaf(Bounds::of([x]).aabb(), 0);
        self.bvh
            .find_best(
                f64::MAX,
                |node: &BvhNode, _| {
                    if node.intersects(&query) {
                        grown.distance(node, x)
                    } else {
                        f64::MAX
                    }
                },
                |leaf, _| {
                    let nodes = self.surface.triangles[self.facet(leaf)];
                    if skip(&nodes) {
                        return None;
                    }
                    project_on_triangle(x, &nodes.map(|n| positions[n])).map(|p| p.distance)
                },
            )
            .map(|(_, d)| d)
    }

    /// How its boxes were grown, where they were made from `positions`.
    fn grown_at(&self, positions: &[Vector3<f64>]) -> Option<&Grown<'_>> {
        self.grown
            .as_ref()
            .filter(|g| std::ptr::eq(g.positions, positions))
    }

    /// Calls `f` with the corners and the projection of `x` of every facet whose grown box
    /// contains `x` and that `skip` leaves, of those that may lie within `within` of `x` (a
    /// subtree whose facets all lie farther by its box is left out).
    fn for_each_facet(
        &self,
        x: &Vector3<f64>,
        positions: &[Vector3<f64>],
        skip: impl Fn(&[usize; 3]) -> bool,
        within: f64,
        f: impl FnMut(&[Vector3<f64>; 3], Projection),
    ) {
        let query = BvhNode::leaf(Bounds::of([x]).aabb(), 0);
        // (The boxes shrunk back to their facets' only at the positions they were made from.)
        let grown = self.grown_at(positions);
        let near = |node: &BvhNode| {
            grown.is_none_or(|g| {
                // (An allowance far above the rounding of the boxes grown and shrunk, and above
                // the ties of `nearer` and `behind_feature`, relative to sizes their tolerances
                // scale with: the distance and a facet's edge.)
                g.distance(node, x) <= within + 1e-6 * (within + g.margin + g.longest_edge)
            })
        };
        let leaves = self
            .bvh
            .leaves(|node| node.intersects(&query) && near(node));
        self.project_on_leaves(leaves, x, positions, skip, f)
    }

    /// Calls `f` with the corners and the projection of `x` of every facet whose box meets
    /// `query` and that `skip` leaves.
    fn for_each_facet_in(
        &self,
        query: &Aabb,
        x: &Vector3<f64>,
        positions: &[Vector3<f64>],
        skip: impl Fn(&[usize; 3]) -> bool,
        f: impl FnMut(&[Vector3<f64>; 3], Projection),
    ) {
        self.project_on_leaves(self.bvh.intersect_aabb(query), x, positions, skip, f)
    }

    /// Calls `f` with the corners and the projection of `x` of the facet of each of `leaves`
    /// that `skip` leaves (and that is not flat), in their order.
    fn project_on_leaves(
        &self,
        leaves: impl Iterator<Item = u32>,
        x: &Vector3<f64>,
        positions: &[Vector3<f64>],
        skip: impl Fn(&[usize; 3]) -> bool,
        mut f: impl FnMut(&[Vector3<f64>; 3], Projection),
    ) {
        for leaf in leaves {
            let nodes = self.surface.triangles[self.facet(leaf)];
            if skip(&nodes) {
                continue;
            }
            let p = nodes.map(|n| positions[n]);
            if let Some(proj) = project_on_triangle(x, &p) {
                f(&p, Projection { nodes, ..proj });
            }
        }
    }

    /// Whether `x`, whose nearest facet is `nearest` with its closest point on an edge or a
    /// corner (where the facet's own side can be wrong: a point in a pit of a dented surface
    /// is beyond every facet around the pit's bottom, yet in front of the nearest one's
    /// plane), lies inside by the angle-weighted pseudonormal of that edge or corner
    /// (Bærentzen and Aanæs 2005): then the facet around it the point is deepest behind, with
    /// its own signed gap from the shared closest point.
    pub fn behind_feature(
        &self,
        x: &Vector3<f64>,
        positions: &[Vector3<f64>],
        nearest: &Projection,
        skip: impl Fn(&[usize; 3]) -> bool,
    ) -> Option<Projection> {
        // Interior closest point: the facet's own side is right.
        if nearest.weights.iter().all(|&w| w > 1e-9) {
            return None;
        }
        let closest: Vector3<f64> = (0..3)
            .map(|i| positions[nearest.nodes[i]] * nearest.weights[i])
            .sum();
        let scale =
            nearest.distance + (positions[nearest.nodes[1]] - positions[nearest.nodes[0]]).norm();
        let mut pseudonormal = Vector3::zeros();
        let mut deepest: Option<Projection> = None;
        self.for_each_facet(x, positions, skip, nearest.distance, |p, proj| {
            if (proj.distance - nearest.distance).abs() > 1e-9 * scale {
                return;
            }
            // The facet's angle at the shared corner (π along an edge: both sides alike).
            let corner = proj.weights.iter().position(|&w| w > 1.0 - 1e-9);
            let angle = corner.map_or(std::f64::consts::PI, |i| {
                let (a, b) = (p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]);
                a.angle(&b)
            });
            pseudonormal += proj.normal * angle;
            let gap = proj.normal.dot(&(x - closest));
            if deepest.as_ref().is_none_or(|d| gap < d.gap) {
                deepest = Some(Projection { gap, ..proj });
            }
        });
        (pseudonormal.dot(&(x - closest)) < 0.0)
            .then_some(deepest)
            .flatten()
            .filter(|d| d.gap < 0.0)
    }
}

/// Whether `proj` is nearer than `best`: nearest first; on a tie (a node on an edge or a corner,
/// as close to two facets; `edge`: a length of the facet, for the round-off), the facet that
/// faces `prefer` (the point's own normal) most.
fn nearer(
    proj: &Projection,
    best: Option<&Projection>,
    edge: f64,
    prefer: Option<&Vector3<f64>>,
) -> bool {
    match best {
        None => true,
        Some(b) => {
            let tie =
                (proj.distance - b.distance).abs() <= 1e-9 * (proj.distance.max(b.distance) + edge);
            if tie {
                match prefer {
                    Some(m) => proj.normal.dot(m) < b.normal.dot(m),
                    None => false,
                }
            } else {
                proj.distance < b.distance
            }
        }
    }
}

/// Closest point of triangle `p` to `x` (Ericson, Real-Time Collision Detection §5.1.5), with
/// its barycentric weights, the facet normal and the signed gap; `None` for a flat triangle.
pub fn project_on_triangle(x: &Vector3<f64>, p: &[Vector3<f64>; 3]) -> Option<Projection> {
    let (a, b, c) = (p[0], p[1], p[2]);
    let normal = (b - a).cross(&(c - a));
    let area2 = normal.norm();
    if area2 <= 0.0 || !area2.is_finite() {
        return None;
    }
    let normal = normal / area2;
    let ab = b - a;
    let ac = c - a;
    let ap = x - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    let weights = if d1 <= 0.0 && d2 <= 0.0 {
        [1.0, 0.0, 0.0]
    } else {
        let bp = x - b;
        let d3 = ab.dot(&bp);
        let d4 = ac.dot(&bp);
        let cp = x - c;
        let d5 = ab.dot(&cp);
        let d6 = ac.dot(&cp);
        let vc = d1 * d4 - d3 * d2;
        let vb = d5 * d2 - d1 * d6;
        let va = d3 * d6 - d5 * d4;
        if d3 >= 0.0 && d4 <= d3 {
            [0.0, 1.0, 0.0]
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            let v = d1 / (d1 - d3);
            [1.0 - v, v, 0.0]
        } else if d6 >= 0.0 && d5 <= d6 {
            [0.0, 0.0, 1.0]
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            let w = d2 / (d2 - d6);
            [1.0 - w, 0.0, w]
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            [0.0, 1.0 - w, w]
        } else {
            let denom = 1.0 / (va + vb + vc);
            let v = vb * denom;
            let w = vc * denom;
            [1.0 - v - w, v, w]
        }
    };
    let point = a * weights[0] + b * weights[1] + c * weights[2];
    Some(Projection {
        nodes: [0, 1, 2],
        weights,
        normal,
        gap: (x - point).dot(&normal),
        distance: (x - point).norm(),
    })
}

/// The closed pieces of a surface (a shell's outer and inner surfaces): its triangles grouped
/// by the nodes they share.
pub fn connected_pieces(triangles: &[[usize; 3]]) -> Vec<Vec<[usize; 3]>> {
    let mut parent: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    fn root(parent: &mut std::collections::HashMap<usize, usize>, n: usize) -> usize {
        let mut r = n;
        while let Some(&p) = parent.get(&r) {
            if p == r {
                break;
            }
            r = p;
        }
        parent.insert(n, r);
        r
    }
    for t in triangles {
        for &n in t {
            parent.entry(n).or_insert(n);
        }
        let r0 = root(&mut parent, t[0]);
        for &n in &t[1..] {
            let r = root(&mut parent, n);
            if r != r0 {
                parent.insert(r, r0);
            }
        }
    }
    let mut pieces: std::collections::BTreeMap<usize, Vec<[usize; 3]>> = Default::default();
    for t in triangles {
        let r = root(&mut parent, t[0]);
        pieces.entry(r).or_default().push(*t);
    }
    pieces.into_values().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sheet of (n − 1)² quads 1 mm apart over x and y, each split into two triangles, at
    /// height `z(x, y)`: its nodes and its surface.
    fn sheet(n: usize, z: impl Fn(f64, f64) -> f64) -> (Vec<Vector3<f64>>, ContactSurface) {
        let nodes: Vec<Vector3<f64>> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f64 * 1e-3, (i / n) as f64 * 1e-3);
                Vector3::new(x, y, z(x, y))
            })
            .collect();
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = j * n + i;
                triangles.push([a, a + 1, a + n + 1]);
                triangles.push([a, a + n + 1, a + n]);
            }
        }
        let surface = ContactSurface::new(0, triangles, &nodes);
        (nodes, surface)
    }

    /// A wave 0.5 mm high.
    fn wave(x: f64, y: f64) -> f64 {
        0.5e-3 * (300.0 * x).sin() * (200.0 * y).cos()
    }

    /// The nearest facet found by leaving the subtrees farther than the nearest is the one a
    /// search of every facet whose grown box holds the point finds — the same facet, gap and
    /// weights, where two or more facets are equally near too (points over the edges and
    /// corners of a sheet's flat half, with and without a normal to prefer, some facets
    /// skipped) — and so is the facet a point is deepest behind at an edge or a corner.
    #[test]
    fn the_pruned_search_finds_the_facet_a_search_of_every_facet_finds() {
        // Flat for x < 8 mm, wavy beyond.
        let n = 21;
        let (nodes, surface) = sheet(n, |x, y| if x < 8e-3 { 0.0 } else { wave(x, y) });
        let margin = 2e-3;
        let pruned = surface.hierarchy(&nodes, margin);
        // (At other positions — the same values elsewhere — nothing is left out.)
        let elsewhere = nodes.clone();
        let mut rng = crate::contact::differences::Rng(777);
        let (mut ties, mut found, mut behind) = (0, 0, 0);
        for k in 0..3000 {
            // Over a vertex or an edge's midpoint of the flat half, or anywhere.
            let (i, j) = ((k % 15) as f64, ((k / 15) % 19) as f64);
            let half = if k % 3 == 1 { 0.5 } else { 0.0 };
            let x = match k % 4 {
                3 => Vector3::from_fn(|a, _| rng.range(-1e-3, [21e-3, 21e-3, 2e-3][a])),
                _ => Vector3::new(
                    (i * 0.5 + half) * 1e-3,
                    (j + half) * 1e-3,
                    rng.range(-2e-3, 2e-3),
                ),
            };
            let up = Vector3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 1.0).normalize();
            let prefer = (k % 2 == 0).then_some(&up);
            let skip = |t: &[usize; 3]| k % 5 == 0 && t.contains(&(k % (n * n)));
            let a = pruned.project(&x, &nodes, prefer, skip);
            let b = pruned.project(&x, &elsewhere, prefer, skip);
            match (&a, &b) {
                (Some(a), Some(b)) => {
                    assert_eq!(
                        (a.nodes, a.gap, a.weights),
                        (b.nodes, b.gap, b.weights),
                        "{x:?}"
                    );
                    found += 1;
                    let mut equally = 0;
                    pruned.for_each_facet(&x, &elsewhere, skip, f64::INFINITY, |p, q| {
                        let scale = q.distance + (p[1] - p[0]).norm();
                        equally += usize::from((q.distance - a.distance).abs() <= 1e-9 * scale);
                    });
                    ties += usize::from(equally > 1);
                    let c = pruned.behind_feature(&x, &nodes, a, skip);
                    let d = pruned.behind_feature(&x, &elsewhere, a, skip);
                    assert_eq!(c.map(|c| (c.nodes, c.gap)), d.map(|d| (d.nodes, d.gap)));
                    behind += usize::from(c.is_some());
                }
                (None, None) => {}
                _ => panic!(
                    "{x:?}: {:?} against {:?}",
                    a.map(|p| p.nodes),
                    b.map(|p| p.nodes)
                ),
            }
        }
        assert!(
            found > 2000 && ties > 300,
            "{found} found, {ties} with ties"
        );
        assert!(behind > 0, "no point behind an edge or a corner");
    }

    /// A hierarchy over the facets that may hold a point of a box answers as the whole one for
    /// every point in the box — the same facets met, and (no two facets equally near a random
    /// point of this sheet) the same nearest facet, gap and weights — and holds fewer facets (a
    /// hand's skin against the box of a ball).
    #[test]
    fn a_hierarchy_over_the_facets_near_a_box_answers_as_the_whole_one_inside_it() {
        // A wavy sheet.
        let (nodes, surface) = sheet(21, wave);
        let margin = 2e-3;
        let region = Bounds {
            lo: Vector3::new(4e-3, 5e-3, -3e-3),
            hi: Vector3::new(9e-3, 8e-3, 3e-3),
        };
        let whole = surface.hierarchy(&nodes, margin);
        let near = surface.hierarchy_meeting(&nodes, margin, &region);
        let held = near.facets.as_ref().map_or(0, Vec::len);
        assert!(
            held > 0 && held < surface.triangles.len() / 2,
            "{held} facets held"
        );
        let mut rng = crate::contact::differences::Rng(12345);
        let mut found = 0;
        for _ in 0..500 {
            let x = Vector3::from_fn(|i, _| rng.range(region.lo[i], region.hi[i]));
            let a = whole.project(&x, &nodes, None, |_| false);
            let b = near.project(&x, &nodes, None, |_| false);
            match (a, b) {
                (Some(a), Some(b)) => {
                    assert_eq!(a.nodes, b.nodes);
                    assert_eq!(a.gap, b.gap);
                    assert_eq!(a.weights, b.weights);
                    found += 1;
                }
                (None, None) => {}
                (a, b) => panic!(
                    "{x:?}: {:?} against {:?}",
                    a.map(|p| p.nodes),
                    b.map(|p| p.nodes)
                ),
            }
            let query = Bounds::of([&x]);
            let mut met_whole = whole.facets_meeting(&query);
            let mut met_near = near.facets_meeting(&query);
            met_whole.sort_unstable();
            met_near.sort_unstable();
            assert_eq!(met_whole, met_near);
        }
        assert!(found > 100, "{found} points near the sheet");
    }

    /// The hierarchy of swept boxes holds a facet wherever it passed over a step: a path that
    /// met its sweep finds it (the nearest of those `skip` leaves, as [`SurfaceBvh::project`]
    /// finds it among the facets near a point), a path beside the sweep does not.
    #[test]
    fn a_swept_hierarchy_finds_the_facets_a_path_may_have_met() {
        // Two unit triangles facing +z, side by side along x; both rise from z = 0 to z = 1.
        let start = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(3.0, 0.0, 0.0),
            Vector3::new(4.0, 0.0, 0.0),
            Vector3::new(3.0, 1.0, 0.0),
        ];
        let now: Vec<Vector3<f64>> = start.iter().map(|p| p + Vector3::z()).collect();
        let surface = ContactSurface::new(0, vec![[0, 1, 2], [3, 4, 5]], &start);
        let swept = surface.swept_hierarchy(&start, &now);
        // A still point at z = 0.5 over the first: the first's sweep passed it.
        let x = Vector3::new(0.2, 0.2, 0.5);
        let found = swept
            .project_near(&x, &Bounds::of([&x, &x]), &now, None, |_| false)
            .unwrap();
        assert_eq!(found.nodes, [0, 1, 2]);
        assert!((found.gap + 0.5).abs() < 1e-12, "{found:?}");
        // Neither facet when it is skipped... the other one only if the path reaches it.
        let first = |t: &[usize; 3]| t[0] == 0;
        assert!(swept
            .project_near(&x, &Bounds::of([&x, &x]), &now, None, first)
            .is_none());
        let to = Vector3::new(3.2, 0.2, 0.5);
        let near = swept
            .project_near(&to, &Bounds::of([&x, &to]), &now, None, first)
            .unwrap();
        assert_eq!(near.nodes, [3, 4, 5]);
        // Above every sweep, or beside both: nothing.
        let above = Vector3::new(0.2, 0.2, 1.5);
        assert!(swept
            .project_near(&above, &Bounds::of([&above, &above]), &now, None, |_| false)
            .is_none());
        let beside = Vector3::new(1.8, 0.5, 0.5);
        assert!(swept
            .project_near(&beside, &Bounds::of([&beside, &beside]), &now, None, |_| {
                false
            })
            .is_none());
    }

    /// Two triangles sharing the edge 0–1 along x, the second folded down by `fold` degrees
    /// about it: nodes 0, 1 on the edge, 2 on the flat side (y < 0), 3 on the folded side.
    fn folded(fold: f64) -> (ContactSurface, Vec<Vector3<f64>>) {
        let a = fold.to_radians();
        let positions = vec![
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.5, -1.0, 0.0),
            Vector3::new(0.5, a.cos(), -a.sin()),
        ];
        let s = ContactSurface::new(0, vec![[0, 2, 1], [0, 1, 3]], &positions);
        (s, positions)
    }

    /// Across an edge folded by less than the feature angle the contact normal is continuous:
    /// at a point of the shared edge both facets give the same normal, the bisector of theirs;
    /// at their far corners each gives its own. An edge folded by more (a body's crease) stays
    /// sharp: each facet gives its own normal everywhere.
    #[test]
    fn the_contact_normal_is_smooth_across_a_gentle_edge_and_sharp_at_a_crease() {
        let (s, x) = folded(10.0);
        let on_edge = |t: [usize; 3]| {
            let w = t.map(|n| match n {
                0 => 0.3,
                1 => 0.7,
                _ => 0.0,
            });
            s.smoothed_normal(&t, &w, &x).unwrap()
        };
        let (flat, bent) = (on_edge([0, 2, 1]), on_edge([0, 1, 3]));
        assert!((flat - bent).norm() < 1e-12, "{flat} against {bent}");
        let bisector = Vector3::new(0.0, 5f64.to_radians().sin(), 5f64.to_radians().cos());
        assert!((flat - bisector).norm() < 1e-12, "{flat}");
        let far = s.smoothed_normal(&[0, 2, 1], &[0.0, 1.0, 0.0], &x).unwrap();
        assert!((far - Vector3::z()).norm() < 1e-12, "{far}");
        // Against the facet normals it replaces, the jump across the edge: 10°.
        let own = |t: [usize; 3]| {
            project_on_triangle(&Vector3::new(0.5, 0.0, 1.0), &t.map(|n| x[n]))
                .unwrap()
                .normal
        };
        assert!((own([0, 2, 1]).angle(&own([0, 1, 3])).to_degrees() - 10.0).abs() < 1e-9);

        let (s, x) = folded(60.0);
        for t in [[0, 2, 1], [0, 1, 3]] {
            let own = project_on_triangle(&Vector3::zeros(), &t.map(|n| x[n]))
                .unwrap()
                .normal;
            let n = s.smoothed_normal(&t, &[0.5, 0.5, 0.0], &x).unwrap();
            assert!((n - own).norm() < 1e-12, "{n} against {own}");
        }
    }

    #[test]
    fn projection_inside_edge_and_vertex() {
        let p = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
        ];
        let q = project_on_triangle(&Vector3::new(0.25, 0.25, -0.5), &p).unwrap();
        assert!((q.weights[0] - 0.5).abs() < 1e-15 && (q.weights[1] - 0.25).abs() < 1e-15);
        assert!((q.gap + 0.5).abs() < 1e-15);
        let e = project_on_triangle(&Vector3::new(0.5, -1.0, 0.0), &p).unwrap();
        assert_eq!(e.weights, [0.5, 0.5, 0.0]);
        let v = project_on_triangle(&Vector3::new(2.0, -1.0, 0.3), &p).unwrap();
        assert_eq!(v.weights, [0.0, 1.0, 0.0]);
    }
}
