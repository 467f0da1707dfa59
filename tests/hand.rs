//! The hand: skeleton and limits, flesh mesh, incremental flexion (convergence, volume,
//! locality, equilibrium of the bone reactions), display skin, scene errors.

use nalgebra::{Point3, Vector3};
use prehensile::fem::hex8::scaled_jacobian;
use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::{DisplaySkin, HandModel, Pose, PoseError, Side, Skeleton};
use prehensile::model::{FleshMethod, FleshRegion, FlexionScheme, FlexionSettings};
use prehensile::solve::Flexion;
use prehensile::state::HandState;
use std::sync::OnceLock;

fn hand() -> &'static HandModel {
    static HAND: OnceLock<HandModel> = OnceLock::new();
    HAND.get_or_init(|| HandModel::new(Side::Right, 1.0).unwrap())
}

const FLESH: Material = Material {
    young: 5.0e4,
    poisson: 0.45,
    density: 1050.0,
};

fn pose(entries: &[(&str, f64)]) -> Pose {
    entries.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// Flexes the hand from rest to `entries` with `settings`; returns the final state.
fn flex(entries: &[(&str, f64)], settings: FlexionSettings) -> HandState {
    let hand = hand();
    let materials = vec![FLESH; hand.flesh.mesh.cells.len()];
    let mut stepper = Flexion::new(hand, "hand", materials, settings, FillOrdering::Auto);
    let mut state = HandState::rest(hand);
    let target = hand
        .skeleton
        .apply_pose(&state.angles, &pose(entries))
        .unwrap();
    stepper.move_to(&mut state, &target).unwrap();
    state
}

fn with_step(step: f64, scheme: FlexionScheme) -> FlexionSettings {
    FlexionSettings {
        max_step_deg: step,
        scheme,
        ..Default::default()
    }
}

fn max_distance(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

#[test]
fn pip_flexion_turns_the_middle_and_distal_phalanges_about_the_condyle() {
    let sk = Skeleton::new(Side::Right);
    let angles = sk
        .apply_pose(&sk.rest_angles(), &pose(&[("index.pip", 90.0)]))
        .unwrap();
    let t = sk.transforms(&angles);
    let distal = sk.bone_index("index.distal").unwrap();
    let pip = sk.dofs.iter().find(|d| d.name == "index.pip").unwrap();
    let tip = sk.bones[distal].end;
    // Flexion by 90° about the lateral (+y) axis through the hinge takes +x to −z.
    let rel = tip - pip.center;
    let expected = pip.center + Vector3::new(rel.z, rel.y, -rel.x);
    let got = (t[distal] * Point3::from(tip)).coords;
    assert!((got - expected).norm() < 1e-12, "{got} vs {expected}");
    // The hinge sits inside the proximal phalanx's head, palm side untouched.
    let proximal = sk.bone_index("index.proximal").unwrap();
    assert!(sk.bones[proximal].distance(&pip.center) < 0.0);
    assert_eq!(t[proximal], nalgebra::Isometry3::identity());
}

#[test]
fn the_left_hand_mirrors_the_right() {
    let (r, l) = (Skeleton::new(Side::Right), Skeleton::new(Side::Left));
    let p = pose(&[
        ("thumb.cmc.abd", 30.0),
        ("thumb.mcp", 20.0),
        ("index.mcp.abd", 10.0),
        ("index.mcp.flex", 45.0),
        ("ring.pip", 70.0),
    ]);
    let (ar, al) = (
        r.apply_pose(&r.rest_angles(), &p).unwrap(),
        l.apply_pose(&l.rest_angles(), &p).unwrap(),
    );
    let (tr, tl) = (r.transforms(&ar), l.transforms(&al));
    let m = |v: Vector3<f64>| Vector3::new(v.x, -v.y, v.z);
    for b in 0..r.bones.len() {
        let pr = (tr[b] * Point3::from(r.bones[b].end)).coords;
        let pl = (tl[b] * Point3::from(l.bones[b].end)).coords;
        assert!((m(pr) - pl).norm() < 1e-12, "bone {}", r.bones[b].name);
    }
}

/// The left hand is meshed as the right one mirrored: the same cells, the flesh nodes the
/// mirrors of the right hand's, the display skin of as many vertices and triangles, and
/// closed. (Until 2026-11-27 the left hand's lattice started at its own bound across the hand,
/// cut the skin elsewhere, and its display skin had a hole at the index's knuckle: exported as a
/// rig and imported back it was refused, "the skin mesh has a hole".)
#[test]
fn the_left_hand_is_meshed_as_the_right_one_mirrored() {
    let right = hand();
    let left = HandModel::new(Side::Left, 1.0).unwrap();
    let (r, l) = (&right.flesh.mesh, &left.flesh.mesh);
    assert_eq!(r.cells.len(), l.cells.len());
    let key = |p: &Vector3<f64>| [p.x, p.y, p.z].map(|c| (c * 1e6).round() as i64);
    let mirrored: std::collections::HashSet<[i64; 3]> = r
        .nodes
        .iter()
        .map(|p| key(&Vector3::new(p.x, -p.y, p.z)))
        .collect();
    let own: std::collections::HashSet<[i64; 3]> = l.nodes.iter().map(key).collect();
    // The lattice is the mirror; of the nodes projected onto the bones, a few land otherwise
    // (measured 2026-11-27: 41 of 12 889, by more than 1 µm, all on the index's side of the
    // palm, x ≈ 100 mm, and one node more on the right: the bones' surfaces are not exact
    // mirrors there yet; the index's flexion reactions still mirror to 1e-6 N).
    let unmatched = own.symmetric_difference(&mirrored).count();
    println!(
        "{} / {} nodes, {unmatched} without a mirror",
        l.nodes.len(),
        r.nodes.len()
    );
    for p in own.difference(&mirrored).take(6) {
        println!("unmatched left node at {p:?} µm");
    }
    assert!(
        unmatched * 200 <= l.nodes.len(),
        "{unmatched} nodes without a mirror"
    );
    assert_eq!(right.skin.vertex_count(), left.skin.vertex_count());
    assert_eq!(right.skin.triangles().len(), left.skin.triangles().len());
    assert_skin_closed(&left, &left.skin);
}

/// `skin` of `hand` is closed: every edge is shared by exactly two triangles, but the wrist's
/// cut.
fn assert_skin_closed(hand: &HandModel, skin: &DisplaySkin) {
    let triangles = skin.triangles();
    let mut edges: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for t in &triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let at = skin.positions(&hand.flesh.mesh.nodes);
    let wrist = at.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let open: Vec<_> = edges
        .iter()
        .filter(|(_, &n)| n != 2)
        .filter(|((a, b), _)| at[*a as usize].x > wrist + 1e-3 || at[*b as usize].x > wrist + 1e-3)
        .collect();
    assert!(
        open.is_empty(),
        "{} open edges away from the wrist",
        open.len()
    );
}

/// Split (`hand::subdivide`, two along each edge), the left hand is still the right one
/// mirrored: as many cells, its display and contact skins closed, its contact skin through every
/// point of the unsplit one (embedded alike), and the index's flexion
/// (PIP 45°) felt alike by the bones to 10⁻⁵ of the largest reaction.
#[test]
fn a_split_left_hand_is_the_split_right_one_mirrored() {
    let split = |side| {
        HandModel::build_nested(
            Skeleton::new(side),
            prehensile::hand::SkinShape::new(side),
            1.0,
            2,
            None,
            Vector3::zeros(),
        )
        .unwrap()
    };
    let (right, left) = (split(Side::Right), split(Side::Left));
    assert_eq!(right.flesh.mesh.cells.len(), left.flesh.mesh.cells.len());
    assert_eq!(
        right.flesh.mesh.cells.len(),
        8 * hand().flesh.mesh.cells.len()
    );
    for h in [&right, &left] {
        assert_skin_closed(h, &h.skin);
        assert_skin_closed(h, &h.contact_skin);
    }
    // The contact skin, embedded through each cell's parent, lies where the unsplit hand's does:
    // each of its points at rest is a point of the split one (which has about four for one).
    let coarse = hand().contact_skin.positions(&hand().flesh.mesh.nodes);
    let fine = right.contact_skin.positions(&right.flesh.mesh.nodes);
    assert!(
        fine.len() > 3 * coarse.len(),
        "{} → {}",
        coarse.len(),
        fine.len()
    );
    let off = coarse
        .iter()
        .map(|p| {
            fine.iter()
                .map(|q| (p - q).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    assert!(
        off < 1e-9,
        "an unsplit contact skin point {off:e} m from the split skin"
    );
    let reactions =
        |h: &HandModel| crate::common::flexion::bone_reactions(h, &[("index.pip", 45.0)]);
    let (r, l) = (reactions(&right), reactions(&left));
    let largest = r.iter().copied().fold(0.0, f64::max);
    let apart = (0..r.len())
        .map(|b| (r[b] - l[b]).abs())
        .fold(0.0, f64::max);
    println!(
        "split 2, index PIP 45°: largest bone reaction {largest:.4} N, the hands apart by at \
         most {apart:.2e} N"
    );
    // (Measured 2026-12-07: at most 1.8·10⁻⁶ N apart, the largest reaction 0.91 N: the few
    // nodes the lattice projects onto the bones a little differently in each hand, as unsplit —
    // 41 of 12 889 at resolution 1, above.)
    for (b, bone) in right.skeleton.bones.iter().enumerate() {
        assert!(
            (r[b] - l[b]).abs() < 1e-5 * largest,
            "{}: {} N right, {} N left",
            bone.name,
            r[b],
            l[b]
        );
    }
}

#[test]
fn joint_limits_and_unknown_joints_are_errors() {
    let sk = Skeleton::new(Side::Right);
    let rest = sk.rest_angles();
    let e = sk
        .apply_pose(&rest, &pose(&[("index.pip", 130.0)]))
        .unwrap_err();
    assert_eq!(
        e,
        PoseError::OutOfRange {
            name: "index.pip".into(),
            angle: 130.0,
            min: 0.0,
            max: 110.0
        }
    );
    assert!(e.to_string().contains("outside its range 0° … 110°"));
    let e = sk
        .apply_pose(&rest, &pose(&[("index.knuckle", 10.0)]))
        .unwrap_err();
    assert!(matches!(e, PoseError::UnknownJoint { .. }));
    assert!(e.to_string().contains("index.mcp.flex"), "{e}");
    assert_eq!(sk.dofs.len(), 21);
    assert_eq!(sk.bones.len(), 20);
}

#[test]
fn the_flesh_mesh_is_one_well_shaped_piece_holding_every_bone() {
    let hand = hand();
    let mesh = &hand.flesh.mesh;
    let (_, pieces) = mesh.connected_pieces();
    assert_eq!(pieces, 1);
    let worst = (0..mesh.cells.len())
        .map(|c| scaled_jacobian(&mesh.cell_coords(c)))
        .fold(f64::INFINITY, f64::min);
    assert!(worst >= 0.3, "worst scaled Jacobian {worst}");
    for b in 0..hand.skeleton.bones.len() {
        assert!(!hand.bone_nodes(b).is_empty());
    }
    // An adult hand (to the wrist) displaces about 350–450 ml, bones included; this slender
    // model's flesh takes about 240 ml.
    let volume = HandState::rest(hand).flesh_volume(hand);
    println!(
        "cells {}, nodes {}, flesh volume {:.1} cm³",
        mesh.cells.len(),
        mesh.nodes.len(),
        volume * 1e6
    );
    assert!((2.0e-4..4.5e-4).contains(&volume), "volume {volume}");
    // The finger-tip pads are twice as fine as the palm.
    let size = |c: usize| {
        let p = mesh.cell_coords(c);
        (p[1] - p[0]).norm()
    };
    let pad = (0..mesh.cells.len())
        .filter(|&c| hand.flesh.cell_digit[c] == Some(1) && mesh.cell_coords(c)[0].x > 0.165)
        .map(size)
        .fold(f64::INFINITY, f64::min);
    let palm = (0..mesh.cells.len())
        .filter(|&c| hand.flesh.cell_digit[c].is_none())
        .map(size)
        .fold(0.0, f64::max);
    assert!(palm / pad > 1.9, "palm {palm} pad {pad}");
}

/// PIP 0° → 90° in 10°, 5° and 2.5° increments: (largest displacement, gap 10°–5°, gap
/// 5°–2.5°, volume changes).
fn pip_convergence(scheme: FlexionScheme) -> (f64, f64, f64, Vec<f64>) {
    let hand = hand();
    let target = [("index.pip", 90.0)];
    let states: Vec<HandState> = [10.0, 5.0, 2.5]
        .iter()
        .map(|&s| flex(&target, with_step(s, scheme)))
        .collect();
    let rest = &hand.flesh.mesh.nodes;
    let tip = max_distance(&states[2].positions, rest);
    let d1 = max_distance(&states[0].positions, &states[1].positions);
    let d2 = max_distance(&states[1].positions, &states[2].positions);
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let dv: Vec<f64> = states
        .iter()
        .map(|s| s.flesh_volume(hand) / v0 - 1.0)
        .collect();
    println!(
        "{scheme:?}: largest displacement {tip:.4e} m; 10° vs 5°: {d1:.3e} m, 5° vs 2.5°: \
         {d2:.3e} m (ratio {:.2}); volume change {dv:?}",
        d1 / d2
    );
    (tip, d1, d2, dv)
}

#[test]
fn the_papers_increments_converge_and_keep_the_volume() {
    let (tip, d1, d2, dv) = pip_convergence(FlexionScheme::UpdatedLagrangian);
    // Stated tolerance: 10° increments agree with 5° ones within 1.5 % of the largest
    // displacement, and the scheme converges at first order (halving the step halves the gap).
    assert!(tip > 0.06, "the finger tip travels about 7 cm");
    assert!(d1 < 0.015 * tip, "{d1} vs {tip}");
    assert!((1.6..2.6).contains(&(d1 / d2)), "ratio {}", d1 / d2);
    // Stated bound: the flesh volume changes by less than 1 % (ν = 0.45).
    for v in dv {
        assert!(v.abs() < 0.01, "volume change {v}");
    }
}

#[test]
fn corotated_increments_converge_faster_than_the_papers() {
    let (tip, d1, d2, dv) = pip_convergence(FlexionScheme::Corotational);
    let (_, paper, _, _) = pip_convergence(FlexionScheme::UpdatedLagrangian);
    // Stated tolerance: within 0.5 % of the largest displacement, first order, and at least
    // twice as close as the paper's scheme at 10°.
    assert!(d1 < 0.005 * tip, "{d1} vs {tip}");
    assert!((1.6..2.6).contains(&(d1 / d2)), "ratio {}", d1 / d2);
    assert!(d1 < 0.5 * paper, "{d1} vs the paper's {paper}");
    // Volume: within 0.2 %, and nearly independent of the step.
    for v in &dv {
        assert!(v.abs() < 0.002, "volume change {v}");
    }
    assert!((dv[0] - dv[2]).abs() < 1e-4);
}

#[test]
fn bending_one_finger_leaves_the_others_in_place_and_the_bones_balance() {
    let hand = hand();
    let whole = FlexionSettings {
        region: FleshRegion::Whole,
        ..Default::default()
    };
    let state = flex(&[("index.pip", 60.0)], whole);
    let rest = &hand.flesh.mesh.nodes;
    let mut moved = [0.0f64; 6];
    for (c, cell) in hand.flesh.mesh.cells.iter().enumerate() {
        let part = hand.flesh.cell_digit[c].map_or(0, |d| d + 1);
        for &n in cell {
            moved[part] = moved[part].max((state.positions[n] - rest[n]).norm());
        }
    }
    println!("largest displacement per part (palm, thumb … little): {moved:?}");
    // Whole-hand FEM: the index moves centimetres, the other digits' flesh less than 1e-4 of
    // that (about a micrometre), the palm next to the index a few hundredths of a millimetre.
    assert!(moved[2] > 0.03);
    for part in [1, 3, 4, 5] {
        assert!(
            moved[part] < 1e-4 * moved[2],
            "part {part} moved {}",
            moved[part]
        );
    }
    assert!(moved[0] < 2e-3 * moved[2], "palm moved {}", moved[0]);
    // Action and reaction: the flesh carries no outside load, so the bones' reactions cancel.
    let reactions = state.bone_reactions(hand);
    let sum: Vector3<f64> = reactions.iter().sum();
    let largest = reactions.iter().map(|r| r.norm()).fold(0.0, f64::max);
    println!(
        "bone reactions: largest {largest:.3} N, sum {:.2e} N",
        sum.norm()
    );
    assert!(largest > 0.1);
    assert!(sum.norm() < 1e-10 * largest);
}

#[test]
fn the_local_region_agrees_with_the_whole_hand_and_skinning_does_not() {
    let hand = hand();
    let target = [("index.pip", 60.0)];
    let local = flex(&target, FlexionSettings::default());
    let whole = flex(
        &target,
        FlexionSettings {
            region: FleshRegion::Whole,
            ..Default::default()
        },
    );
    let skinned = flex(
        &target,
        FlexionSettings {
            methods: [FleshMethod::Skinning; 6],
            ..Default::default()
        },
    );
    let skin = |s: &HandState| hand.skin.positions(&s.positions);
    let (l, w, k) = (skin(&local), skin(&whole), skin(&skinned));
    let (lw, kw) = (max_distance(&l, &w), max_distance(&k, &w));
    println!("skin distance to whole-hand FEM: local region {lw:.3e} m, skinning {kw:.3e} m");
    // The two FEM regions differ by a few hundredths of a millimetre (corotated increments,
    // measured 0.019 mm); skinning is hundreds of times farther from either.
    assert!(lw < 1.0e-4, "local vs whole {lw}");
    assert!(
        kw > 50.0 * lw,
        "skinning differs from FEM at the crease: {kw}"
    );
}

#[test]
fn the_display_skin_is_an_affine_combination_of_nodes() {
    let hand = hand();
    let skin = &hand.skin;
    assert!(skin.vertex_count() > 16 * hand.flesh.skin_quads.len() / 2);
    // Moving every node by the same rigid motion moves every skin vertex by it (weights sum to 1).
    let rot = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 1.1);
    let shift = Vector3::new(0.1, -0.2, 0.05);
    let moved: Vec<Vector3<f64>> = hand
        .flesh
        .mesh
        .nodes
        .iter()
        .map(|p| rot * p + shift)
        .collect();
    let a = skin.positions(&hand.flesh.mesh.nodes);
    let b = skin.positions(&moved);
    for (p, q) in a.iter().zip(&b) {
        assert!((rot * p + shift - q).norm() < 1e-7);
    }
    // On a closed cube of six quads, one level of Catmull–Clark puts the corner at (5/9)·corner.
    let cube = prehensile::mesh::box_mesh(Vector3::repeat(-1.0), Vector3::repeat(1.0), [1, 1, 1]);
    let quads: Vec<[usize; 4]> = prehensile::mesh::HEX_FACES
        .iter()
        .map(|f| f.map(|i| cube.cells[0][i]))
        .collect();
    let s = DisplaySkin::new(&quads, 8, 1);
    let p = s.positions(&cube.nodes);
    // The first eight display vertices are the moved corners (in order of first use).
    for v in &p[..8] {
        for k in 0..3 {
            assert!((v[k].abs() - 5.0 / 9.0).abs() < 1e-12, "{v}");
        }
    }
}

#[test]
fn skinning_can_be_chosen_per_digit() {
    let hand = hand();
    let mut methods = [FleshMethod::Fem; 6];
    methods[5] = FleshMethod::Skinning; // little finger
    let target = [("index.pip", 60.0), ("little.pip", 60.0)];
    let mixed = flex(
        &target,
        FlexionSettings {
            methods,
            ..Default::default()
        },
    );
    let skinned = flex(
        &target,
        FlexionSettings {
            methods: [FleshMethod::Skinning; 6],
            ..Default::default()
        },
    );
    let fem = flex(&target, FlexionSettings::default());
    let mut little = (0.0f64, 0.0f64);
    let mut index = (0.0f64, 0.0f64);
    for (c, cell) in hand.flesh.mesh.cells.iter().enumerate() {
        for &n in cell {
            let (to_skin, to_fem) = (
                (mixed.positions[n] - skinned.positions[n]).norm(),
                (mixed.positions[n] - fem.positions[n]).norm(),
            );
            match hand.flesh.cell_digit[c] {
                Some(4) => little = (little.0.max(to_skin), little.1.max(to_fem)),
                Some(1) => index = (index.0.max(to_skin), index.1.max(to_fem)),
                _ => {}
            }
        }
    }
    println!(
        "little: to skinning {:.2e}, to FEM {:.2e}; index: {:.2e}, {:.2e}",
        little.0, little.1, index.0, index.1
    );
    // The index's flesh is exactly the FEM one; the little finger's is the skinned one (to
    // 0.03 mm where it meets the FEM palm, whose nodes follow incremental skinning), millimetres
    // away from the FEM one.
    assert!(little.1 > 1e-3 && little.0 < 1e-2 * little.1);
    assert!(index.1 < 1e-12 && index.0 > 1e-4);
}

/// A fine lattice leaves no cells in a joint space: the band of nodes that follow the nearer of
/// two bones reaches as far from them as at resolution 1. At resolution 2 the index's PIP flexion
/// used to turn a crease cell inside out at 30.6° (two layers of cells across the joint space),
/// then, with a band never thinner than at resolution 1, at 56.9° (a cell wedged in the palmar
/// recess between the cupped base of the middle phalanx and the head of the proximal one). The
/// whole scene — PIP 45°, 90°, then DIP 40° — now flexes with the flesh's volume kept (measured
/// −0.008 %, −0.033 %, −0.046 %).
#[test]
fn resolution_2_flexes_the_pip_to_90_and_the_dip_to_40() {
    let text = std::fs::read_to_string("assets/scenes/finger-flexion.toml").unwrap();
    let text = text.replace("resolution = 1.0", "resolution = 2.0");
    let scene = prehensile::scene::Scene::parse(&text, "flex.toml").unwrap();
    let solved =
        prehensile::headless::solve_scene(&scene, "flex.toml").unwrap_or_else(|e| panic!("{e}"));
    let frame = solved.frames.last().unwrap();
    let pip = hand()
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == "index.pip")
        .unwrap();
    let dip = hand()
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == "index.dip")
        .unwrap();
    assert!((frame.hands[0].angles[pip] - 90.0).abs() < 1e-9);
    assert!((frame.hands[0].angles[dip] - 40.0).abs() < 1e-9);
    let report = &solved.report.frames.last().unwrap().hands["hand"];
    assert!(
        report.volume_change.abs() < 1e-3,
        "volume change {}",
        report.volume_change
    );
    // The bones balance the flesh (no external load): their reactions sum to round-off.
    let sum = Vector3::from(report.bone_reaction_sum).norm();
    let largest = report
        .bones
        .values()
        .map(|b| b.magnitude)
        .fold(0.0, f64::max);
    assert!(
        largest > 0.1 && sum < 1e-9 * largest.max(1.0),
        "{sum} of {largest} N"
    );
}

/// The display skin moved by the contact skin (src/hand/skin_follow.rs): at rest each vertex is
/// where its own embedding puts it, and under a rigid motion of the flesh the skin moves
/// rigidly — its rest offsets turn with the surface, also where the split skin's seams collapse
/// a control quad (0.40 mm off before those took a neighbour's frame). What it is for is
/// asserted in tests/grasp_presets.rs (a ball 100 times stiffer: the display skin 1.43 mm into
/// it before, 0.49 mm now).
#[test]
fn the_display_skin_follows_the_contact_skin() {
    let hand = hand();
    let rest = &hand.flesh.mesh.nodes;
    let own = |nodes: &[Vector3<f64>]| -> Vec<Vector3<f64>> {
        (0..hand.skin.vertex_count())
            .map(|v| hand.skin.terms(v).map(|(n, w)| nodes[n] * w).sum())
            .collect()
    };
    let at_rest = hand.skin.positions(rest);
    assert!(max_distance(&at_rest, &own(rest)) < 1e-12);

    let turn = nalgebra::Rotation3::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(0.3, -0.5, 0.8)),
        0.9,
    );
    let shift = Vector3::new(0.02, -0.01, 0.05);
    let moved: Vec<Vector3<f64>> = rest.iter().map(|p| turn * p + shift).collect();
    let expected: Vec<Vector3<f64>> = at_rest.iter().map(|p| turn * p + shift).collect();
    let rigid = max_distance(&hand.skin.positions(&moved), &expected);
    assert!(rigid < 1e-12, "{rigid} m off a rigid motion");
}
