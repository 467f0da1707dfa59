//! CPU geometry: vertex normals of deformed surfaces, arrow meshes, back-to-front sorting.

use glam::Vec3;

/// Area-weighted vertex normals: each triangle adds its (unnormalised) cross product, twice its
/// area along its normal, to its three vertices; the sums are normalised. A vertex of no
/// triangle, or of triangles of zero area, gets +z. `normals` is resized to `positions`.
pub fn vertex_normals_into(positions: &[[f32; 3]], indices: &[u32], normals: &mut Vec<[f32; 3]>) {
    normals.clear();
    normals.resize(positions.len(), [0.0; 3]);
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let (pa, pb, pc) = (
            Vec3::from(positions[a]),
            Vec3::from(positions[b]),
            Vec3::from(positions[c]),
        );
        let n = (pb - pa).cross(pc - pa);
        for v in [a, b, c] {
            let s = &mut normals[v];
            s[0] += n.x;
            s[1] += n.y;
            s[2] += n.z;
        }
    }
    for n in normals.iter_mut() {
        *n = Vec3::from(*n).try_normalize().unwrap_or(Vec3::Z).into();
    }
}

/// [`vertex_normals_into`] into a new vector.
pub fn vertex_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut n = Vec::new();
    vertex_normals_into(positions, indices, &mut n);
    n
}

/// Vertices of a surface split along its creases, so that smooth shading does not round off
/// sharp edges (a box stays a box) while curved parts stay smooth.
#[derive(Clone, Debug, PartialEq)]
pub struct CreaseSplit {
    /// For each drawn vertex, the input vertex it copies.
    pub source: Vec<u32>,
    /// The triangles over the drawn vertices.
    pub indices: Vec<u32>,
}

/// Default crease: faces meeting at more than 50° are shaded apart.
pub const CREASE_DEGREES: f32 = 50.0;

/// Splits the vertices of a triangle surface where faces meet at more than `crease_degrees`:
/// around each vertex, its triangles are grouped with the first group whose first triangle's
/// normal lies within the crease angle of theirs; each group becomes a drawn vertex.
/// Degenerate triangles (slivers) join the vertex's first group.
pub fn split_creases(positions: &[[f32; 3]], indices: &[u32], crease_degrees: f32) -> CreaseSplit {
    let cos = crease_degrees.to_radians().cos();
    let normals: Vec<Option<Vec3>> = indices
        .chunks_exact(3)
        .map(|t| {
            let p = [t[0], t[1], t[2]].map(|i| Vec3::from(positions[i as usize]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            let longest = (p[1] - p[0])
                .length_squared()
                .max((p[2] - p[1]).length_squared())
                .max((p[0] - p[2]).length_squared());
            // A sliver (area tiny against its longest edge) has no trustworthy direction.
            (n.length() > 1e-6 * longest).then(|| n.normalize())
        })
        .collect();
    // Groups around each vertex: (normal of the first triangle, drawn vertex).
    let mut groups: Vec<Vec<(Option<Vec3>, u32)>> = vec![Vec::new(); positions.len()];
    let mut source = Vec::new();
    let mut out = Vec::with_capacity(indices.len());
    for (t, tri) in indices.chunks_exact(3).enumerate() {
        let n = normals[t];
        for &v in tri {
            let around = &mut groups[v as usize];
            let found = around.iter().find(|(g, _)| match (g, n) {
                (Some(g), Some(n)) => g.dot(n) >= cos,
                _ => true,
            });
            let drawn = match found {
                Some(&(_, d)) => d,
                None => {
                    source.push(v);
                    let d = (source.len() - 1) as u32;
                    around.push((n, d));
                    d
                }
            };
            out.push(drawn);
        }
    }
    CreaseSplit {
        source,
        indices: out,
    }
}

/// Segments around an arrow's circumference.
const ARROW_SIDES: usize = 20;

/// A closed arrow mesh (cylinder shaft, cone head, discs closing them) from `origin` along
/// `vector`, with its own flat-shaded normals: (positions, normals, indices). Its thickness
/// follows its length: head 28% of the length, shaft radius `radius` (or 4% of the length when
/// `None`), head radius 2.2× the shaft. A zero vector gives an empty mesh.
pub fn arrow_mesh(
    origin: Vec3,
    vector: Vec3,
    radius: Option<f32>,
) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
    let len = vector.length();
    if !(len > 0.0 && len.is_finite() && origin.is_finite()) {
        return (Vec::new(), Vec::new(), Vec::new());
    }
    let axis = vector / len;
    let r = radius.unwrap_or(0.04 * len).min(0.2 * len);
    let head_r = 2.2 * r;
    let head_len = (0.28 * len).min(6.0 * head_r);
    let shaft_end = origin + axis * (len - head_len);
    let tip = origin + vector;
    // A right-handed frame (u, v, axis), so that the windings below face outwards.
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let ring = |k: usize| {
        let a = k as f32 / ARROW_SIDES as f32 * std::f32::consts::TAU;
        u * a.cos() + v * a.sin()
    };
    let (mut pos, mut nor, mut idx) = (Vec::new(), Vec::new(), Vec::new());
    let mut push = |p: Vec3, n: Vec3| {
        pos.push(p.into());
        nor.push(n.into());
        (pos.len() - 1) as u32
    };
    // Cone slope: the normal tilts towards the tip by atan(head_r / head_len).
    let slope = head_r / head_len;
    for k in 0..ARROW_SIDES {
        let (d0, d1) = (ring(k), ring(k + 1));
        // Shaft side.
        let a = push(origin + d0 * r, d0);
        let b = push(origin + d1 * r, d1);
        let c = push(shaft_end + d1 * r, d1);
        let d = push(shaft_end + d0 * r, d0);
        idx.extend([a, b, c, a, c, d]);
        // Tail disc.
        let n = -axis;
        let o = push(origin, n);
        let p1 = push(origin + d1 * r, n);
        let p0 = push(origin + d0 * r, n);
        idx.extend([o, p1, p0]);
        // Head base ring (annulus under the cone).
        let q0 = push(shaft_end + d0 * head_r, n);
        let q1 = push(shaft_end + d1 * head_r, n);
        let s1 = push(shaft_end + d1 * r, n);
        let s0 = push(shaft_end + d0 * r, n);
        idx.extend([q0, s1, q1, q0, s0, s1]);
        // Cone side.
        let n0 = (d0 + axis * slope).normalize();
        let n1 = (d1 + axis * slope).normalize();
        let nm = (ring(k) + ring(k + 1)).normalize_or(d0) + axis * slope;
        let c0 = push(shaft_end + d0 * head_r, n0);
        let c1 = push(shaft_end + d1 * head_r, n1);
        let t = push(tip, nm.normalize());
        idx.extend([c0, c1, t]);
    }
    (pos, nor, idx)
}

/// Reorders the triangles of `indices` so that those farther from `eye` come first (for
/// translucent drawing). Distances are taken at the triangle centroids.
pub fn sort_back_to_front(positions: &[[f32; 3]], indices: &mut [u32], eye: Vec3) {
    let mut tris: Vec<(f32, [u32; 3])> = indices
        .chunks_exact(3)
        .map(|t| {
            let c = (Vec3::from(positions[t[0] as usize])
                + Vec3::from(positions[t[1] as usize])
                + Vec3::from(positions[t[2] as usize]))
                / 3.0;
            ((c - eye).length_squared(), [t[0], t[1], t[2]])
        })
        .collect();
    tris.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (dst, (_, t)) in indices.chunks_exact_mut(3).zip(tris) {
        dst.copy_from_slice(&t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of radius `r` around `c`, triangles counter-clockwise from outside.
    fn uv_sphere(c: Vec3, r: f32) -> (Vec<[f32; 3]>, Vec<u32>) {
        let (nu, nv) = (24u32, 12u32);
        let mut pos = Vec::new();
        for j in 0..=nv {
            let th = j as f32 / nv as f32 * std::f32::consts::PI;
            for i in 0..nu {
                let ph = i as f32 / nu as f32 * std::f32::consts::TAU;
                pos.push(
                    (c + r * Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos())).into(),
                );
            }
        }
        let mut idx = Vec::new();
        for j in 0..nv {
            for i in 0..nu {
                let a = j * nu + i;
                let b = j * nu + (i + 1) % nu;
                let (c2, d) = (a + nu, b + nu);
                idx.extend([a, c2, d, a, d, b]);
            }
        }
        (pos, idx)
    }

    #[test]
    fn sphere_normals_point_outward() {
        let c = Vec3::new(1.0, -2.0, 0.5);
        let (pos, idx) = uv_sphere(c, 0.3);
        let n = vertex_normals(&pos, &idx);
        // Skip the poles, where the duplicated vertices of the UV sphere meet.
        for (p, n) in pos.iter().zip(&n).skip(24).take(pos.len() - 48) {
            let radial = (Vec3::from(*p) - c).normalize();
            assert!(Vec3::from(*n).dot(radial) > 0.99, "{n:?} vs {radial:?}");
        }
    }

    #[test]
    fn area_weighting() {
        // Two triangles sharing vertex 0: a large one in the xy plane, a small one in xz.
        let pos = [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [0.0, 10.0, 0.0],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
        ];
        let idx = [0, 1, 2, 0, 3, 4];
        let n = vertex_normals(&pos, &idx);
        // Normals (0,0,100) and (0,-1,0)... weighted by twice the areas 100 and 1.
        let expected = Vec3::new(0.0, -1.0, 100.0).normalize();
        assert!((Vec3::from(n[0]) - expected).length() < 1e-6);
        assert_eq!(n[2], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn arrow_spans_origin_to_tip() {
        let o = Vec3::new(0.1, 0.2, 0.3);
        let v = Vec3::new(0.0, 0.0, -0.5);
        let (pos, nor, idx) = arrow_mesh(o, v, None);
        assert_eq!(pos.len(), nor.len());
        assert_eq!(idx.len() % 3, 0);
        let zs: Vec<f32> = pos.iter().map(|p| p[2]).collect();
        let (lo, hi) = zs
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &z| (a.min(z), b.max(z)));
        assert!(
            (hi - 0.3).abs() < 1e-6 && (lo + 0.2).abs() < 1e-6,
            "{lo} {hi}"
        );
        // Triangles face outwards: each face normal agrees with its vertices' normals.
        for t in idx.chunks_exact(3) {
            let p = [t[0], t[1], t[2]].map(|i| Vec3::from(pos[i as usize]));
            let f = (p[1] - p[0]).cross(p[2] - p[0]);
            if f.length() < 1e-12 {
                continue;
            }
            assert!(f.dot(Vec3::from(nor[t[0] as usize])) > 0.0);
        }
        assert!(arrow_mesh(o, Vec3::ZERO, None).0.is_empty());
    }

    #[test]
    fn creases_split_a_cube_but_not_a_sphere() {
        // A unit cube: 8 corners, 12 triangles; every corner joins 3 faces at 90°.
        let pos: Vec<[f32; 3]> = (0..8)
            .map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32])
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let idx: Vec<u32> = quads
            .iter()
            .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
            .collect();
        let split = split_creases(&pos, &idx, CREASE_DEGREES);
        assert_eq!(split.source.len(), 24);
        let drawn: Vec<[f32; 3]> = split.source.iter().map(|&s| pos[s as usize]).collect();
        let n = vertex_normals(&drawn, &split.indices);
        // Every drawn normal is a face normal: one axis exactly.
        for v in &n {
            let max = v.iter().fold(0.0f32, |m, c| m.max(c.abs()));
            assert!((max - 1.0).abs() < 1e-6, "{v:?}");
        }
        let (pos, idx) = uv_sphere(Vec3::ZERO, 1.0);
        let split = split_creases(&pos, &idx, CREASE_DEGREES);
        assert_eq!(split.source.len(), pos.len());
    }

    #[test]
    fn back_to_front() {
        let pos = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 5.0],
            [1.0, 0.0, 5.0],
            [0.0, 1.0, 5.0],
        ];
        let mut idx = [0, 1, 2, 3, 4, 5];
        sort_back_to_front(&pos, &mut idx, Vec3::new(0.0, 0.0, 10.0));
        assert_eq!(idx, [0, 1, 2, 3, 4, 5]);
        sort_back_to_front(&pos, &mut idx, Vec3::new(0.0, 0.0, -10.0));
        assert_eq!(idx, [3, 4, 5, 0, 1, 2]);
    }
}
