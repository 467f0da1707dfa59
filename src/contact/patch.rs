//! The contact pressure over a patch of surface: at each vertex, the normal contact forces of
//! the vertices within a radius of it that face the same way, over their area,
//!
//!   p̄(v) = Σ_{u ∈ P(v)} F_u / Σ_{u ∈ P(v)} A_u,   P(v) = { u : |x_u − x_v| ≤ r, n_u·n_v > 0 }.
//!
//! A vertex's own force over its own area (the nodal map, `pressure.rs`) is what node-to-facet
//! contact gives at one point: where the surfaces first meet it is spiky, and its peak does not
//! converge under refinement (the forces of a vertex's neighbours move to it and back as the
//! mesh changes). The patch's pressure is the nodal map filtered at a length of the body, not of
//! the mesh: it converges where the forces do, as a pressure-mapping film's sensel or the skin's
//! tactile resolution reads a press. A uniform pressure reads the same at every radius; a press
//! smaller than the patch reads its force over the patch's area. Opposite sides of a fold (the
//! two sides of a crease, both pressed) are kept apart by their normals.

use crate::util::near::NearPoints;
use nalgebra::Vector3;

/// The patch pressure p̄ at every vertex (Pa; 0 where no force lies within the patch), from
/// each vertex's position, unit outward normal (a zero normal faces nowhere: only the vertex
/// itself joins its patch), area (m²) and normal force (N), over a patch of radius `radius` (m,
/// positive and finite, else the nodal map F/A). Vertices at non-finite positions join no
/// patch but their own; a force or an area that is not finite counts as none.
pub fn patch_pressure(
    positions: &[Vector3<f64>],
    normals: &[Vector3<f64>],
    area: &[f64],
    force: &[f64],
    radius: f64,
) -> Vec<f64> {
    let n = positions.len();
    assert!(
        normals.len() == n && area.len() == n && force.len() == n,
        "one normal, area and force per vertex"
    );
    // A force or an area that is not a finite number counts as none.
    let finite = |x: f64| if x.is_finite() { x } else { 0.0 };
    let force: Vec<f64> = force.iter().map(|&f| finite(f)).collect();
    let area: Vec<f64> = area.iter().map(|&a| finite(a)).collect();
    let nodal = |v: usize| {
        if area[v] > 0.0 {
            force[v] / area[v]
        } else {
            0.0
        }
    };
    if !(radius > 0.0 && radius.is_finite()) {
        return (0..n).map(nodal).collect();
    }
    // A vertex at a position that is not finite is in no patch but its own.
    let placed = |v: usize| {
        positions[v]
            .iter()
            .all(|a| a.is_finite() && a.abs() < 1e15 * radius)
    };
    let near = NearPoints::new(positions, radius);
    // Only patches that hold a force need the search.
    let mut pressed = vec![false; n];
    for v in 0..n {
        if force[v] != 0.0 {
            pressed[v] = true;
            if placed(v) {
                near.for_each_within(&positions[v], |u| pressed[u] = true);
            }
        }
    }
    (0..n)
        .map(|v| {
            if !pressed[v] {
                return 0.0;
            }
            if !placed(v) {
                return nodal(v);
            }
            let (mut f, mut a) = (force[v], area[v]);
            near.for_each_within(&positions[v], |u| {
                if u != v && normals[u].dot(&normals[v]) > 0.0 {
                    f += force[u];
                    a += area[u];
                }
            });
            if a > 0.0 {
                f / a
            } else {
                0.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square of side `side` in the plane z = `z`, in `cells`² cells: its vertices and
    /// their areas (a quarter of each cell they belong to).
    fn plate(side: f64, cells: usize, z: f64) -> (Vec<Vector3<f64>>, Vec<f64>) {
        let h = side / cells as f64;
        let mut points = Vec::new();
        let mut area = Vec::new();
        for i in 0..=cells {
            for j in 0..=cells {
                points.push(Vector3::new(i as f64 * h, j as f64 * h, z));
                let edge = |k: usize| if k == 0 || k == cells { 0.5 } else { 1.0 };
                area.push(h * h * edge(i) * edge(j));
            }
        }
        (points, area)
    }

    #[test]
    fn a_uniform_pressure_reads_the_same_over_any_patch() {
        let (points, area) = plate(0.02, 40, 0.0);
        let normals = vec![Vector3::z(); points.len()];
        let p = 3.7e4;
        let force: Vec<f64> = area.iter().map(|a| p * a).collect();
        for radius in [1e-4, 1e-3, 3.2e-3, 1e-2] {
            for (v, q) in patch_pressure(&points, &normals, &area, &force, radius)
                .iter()
                .enumerate()
            {
                assert!(
                    (q - p).abs() < 1e-9 * p,
                    "vertex {v}, radius {radius}: {q} Pa"
                );
            }
        }
    }

    #[test]
    fn a_point_force_reads_its_force_over_the_patch_area() {
        // 0.2 mm spacing, a 3 mm patch: the disc's area within the spacing's share.
        let (points, area) = plate(0.02, 100, 0.0);
        let normals = vec![Vector3::z(); points.len()];
        let centre = 50 * 101 + 50;
        let mut force = vec![0.0; points.len()];
        force[centre] = 0.8;
        let r = 3e-3;
        let p = patch_pressure(&points, &normals, &area, &force, r);
        let expected = 0.8 / (std::f64::consts::PI * r * r);
        assert!(
            (p[centre] / expected - 1.0).abs() < 0.03,
            "{} Pa",
            p[centre]
        );
        // Vertices farther than the radius from the force read none; the nodal map's peak is
        // the force over one vertex's area, 700 times more.
        let far = 50 * 101 + 50 + 20;
        assert_eq!(p[far], 0.0);
        assert!(0.8 / area[centre] > 500.0 * p[centre]);
        // Refined twice over, the patch reads the same within the spacing's share.
        let (fine, fine_area) = plate(0.02, 200, 0.0);
        let mut fine_force = vec![0.0; fine.len()];
        fine_force[100 * 201 + 100] = 0.8;
        let q = patch_pressure(
            &fine,
            &vec![Vector3::z(); fine.len()],
            &fine_area,
            &fine_force,
            r,
        );
        assert!((q[100 * 201 + 100] / p[centre] - 1.0).abs() < 0.03);
    }

    #[test]
    fn the_two_sides_of_a_fold_are_read_apart() {
        // Two plates 1 mm apart facing each other (a crease pressed shut), only the lower
        // pressed: the upper reads nothing, the lower its pressure, though within the radius.
        let (lower, area) = plate(0.01, 20, 0.0);
        let (upper, _) = plate(0.01, 20, 1e-3);
        let n = lower.len();
        let points: Vec<_> = lower.into_iter().chain(upper).collect();
        let area: Vec<f64> = area.iter().chain(area.iter()).copied().collect();
        let normals: Vec<_> = (0..2 * n)
            .map(|v| if v < n { Vector3::z() } else { -Vector3::z() })
            .collect();
        let p = 5e4;
        let force: Vec<f64> = (0..2 * n)
            .map(|v| if v < n { p * area[v] } else { 0.0 })
            .collect();
        let q = patch_pressure(&points, &normals, &area, &force, 3e-3);
        assert!(q[..n].iter().all(|q| (q - p).abs() < 1e-9 * p));
        assert!(q[n..].iter().all(|&q| q == 0.0));
    }

    #[test]
    fn hostile_positions_and_radii_give_finite_pressures() {
        let points = vec![
            Vector3::new(f64::NAN, 0.0, 0.0),
            Vector3::new(1e300, 0.0, 0.0),
            Vector3::zeros(),
        ];
        let normals = vec![Vector3::z(); 3];
        let area = vec![1e-6, 1e-6, 0.0];
        let force = vec![1.0, 1.0, 1.0];
        for radius in [3e-3, 0.0, -1.0, f64::NAN, f64::INFINITY] {
            let p = patch_pressure(&points, &normals, &area, &force, radius);
            assert_eq!(p, vec![1e6, 1e6, 0.0], "radius {radius}");
        }
        let p = patch_pressure(
            &[Vector3::zeros(), Vector3::new(1e-3, 0.0, 0.0)],
            &[Vector3::z(); 2],
            &[1e-6, f64::INFINITY],
            &[f64::NAN, 2e-6],
            3e-3,
        );
        // (Each patch holds both: the second's force over the first's area.)
        assert_eq!(p, vec![2.0, 2.0]);
    }
}
