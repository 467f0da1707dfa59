//! Hertz contact on a ball refined toward the contact (`refine`, issue 15 item 7): with the
//! ball's default refinement the contact radius and the peak of the tactile map come within 3 %
//! of Hertz's closed form at the force the solver finds, and both errors fall with the
//! refinement (the problem of `prehensile bench accuracy --problems hertz`).

use prehensile::bench::accuracy::{run_scene, ProblemId};
use prehensile::mesh::{boundary_facets, mesh_quality};
use prehensile::scene::Shape;

#[test]
fn hertz_within_3_percent_with_the_default_refinement_and_falling_with_it() {
    let mut radius_errors = Vec::new();
    let mut peak_errors = Vec::new();
    for level in [8, 16, 32] {
        let scene = ProblemId::Hertz.scene(level as f64);
        let Shape::Sphere {
            refine: Some(refine),
            ..
        } = &scene.body[0].shape
        else {
            panic!("the Hertz ball is refined");
        };
        // R/32 is the default: the scene leaves `size` out.
        assert_eq!(refine.size.is_none(), level == 32);
        let t = std::time::Instant::now();
        let solved = run_scene(&scene, "hertz")
            .map_err(|e| format!("{e:?}"))
            .unwrap();
        let m = ProblemId::Hertz
            .measure(&solved, level as f64, None)
            .unwrap();
        let (a, p, force) = (m[1], m[2], m[3]);
        let mesh = &solved.model.mesh;
        let (jacobian, aspect) = mesh_quality(mesh);
        let contact = solved.frames[0].contact.as_ref().unwrap();
        println!(
            "R/{level}: {} nodes, {} cells, min scaled Jacobian {jacobian:.3}, max aspect \
             {aspect:.1}; F = {force:.4} N on {} nodes; a / a_Hertz − 1 = {:+.2} %, peak / p0 − 1 \
             = {:+.2} %; solve {:.0} ms, all {:.0} ms",
            mesh.nodes.len(),
            mesh.cells.len(),
            contact.contacts.len(),
            a * 100.0,
            p * 100.0,
            solved.solve_ms,
            t.elapsed().as_secs_f64() * 1e3
        );
        assert!(
            contact.max_penetration <= 1e-9,
            "{}",
            contact.max_penetration
        );
        assert!(jacobian > 0.55, "{jacobian}");
        assert!(mesh.nodes.len() < 20_000);
        assert_eq!(
            boundary_facets(mesh).len(),
            solved.model.bodies[0].facets.len()
        );
        radius_errors.push(a.abs());
        peak_errors.push(p.abs());
    }
    assert!(radius_errors[2] < 0.03, "{radius_errors:?}");
    assert!(peak_errors[2] < 0.03, "{peak_errors:?}");
    for e in [&radius_errors, &peak_errors] {
        assert!(e[0] > e[1] && e[1] > e[2], "{e:?}");
    }
}
