//! Balls meshed finer where they are touched (`refine`): surface nodes on the sphere, boundary
//! facets outward and on the right surface, cells of the asked size at the touched point,
//! well-shaped cells, volumes converging to the ball's, and the key's errors naming the field.

use nalgebra::Vector3;
use prehensile::fem::hex8::mapped_points;
use prehensile::mesh::{
    boundary_facets, graded_shell_mesh, graded_sphere_mesh, mesh_quality, Facet, Mesh, Refinement,
};
use prehensile::model::Model;
use prehensile::scene::Scene;
use std::f64::consts::PI;

fn volume(mesh: &Mesh) -> f64 {
    (0..mesh.cells.len())
        .map(|c| {
            mapped_points(&mesh.cell_coords(c))
                .expect("no inverted cell")
                .iter()
                .map(|g| g.volume)
                .sum::<f64>()
        })
        .sum()
}

fn centroid(mesh: &Mesh, f: &Facet) -> Vector3<f64> {
    f.nodes.iter().map(|&n| mesh.nodes[n]).sum::<Vector3<f64>>() / 4.0
}

/// Outward: (n1 − n0) × (n3 − n0) points away from the centre.
fn outward(mesh: &Mesh, f: &Facet, center: &Vector3<f64>, inner: bool) -> bool {
    let p = f.nodes.map(|n| mesh.nodes[n]);
    let normal = (p[1] - p[0]).cross(&(p[3] - p[0]));
    let away = normal.dot(&(centroid(mesh, f) - center)) > 0.0;
    away != inner
}

/// The longest edge of the boundary facet whose centroid is nearest `point`.
fn facet_size_near(mesh: &Mesh, facets: &[Facet], point: &Vector3<f64>) -> f64 {
    let f = facets
        .iter()
        .min_by(|a, b| {
            let (da, db) = (
                (centroid(mesh, a) - point).norm(),
                (centroid(mesh, b) - point).norm(),
            );
            da.total_cmp(&db)
        })
        .unwrap();
    (0..4)
        .map(|i| (mesh.nodes[f.nodes[i]] - mesh.nodes[f.nodes[(i + 1) % 4]]).norm())
        .fold(0.0, f64::max)
}

#[test]
fn a_graded_ball_is_on_its_sphere_fine_where_touched_and_well_shaped() {
    let (c, r) = (Vector3::new(0.01, -0.02, 0.05), 0.05f64);
    for direction in [-Vector3::z(), Vector3::new(1.0, 2.0, -3.0).normalize()] {
        let refine = Refinement {
            direction,
            size: r / 32.0,
        };
        let mesh = graded_sphere_mesh(c, r, 12, &refine);
        let facets = boundary_facets(&mesh);
        let mut surface = vec![false; mesh.nodes.len()];
        for f in &facets {
            assert!(outward(&mesh, f, &c, false), "{f:?}");
            for &n in &f.nodes {
                surface[n] = true;
            }
        }
        for (n, p) in mesh.nodes.iter().enumerate() {
            let d = (p - c).norm();
            if surface[n] {
                assert!((d - r).abs() < 1e-14, "surface node {n} at {d}");
            } else {
                assert!(d < r * (1.0 - 1e-6), "inner node {n} at {d}");
            }
        }
        let touched = c + direction * r;
        let h = facet_size_near(&mesh, &facets, &touched);
        assert!(h <= r / 32.0 * 1.001 && h > r / 32.0 * 0.8, "{h}");
        // A quarter circle away, the lattice lines across the touched point are still fine but
        // the others have the base size (a quarter circle in 12/2 arcs). (The lines through the
        // touched point run on through the opposite point, which is as fine.)
        let side = direction.cross(&Vector3::x()).normalize();
        let far = facet_size_near(&mesh, &facets, &(c + side * r));
        assert!(far > 3.0 * h, "{far} vs {h}");
        let (jacobian, aspect) = mesh_quality(&mesh);
        let error = volume(&mesh) / (4.0 / 3.0 * PI * r.powi(3)) - 1.0;
        println!(
            "ball toward {direction:?}: {} nodes, {} cells, min scaled Jacobian {jacobian:.3}, \
             max aspect ratio {aspect:.1}, touched facet {:.3} mm, far facet {:.2} mm, \
             volume error {:.3} %",
            mesh.nodes.len(),
            mesh.cells.len(),
            h * 1e3,
            far * 1e3,
            error * 100.0
        );
        assert!(jacobian > 0.55, "{jacobian}");
        assert!(aspect < 15.0, "{aspect}");
        assert!(mesh.nodes.len() < 20_000);
        assert!(error < 0.0 && error > -0.01, "{error}");
        let (_, pieces) = mesh.connected_pieces();
        assert_eq!(pieces, 1);
    }
}

#[test]
fn a_graded_shell_has_its_two_surfaces_and_its_volume_converges() {
    let (c, inner, outer) = (Vector3::new(0.0, 0.0, 0.0), 0.031f64, 0.035f64);
    let exact = 4.0 / 3.0 * PI * (outer.powi(3) - inner.powi(3));
    let mut errors = Vec::new();
    for (cells, size) in [(6, 0.004), (12, 0.002), (24, 0.001)] {
        for on_outer in [true, false] {
            let direction = Vector3::new(0.3, -0.2, -1.0).normalize();
            let refine = Refinement { direction, size };
            let mesh = graded_shell_mesh(c, inner, outer, (cells, 2), &refine, on_outer);
            let facets = boundary_facets(&mesh);
            let (mut n_inner, mut n_outer) = (0, 0);
            for f in &facets {
                let radii = f.nodes.map(|n| (mesh.nodes[n] - c).norm());
                if radii.iter().all(|d| (d - outer).abs() < 1e-14) {
                    n_outer += 1;
                    assert!(outward(&mesh, f, &c, false));
                } else if radii.iter().all(|d| (d - inner).abs() < 1e-14) {
                    n_inner += 1;
                    assert!(outward(&mesh, f, &c, true));
                } else {
                    panic!("a boundary facet off both spheres: {radii:?}");
                }
            }
            // One quad per column of cells on each surface; a closed quad surface on a sphere
            // has two nodes more than quads, repeated on every layer's surface.
            assert_eq!(n_inner, n_outer);
            assert_eq!(mesh.nodes.len() % (n_outer + 2), 0);
            let layers = mesh.nodes.len() / (n_outer + 2) - 1;
            assert_eq!(mesh.cells.len(), n_outer * layers);
            let touched_radius = if on_outer { outer } else { inner };
            let h = facet_size_near(&mesh, &facets, &(c + direction * touched_radius));
            assert!(h <= size * 1.001, "{h} > {size}");
            let (jacobian, aspect) = mesh_quality(&mesh);
            let error = (volume(&mesh) / exact - 1.0).abs();
            println!(
                "shell {cells} cells, size {size} on the {} surface: {} nodes, min scaled \
                 Jacobian {jacobian:.3}, max aspect ratio {aspect:.1}, volume error {:.4} %",
                if on_outer { "outer" } else { "inner" },
                mesh.nodes.len(),
                error * 100.0
            );
            assert!(jacobian > 0.8, "{jacobian}");
            if on_outer {
                errors.push(error);
            }
        }
    }
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
    assert!(errors[2] < 2e-3, "{errors:?}");
}

const MATERIAL: &str = "[[material]]\nname = \"m\"\nyoung = 1e5\npoisson = 0.3\n";

fn build(shape: &str) -> Result<Model, String> {
    let text = format!(
        "{MATERIAL}[[body]]\nname = \"ball\"\nmaterial = \"m\"\nshape = {shape}\n\
         [[constraint]]\nname = \"all\"\nbody = \"ball\"\n\
         where = {{ box = {{ min = [-1, -1, -1], max = [1, 1, 1] }} }}\ndisplacement = [0, 0, 0]\n"
    );
    let scene = Scene::parse(&text, "t.toml").map_err(|e| e.to_string())?;
    Model::build(&scene, "t.toml").map_err(|e| e.to_string())
}

#[test]
fn the_refine_key_is_checked_and_its_errors_name_the_field() {
    let sphere = |refine: &str| {
        format!("{{ sphere = {{ center = [0, 0, 0.05], radius = 0.05, cells = 8, refine = {refine} }} }}")
    };
    let shell = |refine: &str| {
        format!(
            "{{ shell = {{ center = [0, 0, 0], inner_radius = 0.031, outer_radius = 0.035, \
             cells = 8, layers = 2, refine = {refine} }} }}"
        )
    };
    let field = "body \"ball\" (body[0]).shape";
    for (shape, at, words) in [
        (
            sphere("{ toward = [0, 0, 0], size = -0.001 }"),
            ".sphere.refine.size",
            "finite length",
        ),
        (
            sphere("{ toward = [0, 0, 0], size = 0.0 }"),
            ".sphere.refine.size",
            "finite length",
        ),
        (
            sphere("{ toward = [0, 0, 0], size = nan }"),
            ".sphere.refine.size",
            "finite length",
        ),
        (
            sphere("{ toward = [0, 0, 0], size = inf }"),
            ".sphere.refine.size",
            "finite length",
        ),
        (
            sphere("{ toward = [0, 0, 0], size = 1.0 }"),
            ".sphere.refine.size",
            "touched radius",
        ),
        (
            sphere("{ toward = [0, 0, 0.05] }"),
            ".sphere.refine.toward",
            "centre",
        ),
        (
            sphere("{ toward = [0, nan, 0] }"),
            ".sphere.refine.toward",
            "finite point",
        ),
        (
            shell("{ toward = [0, 0, 0], size = 0.001 }"),
            ".shell.refine.toward",
            "centre",
        ),
        (
            shell("{ toward = [0, 0, -1], size = -1 }"),
            ".shell.refine.size",
            "finite length",
        ),
    ] {
        let e = build(&shape).expect_err(&shape);
        assert!(
            e.contains(&format!("{field}{at}:")) && e.contains(words),
            "{shape}: {e}"
        );
    }
    // An unknown key under refine is a located syntax error naming it.
    let e = build(&sphere("{ toward = [0, 0, 0], sise = 0.001 }")).unwrap_err();
    assert!(e.contains("t.toml:") && e.contains("sise"), "{e}");
    // A point outside the ball, inside it, or in a shell's cavity all refine the nearest surface.
    for (shape, touched) in [
        (
            sphere("{ toward = [0, 0, -1] }"),
            Vector3::new(0.0, 0.0, 0.0),
        ),
        (
            sphere("{ toward = [0, 0.01, 0.05] }"),
            Vector3::new(0.0, 0.05, 0.05),
        ),
        (
            shell("{ toward = [0.1, 0, 0] }"),
            Vector3::new(0.035, 0.0, 0.0),
        ),
        (
            shell("{ toward = [0.001, 0, 0] }"),
            Vector3::new(0.031, 0.0, 0.0),
        ),
    ] {
        let model = build(&shape).unwrap();
        let mesh = &model.mesh;
        let facets = boundary_facets(mesh);
        let h = facet_size_near(mesh, &facets, &touched);
        let default = if touched.norm() > 0.032 || touched.norm() == 0.0 {
            // The ball's or the shell's outer radius over 32.
            if shape.contains("shell") {
                0.035
            } else {
                0.05
            }
        } else {
            0.031
        } / 32.0;
        assert!(h <= default * 1.001 && h > 0.8 * default, "{shape}: {h}");
        let nearest = mesh
            .nodes
            .iter()
            .map(|p| (p - touched).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-12,
            "{shape}: no node at the touched point ({nearest})"
        );
    }
}

/// ∫ N_i dA of each node over the boundary facets (bilinear, 2 × 2 Gauss points), and the
/// tactile map's tributary area (a quarter of each facet's area, as `contact::nodal_pressure`).
fn tributary_areas(mesh: &Mesh, facets: &[Facet]) -> (Vec<f64>, Vec<f64>) {
    let mut exact = vec![0.0; mesh.nodes.len()];
    let mut quarter = vec![0.0; mesh.nodes.len()];
    let g = 1.0 / 3.0f64.sqrt();
    for f in facets {
        let p = f.nodes.map(|n| mesh.nodes[n]);
        let area = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm();
        for &n in &f.nodes {
            quarter[n] += area / 4.0;
        }
        for (xi, eta) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
            let shape = [
                (1.0 - xi) * (1.0 - eta) / 4.0,
                (1.0 + xi) * (1.0 - eta) / 4.0,
                (1.0 + xi) * (1.0 + eta) / 4.0,
                (1.0 - xi) * (1.0 + eta) / 4.0,
            ];
            let d_xi = ((p[1] - p[0]) * (1.0 - eta) + (p[2] - p[3]) * (1.0 + eta)) / 4.0;
            let d_eta = ((p[3] - p[0]) * (1.0 - xi) + (p[2] - p[1]) * (1.0 + xi)) / 4.0;
            let jacobian = d_xi.cross(&d_eta).norm();
            for i in 0..4 {
                exact[f.nodes[i]] += shape[i] * jacobian;
            }
        }
    }
    (exact, quarter)
}

#[test]
fn around_the_touched_point_the_tactile_maps_tributary_areas_are_the_consistent_ones() {
    let (c, r) = (Vector3::new(0.0, 0.0, 0.05), 0.05f64);
    let refine = Refinement {
        direction: -Vector3::z(),
        size: r / 32.0,
    };
    let mesh = graded_sphere_mesh(c, r, 12, &refine);
    let facets = boundary_facets(&mesh);
    let (exact, quarter) = tributary_areas(&mesh, &facets);
    // Hertz's contact disc at the bench's force is 8 mm in radius: the nodes within 12 mm.
    let mut worst_near = 0.0f64;
    let mut worst = 0.0f64;
    for (n, p) in mesh.nodes.iter().enumerate() {
        if exact[n] > 0.0 {
            let d = (quarter[n] / exact[n] - 1.0).abs();
            worst = worst.max(d);
            if (p.x * p.x + p.y * p.y).sqrt() < 0.012 && p.z < 0.01 {
                worst_near = worst_near.max(d);
            }
        }
    }
    println!(
        "quarter-facet tributary area against ∫N dA: within {:.3} % near the contact, {:.2} % \
         anywhere on the surface",
        worst_near * 100.0,
        worst * 100.0
    );
    assert!(worst_near < 2e-3, "{worst_near}");
}
