//! Modelling only what a scene requires: the finger press solved with FEM only near the moving
//! joint and near the contact, against the whole flesh everywhere (`prehensile bench region`).

use prehensile::bench_region::region_runs;

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
    for (i, (a, b)) in cheap.frames.iter().zip(&full.frames).enumerate() {
        let force = |f: &prehensile::sim::Frame| {
            f.hands
                .iter()
                .flat_map(|h| &h.contact_force)
                .sum::<nalgebra::Vector3<f64>>()
                .norm()
        };
        let gap = a.hands[0]
            .positions
            .iter()
            .zip(&b.hands[0].positions)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        println!(
            "frame {i}: force {:.4} / {:.4} N, largest node difference {:.3} mm",
            force(a),
            force(b),
            gap * 1e3
        );
        // The press force within 4 %, the flesh within 1 mm (of a 35 mm ball pressed 2-3 mm).
        assert!(force(b) > 1.0);
        assert!((force(a) - force(b)).abs() < 0.04 * force(b));
        assert!(gap < 1e-3, "{gap}");
    }
}
