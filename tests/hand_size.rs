//! The built-in hand at another size (issue 18): an ANSUR II percentile or a measured length
//! and breadth stretches the whole hand — joints, bones, flesh — so that its flesh's volume
//! scales as length × breadth², and a hand scaled alike in every direction feels forces scaled
//! as the square of its size (linear elasticity: strains are the same for the same joint angles,
//! forces go as stress × area).

use crate::common;

use common::flexion::bone_reactions;
use prehensile::fem::hex8::{cell_volume, scaled_jacobian};
use prehensile::hand::{DisplaySkin, HandForm, HandModel, HandSize, Side, SkinShape};

/// The index's PIP flexed 90° from rest.
const PIP_90: [(&str, f64); 1] = [("index.pip", 90.0)];

fn flesh_volume(hand: &HandModel) -> f64 {
    let mesh = &hand.flesh.mesh;
    mesh.cells
        .iter()
        .map(|c| cell_volume(&c.map(|n| mesh.nodes[n])))
        .sum()
}

#[test]
fn a_sized_hands_flesh_scales_as_its_length_times_its_breadth_squared() {
    let reference = HandModel::new(Side::Right, 1.0).unwrap();
    let v0 = flesh_volume(&reference);
    for name in ["female-5", "male-95"] {
        let size = HandSize::percentile(name).unwrap();
        for side in [Side::Right, Side::Left] {
            let hand = HandModel::sized(side, size, 1.0, None).unwrap();
            let s = size.stretch().scale;
            let expected = s.x * s.y * s.z;
            let ratio = flesh_volume(&hand) / v0;
            println!(
                "{name} {side:?}: {} cells, flesh {:.1} ml, ratio {ratio:.4} against {expected:.4}",
                hand.flesh.mesh.cells.len(),
                flesh_volume(&hand) * 1e6
            );
            // The lattice's spacing is the same in millimetres: a smaller hand has fewer cells
            // and its skin is followed as closely in millimetres (1.1 % off for the 5th-percentile
            // woman).
            assert!(
                (ratio / expected - 1.0).abs() < 0.015,
                "{name} {side:?}: volume ratio {ratio} against {expected}"
            );
            assert_eq!(hand.skeleton.bones.len(), reference.skeleton.bones.len());
            let (worst, at) = hand
                .flesh
                .mesh
                .cells
                .iter()
                .map(|c| {
                    let x = c.map(|n| hand.flesh.mesh.nodes[n]);
                    (
                        scaled_jacobian(&x),
                        x.iter().sum::<nalgebra::Vector3<f64>>() / 8.0,
                    )
                })
                .fold((f64::INFINITY, Default::default()), |a, b| {
                    if b.0 < a.0 {
                        b
                    } else {
                        a
                    }
                });
            assert!(
                worst >= 0.29,
                "{name} {side:?}: a cell of scaled Jacobian {worst} at {at:?}"
            );
        }
    }
}

#[test]
fn a_hand_scaled_alike_in_every_direction_feels_forces_scaled_by_its_size_squared() {
    // Scaled by s with the lattice scaled alike (resolution 1 / s), the mesh is the reference's
    // scaled but for the joint spaces, which keep their width in millimetres.
    let s = 0.85;
    let size = HandSize::of_length(s * HandSize::reference().length);
    let reference = HandModel::new(Side::Right, 1.0).unwrap();
    let small = HandModel::sized(Side::Right, size, 1.0 / s, None).unwrap();
    let (r0, r1) = (
        bone_reactions(&reference, &PIP_90),
        bone_reactions(&small, &PIP_90),
    );
    // The distal phalanx's reaction (60 times smaller) is set by the DIP's joint space alone,
    // whose width is the same in millimetres at every size: it is not compared.
    for bone in ["index.proximal", "index.middle"] {
        let b = reference.skeleton.bone_index(bone).unwrap();
        let ratio = r1[b] / r0[b];
        println!(
            "{bone}: {:.4} N at the reference size, {:.4} N at {s}: ratio {ratio:.4} (s² = {:.4})",
            r0[b],
            r1[b],
            s * s
        );
        assert!(
            (ratio / (s * s) - 1.0).abs() < 0.03,
            "{bone}: reaction ratio {ratio}, expected {}",
            s * s
        );
    }
}

/// Over a skin's rest vertices: how many lie farther than `tolerance` from the skin's shape, of
/// how many, the farthest (m), and the largest weight any vertex puts on a node.
pub fn skin_fidelity(
    hand: &HandModel,
    shape: &SkinShape,
    skin: &DisplaySkin,
    tolerance: f64,
) -> (usize, usize, f64, f64) {
    let at = skin.positions(&hand.flesh.mesh.nodes);
    let d: Vec<f64> = at.iter().map(|p| shape.distance(p).abs()).collect();
    let off = d.iter().filter(|&&d| d > tolerance).count();
    let weight = (0..skin.vertex_count())
        .flat_map(|v| skin.terms(v).map(|(_, w)| w.abs()))
        .fold(0.0, f64::max);
    (off, at.len(), d.iter().cloned().fold(0.0, f64::max), weight)
}

/// Every vertex of the display skin is embedded in the flesh exactly where the skin's shape is
/// (a vertex beyond its own cell's reach is embedded in a neighbour holding it, or extrapolated
/// along the nearest cell's tangent map), with bounded weights. Until 2026-11-27 a vertex more
/// than a cell's half beyond its cell was pulled in: 714 of the built-in hand's 104 930 display
/// vertices lay more than 0.2 mm inside the skin, the deepest 4.2 mm (5.8 mm on the
/// 5th-percentile woman's hand) — dents on the backs of the fingers. The contact skin still is
/// (106 of its 6 560 vertices, 4.2 mm deep): bounded here, its reason in src/hand/model.rs.
#[test]
fn the_display_skin_lies_on_the_skins_shape_at_every_size() {
    for name in ["built-in", "female-5", "male-95"] {
        for side in [Side::Right, Side::Left] {
            let (hand, shape) = match HandSize::percentile(name) {
                Some(size) => (
                    HandModel::sized(side, size, 1.0, None).unwrap(),
                    SkinShape::sized(side, size.stretch(), HandForm::Simple),
                ),
                None => (HandModel::new(side, 1.0).unwrap(), SkinShape::new(side)),
            };
            for (what, skin) in [("display", &hand.skin), ("contact", &hand.contact_skin)] {
                let (off, of, farthest, weight) = skin_fidelity(&hand, &shape, skin, 0.1e-3);
                println!(
                    "{name} {side:?} {what} skin: {off} of {of} vertices more than 0.1 mm off \
                     the shape, the farthest {:.3} mm; largest weight {weight:.2}",
                    farthest * 1e3
                );
                if what == "contact" {
                    // Kept within reach of its own cells (src/hand/model.rs): measured 106 of
                    // 6 560 vertices more than 0.2 mm inside, the deepest 4.2 mm; not worse.
                    assert!(
                        farthest < 6e-3 && off < of / 20,
                        "{name} {side:?} contact skin"
                    );
                    continue;
                }
                // Measured: at most 0.020 mm (the shape's own projection), weights ≤ 4.6.
                assert_eq!(off, 0, "{name} {side:?} {what} skin off its shape");
                // A trilinear map extrapolated three cells out weighs nodes by 30 to 60.
                assert!(weight < 6.0, "{name} {side:?} {what} skin weight {weight}");
            }
        }
    }
}
