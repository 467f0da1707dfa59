//! An imported skin: a triangle mesh (an animator's hand, in the hand frame) as the skin's shape,
//! a signed distance cut at the wrist.
//!
//! The mesh is checked and mended before it is used: vertices at one position (split along UV
//! seams by exporters) are welded, degenerate triangles dropped, the triangles proximal of the
//! wrist cut dropped (a forearm, an arm or a whole body beyond it does not matter), the faces
//! oriented consistently and outwards. Sheets that touch along edges (fingers modelled touching)
//! are kept. What cannot be mended is an error that says where: a fin (an edge of three
//! triangles, or of more that do not pair up), a hole other than the wrist's, the skin passing
//! through itself. The sign of the distance comes from the angle-weighted pseudonormals of the
//! nearest feature (Bærentzen & Aanæs 2005), so the mesh may stay open at the wrist: every point
//! distal of the cut is nearer the skin around it than the open rim.

use nalgebra::Vector3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vec3;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query::{PointQuery, Ray, RayCast};
use parry3d_f64::shape::{TriMesh, TriMeshFlags};
use std::collections::HashMap;

/// What makes a skin mesh unusable. Points are in the hand frame, m (the importer states them in
/// the file's coordinates).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SkinMeshError {
    /// No triangle distal of the wrist.
    #[error("the skin mesh has no triangle distal of the wrist")]
    Empty,
    /// A coordinate is not a finite number.
    #[error("vertex {vertex} of the skin mesh is not a finite point")]
    NotFinite {
        /// The vertex (as in the file).
        vertex: usize,
    },
    /// Edges shared by more than two triangles that do not pair up, on more than 0.5 % of the
    /// edges.
    #[error(
        "the skin mesh is not manifold: {edges} of its edges are shared by more than two \
         triangles, one near {at} by {faces}"
    )]
    NonManifold {
        /// The first such edge's midpoint.
        at: Located,
        /// Triangles on it.
        faces: usize,
        /// How many such edges.
        edges: usize,
    },
    /// Faces that cannot be oriented consistently (a Möbius-like strip).
    #[error("the skin mesh cannot be oriented consistently (near {at}): it has no inside")]
    NotOrientable {
        /// A point of the conflict.
        at: Located,
    },
    /// A hole away from the wrist.
    #[error(
        "the skin mesh has a hole near {at}, {edges} edges around, {across_mm:.1} mm across, away \
         from the wrist: close it in the modelling tool (only the wrist may be open)"
    )]
    Hole {
        /// The hole's centre.
        at: Located,
        /// Edges around it.
        edges: usize,
        /// Its largest extent, mm.
        across_mm: f64,
        /// The largest x of its rim (hand frame), m.
        reach_x: f64,
    },
    /// Two triangles pass through each other.
    #[error(
        "the skin mesh passes through itself near {at}: two of its triangles cross there, \
         {depth_mm:.2} mm deep (shallower than {tolerance_mm:.2} mm is let be)"
    )]
    SelfIntersecting {
        /// A point on the crossing.
        at: Located,
        /// How deep the triangles pass through each other, mm.
        depth_mm: f64,
        /// The depth let be, mm.
        tolerance_mm: f64,
    },
}

/// A point of an error, printed in mm in the coordinates it has been mapped to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Located(pub Vector3<f64>);

impl std::fmt::Display for Located {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = self.0 * 1000.0;
        write!(f, "({:.1}, {:.1}, {:.1}) mm", p.x, p.y, p.z)
    }
}

impl SkinMeshError {
    /// The error with its point mapped by `f` (from the hand frame to the file's coordinates).
    pub fn mapped(self, f: impl Fn(Vector3<f64>) -> Vector3<f64>) -> SkinMeshError {
        let m = |l: Located| Located(f(l.0));
        match self {
            SkinMeshError::NonManifold { at, faces, edges } => SkinMeshError::NonManifold {
                at: m(at),
                faces,
                edges,
            },
            SkinMeshError::NotOrientable { at } => SkinMeshError::NotOrientable { at: m(at) },
            SkinMeshError::Hole {
                at,
                edges,
                across_mm,
                reach_x,
            } => SkinMeshError::Hole {
                at: m(at),
                edges,
                across_mm,
                reach_x,
            },
            SkinMeshError::SelfIntersecting {
                at,
                depth_mm,
                tolerance_mm,
            } => SkinMeshError::SelfIntersecting {
                at: m(at),
                depth_mm,
                tolerance_mm,
            },
            other => other,
        }
    }
}

/// The skin of an imported hand: its mesh, distal of the wrist cut `x = cut_x` (hand frame).
#[derive(Clone)]
pub struct MeshSkin {
    mesh: TriMesh,
    cut_x: f64,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    anchor: Option<Vector3<f64>>,
}

impl std::fmt::Debug for MeshSkin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshSkin")
            .field("triangles", &self.mesh.indices().len())
            .field("cut_x", &self.cut_x)
            .finish()
    }
}

fn v3(p: &Vector3<f64>) -> Vec3 {
    Vec3::new(p.x, p.y, p.z)
}

fn na(p: Vec3) -> Vector3<f64> {
    Vector3::new(p.x, p.y, p.z)
}

impl MeshSkin {
    /// The skin of `triangles` over `vertices` (hand frame, m), cut at `x = cut_x`; triangles
    /// crossing each other by no more than `tolerance` (m), and holes no wider than a quarter
    /// of it, are let be.
    pub fn new(
        vertices: &[Vector3<f64>],
        triangles: &[[u32; 3]],
        cut_x: f64,
        tolerance: f64,
    ) -> Result<MeshSkin, SkinMeshError> {
        if let Some(v) = vertices
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(SkinMeshError::NotFinite { vertex: v });
        }
        let (points, mut tris) = welded(vertices, triangles);
        // Only what reaches past the cut, with a margin of two mean edges, is the hand.
        let mean_edge = mean_edge(&points, &tris).max(1e-4);
        let margin = (2.0 * mean_edge).max(0.001);
        tris.retain(|t| t.iter().any(|&v| points[v].x >= cut_x - margin));
        let tris = largest_component(&points, orient(&points, tris)?);
        if tris.is_empty() {
            return Err(SkinMeshError::Empty);
        }
        let loops = boundary_loops(&tris);
        for l in &loops {
            if l.iter().any(|&v| points[v].x >= cut_x) {
                let c = l.iter().map(|&v| points[v]).sum::<Vector3<f64>>() / l.len() as f64;
                let across = l
                    .iter()
                    .map(|&v| (points[v] - c).norm() * 2.0)
                    .fold(0.0, f64::max);
                // Pinholes where touching sheets meet (no wider than a quarter of the crossing
                // depth let be, 1 mm at the built-in hand's size) do not change which cells are
                // flesh.
                if across <= 0.25 * tolerance {
                    continue;
                }
                return Err(SkinMeshError::Hole {
                    at: Located(c),
                    edges: l.len(),
                    across_mm: across * 1000.0,
                    reach_x: l
                        .iter()
                        .map(|&v| points[v].x)
                        .fold(f64::NEG_INFINITY, f64::max),
                });
            }
        }
        let mut tris = tris;
        if closed_volume(&points, &tris, &loops) < 0.0 {
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        if let Some((at, depth)) = self_crossing(&points, &tris, tolerance) {
            return Err(SkinMeshError::SelfIntersecting {
                at: Located(at),
                depth_mm: depth * 1e3,
                tolerance_mm: tolerance * 1e3,
            });
        }
        let mut lo = Vector3::repeat(f64::INFINITY);
        let mut hi = -lo;
        for t in &tris {
            for &v in t {
                lo = lo.inf(&points[v]);
                hi = hi.sup(&points[v]);
            }
        }
        lo.x = lo.x.max(cut_x);
        let pad = Vector3::repeat(0.002);
        let indices: Vec<[u32; 3]> = tris.iter().map(|t| t.map(|v| v as u32)).collect();
        let mesh = TriMesh::with_flags(
            points.iter().map(v3).collect(),
            indices,
            TriMeshFlags::ORIENTED,
        )
        .map_err(|_| SkinMeshError::Empty)?;
        Ok(MeshSkin {
            mesh,
            cut_x,
            lo: lo - pad,
            hi: hi + pad,
            anchor: None,
        })
    }

    /// Signed distance from `p` to the mesh alone (negative inside), m.
    fn mesh_distance(&self, p: &Vector3<f64>) -> (f64, Vector3<f64>) {
        let proj = self.mesh.project_local_point(v3(p), false);
        let q = na(proj.point);
        let d = (p - q).norm();
        (if proj.is_inside { -d } else { d }, q)
    }

    /// Signed distance from `p` to the skin (negative inside), m: the mesh cut at the wrist.
    pub fn distance(&self, p: &Vector3<f64>) -> f64 {
        self.mesh_distance(p).0.max(self.cut_x - p.x)
    }

    /// The point of the skin nearest `p`: on the wrist's cut where that is the nearer face.
    pub fn project(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let (d, q) = self.mesh_distance(p);
        let on_cut = Vector3::new(self.cut_x, p.y, p.z);
        if self.cut_x - p.x > d && self.mesh_distance(&on_cut).0 <= 0.0 {
            return on_cut;
        }
        Vector3::new(q.x.max(self.cut_x), q.y, q.z)
    }

    /// Bounds of the skin distal of the cut, padded by 2 mm.
    pub fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.lo, self.hi)
    }

    /// The skin's point farthest from `p` (a vertex of its mesh), and how far it is, m.
    pub fn farthest_from(&self, p: &Vector3<f64>) -> (Vector3<f64>, f64) {
        self.mesh
            .vertices()
            .iter()
            .map(|&v| {
                let v = na(v);
                (v, (v - p).norm())
            })
            .fold((*p, 0.0), |a, b| if b.1 > a.1 { b } else { a })
    }

    /// Distance from `p` along unit `dir` to where the ray first crosses the mesh, m.
    pub fn ray(&self, p: &Vector3<f64>, dir: &Vector3<f64>, max: f64) -> Option<f64> {
        self.mesh
            .cast_local_ray(&Ray::new(v3(p), v3(dir)), max, false)
    }

    /// The wrist cut, x in the hand frame, m.
    pub fn cut_x(&self) -> f64 {
        self.cut_x
    }

    /// The skin with the flesh lattice's lines passing through `anchor` (a right hand's frame,
    /// as [`super::SkinShape::lattice_anchor`]), instead of starting from its bounds.
    pub fn with_lattice_anchor(mut self, anchor: Vector3<f64>) -> MeshSkin {
        self.anchor = Some(anchor);
        self
    }

    /// The point the flesh lattice's lines pass through, if one was set.
    pub fn lattice_anchor(&self) -> Option<Vector3<f64>> {
        self.anchor
    }
}

/// Vertices nearer each other than 10⁻⁷ of the mesh's size merged (exporters split vertices
/// along UV seams and normal creases); triangles that lose a corner or their area dropped.
fn welded(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
) -> (Vec<Vector3<f64>>, Vec<[usize; 3]>) {
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = -lo;
    for p in vertices {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let q = ((hi - lo).norm() * 1e-7).max(1e-12);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    let mut points: Vec<Vector3<f64>> = Vec::new();
    let map: Vec<usize> = vertices
        .iter()
        .map(|p| {
            let cell = [0, 1, 2].map(|i| ((p[i] - lo[i]) / q).floor() as i64);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let key = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                        if let Some(found) = grid.get(&key) {
                            if let Some(&i) = found.iter().find(|&&i| (points[i] - p).norm() <= q) {
                                return i;
                            }
                        }
                    }
                }
            }
            points.push(*p);
            grid.entry(cell).or_default().push(points.len() - 1);
            points.len() - 1
        })
        .collect();
    let tris = triangles
        .iter()
        .filter(|t| t.iter().all(|&v| (v as usize) < vertices.len()))
        .map(|t| t.map(|v| map[v as usize]))
        .filter(|t| {
            t[0] != t[1]
                && t[1] != t[2]
                && t[0] != t[2]
                && (points[t[1]] - points[t[0]])
                    .cross(&(points[t[2]] - points[t[0]]))
                    .norm()
                    > 0.0
        })
        .collect();
    (points, tris)
}

fn mean_edge(points: &[Vector3<f64>], tris: &[[usize; 3]]) -> f64 {
    if tris.is_empty() {
        return 0.0;
    }
    let sum: f64 = tris
        .iter()
        .map(|t| {
            (0..3)
                .map(|i| (points[t[i]] - points[t[(i + 1) % 3]]).norm())
                .sum::<f64>()
        })
        .sum();
    sum / (3 * tris.len()) as f64
}

/// Triangles on each undirected edge.
fn edge_faces(tris: &[[usize; 3]]) -> HashMap<(usize, usize), Vec<usize>> {
    let mut edges: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    edges
}

/// Whether triangle `tri` runs along the edge `a → b`.
fn runs(tri: &[usize; 3], a: usize, b: usize) -> bool {
    (0..3).any(|i| tri[i] == a && tri[(i + 1) % 3] == b)
}

/// Every connected piece's faces turned to agree with its first (breadth first over shared
/// edges); an edge of more than two faces, or a piece that cannot agree, is an error.
fn orient(
    points: &[Vector3<f64>],
    mut tris: Vec<[usize; 3]>,
) -> Result<Vec<[usize; 3]>, SkinMeshError> {
    let edges = edge_faces(&tris);
    // Two sheets touching along an edge (fingers modelled touching, welded where they meet)
    // are kept: as many faces run each way along it. Anything else is a fin; a few of them
    // (slivers where touching sheets were welded: 0.5 % of the edges at most) are let be and
    // not crossed when the faces are oriented; more is a mesh that is not a surface.
    let mut fins: Vec<(&(usize, usize), usize)> = edges
        .iter()
        .filter(|((a, b), faces)| {
            let forward = faces.iter().filter(|&&t| runs(&tris[t], *a, *b)).count();
            faces.len() > 2 && (faces.len() % 2 == 1 || 2 * forward != faces.len())
        })
        .map(|(e, faces)| (e, faces.len()))
        .collect();
    fins.sort_unstable();
    if fins.len() as f64 > 0.005 * edges.len() as f64 {
        let (&(a, b), faces) = fins[0];
        return Err(SkinMeshError::NonManifold {
            at: Located((points[a] + points[b]) / 2.0),
            faces,
            edges: fins.len(),
        });
    }
    let mut done = vec![false; tris.len()];
    for seed in 0..tris.len() {
        if done[seed] {
            continue;
        }
        done[seed] = true;
        let mut queue = std::collections::VecDeque::from([seed]);
        while let Some(t) = queue.pop_front() {
            for i in 0..3 {
                let (a, b) = (tris[t][i], tris[t][(i + 1) % 3]);
                let faces = &edges[&(a.min(b), a.max(b))];
                if faces.len() > 2 {
                    // Touching sheets (their faces agree already) or a fin: not crossed.
                    continue;
                }
                for &u in faces {
                    if u == t {
                        continue;
                    }
                    let agrees = runs(&tris[u], b, a);
                    if done[u] {
                        if !agrees {
                            return Err(SkinMeshError::NotOrientable {
                                at: Located((points[a] + points[b]) / 2.0),
                            });
                        }
                        continue;
                    }
                    if !agrees {
                        tris[u].swap(1, 2);
                    }
                    done[u] = true;
                    queue.push_back(u);
                }
            }
        }
    }
    Ok(tris)
}

/// The connected piece with the most triangles (a hand mesh may carry loose parts: nails,
/// jewellery; only the skin is kept).
fn largest_component(points: &[Vector3<f64>], tris: Vec<[usize; 3]>) -> Vec<[usize; 3]> {
    let mut parent: Vec<usize> = (0..points.len()).collect();
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for t in &tris {
        for i in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[i]));
            parent[a] = b;
        }
    }
    let mut count: HashMap<usize, usize> = HashMap::new();
    for t in &tris {
        *count.entry(root(&mut parent, t[0])).or_default() += 1;
    }
    let Some((&best, _)) = count
        .iter()
        .max_by_key(|(&r, &n)| (n, std::cmp::Reverse(r)))
    else {
        return tris;
    };
    tris.into_iter()
        .filter(|t| root(&mut parent, t[0]) == best)
        .collect()
}

/// The mesh's open rims, each a loop of vertices.
fn boundary_loops(tris: &[[usize; 3]]) -> Vec<Vec<usize>> {
    let edges = edge_faces(tris);
    // Directed boundary edges a → b (as their triangle runs).
    let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
    for (&(a, b), faces) in &edges {
        if faces.len() == 1 {
            let (from, to) = if runs(&tris[faces[0]], a, b) {
                (a, b)
            } else {
                (b, a)
            };
            next.entry(from).or_default().push(to);
        }
    }
    let mut loops = Vec::new();
    let mut starts: Vec<usize> = next.keys().copied().collect();
    starts.sort_unstable();
    for s in starts {
        while let Some(mut v) = next.get_mut(&s).and_then(|n| n.pop()) {
            let mut l = vec![s];
            while v != s {
                l.push(v);
                match next.get_mut(&v).and_then(|n| n.pop()) {
                    Some(w) => v = w,
                    None => break,
                }
            }
            loops.push(l);
        }
    }
    loops
}

/// The volume the mesh encloses with each open rim closed by a fan around its centre
/// (divergence theorem); positive when the faces point outwards.
fn closed_volume(points: &[Vector3<f64>], tris: &[[usize; 3]], loops: &[Vec<usize>]) -> f64 {
    let tet = |a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>| a.dot(&b.cross(c)) / 6.0;
    let mut v: f64 = tris
        .iter()
        .map(|t| tet(&points[t[0]], &points[t[1]], &points[t[2]]))
        .sum();
    for l in loops {
        let c = l.iter().map(|&i| points[i]).sum::<Vector3<f64>>() / l.len() as f64;
        for i in 0..l.len() {
            // The rim runs as its triangles do; the cap runs the other way.
            v += tet(&points[l[(i + 1) % l.len()]], &points[l[i]], &c);
        }
    }
    v
}

/// Where segment `a`–`b` crosses triangle `t` (Möller–Trumbore), if it does.
fn segment_crossing(
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    t: [&Vector3<f64>; 3],
) -> Option<Vector3<f64>> {
    let d = b - a;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(&e2);
    let det = e1.dot(&p);
    if det.abs() < 1e-30 {
        return None;
    }
    let s = a - t[0];
    let u = s.dot(&p) / det;
    let q = s.cross(&e1);
    let v = d.dot(&q) / det;
    let w = e2.dot(&q) / det;
    let eps = 1e-9;
    (u > eps && v > eps && u + v < 1.0 - eps && w > eps && w < 1.0 - eps).then(|| a + d * w)
}

/// How far triangle `x` reaches behind the plane of triangle `y` (against its normal), m.
fn behind(points: &[Vector3<f64>], x: &[usize; 3], y: &[usize; 3]) -> f64 {
    let n = (points[y[1]] - points[y[0]])
        .cross(&(points[y[2]] - points[y[0]]))
        .normalize();
    x.iter()
        .map(|&v| -(points[v] - points[y[0]]).dot(&n))
        .fold(0.0, f64::max)
}

/// A point where two triangles that share no vertex pass through each other by more than
/// `tolerance` (each reaching that far behind the other: sheets that graze each other, as
/// fingers modelled touching do, are kept).
fn self_crossing(
    points: &[Vector3<f64>],
    tris: &[[usize; 3]],
    tolerance: f64,
) -> Option<(Vector3<f64>, f64)> {
    let boxes: Vec<Aabb> = tris
        .iter()
        .map(|t| {
            let mut lo = points[t[0]];
            let mut hi = lo;
            for &v in &t[1..] {
                lo = lo.inf(&points[v]);
                hi = hi.sup(&points[v]);
            }
            Aabb::new(v3(&lo), v3(&hi))
        })
        .collect();
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
    for (i, t) in tris.iter().enumerate() {
        for j in bvh.intersect_aabb(&boxes[i]) {
            let j = j as usize;
            let u = &tris[j];
            if j <= i
                || t.iter().any(|v| u.contains(v))
                || behind(points, t, u).min(behind(points, u, t)) <= tolerance
            {
                continue;
            }
            let corners = |x: &[usize; 3]| -> [&Vector3<f64>; 3] {
                [&points[x[0]], &points[x[1]], &points[x[2]]]
            };
            for (x, y) in [(t, u), (u, t)] {
                for k in 0..3 {
                    if let Some(at) =
                        segment_crossing(&points[x[k]], &points[x[(k + 1) % 3]], corners(y))
                    {
                        return Some((at, behind(points, t, u).min(behind(points, u, t))));
                    }
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed box from `lo` to `hi` (12 triangles, outward).
    fn cube(lo: Vector3<f64>, hi: Vector3<f64>) -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
        let v: Vec<Vector3<f64>> = (0..8)
            .map(|i| {
                Vector3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        (v, t)
    }

    #[test]
    fn a_box_gives_its_signed_distance_whatever_its_faces_orientation() {
        let (v, mut t) = cube(Vector3::zeros(), Vector3::repeat(0.02));
        for flip in [false, true] {
            if flip {
                for tri in &mut t {
                    tri.swap(1, 2);
                }
            }
            let s = MeshSkin::new(&v, &t, -1.0, 1e-4).unwrap();
            assert!((s.distance(&Vector3::repeat(0.01)) + 0.01).abs() < 1e-12);
            assert!((s.distance(&Vector3::new(0.03, 0.01, 0.01)) - 0.01).abs() < 1e-12);
            // Past an edge: the distance to the edge.
            let d = s.distance(&Vector3::new(0.03, 0.03, 0.01));
            assert!((d - 0.01 * 2f64.sqrt()).abs() < 1e-12, "{d}");
        }
        // One face turned against the others is turned back.
        t[3].swap(1, 2);
        let s = MeshSkin::new(&v, &t, -1.0, 1e-4).unwrap();
        assert!(s.distance(&Vector3::repeat(0.01)) < 0.0);
    }

    #[test]
    fn the_wrist_may_be_open_but_no_other_hole() {
        let (v, t) = cube(Vector3::zeros(), Vector3::repeat(0.02));
        // Without the x− face (triangles 8 and 9): open at the wrist side.
        let open: Vec<[u32; 3]> = t
            .iter()
            .enumerate()
            .filter(|(i, _)| *i / 2 != 4)
            .map(|(_, t)| *t)
            .collect();
        let s = MeshSkin::new(&v, &open, 0.005, 1e-4).unwrap();
        assert!((s.distance(&Vector3::new(0.01, 0.01, 0.01)) + 0.005).abs() < 1e-12);
        assert!((s.distance(&Vector3::new(0.001, 0.01, 0.01)) - 0.004).abs() < 1e-12);
        // Without the x+ face: a hole distal of the cut.
        let holed: Vec<[u32; 3]> = t
            .iter()
            .enumerate()
            .filter(|(i, _)| *i / 2 != 5)
            .map(|(_, t)| *t)
            .collect();
        match MeshSkin::new(&v, &holed, 0.005, 1e-4) {
            Err(SkinMeshError::Hole { at, edges, .. }) => {
                assert!((at.0.x - 0.02).abs() < 1e-12, "{at}");
                assert_eq!(edges, 4);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn non_manifold_and_self_crossing_meshes_are_refused_where_they_are() {
        let (mut v, mut t) = cube(Vector3::zeros(), Vector3::repeat(0.02));
        // A fin on the edge 0–1: a third triangle on it.
        v.push(Vector3::new(0.01, -0.01, -0.01));
        t.push([0, 1, 8]);
        let e = MeshSkin::new(&v, &t, -1.0, 1e-4).unwrap_err();
        assert!(
            matches!(e, SkinMeshError::NonManifold { faces: 3, .. }),
            "{e}"
        );
        // Two boxes passing through each other, joined into one piece by nothing: the larger
        // piece is kept, so make them one piece by overlapping a second closed box.
        let (v1, t1) = cube(Vector3::zeros(), Vector3::repeat(0.02));
        let (v2, t2) = cube(Vector3::new(0.013, 0.007, 0.004), Vector3::repeat(0.03));
        let mut v = v1.clone();
        v.extend(v2);
        let mut t = t1.clone();
        t.extend(t2.iter().map(|x| x.map(|i| i + 8)));
        // Join them at one vertex so they are one piece.
        v[14] = v[7];
        let e = MeshSkin::new(&v, &t, -1.0, 1e-4).unwrap_err();
        assert!(matches!(e, SkinMeshError::SelfIntersecting { .. }), "{e}");
    }
}
