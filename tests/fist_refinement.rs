//! A full fist under refinement (issue 16): every finger at MCP 88°, PIP 105°, DIP 70°, the
//! thumb across (CMC flexion 25°, abduction 40°, MCP 30°, IP 30°), from rest in 10° corotated
//! increments, at resolutions 1, 1.5 and 2. Before the joint spaces were sized alike at every
//! resolution (src/hand/lattice.rs) the fist at resolution 2 stopped at PIP 59.1° with a cell
//! of the index's palmar joint recess crushed; the fist preset of the viewer was held back to
//! MCP 75°, PIP 90°, DIP 50°.
//!
//! Asserted: every resolution reaches the pose; the flesh keeps its volume to 1.5 %; the bones
//! balance (the flexion's bone reactions sum to round-off, 10⁻⁷ of the largest: no external
//! load). Printed: the
//! largest bone reactions at each resolution (docs/hand.md records them: they do not converge
//! yet, see there).

use crate::common;

use common::flexion::bone_reactions;
use nalgebra::Vector3;
use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::{full_fist, HandModel, Side, Skeleton, SkinShape, BASE_SPACING};
use prehensile::model::FlexionSettings;
use prehensile::solve::Flexion;
use prehensile::state::HandState;

const FLESH: Material = Material {
    young: 5.0e4,
    poisson: 0.45,
    density: 1050.0,
};

/// The full fist closed at `resolution`: reaches the pose, keeps the flesh's volume to 1.5 %,
/// its bones balance. Returns the largest bone reaction, N. (One test per resolution: the test
/// threads run them side by side.)
fn full_fist_at(resolution: f64) -> f64 {
    let hand = HandModel::new(Side::Right, resolution).unwrap();
    let mut stepper = Flexion::new(
        &hand,
        "hand",
        vec![FLESH; hand.flesh.mesh.cells.len()],
        FlexionSettings::default(),
        FillOrdering::Auto,
    );
    let mut state = HandState::rest(&hand);
    let v0 = state.flesh_volume(&hand);
    let target = hand
        .skeleton
        .apply_pose(&state.angles, &full_fist())
        .unwrap();
    let stats = stepper
        .move_to(&mut state, &target)
        .unwrap_or_else(|e| panic!("resolution {resolution}: {e}"));
    assert_eq!(state.angles, target);
    let volume = state.flesh_volume(&hand) / v0 - 1.0;
    let reactions = state.bone_reactions(&hand);
    let sum: Vector3<f64> = reactions.iter().sum();
    let largest = reactions.iter().map(|r| r.norm()).fold(0.0, f64::max);
    let mut named: Vec<(String, f64)> = hand
        .skeleton
        .bones
        .iter()
        .zip(&reactions)
        .map(|(b, r)| (b.name.clone(), r.norm()))
        .collect();
    named.sort_by(|a, b| b.1.total_cmp(&a.1));
    println!(
        "resolution {resolution}: {} cells, {} factorizations, {:.1} s; volume {:+.3} %; \
         largest reactions {:?}",
        hand.flesh.mesh.cells.len(),
        stats.factorizations,
        stats.total_ms * 1e-3,
        100.0 * volume,
        &named[..5]
    );
    assert!(
        volume.abs() < 0.015,
        "resolution {resolution}: volume {volume:+.2e}"
    );
    // (Round-off of 11–22 linear solves of up to 215 000 dofs: 7·10⁻⁸ N at resolution 2.)
    assert!(
        sum.norm() < 1e-7 * largest,
        "resolution {resolution}: Σ bone reactions {sum} of {largest} N"
    );
    largest
}

#[test]
fn the_full_fist_closes_at_resolution_1() {
    full_fist_at(1.0);
}

#[test]
fn the_full_fist_closes_at_resolution_1_5() {
    full_fist_at(1.5);
}

#[test]
fn the_full_fist_closes_at_resolution_2() {
    full_fist_at(2.0);
}

/// Where the lattice falls (issue 16): the index's PIP flexed 90° with the flesh lattice moved by
/// six offsets (fractions of a cell, [`HandModel::build_offset`]) at resolutions 1 and 2. At a
/// given resolution the middle phalanx's reaction depends on which cells bridge the joint; the
/// spread over the offsets shrinks with refinement, not monotonically (measured, half-range
/// over mean: ±63 % at 0.75, ±23 % at 1, ±34 % at 1.25, ±16 % at 1.5, ±10 % at 2, ±8 % at
/// 2.5: about h^1.4) while the mean grows towards about 4.5 N (1.82 / 3.25 / 3.72 / 3.38 /
/// 4.15 / 4.43 N). docs/hand.md has the table.
#[test]
fn where_the_lattice_falls_matters_less_as_it_refines() {
    let offsets = prehensile::bench::flexion_refinement::OFFSETS;
    let spread = |resolution: f64| {
        let h = BASE_SPACING / resolution;
        let middle: Vec<f64> = offsets
            .iter()
            .map(|&o| {
                let hand = HandModel::build_offset(
                    Skeleton::new(Side::Right),
                    SkinShape::new(Side::Right),
                    resolution,
                    None,
                    Vector3::from(o) * h,
                )
                .unwrap();
                let b = hand.skeleton.bone_index("index.middle").unwrap();
                bone_reactions(&hand, &[("index.pip", 90.0)])[b]
            })
            .collect();
        let mean = middle.iter().sum::<f64>() / middle.len() as f64;
        let (lo, hi) = middle.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
        println!(
            "resolution {resolution}: index.middle {middle:.3?} N, mean {mean:.3} N, \
             ±{:.1} %",
            50.0 * (hi - lo) / mean
        );
        (mean, (hi - lo) / mean)
    };
    let (m1, s1) = spread(1.0);
    let (m2, s2) = spread(2.0);
    // Measured: ±23 % then ±10 %; the mean 3.25 then 4.15 N.
    assert!(s2 < 0.6 * s1, "spread {s1:.3} at 1, {s2:.3} at 2");
    assert!(s2 < 0.3, "spread {s2:.3} at 2");
    assert!(m2 > m1, "the mean {m1:.3} N at 1, {m2:.3} N at 2");
}

/// The nested refinement converges where the lattice's does not (issue 16): the index's PIP
/// flexed 20° and 90° on the resolution-1 lattice with every cell split into 1, 2 and 3 along
/// each edge (`subdivisions`, `hand::subdivide`: the same hand, finer elements). The middle
/// phalanx's reaction falls monotonically at an observed order of about 1.2 in the spacing
/// (measured 2026-12-07: 0.407 / 0.343 / 0.325 N at 20°, order 1.26, limit 0.297 N, the finest
/// 9.3 % above it; 3.195 / 2.548 / 2.354 N at 90°, order 1.18, limit 2.036 N, 15.6 %) — where
/// successive lattices of resolution 1, 1.5, 2 read 3.195 / 2.931 / 4.202 N at 90°, no order
/// (docs/hand.md, "Nested refinement").
#[test]
fn the_nested_refinement_converges_the_index_flexion_at_a_rate() {
    use prehensile::bench::flexion_refinement::nested_refinement_rows;
    use prehensile::util::convergence::{convergence, Convergence};
    let rows = nested_refinement_rows(&[20.0, 90.0], &[1.0], &[1, 2, 3], 1).unwrap();
    for angle in [20.0, 90.0] {
        let series: Vec<_> = rows.iter().filter(|r| r.angle_deg == angle).collect();
        assert_eq!(series.len(), 3);
        let h = [0, 1, 2].map(|k| series[k].spacing());
        let f = [0, 1, 2].map(|k| series[k].mean());
        assert_eq!(
            [0, 1, 2].map(|k| series[k].cells),
            [1, 8, 27].map(|m| m * series[0].cells),
            "{angle}°: each cell split into n³"
        );
        assert!(
            f[0] > f[1] && f[1] > f[2],
            "PIP {angle}°: {f:.4?} N, not falling"
        );
        match convergence(h, f) {
            Convergence::Order { order, limit } => {
                println!("PIP {angle}°: {f:.4?} N, order {order:.2}, limit {limit:.4} N");
                assert!(
                    (0.8..2.5).contains(&order),
                    "PIP {angle}°: {f:.4?} N, observed order {order:.2}"
                );
                assert!(
                    (f[2] - limit).abs() < 0.2 * limit,
                    "PIP {angle}°: the finest {:.4} N against the limit {limit:.4} N",
                    f[2]
                );
            }
            other => panic!("PIP {angle}°: {f:.4?} N: {other:?}"),
        }
    }
}
