//! The display skin: the flesh mesh's skin quads refined by Catmull–Clark subdivision. Every
//! display vertex is a fixed weighted average of simulation nodes, so the skin is embedded in the
//! flesh and follows its displacement field at the cost of one sparse product per frame; the
//! display resolution never costs simulation time.

use super::embed::{embed_split, NodeCells, Reach};
use super::skin_follow::{Combinations, Follow};
use crate::mesh::Mesh;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::collections::HashMap;

/// A smooth quad surface whose vertices are fixed linear combinations of simulation nodes.
#[derive(Clone, Debug, Default)]
pub struct DisplaySkin {
    /// Start of each vertex's weights in `nodes`/`weights` (CSR), one more than vertices.
    offsets: Vec<u32>,
    nodes: Vec<u32>,
    weights: Vec<f64>,
    /// Quads (outward normals), display vertex indices.
    pub quads: Vec<[u32; 4]>,
    /// Catmull–Clark levels from the control net.
    levels: usize,
    /// Where set, the vertices are moved by the contact skin rather than by their own cells
    /// (`skin_follow.rs`).
    follow: Option<Box<Follow>>,
}

type Row = Vec<(usize, f64)>;

fn combine(parts: &[(&Row, f64)]) -> Row {
    let mut out: Row = Vec::new();
    for (row, c) in parts {
        for &(n, w) in row.iter() {
            out.push((n, w * c));
        }
    }
    out.sort_unstable_by_key(|e| e.0);
    let mut merged: Row = Vec::with_capacity(out.len());
    for (n, w) in out {
        match merged.last_mut() {
            Some(last) if last.0 == n => last.1 += w,
            _ => merged.push((n, w)),
        }
    }
    merged.retain(|e| e.1.abs() > 1e-9);
    merged
}

/// One Catmull–Clark step on quads whose vertices are the rows `rows`; non-manifold edges and
/// their vertices are kept sharp.
fn subdivide(rows: &[Row], quads: &[[usize; 4]]) -> (Vec<Row>, Vec<[usize; 4]>) {
    let mut edge_faces: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (f, q) in quads.iter().enumerate() {
        for i in 0..4 {
            let (a, b) = (q[i], q[(i + 1) % 4]);
            edge_faces.entry((a.min(b), a.max(b))).or_default().push(f);
        }
    }
    let face_rows: Vec<Row> = quads
        .iter()
        .map(|q| combine(&q.map(|v| (&rows[v], 0.25))))
        .collect();
    let mut edge_index: HashMap<(usize, usize), usize> = HashMap::new();
    let mut new_rows: Vec<Row> = Vec::new();
    // Vertex points first (same indices as the old vertices).
    let mut vertex_faces: Vec<Vec<usize>> = vec![Vec::new(); rows.len()];
    for (f, q) in quads.iter().enumerate() {
        for &v in q {
            vertex_faces[v].push(f);
        }
    }
    let mut vertex_edges: Vec<Vec<(usize, usize)>> = vec![Vec::new(); rows.len()];
    for &e in edge_faces.keys() {
        vertex_edges[e.0].push(e);
        vertex_edges[e.1].push(e);
    }
    for v in 0..rows.len() {
        let edges = &vertex_edges[v];
        let faces = &vertex_faces[v];
        let smooth = !edges.is_empty()
            && edges.iter().all(|e| edge_faces[e].len() == 2)
            && edges.len() == faces.len();
        if !smooth {
            new_rows.push(rows[v].clone());
            continue;
        }
        let n = edges.len() as f64;
        let mut parts: Vec<(&Row, f64)> = Vec::new();
        for &f in faces {
            parts.push((&face_rows[f], 1.0 / (n * n)));
        }
        for e in edges {
            let other = if e.0 == v { e.1 } else { e.0 };
            // 2R/n with R the mean of edge midpoints: each midpoint (P + Q)/2.
            parts.push((&rows[other], 1.0 / (n * n)));
        }
        parts.push((&rows[v], (n - 3.0) / n + 1.0 / n));
        new_rows.push(combine(&parts));
    }
    // Face points.
    let face_base = new_rows.len();
    new_rows.extend(face_rows.iter().cloned());
    // Edge points.
    let mut new_quads = Vec::with_capacity(quads.len() * 4);
    let mut edge_point = |a: usize, b: usize, new_rows: &mut Vec<Row>| -> usize {
        let key = (a.min(b), a.max(b));
        if let Some(&i) = edge_index.get(&key) {
            return i;
        }
        let faces = &edge_faces[&key];
        let row = if faces.len() == 2 {
            combine(&[
                (&rows[a], 0.25),
                (&rows[b], 0.25),
                (&face_rows[faces[0]], 0.25),
                (&face_rows[faces[1]], 0.25),
            ])
        } else {
            combine(&[(&rows[a], 0.5), (&rows[b], 0.5)])
        };
        new_rows.push(row);
        edge_index.insert(key, new_rows.len() - 1);
        new_rows.len() - 1
    };
    for (f, q) in quads.iter().enumerate() {
        for i in 0..4 {
            let (prev, cur, next) = (q[(i + 3) % 4], q[i], q[(i + 1) % 4]);
            let e_next = edge_point(cur, next, &mut new_rows);
            let e_prev = edge_point(prev, cur, &mut new_rows);
            new_quads.push([cur, e_next, face_base + f, e_prev]);
        }
    }
    (new_rows, new_quads)
}

/// Where each vertex lies on the control net: its control quad (index into the quads it was
/// subdivided from) and bilinear coordinates (u, v) there, corners 0…3 at (0, 0), (1, 0),
/// (1, 1), (0, 1); for quads made by `levels` subdivisions of control quads (child `i` of a
/// quad is [corner i, midpoint of edge i → i+1, centre, midpoint of edge i−1 → i], see
/// [`subdivide`]).
fn control_coordinates(quads: &[[u32; 4]], vertices: usize, levels: usize) -> Vec<(u32, [f64; 2])> {
    let per = 4usize.pow(levels as u32);
    let mut out = vec![(u32::MAX, [0.0; 2]); vertices];
    for (q, quad) in quads.iter().enumerate() {
        let mut corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        // The child index at each level, coarsest first.
        let mut rest = q % per;
        for level in (0..levels).rev() {
            let i = rest / 4usize.pow(level as u32);
            rest %= 4usize.pow(level as u32);
            let mid = |a: [f64; 2], b: [f64; 2]| [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
            let centre = mid(mid(corners[0], corners[1]), mid(corners[2], corners[3]));
            corners = [
                corners[i],
                mid(corners[i], corners[(i + 1) % 4]),
                centre,
                mid(corners[(i + 3) % 4], corners[i]),
            ];
        }
        for (slot, &v) in quad.iter().enumerate() {
            if out[v as usize].0 == u32::MAX {
                out[v as usize] = ((q / per) as u32, corners[slot]);
            }
        }
    }
    out
}

impl DisplaySkin {
    /// The skin quads of a flesh mesh (node indices) subdivided `levels` times.
    pub fn new(quads: &[[usize; 4]], node_count: usize, levels: usize) -> DisplaySkin {
        // Keep only the nodes the quads use, renumbered.
        let mut local = vec![usize::MAX; node_count];
        let mut rows: Vec<Row> = Vec::new();
        let mut q: Vec<[usize; 4]> = quads
            .iter()
            .map(|quad| {
                quad.map(|n| {
                    if local[n] == usize::MAX {
                        local[n] = rows.len();
                        rows.push(vec![(n, 1.0)]);
                    }
                    local[n]
                })
            })
            .collect();
        for _ in 0..levels {
            let (r, qq) = subdivide(&rows, &q);
            rows = r;
            q = qq;
        }
        let mut skin = DisplaySkin {
            offsets: vec![0],
            ..Default::default()
        };
        for row in &rows {
            for &(n, w) in row {
                skin.nodes.push(n as u32);
                skin.weights.push(w);
            }
            skin.offsets.push(skin.nodes.len() as u32);
        }
        skin.quads = q.iter().map(|v| v.map(|i| i as u32)).collect();
        skin.levels = levels;
        skin
    }

    /// A control net (`quads` over `vertices`, each quad tied to a cell of `mesh` by
    /// `quad_cells`) subdivided `levels` times, then every display vertex moved onto the true
    /// skin surface (`project` maps a point to its nearest skin point, at rest) and embedded in
    /// the cell its quad is tied to, or where that cell cannot reproduce it, in the nearest cell
    /// around it ([`super::embed`]): its weights become the trilinear shape functions of that
    /// cell at the vertex's local coordinates (extrapolated outside the cell where the skin is).
    /// The skin is then as smooth as the skin shape, whatever the lattice's steps, and follows
    /// the flesh's displacement field. `mesh` split `split` × `split` × `split` from a lattice
    /// (`super::subdivide`): each vertex is embedded by its quad's cell's parent
    /// ([`super::embed::embed_split`]), as in the unsplit lattice.
    pub fn embedded(
        quads: &[[usize; 4]],
        vertices: &[Vector3<f64>],
        quad_cells: &[usize],
        (mesh, split): (&Mesh, usize),
        levels: usize,
        reach: Reach,
        project: impl Fn(&Vector3<f64>) -> Vector3<f64> + Sync,
    ) -> DisplaySkin {
        let mut skin = DisplaySkin::new(quads, vertices.len(), levels);
        let rest = skin.positions(vertices);
        let mut cell_of = vec![usize::MAX; rest.len()];
        let per_quad = 4usize.pow(levels as u32);
        for (q, quad) in skin.quads.iter().enumerate() {
            for &v in quad {
                if cell_of[v as usize] == usize::MAX {
                    cell_of[v as usize] = quad_cells[q / per_quad];
                }
            }
        }
        let around = NodeCells::new(mesh);
        let embedded: Vec<[(u32, f64); 8]> = rest
            .par_iter()
            .enumerate()
            .map(|(v, p)| {
                let (c, n) = embed_split(mesh, &around, cell_of[v], &project(p), reach, split);
                let cell = mesh.cells[c];
                std::array::from_fn(|a| (cell[a] as u32, n[a]))
            })
            .collect();
        skin.offsets = (0..=embedded.len()).map(|v| (8 * v) as u32).collect();
        skin.nodes = embedded.iter().flatten().map(|e| e.0).collect();
        skin.weights = embedded.iter().flatten().map(|e| e.1).collect();
        skin
    }

    /// The (node, weight) terms of display vertex `v`.
    pub fn terms(&self, v: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (a, b) = (self.offsets[v] as usize, self.offsets[v + 1] as usize);
        (a..b).map(|i| (self.nodes[i] as usize, self.weights[i]))
    }

    /// Values at every vertex from values at the control net's corners (`corner(q, i)`: corner
    /// `i` of control quad `q`), bilinear over each control quad at the vertex's coordinates
    /// there.
    pub fn from_control(&self, corner: impl Fn(usize, usize) -> f64) -> Vec<f64> {
        control_coordinates(&self.quads, self.vertex_count(), self.levels)
            .iter()
            .map(|&(q, [u, v])| {
                let c = |i| corner(q as usize, i);
                (1.0 - u) * (1.0 - v) * c(0)
                    + u * (1.0 - v) * c(1)
                    + u * v * c(2)
                    + (1.0 - u) * v * c(3)
            })
            .collect()
    }

    /// Each display vertex's area at positions `at` (m²): a third of every triangle it is a
    /// corner of ([`Self::triangles`]), so that a value at the vertices integrates over the skin,
    /// linear on each triangle, to the sum of value × area.
    pub fn vertex_areas(&self, at: &[Vector3<f64>]) -> Vec<f64> {
        let mut area = vec![0.0; at.len()];
        for t in self.triangle_indices() {
            let a = 0.5 * (at[t[1]] - at[t[0]]).cross(&(at[t[2]] - at[t[0]])).norm();
            for v in t {
                area[v] += a / 3.0;
            }
        }
        area
    }

    /// The transpose of [`Self::from_control`]: what values at every display vertex
    /// (`display`) give to each vertex of the control net (`control`, its quads' corners
    /// numbered over `count` vertices), by the same bilinear weights. With `display` the
    /// vertices' areas, each control vertex's area on the display skin: a value at the control
    /// vertices carried by [`Self::from_control`] then integrates over the display skin to the
    /// sum of value × that area.
    pub fn to_control(&self, display: &[f64], control: &[[u32; 4]], count: usize) -> Vec<f64> {
        let mut out = vec![0.0; count];
        for (&(q, [u, v]), d) in control_coordinates(&self.quads, self.vertex_count(), self.levels)
            .iter()
            .zip(display)
        {
            let weights = [(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v];
            for (&c, w) in control[q as usize].iter().zip(weights) {
                out[c as usize] += w * d;
            }
        }
        out
    }

    /// The node weighing most in display vertex `v` (the first of equal weights).
    pub fn heaviest_node(&self, v: usize) -> usize {
        self.terms(v)
            .fold(
                (0, f64::NEG_INFINITY),
                |a, (n, w)| if w > a.1 { (n, w) } else { a },
            )
            .0
    }

    /// Number of display vertices.
    pub fn vertex_count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Moves the vertices with `control`, the contact skin (the control net this skin was
    /// subdivided `levels` times from, `quads` over `count` vertices, at level 0), instead of
    /// with their own cells: each the subdivision of the contact skin's vertices plus its
    /// offset from that at rest (`rest`: the flesh nodes at rest), turned with the surface
    /// (`skin_follow.rs`). Where the contact holds the contact skin out of a body, the display
    /// skin lies on a smooth surface through the points it holds.
    pub fn follow(
        &mut self,
        control: DisplaySkin,
        (quads, count, levels): (&[[usize; 4]], usize, usize),
        rest: &[Vector3<f64>],
    ) {
        assert_eq!(levels, self.levels, "subdivided as this skin was");
        assert_eq!(control.levels, 0, "the contact skin is the control net");
        // The contact skin numbers the control net's vertices by their first appearance.
        let mut local = vec![u32::MAX; count];
        let mut next = 0u32;
        for &v in quads.iter().flatten() {
            if local[v] == u32::MAX {
                local[v] = next;
                next += 1;
            }
        }
        assert_eq!(
            next as usize,
            control.vertex_count(),
            "the control net's vertices"
        );
        // One Catmull–Clark level after the other, each over the vertices of the one before:
        // the levels' weights composed would hold ≈ 25 terms a display vertex (168 MB more at
        // resolution 2), each level's hold ≈ 7.
        let mut q: Vec<[usize; 4]> = quads.iter().map(|q| q.map(|v| local[v] as usize)).collect();
        let mut vertices = next as usize;
        let mut rows = Vec::with_capacity(levels);
        for _ in 0..levels {
            let identity: Vec<Row> = (0..vertices).map(|v| vec![(v, 1.0)]).collect();
            let (level, finer) = subdivide(&identity, &q);
            rows.push(Combinations {
                offsets: std::iter::once(0)
                    .chain(level.iter().scan(0u32, |end, row| {
                        *end += row.len() as u32;
                        Some(*end)
                    }))
                    .collect(),
                terms: level
                    .iter()
                    .flatten()
                    .map(|&(v, w)| (v as u32, w))
                    .collect(),
            });
            vertices = level.len();
            q = finer;
        }
        assert_eq!(vertices, self.vertex_count(), "subdivided as this skin was");
        let control = Combinations {
            offsets: control.offsets,
            terms: control.nodes.into_iter().zip(control.weights).collect(),
        };
        let control_quads = quads.iter().map(|q| q.map(|v| local[v])).collect();
        let site = control_coordinates(&self.quads, self.vertex_count(), levels);
        let at_rest = self.embedded_positions(rest);
        self.follow = Some(Box::new(Follow::new(
            (control, rows),
            (control_quads, site),
            (&at_rest, rest),
        )));
    }

    /// Display vertex positions for node positions `nodes`.
    pub fn positions(&self, nodes: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        match &self.follow {
            Some(follow) => follow.positions(nodes),
            None => self.embedded_positions(nodes),
        }
    }

    /// Display vertex positions for node positions `nodes`, each by its own embedding
    /// ([`Self::terms`]).
    pub(super) fn embedded_positions(&self, nodes: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        (0..self.vertex_count())
            .map(|v| {
                let (a, b) = (self.offsets[v] as usize, self.offsets[v + 1] as usize);
                let mut p = Vector3::zeros();
                for i in a..b {
                    p += nodes[self.nodes[i] as usize] * self.weights[i];
                }
                p
            })
            .collect()
    }

    /// Values at display vertices interpolated from values at nodes (same weights).
    pub fn interpolate(&self, values: &[f64]) -> Vec<f64> {
        (0..self.vertex_count())
            .map(|v| {
                let (a, b) = (self.offsets[v] as usize, self.offsets[v + 1] as usize);
                (a..b)
                    .map(|i| values[self.nodes[i] as usize] * self.weights[i])
                    .sum()
            })
            .collect()
    }

    /// Triangles (two per quad), display vertex indices.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect()
    }

    /// [`Self::triangles`] with `usize` vertex indices (for geometry indexing a slice of the
    /// vertices' positions).
    pub fn triangle_indices(&self) -> Vec<[usize; 3]> {
        self.triangles()
            .into_iter()
            .map(|t| t.map(|v| v as usize))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two equal flat quads side by side, 1 × 2 each, sharing an edge: (nodes, quads).
    fn two_flat_quads() -> ([Vector3<f64>; 6], [[usize; 4]; 2]) {
        let nodes = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.0, 2.0, 0.0),
            Vector3::new(0.0, 2.0, 0.0),
            Vector3::new(2.0, 0.0, 0.0),
            Vector3::new(2.0, 2.0, 0.0),
        ];
        (nodes, [[0, 1, 2, 3], [1, 4, 5, 2]])
    }

    #[test]
    fn to_control_is_the_transpose_of_from_control() {
        // Σ_d y_d · (from_control x)_d = Σ_v (to_control y)_v · x_v for any x, y; and the
        // display vertices' areas carried back sum to the whole area (the weights are a
        // partition of unity): here two flat quads of area 2 each.
        let (nodes, quads) = two_flat_quads();
        let control: Vec<[u32; 4]> = quads.iter().map(|q| q.map(|v| v as u32)).collect();
        let x = [0.3, -1.2, 2.5, 0.7, 1.9, -0.4];
        for levels in 0..3 {
            let skin = DisplaySkin::new(&quads, nodes.len(), levels);
            let y: Vec<f64> = (0..skin.vertex_count())
                .map(|d| ((d * 7919) % 13) as f64 - 6.0)
                .collect();
            let forward = skin.from_control(|q, i| x[quads[q][i]]);
            let back = skin.to_control(&y, &control, nodes.len());
            let lhs: f64 = y.iter().zip(&forward).map(|(a, b)| a * b).sum();
            let rhs: f64 = back.iter().zip(&x).map(|(a, b)| a * b).sum();
            assert!(
                (lhs - rhs).abs() < 1e-12 * lhs.abs().max(1.0),
                "level {levels}: {lhs} {rhs}"
            );
            let area = skin.vertex_areas(&skin.positions(&nodes));
            let shares = skin.to_control(&area, &control, nodes.len());
            let total: f64 = shares.iter().sum();
            assert!((total - 4.0).abs() < 1e-12, "level {levels}: {total}");
        }
    }

    #[test]
    fn control_coordinates_place_every_vertex_on_its_control_quad() {
        // Two equal flat quads side by side: every edge but the shared one is a border (kept
        // sharp) and the shared one is symmetric, so subdivision is bilinear and a vertex's
        // position is the bilinear interpolation of its control quad's corners at its
        // coordinates.
        let (nodes, quads) = two_flat_quads();
        for levels in 0..3 {
            let skin = DisplaySkin::new(&quads, nodes.len(), levels);
            let at = skin.positions(&nodes);
            for axis in 0..2 {
                let field = skin.from_control(|q, i| nodes[quads[q][i]][axis]);
                for (v, p) in at.iter().enumerate() {
                    assert!(
                        (field[v] - p[axis]).abs() < 1e-12,
                        "level {levels}, vertex {v}: {} against {}",
                        field[v],
                        p[axis]
                    );
                }
            }
            assert_eq!(
                skin.vertex_count(),
                (2 * 2usize.pow(levels as u32) + 1) * (2usize.pow(levels as u32) + 1)
            );
        }
    }
}
