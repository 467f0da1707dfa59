//! Structured hexahedral meshes: box, solid ball (a mapped cube) and hollow ball (a cubed sphere).

use super::{Hex, Mesh};
use nalgebra::Vector3;
use std::collections::HashMap;

/// A box from `min` to `max` with `cells[i]` cells along axis i. Node (i, j, k) has index
/// `i + (nx+1)·(j + (ny+1)·k)`.
pub fn box_mesh(min: Vector3<f64>, max: Vector3<f64>, cells: [usize; 3]) -> Mesh {
    let lines: [Vec<f64>; 3] = std::array::from_fn(|a| {
        (0..=cells[a])
            .map(|i| min[a] + (max[a] - min[a]) * (i as f64 / cells[a] as f64))
            .collect()
    });
    lattice(&[&lines[0], &lines[1], &lines[2]])
}

/// The lattice of the given lines along x, y and z (node (i, j, k) has index `i + (nx+1)·(j + (ny+1)·k)`).
pub(super) fn lattice(lines: &[&[f64]; 3]) -> Mesh {
    let [nx, ny, nz] = lines.map(|l| l.len() - 1);
    let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for &z in lines[2] {
        for &y in lines[1] {
            for &x in lines[0] {
                nodes.push(Vector3::new(x, y, z));
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
    let mut cells: Vec<Hex> = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                cells.push([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    Mesh { nodes, cells }
}

/// A solid ball: the cube [−1, 1]³ with `cells` cells per edge, mapped onto the ball.
///
/// A point p of the cube with ∞-norm t is sent to `R·p·((1−t)·β + t/|p|)`: the cube's surface
/// (t = 1) lands on the sphere, the core stays a scaled cube (β = 0.6), and the map is monotone
/// along every ray, so no cell inverts.
pub fn sphere_mesh(center: Vector3<f64>, radius: f64, cells: usize) -> Mesh {
    const BETA: f64 = 0.6;
    let mut mesh = box_mesh(
        Vector3::from_element(-1.0),
        Vector3::from_element(1.0),
        [cells; 3],
    );
    for p in &mut mesh.nodes {
        let t = p.amax();
        let norm = p.norm();
        let scale = if norm > 0.0 {
            (1.0 - t) * BETA + t / norm * t
        } else {
            BETA
        };
        *p = center + *p * (radius * scale);
    }
    mesh
}

/// A hollow ball: a cubed sphere with `cells` × `cells` quads on each of the six cube faces
/// (equiangular projection) extruded through `layers` cells from `inner_radius` to `outer_radius`.
pub fn shell_mesh(
    center: Vector3<f64>,
    inner_radius: f64,
    outer_radius: f64,
    cells: usize,
    layers: usize,
) -> Mesh {
    let n = cells;
    let coords: Vec<f64> = (0..=n)
        .map(|i| (std::f64::consts::FRAC_PI_4 * (2.0 * i as f64 / n as f64 - 1.0)).tan())
        .collect();
    let radii: Vec<f64> = (0..=layers)
        .map(|l| inner_radius + (outer_radius - inner_radius) * l as f64 / layers as f64)
        .collect();
    cubed_shell(&[&coords, &coords, &coords], layers, |q, l| {
        center + q.normalize() * radii[l]
    })
}

/// A cubed sphere: the lattice lines `lines[axis]` (from −1 to 1) on the surface of the cube
/// [−1, 1]³, repeated on `layers + 1` surfaces, one layer of cells between two; `place(q, l)`
/// positions the point q of the cube's surface on surface l (0 the innermost).
pub(super) fn cubed_shell(
    lines: &[&[f64]; 3],
    layers: usize,
    place: impl Fn(Vector3<f64>, usize) -> Vector3<f64>,
) -> Mesh {
    let [nx, ny, nz] = lines.map(|l| l.len() - 1);
    // Unique nodes on the surface of the lattice.
    let mut surface_index: HashMap<(usize, usize, usize), usize> = HashMap::new();
    let mut points: Vec<Vector3<f64>> = Vec::new();
    let mut node = |i: usize, j: usize, k: usize| -> usize {
        *surface_index.entry((i, j, k)).or_insert_with(|| {
            points.push(Vector3::new(lines[0][i], lines[1][j], lines[2][k]));
            points.len() - 1
        })
    };
    // Quads with outward normals (first edge × second edge points out of the cube).
    let mut quads: Vec<[usize; 4]> = Vec::with_capacity(2 * (nx * ny + ny * nz + nz * nx));
    let m = nx.max(ny).max(nz);
    for a in 0..m {
        for b in 0..m {
            if a < ny && b < nz {
                // ±x faces over (y, z) = (a, b)
                quads.push([
                    node(nx, a, b),
                    node(nx, a + 1, b),
                    node(nx, a + 1, b + 1),
                    node(nx, a, b + 1),
                ]);
                quads.push([
                    node(0, a, b),
                    node(0, a, b + 1),
                    node(0, a + 1, b + 1),
                    node(0, a + 1, b),
                ]);
            }
            if a < nz && b < nx {
                // ±y faces over (z, x) = (a, b)
                quads.push([
                    node(b, ny, a),
                    node(b, ny, a + 1),
                    node(b + 1, ny, a + 1),
                    node(b + 1, ny, a),
                ]);
                quads.push([
                    node(b, 0, a),
                    node(b + 1, 0, a),
                    node(b + 1, 0, a + 1),
                    node(b, 0, a + 1),
                ]);
            }
            if a < nx && b < ny {
                // ±z faces over (x, y) = (a, b)
                quads.push([
                    node(a, b, nz),
                    node(a + 1, b, nz),
                    node(a + 1, b + 1, nz),
                    node(a, b + 1, nz),
                ]);
                quads.push([
                    node(a, b, 0),
                    node(a, b + 1, 0),
                    node(a + 1, b + 1, 0),
                    node(a + 1, b, 0),
                ]);
            }
        }
    }
    let per_layer = points.len();
    let mut nodes = Vec::with_capacity(per_layer * (layers + 1));
    for l in 0..=layers {
        nodes.extend(points.iter().map(|&q| place(q, l)));
    }
    let mut hexes: Vec<Hex> = Vec::with_capacity(quads.len() * layers);
    for l in 0..layers {
        let (lo, hi) = (l * per_layer, (l + 1) * per_layer);
        for q in &quads {
            hexes.push([
                q[0] + lo,
                q[1] + lo,
                q[2] + lo,
                q[3] + lo,
                q[0] + hi,
                q[1] + hi,
                q[2] + hi,
                q[3] + hi,
            ]);
        }
    }
    Mesh {
        nodes,
        cells: hexes,
    }
}
