//! Modelling only what a scene requires: the finger press solved with FEM only near the moving
//! joint and near the contact, against the whole flesh everywhere (`prehensile bench region`).

use prehensile::bench::region::region_runs;

#[test]
fn the_local_regions_cost_a_fraction_and_change_the_press_by_little() {
    let runs = region_runs("assets/scenes/finger-press-ball.toml").unwrap();
    let (cheap, full) = (&runs[0], &runs[1]);
    println!(
        "flexion cells {} / {}, contact cells {:?} / {:?}",
        cheap.flexion_cells, full.flexion_cells, cheap.contact_cells, full.contact_cells
    );
    // One finger flexes: the local region is under half the flesh; the contact region a few
    // percent of it.
    assert!(2 * cheap.flexion_cells < full.flexion_cells);
    for (a, b) in cheap.contact_cells.iter().zip(&full.contact_cells) {
        assert!(*a > 0 && 20 * a < *b, "{a} of {b}");
    }
    // Nodes of the index's flesh (the pressing finger): cells of digit 1.
    let hand = runs[0].frames[0].hands[0].positions.len();
    let solved = prehensile::headless::solve_scene(
        &prehensile::scene::Scene::load(std::path::Path::new(
            "assets/scenes/finger-press-ball.toml",
        ))
        .unwrap(),
        "press",
    )
    .unwrap();
    let flesh = &solved.model.bodies[0].hand.as_deref().unwrap().flesh;
    let mut index = vec![false; hand];
    for (cell, digit) in flesh.mesh.cells.iter().zip(&flesh.cell_digit) {
        if *digit == Some(1) {
            for &n in cell {
                index[n] = true;
            }
        }
    }
    for (i, (a, b)) in cheap.frames.iter().zip(&full.frames).enumerate() {
        let force = |f: &prehensile::state::Frame| {
            f.hands
                .iter()
                .flat_map(|h| &h.contact_force)
                .sum::<nalgebra::Vector3<f64>>()
                .norm()
        };
        let gap = |only_index: bool| {
            a.hands[0]
                .positions
                .iter()
                .zip(&b.hands[0].positions)
                .enumerate()
                .filter(|(n, _)| !only_index || index[*n])
                .map(|(_, (p, q))| (p - q).norm())
                .fold(0.0, f64::max)
        };
        let (near, all) = (gap(true), gap(false));
        println!(
            "frame {i}: force {:.4} / {:.4} N, largest node difference {:.3} mm in the index, \
             {:.3} mm in the hand",
            force(a),
            force(b),
            near * 1e3,
            all * 1e3
        );
        // The press force within 4 %, the pressing finger's flesh within 1 mm (of a 35 mm ball
        // pressed 2-3 mm); the fingers far from the ball, skinned, within 2.5 mm.
        assert!(force(b) > 1.0);
        assert!((force(a) - force(b)).abs() < 0.04 * force(b));
        assert!(near < 1e-3, "{near}");
        assert!(all < 2.5e-3, "{all}");
    }
}
