//! Self-contact of the hand's skin in the flexion increments (issue 16, experimental:
//! `[solver] self_contact = true`), at resolution 1:
//!
//! - the middle finger adducted against the ring finger (middle MCP abduction 0 → −5°, 1°
//!   increments, the whole hand by FEM): its skin presses on the ring's and does not enter it,
//!   the ring's bones feel the press, and the hand's bones balance — the contact forces are
//!   internal to the hand;
//! - the index PIP flexed to 110°: the palmar skin of its crease folds onto itself without
//!   crossing (a surface self-intersection check: triangle against triangle).

use nalgebra::Vector3;
use prehensile::contact::{winding_number_of, ContactSettings};
use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::{HandModel, Pose, Side};
use prehensile::model::{FleshRegion, FlexionSettings};
use prehensile::solve::Flexion;
use prehensile::state::{HandState, KeyframeStats};
use std::sync::OnceLock;

fn hand() -> &'static HandModel {
    static HAND: OnceLock<HandModel> = OnceLock::new();
    HAND.get_or_init(|| HandModel::new(Side::Right, 1.0).unwrap())
}

fn left_hand() -> &'static HandModel {
    static HAND: OnceLock<HandModel> = OnceLock::new();
    HAND.get_or_init(|| HandModel::new(Side::Left, 1.0).unwrap())
}

const FLESH: Material = Material {
    young: 5.0e4,
    poisson: 0.45,
    density: 1050.0,
};

/// `joint` of `hand` moved to `angle` from rest with `settings`, with or without self-contact.
fn posed(
    hand: &HandModel,
    (joint, angle): (&str, f64),
    settings: FlexionSettings,
    self_contact: bool,
) -> (HandState, KeyframeStats) {
    let pose: Pose = [(joint.to_string(), angle)].into_iter().collect();
    posed_to(hand, &pose, settings, self_contact)
}

/// `hand` moved to `pose` from rest with `settings`, with or without self-contact; it reaches
/// the pose.
fn posed_to(
    hand: &HandModel,
    pose: &Pose,
    settings: FlexionSettings,
    self_contact: bool,
) -> (HandState, KeyframeStats) {
    let mut stepper = Flexion::new(
        hand,
        "hand",
        vec![FLESH; hand.flesh.mesh.cells.len()],
        FlexionSettings {
            self_contact: self_contact.then(ContactSettings::default),
            ..settings
        },
        FillOrdering::NestedDissection,
    );
    let mut state = HandState::rest(hand);
    let target = hand.skeleton.apply_pose(&state.angles, pose).unwrap();
    let stats = stepper
        .move_to(&mut state, &target)
        .unwrap_or_else(|e| panic!("{pose:?}, self-contact {self_contact}: {e}"));
    assert_eq!(state.angles, target);
    (state, stats)
}

/// The middle MCP of `hand` abducted to `angle` from rest in 1° increments, the flesh by FEM
/// within 12 mm of the moving joint (the default) or everywhere (`whole`).
fn adducted(
    hand: &HandModel,
    angle: f64,
    self_contact: bool,
    whole: bool,
) -> (HandState, KeyframeStats) {
    let settings = FlexionSettings {
        max_step_deg: 1.0,
        region: if whole {
            FleshRegion::Whole
        } else {
            FlexionSettings::default().region
        },
        ..Default::default()
    };
    posed(hand, ("middle.mcp.abd", angle), settings, self_contact)
}

/// The digit (1 thumb … 5 little, 0 palm) whose bone leads skin vertex `v`'s heaviest node.
fn digit_of_vertex(hand: &HandModel, v: usize) -> usize {
    let node = hand.contact_skin.heaviest_node(v);
    let bone = hand.weights.weights[node][0].0;
    hand.skeleton.bones[bone].digit.map_or(0, |d| d + 1)
}

/// The force the ring finger's bones feel (N): the press of the middle finger's skin on the
/// ring's, carried by the ring's flesh to its bones, which do not move. (Not the contact's
/// summed multipliers: skin on skin is held both ways — the middle's points on the ring's facets
/// and the ring's on the middle's — and one press may be shared between the two rows in any
/// proportion.)
fn ring_press(hand: &HandModel, state: &HandState) -> f64 {
    let r = state.bone_reactions(hand);
    let ring: Vector3<f64> = (0..hand.skeleton.bones.len())
        .filter(|&b| hand.skeleton.bones[b].name.starts_with("ring."))
        .map(|b| r[b])
        .sum();
    ring.norm()
}

/// How deep the middle finger's skin went into the ring finger: the largest distance from the
/// ring's skin of a middle skin vertex inside it (generalised winding number of the ring's open
/// skin tube > ½), mm.
fn middle_inside_ring_mm(hand: &HandModel, state: &HandState) -> f64 {
    let skin = &hand.contact_skin;
    let positions = skin.positions(&state.positions);
    let digit: Vec<usize> = (0..skin.vertex_count())
        .map(|v| digit_of_vertex(hand, v))
        .collect();
    let ring: Vec<[usize; 3]> = skin
        .triangle_indices()
        .into_iter()
        .filter(|t| t.iter().all(|&v| digit[v] == 4))
        .collect();
    let lo = ring
        .iter()
        .flatten()
        .fold(Vector3::repeat(f64::INFINITY), |m, &v| m.inf(&positions[v]));
    let hi = ring
        .iter()
        .flatten()
        .fold(Vector3::repeat(f64::NEG_INFINITY), |m, &v| {
            m.sup(&positions[v])
        });
    (0..skin.vertex_count())
        .filter(|&v| digit[v] == 3)
        .filter(|&v| (0..3).all(|a| positions[v][a] > lo[a] && positions[v][a] < hi[a]))
        .filter(|&v| winding_number_of(&positions[v], &ring, &positions) > 0.5)
        .map(|v| {
            ring.iter()
                .filter_map(|t| {
                    prehensile::contact::project_on_triangle(
                        &positions[v],
                        &t.map(|c| positions[c]),
                    )
                })
                .map(|q| q.distance)
                .fold(f64::INFINITY, f64::min)
                * 1e3
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_middle_finger_presses_on_the_ring_finger_and_does_not_enter_it() {
    let hand = hand();
    let (free, free_stats) = adducted(hand, -5.0, false, true);
    let (held, stats) = adducted(hand, -5.0, true, true);
    let ring_reaction = |s: &HandState| ring_press(hand, s);
    let free_depth = middle_inside_ring_mm(hand, &free);
    // (The skin's crossings beyond 3 lattice spacings, for the record.)
    let apart = 3.0 * hand.flesh.spacing;
    eprintln!(
        "skin crossings: {} without, {} with self-contact",
        skin_crossings(hand, &free.positions, apart, |_, _| true),
        skin_crossings(hand, &held.positions, apart, |_, _| true)
    );
    let held_depth = middle_inside_ring_mm(hand, &held);
    let total: Vector3<f64> = held.bone_reactions(hand).iter().sum();
    eprintln!(
        "without self-contact: middle {free_depth:.3} mm inside the ring, ring bones {:.4} N; \
         with: {held_depth:.3} mm, {} contacts, {:.4} N, ring bones {:.4} N, Σ bones {:.2e} N; \
         {} / {} factorizations",
        ring_reaction(&free),
        stats.self_contacts,
        stats.self_contact_force,
        ring_reaction(&held),
        total.norm(),
        free_stats.factorizations,
        stats.factorizations,
    );
    // Without self-contact the middle finger's skin passes into the ring finger's.
    assert!(free_depth > 0.5, "the free skin crosses: {free_depth} mm");
    assert_eq!(free_stats.self_contacts, 0);
    // With it, it stays out (to the contact's penetration limit, 0.5 mm) and presses.
    assert!(held_depth < 0.5, "held skin {held_depth} mm inside");
    assert!(stats.self_contacts > 0 && stats.self_contact_force > 0.1);
    // The press reaches the ring's bones, which do not move: the ring's flesh carries it to them.
    // (Without the contact they feel only what the palm's flesh passes on.)
    let press = ring_reaction(&held);
    assert!(
        press > 1.0 && press > 100.0 * ring_reaction(&free),
        "ring bones {press} N (without self-contact {} N)",
        ring_reaction(&free)
    );
    // Action and reaction: the contact forces are internal, the bones balance.
    assert!(
        total.norm() < 1e-6 * stats.self_contact_force,
        "Σ bone reactions {total}"
    );
}

/// Whether segment `a`–`b` passes through triangle `t` (Möller–Trumbore).
fn segment_crosses(a: &Vector3<f64>, b: &Vector3<f64>, t: &[Vector3<f64>; 3]) -> bool {
    let d = b - a;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = d.cross(&e2);
    let det = e1.dot(&p);
    if det.abs() < 1e-30 {
        return false;
    }
    let s = a - t[0];
    let u = s.dot(&p) / det;
    let q = s.cross(&e1);
    let v = d.dot(&q) / det;
    let w = e2.dot(&q) / det;
    u >= 0.0 && v >= 0.0 && u + v <= 1.0 && (0.0..=1.0).contains(&w)
}

/// Pairs of the contact skin's triangles at `positions` that pass through each other, among
/// those sharing no vertex, farther apart at rest than `apart` (m) and that `keep` (given the
/// two triangles' skin vertices): where the skin crosses itself (the two sides of a crease
/// within `apart` of its fold are not counted).
fn skin_crossings(
    hand: &HandModel,
    positions: &[Vector3<f64>],
    apart: f64,
    keep: impl Fn(&[usize; 3], &[usize; 3]) -> bool,
) -> usize {
    use std::collections::HashMap;
    let skin = &hand.contact_skin;
    let now = skin.positions(positions);
    let rest = skin.positions(&hand.flesh.mesh.nodes);
    // Split as the self-contact splits them: each quad along its shorter diagonal at rest.
    let quads: Vec<[usize; 4]> = skin.quads.iter().map(|q| q.map(|v| v as usize)).collect();
    let triangles =
        prehensile::contact::ContactSurface::from_quads_split_at(0, &quads, &rest, &now).triangles;
    let corners = |t: &[usize; 3], x: &[Vector3<f64>]| t.map(|v| x[v]);
    let centre = |t: &[usize; 3], x: &[Vector3<f64>]| (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
    let cell = 2.0 * hand.flesh.spacing;
    let key = |p: &Vector3<f64>| p.map(|c| (c / cell).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, t) in triangles.iter().enumerate() {
        let c = corners(t, &now);
        let lo = key(&c[0].inf(&c[1]).inf(&c[2]));
        let hi = key(&c[0].sup(&c[1]).sup(&c[2]));
        for x in lo.x..=hi.x {
            for y in lo.y..=hi.y {
                for z in lo.z..=hi.z {
                    grid.entry([x, y, z]).or_default().push(i);
                }
            }
        }
    }
    let mut crossing = std::collections::HashSet::new();
    for members in grid.values() {
        for (k, &i) in members.iter().enumerate() {
            for &j in &members[k + 1..] {
                let (ti, tj) = (&triangles[i], &triangles[j]);
                if ti.iter().any(|v| tj.contains(v))
                    || (centre(ti, &rest) - centre(tj, &rest)).norm() < apart
                {
                    continue;
                }
                let (a, b) = (corners(ti, &now), corners(tj, &now));
                let crosses = (0..3).any(|e| segment_crosses(&a[e], &a[(e + 1) % 3], &b))
                    || (0..3).any(|e| segment_crosses(&b[e], &b[(e + 1) % 3], &a));
                if crosses && keep(ti, tj) {
                    crossing.insert((i.min(j), i.max(j)));
                }
            }
        }
    }
    crossing.len()
}

/// The contact skin's triangle pairs crossing each other at `positions` (`skin_crossings`,
/// more than 3 base spacings — 9.6 mm — apart at rest: beyond the self-contact's neighbourhood,
/// which reaches at most 1.5 × 6.4 = 9.6 mm along the skin since 2026-12-07): those of two
/// facets facing the palm at rest (outward normal within 45° of −z: a flexion crease's two
/// sides), and all of them.
fn crease_and_all_crossings(hand: &HandModel, positions: &[Vector3<f64>]) -> (usize, usize) {
    let rest = hand.contact_skin.positions(&hand.flesh.mesh.nodes);
    let palmar = |t: &[usize; 3]| {
        let n = (rest[t[1]] - rest[t[0]]).cross(&(rest[t[2]] - rest[t[0]]));
        n.z < -0.7 * n.norm()
    };
    let apart = 3.0 * prehensile::hand::BASE_SPACING;
    (
        skin_crossings(hand, positions, apart, |a, b| palmar(a) && palmar(b)),
        skin_crossings(hand, positions, apart, |_, _| true),
    )
}

/// The index PIP flexed to 110° by `settings` without and with self-contact: the palmar skin of
/// the proximal and of the middle phalanx fold onto each other. Asserted: without self-contact
/// the crease's skin passes through itself; with it, it does not, and it crosses itself less
/// overall; the skin presses; the flesh keeps its volume; the bones balance (the contact is
/// internal to the hand). Returns the state and statistics with self-contact, and the
/// statistics without.
fn index_crease_folded(settings: FlexionSettings) -> (HandState, KeyframeStats, KeyframeStats) {
    let hand = hand();
    let (free, free_stats) = posed(hand, ("index.pip", 110.0), settings.clone(), false);
    let (held, stats) = posed(hand, ("index.pip", 110.0), settings, true);
    let (free_crossings, all_free) = crease_and_all_crossings(hand, &free.positions);
    let (held_crossings, all_held) = crease_and_all_crossings(hand, &held.positions);
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let volume = held.flesh_volume(hand) / v0 - 1.0;
    let reactions = held.bone_reactions(hand);
    let total: Vector3<f64> = reactions.iter().sum();
    let largest = reactions.iter().map(|r| r.norm()).fold(0.0, f64::max);
    eprintln!(
        "palmar crossings {free_crossings} → {held_crossings}, all {all_free} → {all_held}; \
         {} points, {:.3} N; volume {:+.3} %; largest bone {largest:.3} N, Σ bones {:.2e} N; \
         {} → {} factorizations",
        stats.self_contacts,
        stats.self_contact_force,
        100.0 * volume,
        total.norm(),
        free_stats.factorizations,
        stats.factorizations
    );
    assert!(free_crossings >= 10, "{free_crossings} crossings");
    assert_eq!((held_crossings, all_held), (0, 0), "{all_free} without");
    assert!(stats.self_contacts > 0 && stats.self_contact_force > 0.1);
    assert!(volume.abs() < 2e-3, "flesh volume {volume:+.2e}");
    assert!(
        total.norm() < 1e-6 * stats.self_contact_force.min(largest),
        "Σ bone reactions {total}"
    );
    (held, stats, free_stats)
}

/// The index PIP flexed to its limit, 110°, in 10° increments (the default local region), by the
/// corotational increments: the crease's skin held by the barrier, each increment Newton on its
/// quadratic energy plus the barrier's change (`index_crease_folded`; with the active set before
/// it, the lateral skin of the joint crossed itself in 10 triangle pairs).
#[test]
fn the_folded_pip_crease_does_not_cross_itself() {
    index_crease_folded(Default::default());
}

/// The same crease folded by the nonlinear tier (Neo-Hookean flesh, each increment Newton to
/// equilibrium), the skin kept out of itself by a barrier in the energy Newton lowers
/// (`contact::SelfBarrier`, docs/hand.md "Self-contact"; `index_crease_folded`). Also: the
/// skin crosses itself nowhere (its edges held off its edges too: with points against facets
/// only, one pair crossed); the tactile map feels each press on both sides; Newton needs fewer
/// factorizations than without (the folded flesh is no longer left to find its way through
/// itself: 578 → 130 measured).
#[test]
fn the_nonlinear_tier_folds_the_pip_crease_without_crossing_it() {
    let (held, stats, free_stats) = index_crease_folded(FlexionSettings {
        scheme: prehensile::model::FlexionScheme::Nonlinear,
        ..Default::default()
    });
    assert!(stats.self_contacts > 10);
    assert_eq!(crease_and_all_crossings(hand(), &held.positions).1, 0);
    // The point's force, and the facet's corners' shares of it (the closest point's
    // barycentric weights), or each edge's ends' shares of the pair's: twice the press.
    let felt: f64 = held.self_contact.iter().sum();
    assert!(
        (felt - 2.0 * stats.self_contact_force).abs() < 1e-9 * felt,
        "{felt} against {}",
        stats.self_contact_force
    );
    assert!(stats.factorizations < free_stats.factorizations);
}

/// What a hand scene's first keyframe folded: the skin's crossings in the creases and in all
/// (`crease_and_all_crossings`), the press, the bones' reactions' sum and the largest, N.
struct Fold {
    crease: usize,
    all: usize,
    press: prehensile::export::report::SelfContactReport,
    sum: f64,
    largest: f64,
}

fn fold(solved: &prehensile::headless::Solved) -> Fold {
    let hand = solved.model.bodies[0].hand.as_deref().expect("a hand");
    let report = &solved.report.frames[1].hands["hand"];
    let (crease, all) = crease_and_all_crossings(hand, &solved.frames[1].hands[0].positions);
    Fold {
        crease,
        all,
        press: report.self_contact.clone().expect("the press"),
        sum: Vector3::from(report.bone_reaction_sum).norm(),
        largest: report
            .bones
            .values()
            .map(|b| b.magnitude)
            .fold(0.0, f64::max),
    }
}

/// Issue 16's test of the nonlinear tier: index and middle PIP 0° → 110° together at resolution
/// 1.5, from a scene file (`tier = "nonlinear"`, `self_contact = true`), the skin kept out of
/// itself by the barrier: it converges (without self-contact the tier stopped at middle PIP
/// 64°), the skin does not cross itself anywhere, the flesh keeps its volume, the press
/// reaches the bones, which balance. 1 077 factorizations, ≈ 4 minutes (6 455 before the flesh's
/// tangent made definite element by element came before the shifted ones, 2026-12-06; the same
/// motion through the library's `Flexion` with a nested-dissection ordering took longer: the
/// buckled crease's path depends on round-off).
#[test]
fn the_nonlinear_tier_folds_index_and_middle_to_110_at_resolution_1_5() {
    let text = "[solver]\ntier = \"nonlinear\"\nself_contact = true\n\n[[material]]\n\
                name = \"flesh\"\nyoung = 5.0e4\npoisson = 0.45\ndensity = 1050.0\n\n\
                [[body]]\nname = \"hand\"\nmaterial = \"flesh\"\n\
                shape = { hand = { side = \"right\", resolution = 1.5 } }\n\n[[keyframe]]\n\
                time = 1.0\npose = { \"index.pip\" = 110.0, \"middle.pip\" = 110.0 }\n";
    let solved = solve_fist(text).unwrap_or_else(|e| panic!("{e}"));
    let report = &solved.report.frames[1].hands["hand"];
    let Fold {
        crease,
        all,
        press,
        sum,
        largest,
    } = fold(&solved);
    eprintln!(
        "nonlinear, index and middle, resolution 1.5: crossings {crease} in the creases, {all} in \
         all; press {:.3} N {:?}; volume {:+.3} %; largest bone {largest:.3} N, Σ {sum:.2e} N",
        press.force,
        press.parts,
        100.0 * report.volume_change,
    );
    assert_eq!(report.pose["middle.pip"], 110.0);
    // None: the barrier holds the skin's points off its facets and its edges off its edges
    // (with points against facets only, 28 pairs of the creases' triangles crossed; docs/hand.md,
    // "Self-contact").
    assert_eq!((crease, all), (0, 0));
    assert!(press.force > 1.0, "{press:?}");
    assert!(press.parts.contains_key("index") && press.parts.contains_key("middle"));
    assert!(
        report.volume_change.abs() < 2e-3,
        "{}",
        report.volume_change
    );
    assert!(sum < 1e-6 * largest, "Σ bone reactions {sum} N");
}

/// The user's path: a scene asking the nonlinear tier with `self_contact = true` (index PIP
/// 110°, resolution 0.75) solves without the warning that the tier leaves the skin to pass
/// through itself; the report carries the press (its parts, felt on both sides, sum to twice
/// it, all on the index) and its skin inside its own flesh is less than without.
#[test]
fn a_nonlinear_scene_keeps_its_skin_out_of_itself_and_reports_the_press() {
    let text = |self_contact: bool| {
        format!(
            "[solver]\ntier = \"nonlinear\"\nself_contact = {self_contact}\n\n[[material]]\n\
             name = \"flesh\"\nyoung = 5.0e4\npoisson = 0.45\ndensity = 1050.0\n\n[[body]]\n\
             name = \"hand\"\nmaterial = \"flesh\"\n\
             shape = {{ hand = {{ side = \"right\", resolution = 0.75 }} }}\n\n[[keyframe]]\n\
             time = 1.0\npose = {{ \"index.pip\" = 110.0 }}\n"
        )
    };
    let held = solve_fist(&text(true)).unwrap_or_else(|e| panic!("{e}"));
    let free = solve_fist(&text(false)).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        !held
            .report
            .warnings
            .iter()
            .any(|w| w.contains("may still pass through itself")),
        "{:?}",
        held.report.warnings
    );
    let hand = &held.report.frames[1].hands["hand"];
    let press = hand.self_contact.clone().expect("the press");
    eprintln!(
        "nonlinear scene: press {:.3} N {:?}; skin inside {} → {}",
        press.force,
        press.parts,
        free.report.frames[1].hands["hand"].skin_overlap.vertices,
        hand.skin_overlap.vertices
    );
    assert!(press.force > 0.5, "{press:?}");
    let felt: f64 = press.parts.values().sum();
    assert!((felt - 2.0 * press.force).abs() < 1e-9 * felt, "{press:?}");
    assert_eq!(press.parts.keys().collect::<Vec<_>>(), ["index"]);
    assert!(press.max_patch_pressure > 0.0 && press.max_patch_pressure.is_finite());
    assert!(free.report.frames[1].hands["hand"].self_contact.is_none());
    assert!(hand.skin_overlap.vertices < free.report.frames[1].hands["hand"].skin_overlap.vertices);
}

/// Left and right hands alike: the left hand's middle finger adducted onto its ring finger (the
/// mirrored motion) presses as the right one's, to the lattice's asymmetry (its cells are not
/// mirrored: 1.651 against 1.666 N measured), and stays out of the ring finger.
#[test]
fn the_left_hand_presses_as_the_right_one() {
    let (right, right_stats) = adducted(hand(), -5.0, true, true);
    let (left, left_stats) = adducted(left_hand(), -5.0, true, true);
    let depth = middle_inside_ring_mm(left_hand(), &left);
    eprintln!(
        "right {} points {:.4} N; left {} points {:.4} N, {depth:.3} mm inside the ring",
        right_stats.self_contacts,
        right_stats.self_contact_force,
        left_stats.self_contacts,
        left_stats.self_contact_force
    );
    let (r, l) = (ring_press(hand(), &right), ring_press(left_hand(), &left));
    eprintln!("ring bones: right {r:.4} N, left {l:.4} N");
    assert!(
        r > 1.0 && (l - r).abs() < 0.05 * r,
        "ring bones: left {l} N, right {r} N"
    );
    assert!(depth < 0.5, "left middle {depth} mm inside the ring");
    // The two hands mirror each other: the right hand's middle fingertip lies across the
    // y = 0 plane from the left's.
    let tip = |h: &HandModel, s: &HandState| -> Vector3<f64> {
        let b = h
            .skeleton
            .bones
            .iter()
            .position(|b| b.name == "middle.distal")
            .unwrap();
        let nodes = h.bone_nodes(b);
        nodes.iter().map(|&n| s.positions[n]).sum::<Vector3<f64>>() / nodes.len() as f64
    };
    let (a, b) = (tip(hand(), &right), tip(left_hand(), &left));
    eprintln!("middle tips: right {a:?}, left {b:?}");
    let mirrored = Vector3::new(b.x, -b.y, b.z);
    assert!(
        (a - mirrored).norm() < 0.5e-3,
        "right tip {a:?}, left tip mirrored {mirrored:?}"
    );
}

/// Left and right hands alike in the nonlinear tier: the left hand's index PIP folded to 110°
/// with the skin kept out of itself by the barrier crosses itself nowhere, as the right one's,
/// and its bones feel the same to the lattice's asymmetry (its cells are not mirrored, and the
/// crease's fold follows round-off: 2.974 against 2.952 N measured) and balance.
#[test]
fn the_left_hand_folds_its_nonlinear_pip_crease_as_the_right_one() {
    let nonlinear = || FlexionSettings {
        scheme: prehensile::model::FlexionScheme::Nonlinear,
        ..Default::default()
    };
    let (right, _) = posed(hand(), ("index.pip", 110.0), nonlinear(), true);
    let (left, stats) = posed(left_hand(), ("index.pip", 110.0), nonlinear(), true);
    let largest = |h: &HandModel, s: &HandState| {
        s.bone_reactions(h)
            .iter()
            .map(|r| r.norm())
            .fold(0.0, f64::max)
    };
    let (r, l) = (largest(hand(), &right), largest(left_hand(), &left));
    let crossings = crease_and_all_crossings(left_hand(), &left.positions);
    let sum: Vector3<f64> = left.bone_reactions(left_hand()).iter().sum();
    eprintln!(
        "largest bone: right {r:.4} N, left {l:.4} N; left crossings {crossings:?}, {} pairs, \
         {:.3} N, Σ bones {:.2e} N",
        stats.self_contacts,
        stats.self_contact_force,
        sum.norm()
    );
    assert_eq!(crossings, (0, 0));
    assert!(stats.self_contacts > 10 && stats.self_contact_force > 0.1);
    assert!(
        r > 1.0 && (l - r).abs() < 0.05 * r,
        "largest bone: left {l} N, right {r} N"
    );
    assert!(sum.norm() < 1e-6 * l, "Σ bone reactions {sum}");
}

/// The default local region grows around where the skin will meet itself (predicted by
/// skinning at the keyframe's start): the middle finger adducted 8° onto the ring finger, which
/// does not move and whose flesh lies outside the region of the middle MCP, presses on it
/// (without the growth the press fell on the region's prescribed edge and the contact could not
/// settle). Against the whole hand solved by FEM at 5°: the same press to 3 %.
#[test]
fn the_local_region_grows_around_the_skin_meeting_itself() {
    let hand = hand();
    let (local, local_stats) = adducted(hand, -5.0, true, false);
    let (whole, whole_stats) = adducted(hand, -5.0, true, true);
    let (deep, deep_stats) = adducted(hand, -8.0, true, false);
    let (free, _) = adducted(hand, -8.0, false, false);
    let depth = |s: &HandState| middle_inside_ring_mm(hand, s);
    eprintln!(
        "−5°: local {} points {:.4} N ({} free dofs), whole {:.4} N ({} free dofs); \
         −8°: {} points {:.4} N, {:.3} mm inside the ring (free {:.3} mm)",
        local_stats.self_contacts,
        local_stats.self_contact_force,
        local_stats.free_dofs,
        whole_stats.self_contact_force,
        whole_stats.free_dofs,
        deep_stats.self_contacts,
        deep_stats.self_contact_force,
        depth(&deep),
        depth(&free)
    );
    let (l, w) = (ring_press(hand, &local), ring_press(hand, &whole));
    eprintln!(
        "ring bones: local {l:.4} N, whole {w:.4} N, −8° {:.4} N",
        ring_press(hand, &deep)
    );
    assert!(local_stats.free_dofs < whole_stats.free_dofs / 2);
    assert!((l - w).abs() < 0.03 * w, "local {l} N, whole {w} N");
    assert!(depth(&local) < 0.5 && depth(&deep) < 0.5);
    assert!(depth(&free) > 1.0);
    // Pressed further, harder.
    assert!(ring_press(hand, &deep) > 2.0 * l);
}

/// The press of the skin on itself is part of the tactile map (issue 16): the middle finger
/// adducted onto the ring finger (−5°, 1° increments, the scene's path), each press felt on both
/// sides — the forces on the middle's skin and on the ring's are equal (action = reaction) and
/// nothing else of the skin is pressed; the map on the contact skin and the nodal map of the
/// exports integrate to those forces, and the report's peak skin pressure is the map's.
#[test]
fn the_skin_pressed_on_itself_is_on_the_tactile_map() {
    let text = fist_scene(true, "\"middle.mcp.abd\" = -5.0")
        .replace("[solver]\n", "[solver]\nmax_step_deg = 1.0\n");
    let solved = solve_fist(&text).unwrap();
    let (model, frame) = (&solved.model, solved.frames.last().unwrap());
    let h = &frame.hands[0];
    let hand = model.bodies[h.body].hand.as_deref().unwrap();
    assert!(frame.contact.is_none(), "no other body");
    assert_eq!(h.self_contact.len(), hand.contact_skin.vertex_count());
    let mut by_digit = [0.0; 6];
    for (v, f) in h.self_contact.iter().enumerate() {
        assert!(*f >= 0.0 && f.is_finite());
        by_digit[digit_of_vertex(hand, v)] += f;
    }
    let total: f64 = by_digit.iter().sum();
    eprintln!("self-contact forces by digit (palm, thumb … little): {by_digit:?} N");
    // Some skin of the middle finger's and ring finger's proximal phalanges lies over the palm's
    // heaviest node: count the palm with either side, and require the two sides equal — to 4 %
    // of the total: the map sums each vertex's force magnitudes, and the barrier's pairs of a
    // side press at different distances and directions (an edge pair's mollified ends unequally;
    // measured 4.286 / 4.163 N, 2.9 %; the active set's rows, 10⁻¹⁵).
    let (middle, ring) = (by_digit[3], by_digit[4]);
    assert!(middle > 0.5 && ring > 0.5, "{by_digit:?}");
    assert!(
        (middle - ring).abs() <= 0.04 * total + by_digit[0],
        "middle {middle} N, ring {ring} N, palm {} N",
        by_digit[0]
    );
    assert!(
        by_digit[1] + by_digit[2] + by_digit[5] < 1e-12 * total,
        "{by_digit:?}"
    );
    // The contact skin's map integrates to the forces.
    let pressure = prehensile::state::contact_skin_pressure(model, frame, h.body).unwrap();
    let at = hand.contact_skin.positions(&h.positions);
    let mut area = vec![0.0; at.len()];
    for q in &hand.contact_skin.quads {
        let p = q.map(|v| at[v as usize]);
        let a = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm();
        for &v in q {
            area[v as usize] += 0.25 * a;
        }
    }
    let integral: f64 = pressure.iter().zip(&area).map(|(p, a)| p * a).sum();
    assert!(
        (integral - total).abs() < 1e-9 * total,
        "{integral} vs {total} N"
    );
    // So does the nodal map the VTU and glTF exports carry, over the hand's lattice facets.
    let nodal = prehensile::state::contact_pressure(model, frame).unwrap();
    let body = &model.bodies[h.body];
    let mut node_area = vec![0.0; model.mesh.nodes.len()];
    for f in &body.facets {
        let p = f.nodes.map(|n| model.mesh.nodes[n]);
        let a = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm();
        let mut distinct = f.nodes.to_vec();
        distinct.sort_unstable();
        distinct.dedup();
        for &n in &distinct {
            node_area[n] += a / distinct.len() as f64;
        }
    }
    let integral: f64 = nodal.iter().zip(&node_area).map(|(p, a)| p * a).sum();
    assert!(
        (integral - total).abs() < 1e-9 * total,
        "{integral} vs {total} N"
    );
    // The report: the press counted once, each part's share, the peak of the display skin's
    // map (positive and finite; 400 kPa measured: the node-to-facet forces are spiky, the peak
    // is a vertex's, not a converged pressure).
    let report = solved.report.frames.last().unwrap().hands["hand"]
        .self_contact
        .clone()
        .expect("the report's self-contact");
    assert!((report.force - 0.5 * total).abs() < 1e-12 * total);
    let parts: f64 = report.parts.values().sum();
    assert!((parts - total).abs() < 1e-9 * total, "{:?}", report.parts);
    assert!(report.parts.contains_key("middle") && report.parts.contains_key("ring"));
    let display = prehensile::state::self_contact_skin_pressure(model, h).unwrap();
    let peak = display.iter().copied().fold(0.0, f64::max);
    assert_eq!(report.max_pressure, peak);
    eprintln!(
        "the press {:.3} N, parts {:?}, peak {:.1} kPa (contact skin {:.1} kPa)",
        report.force,
        report.parts,
        peak * 1e-3,
        pressure.iter().copied().fold(0.0, f64::max) * 1e-3
    );
    assert!(peak.is_finite() && peak > 1e3 && peak < 1e6, "{peak} Pa");
    // Read over patches (3.2 mm): each patch's pressure is its vertices' nodal pressures
    // averaged by area, so no more than the contact skin's nodal peak, and the report's is the
    // map's.
    let patches = prehensile::state::self_contact_patch_pressure(model, h).unwrap();
    let patch_peak = patches.iter().copied().fold(0.0, f64::max);
    let nodal_peak = pressure.iter().copied().fold(0.0, f64::max);
    assert_eq!(report.max_patch_pressure, patch_peak);
    assert!(
        patch_peak > 1e3 && patch_peak <= nodal_peak * (1.0 + 1e-12),
        "patch {patch_peak} Pa, nodal {nodal_peak} Pa"
    );
    assert!(patches.iter().all(|p| p.is_finite() && *p >= 0.0));
    // The rest frame presses nowhere.
    assert!(solved.report.frames[0].hands["hand"].self_contact.is_none());
    // The pressure overlay draws it (the skin's colours reach the peak), where a scene whose
    // skin presses nowhere is refused with the reason.
    let options = prehensile::present::VisualOptions {
        overlay: prehensile::present::Overlay::Pressure,
        ..Default::default()
    };
    let lists = prehensile::headless::draw_lists(&solved, &options).unwrap();
    let drawn = lists
        .last()
        .unwrap()
        .surfaces
        .iter()
        .flat_map(|s| s.scalars.iter().flatten())
        .fold(0.0f32, |m, p| m.max(*p));
    assert!(
        (drawn as f64 - peak).abs() < 1e-6 * peak,
        "{drawn} vs {peak}"
    );
    let free = solve_fist(&text.replace("self_contact = true", "self_contact = false")).unwrap();
    let refused = prehensile::headless::draw_lists(&free, &options).unwrap_err();
    assert!(refused.to_string().contains("self_contact"), "{refused}");
}

/// The press of the skin on itself under refinement (issue 16): the middle finger adducted onto
/// the ring finger (as above) at hand resolutions 1 and 1.5, the skin held apart by the barrier.
/// What the ring's bones feel and the peak read over 3.2 mm patches agree between the two within
/// 8 % and 15 %, the press within 12 % (measured 2026-12-05: 4.138 / 4.484 N, 22.1 / 25.2 kPa,
/// 4.224 / 4.670 N; at resolution 2, 4.674 N, 22.3 kPa, 5.051 N: the bones' reaction converging
/// at an observed order of 0.85, the press more slowly — the barrier holds skin up to 1 mm
/// apart; docs/hand.md, "Self-contact").
#[test]
fn the_press_read_over_patches_converges_under_refinement() {
    let read = |resolution: f64| {
        let text = fist_scene(true, "\"middle.mcp.abd\" = -5.0")
            .replace("[solver]\n", "[solver]\nmax_step_deg = 1.0\n")
            .replace(
                "side = \"right\"",
                &format!("side = \"right\", resolution = {resolution}"),
            );
        let solved = solve_fist(&text).unwrap();
        let hand = &solved.report.frames.last().unwrap().hands["hand"];
        let press = hand.self_contact.clone().expect("the press");
        let ring: nalgebra::Vector3<f64> = hand
            .bones
            .iter()
            .filter(|(name, _)| name.starts_with("ring."))
            .map(|(_, b)| nalgebra::Vector3::from(b.reaction))
            .sum();
        eprintln!(
            "resolution {resolution}: press {:.4} N, ring's bones {:.4} N, patch peak {:.2} kPa, \
             vertex peak {:.2} kPa",
            press.force,
            ring.norm(),
            press.max_patch_pressure * 1e-3,
            press.max_pressure * 1e-3
        );
        (press.force, ring.norm(), press.max_patch_pressure)
    };
    let (coarse, fine) = (read(1.0), read(1.5));
    let apart = |a: f64, b: f64| (a - b).abs() / a.max(b);
    assert!(
        apart(coarse.0, fine.0) < 0.12,
        "press {coarse:?} / {fine:?}"
    );
    assert!(apart(coarse.1, fine.1) < 0.08, "ring {coarse:?} / {fine:?}");
    assert!(
        apart(coarse.2, fine.2) < 0.15,
        "patch peak {coarse:?} / {fine:?}"
    );
    // A press of ≈ 4–5 N over the fingers' sides reads tens of kPa, not the vertices' spikes.
    assert!(fine.2 > 5e3 && fine.2 < 5e4, "{fine:?}");
}

/// Vectors by bone name.
type ByBone = std::collections::BTreeMap<String, Vector3<f64>>;

/// What the skin's press on itself adds to each bone's reaction: the reactions with the skin
/// kept out of itself less those of the same keyframe without (vectors, N, by bone name), the
/// reactions with, and the press's force — the little finger closed onto the palm (MCP 88°,
/// `pip`, `dip`) at hand `resolution`.
fn little_finger_press(resolution: f64, pip: f64, dip: f64) -> (ByBone, ByBone, f64) {
    let pose = format!("\"little.mcp.flex\" = 88, \"little.pip\" = {pip}, \"little.dip\" = {dip}");
    let bones = |self_contact: bool| {
        let text = fist_scene(self_contact, &pose).replace(
            "side = \"right\"",
            &format!("side = \"right\", resolution = {resolution}"),
        );
        let solved = solve_fist(&text).unwrap_or_else(|e| panic!("resolution {resolution}: {e}"));
        // The pulp on the palm, not pressed into it: no crushed flesh to warn of (its creases
        // crush 30 and 29 mm³ at resolutions 1 and 1.5, under the warning's 100).
        let crushed = solved
            .report
            .warnings
            .iter()
            .find(|w| w.contains("crushed"));
        assert!(crushed.is_none(), "resolution {resolution}: {crushed:?}");
        let hand = solved.report.frames.last().unwrap().hands["hand"].clone();
        let press = hand.self_contact.as_ref().map_or(0.0, |p| p.force);
        let bones: ByBone = hand
            .bones
            .iter()
            .map(|(name, b)| (name.clone(), Vector3::from(b.reaction)))
            .collect();
        (bones, press)
    };
    let ((held, press), (free, _)) = (bones(true), bones(false));
    let share = held
        .iter()
        .map(|(name, r)| (name.clone(), r - free[name]))
        .collect();
    (share, held, press)
}

/// The press of the skin on itself under refinement, what the bones feel of it (issue 16): the
/// little finger closed onto the palm (MCP 88°, PIP 90°, DIP 50°: its pulp on the palm, not
/// crushed) at hand resolutions 1 and 1.5. What the press adds to the reactions of the
/// fingertip's bone and of the metacarpal it presses over — the reactions with the skin kept
/// out of itself less those without — agrees between the two within 8 % (measured 2026-12-06:
/// 2.797 / 2.766 N and 2.733 / 2.598 N, 1.1 % and 4.9 %; the press 4.87 / 4.48 N; 63 s), where the
/// reactions themselves do not converge: without self-contact the little finger's flexion alone
/// gives its proximal phalanx 3.688 / 4.625 N and its middle one 1.027 / 2.069 N — the flesh
/// bridging each joint is one or two cells (docs/hand.md, "The flexion's bone reactions under
/// refinement"): that, not the contact, moves the reactions at this pose; at the shipped fist's
/// pulp, crushed, the press's share moves them too (docs/hand.md, "What moves it, taken apart").
#[test]
fn what_the_bones_feel_of_the_skins_press_agrees_at_resolutions_1_and_1_5() {
    let (coarse, coarse_held, coarse_press) = little_finger_press(1.0, 90.0, 50.0);
    let (fine, fine_held, fine_press) = little_finger_press(1.5, 90.0, 50.0);
    let apart = |a: f64, b: f64| (a - b).abs() / a.max(b);
    for bone in ["little.distal", "little.metacarpal"] {
        let (c, f) = (coarse[bone].norm(), fine[bone].norm());
        eprintln!(
            "{bone}: the press adds {c:.3} N at resolution 1, {f:.3} N at 1.5 (reactions \
             {:.3} / {:.3} N)",
            coarse_held[bone].norm(),
            fine_held[bone].norm()
        );
        // The fingertip presses the palm with a few newtons: its bone and the metacarpal
        // under the palm take most of it.
        assert!(c > 1.0 && f > 1.0, "{bone}: {c} / {f} N");
        assert!(apart(c, f) < 0.08, "{bone}: {c} → {f} N");
        // Nor turned: the angle between the two (measured 2.6° and 6.9°).
        let angle = coarse[bone].angle(&fine[bone]).to_degrees();
        assert!(angle < 10.0, "{bone}: turned {angle:.1}°");
    }
    // The press is internal to the hand: what it adds sums to nothing over the bones.
    let total: Vector3<f64> = fine.values().sum();
    assert!(total.norm() < 1e-6, "Σ {total}");
    eprintln!("press {coarse_press:.3} / {fine_press:.3} N");
    assert!(
        apart(coarse_press, fine_press) < 0.12,
        "{coarse_press} / {fine_press}"
    );
}

/// The full fist's joints as the TOML of a pose.
fn fist_pose() -> String {
    let pose: Vec<String> = prehensile::hand::full_fist()
        .iter()
        .map(|(joint, angle)| format!("\"{joint}\" = {angle}"))
        .collect();
    pose.join(", ")
}

/// A hand-only scene with `pose` as its one keyframe.
fn fist_scene(self_contact: bool, pose: &str) -> String {
    format!(
        "[solver]\nself_contact = {self_contact}\n\n[[material]]\nname = \"flesh\"\n\
         young = 5.0e4\npoisson = 0.45\ndensity = 1050.0\n\n[[body]]\nname = \"hand\"\n\
         material = \"flesh\"\nshape = {{ hand = {{ side = \"right\" }} }}\n\n\
         [[keyframe]]\ntime = 1.0\npose = {{ {pose} }}\n"
    )
}

fn solve_fist(text: &str) -> Result<prehensile::headless::Solved, String> {
    let scene = prehensile::scene::Scene::parse(text, "fist.toml").unwrap();
    prehensile::headless::solve_scene(&scene, "fist.toml").map_err(|e| e.to_string())
}

/// The share of the keyframe's motion where the error says it failed ("failed at 48.3 % of its
/// way"), as a fraction.
fn failed_share(error: &str) -> f64 {
    let tail = error
        .split("the motion failed at ")
        .nth(1)
        .unwrap_or_else(|| panic!("no share in: {error}"));
    let pct: f64 = tail.split(" %").next().unwrap().parse().unwrap();
    pct / 100.0
}

/// The full fist (issue 16's pose, the thumb across, asked as one keyframe) without
/// self-contact: its skin passes into its own flesh, and the report says where. (With the skin
/// kept out of itself it closed too once the flesh was kept from being crushed inside out,
/// 2026-12-05: before, the thumb's pad was crushed between the thumb's and the index's bones.)
#[test]
fn the_full_fist_without_self_contact_reports_its_skin_inside_its_own_flesh() {
    let solved = solve_fist(&fist_scene(false, &fist_pose())).unwrap_or_else(|e| panic!("{e}"));
    let hand = &solved.report.frames.last().unwrap().hands["hand"];
    assert!(hand.volume_change.abs() < 0.015);
    // Without self-contact the fist's skin passes into its own flesh, and the report says where
    // (858 of 6 560 skin points measured, on every finger), none at rest.
    let overlap = &hand.skin_overlap;
    eprintln!("skin overlap {overlap:?}");
    assert!(overlap.vertices > 300, "{overlap:?}");
    assert_eq!(overlap.parts.values().sum::<usize>(), overlap.vertices);
    for finger in ["index", "middle", "ring", "little"] {
        assert!(
            overlap.parts.get(finger).is_some_and(|&n| n > 20),
            "{overlap:?}"
        );
    }
    assert_eq!(
        solved.report.frames[0].hands["hand"].skin_overlap.vertices,
        0
    );
    let warning = solved
        .report
        .warnings
        .iter()
        .find(|w| w.contains("inside its own flesh"))
        .unwrap_or_else(|| panic!("{:?}", solved.report.warnings));
    assert!(
        warning.starts_with("frame 1: the skin of hand \"hand\"")
            && warning.contains(&format!("at {} skin points", overlap.vertices))
            && warning.contains("self_contact = true"),
        "{warning}"
    );
}

/// The report's skin overlap (skin inside the hand's own flesh, by the closed skin's winding
/// number, away from the webs where the digits' skins meet at rest): the index PIP flexed to
/// 110° puts its crease's skin into the flesh, on the index only; the self-contact keeps less
/// of it there.
#[test]
fn the_report_counts_the_skin_inside_its_own_flesh() {
    let pose = "\"index.pip\" = 110";
    let count = |self_contact: bool| {
        let solved = solve_fist(&fist_scene(self_contact, pose)).unwrap_or_else(|e| panic!("{e}"));
        let overlap = solved.report.frames[1].hands["hand"].skin_overlap.clone();
        eprintln!("self-contact {self_contact}: {overlap:?}");
        assert_eq!(
            solved.report.frames[0].hands["hand"].skin_overlap.vertices,
            0
        );
        assert_eq!(
            overlap.parts.keys().collect::<Vec<_>>(),
            ["index"],
            "{overlap:?}"
        );
        overlap.vertices
    };
    let (free, held) = (count(false), count(true));
    assert!(
        free > 0 && held < free,
        "{free} without, {held} with self-contact"
    );
}

/// The user's path when a pose cannot be reached with the skin kept out of itself: the middle
/// and the ring finger abducted onto each other (MCP abduction −20° each) — their fingertips'
/// flesh is squeezed between their bones within 5° of it (at rest their skins touch). The scene
/// stops with an error that says where (the element, the joint and its angle, the share of the
/// motion) and what to do, and does so at once (the bones' steps cut short of the flesh's
/// collapse; 26 s measured); the keyframe short of that share is reached.
#[test]
fn flesh_crushed_between_bones_says_where_and_stopping_short_works() {
    let pose = |scale: f64| {
        format!(
            "\"middle.mcp.abd\" = {0}, \"ring.mcp.abd\" = {0}",
            -20.0 * scale
        )
    };
    let error = match solve_fist(&fist_scene(true, &pose(1.0))) {
        Ok(_) => panic!("the fingers abducted onto each other were expected to stop"),
        Err(e) => e,
    };
    eprintln!("{error}");
    assert!(
        error.contains("fist.toml") && error.contains("body \"hand\""),
        "{error}"
    );
    assert!(
        error.contains("flesh element") && error.contains("crushed"),
        "{error}"
    );
    assert!(error.contains("self_contact = false"), "{error}");
    // (Not the advice for contact between bodies, which does not help here.)
    assert!(!error.contains("contact_max_iterations"), "{error}");
    let scale = 0.95 * failed_share(&error);
    assert!(scale > 0.02 && scale < 0.95, "{error}");
    let solved = solve_fist(&fist_scene(true, &pose(scale)))
        .unwrap_or_else(|e| panic!("the advised keyframe ({scale:.3} of the way) failed: {e}"));
    let hand = &solved.report.frames.last().unwrap().hands["hand"];
    let angle = hand.pose["middle.mcp.abd"];
    assert!((angle + 20.0 * scale).abs() < 1e-6, "{angle}");
}

/// The four fingers closed into a fist with the skin kept out of itself (issue 16): every finger
/// at MCP 88°, PIP 105°, DIP 70° (the little finger's distal phalanx's bone then within 6.2 mm of
/// its metacarpal's, through the pulp and the palm's flesh; until 2026-12-05 it stopped at
/// 95° / 60°, 11.2 mm). Before the self-contact followed each skin point's path over an
/// increment (continuous collision, 2026-12-02) this stopped at little PIP 50.7° ("the skin's
/// self-contact did not settle"). Asserted: it closes; the fingers press on each other and on
/// the palm; the skin crosses itself nowhere (`skin_crossings`; 318
/// triangle pairs with the active set of point-on-facet rows before the barrier, 2026-12-05,
/// which held no edge against an edge); the skin inside its own flesh beyond its own
/// neighbourhood is at most a third of what it is without (648 → 99 measured); the flesh keeps
/// its volume to 2 % (−1.65 % measured: the little finger's pulp squeezed against the palm;
/// −1.42 % with it at 95° / 60°); the bones balance (the contact is internal to the hand).
#[test]
fn the_four_fingers_close_into_a_fist_with_the_skin_kept_out_of_itself() {
    let hand = hand();
    let pose = prehensile::hand::four_finger_fist();
    let close = |self_contact: bool| posed_to(hand, &pose, Default::default(), self_contact);
    let (free, _) = close(false);
    let (held, stats) = close(true);
    let check = prehensile::model::SkinOverlapCheck::new(hand);
    let (inside_free, inside_held) = (
        check.overlap(hand, &free.positions).len(),
        check.overlap(hand, &held.positions).len(),
    );
    let v0 = HandState::rest(hand).flesh_volume(hand);
    let volume = held.flesh_volume(hand) / v0 - 1.0;
    let reactions = held.bone_reactions(hand);
    let total: Vector3<f64> = reactions.iter().sum();
    let largest = reactions.iter().map(|r| r.norm()).fold(0.0, f64::max);
    let crossings = crease_and_all_crossings(hand, &held.positions);
    eprintln!(
        "skin inside its own flesh {inside_free} → {inside_held}; crossing itself {crossings:?}; \
         {} pairs, {:.3} N; {} increments, {} halvings; volume {:+.3} %; largest bone reaction \
         {largest:.3} N, Σ {:.2e} N",
        stats.self_contacts,
        stats.self_contact_force,
        stats.increments_taken,
        stats.halvings,
        100.0 * volume,
        total.norm()
    );
    assert!(stats.self_contacts > 50 && stats.self_contact_force > 1.0);
    assert_eq!(crossings, (0, 0));
    assert!(
        inside_free > 300 && 3 * inside_held <= inside_free,
        "{inside_free} → {inside_held}"
    );
    assert!(volume.abs() < 0.02, "flesh volume {volume:+.2e}");
    assert!(total.norm() < 1e-7 * largest, "Σ bone reactions {total}");
}

/// The shipped full fist (assets/scenes/hand-full-fist.toml) at hand `resolution`: the four
/// fingers close, then the thumb folds over, with the skin kept out of itself. Both keyframes
/// converge; the skin crosses itself nowhere (`crease_and_all_crossings`, the contact skin's
/// triangles); with `compare`, the skin inside its own flesh (the report's count, away from the
/// webs) is at most a third of what the same scene leaves without self-contact (solved too);
/// the flesh keeps its volume to `volume` (a fraction); the bones balance. Returns the largest
/// bone reaction of the last frame, N.
fn full_fist_closes(resolution: f64, volume: f64, compare: bool) -> f64 {
    full_fist_split_closes(resolution, 1, volume, compare)
}

/// [`full_fist_closes`] on the hand's lattice with every cell split into `subdivisions`³ (a
/// scene's `subdivisions`: the nested refinement).
fn full_fist_split_closes(resolution: f64, subdivisions: usize, volume: f64, compare: bool) -> f64 {
    let text = std::fs::read_to_string("assets/scenes/hand-full-fist.toml").unwrap();
    assert!(text.contains("self_contact = true"));
    let text = text.replace(
        "side = \"right\" }",
        &format!("side = \"right\", resolution = {resolution}, subdivisions = {subdivisions} }}"),
    );
    let solve = |text: &str| {
        let scene = prehensile::scene::Scene::parse(text, "hand-full-fist.toml").unwrap();
        prehensile::headless::solve_scene(&scene, "hand-full-fist.toml")
            .unwrap_or_else(|e| panic!("resolution {resolution}: {e}"))
    };
    let held = solve(&text);
    let free = compare.then(|| solve(&text.replace("self_contact = true", "self_contact = false")));
    let mut largest = 0.0;
    for (i, frame) in held.report.frames.iter().enumerate() {
        let hand = &frame.hands["hand"];
        let free_inside = free
            .as_ref()
            .map(|free| free.report.frames[i].hands["hand"].skin_overlap.vertices);
        let sum = Vector3::from(hand.bone_reaction_sum).norm();
        let (bone, most) = hand
            .bones
            .iter()
            .map(|(name, b)| (name.as_str(), b.magnitude))
            .fold(("none", 0.0), |a, b| if b.1 > a.1 { b } else { a });
        largest = most;
        let without = free_inside.map_or("not solved".to_string(), |n| n.to_string());
        eprintln!(
            "resolution {resolution}, frame {i}: skin inside its own flesh {without} without, \
             {} with; volume {:+.3} %; largest bone reaction {largest:.3} N ({bone}), Σ {sum:.2e} N",
            hand.skin_overlap.vertices,
            100.0 * hand.volume_change
        );
        assert!(hand.volume_change.abs() < volume, "frame {i}");
        assert!(sum < 1e-7 * largest.max(1e-3), "frame {i}: Σ bones {sum} N");
        if i > 0 {
            if let Some(f) = free_inside {
                let h = hand.skin_overlap.vertices;
                assert!(f > 300 && 3 * h <= f, "frame {i}: {f} → {h}");
            }
            let model = held.model.bodies[held.frames[i].hands[0].body]
                .hand
                .clone()
                .unwrap();
            let crossings = crease_and_all_crossings(&model, &held.frames[i].hands[0].positions);
            assert_eq!(crossings, (0, 0), "frame {i}: the skin crosses itself");
        }
    }
    // The thumb folded: its IP at the pose.
    let last = &held.report.frames[2].hands["hand"];
    assert!((last.pose["thumb.ip"] - 70.0).abs() < 1e-9);
    // The flesh crushed below half its volume (the report's `crushed_flesh`), never inside out;
    // at resolution 1 most of it the little finger's, its pulp squeezed between its distal
    // phalanx and its metacarpal (docs/hand.md: the counts; down to 0.17 of its volume at the
    // middle finger's PIP crease).
    let crushed = &last.crushed_flesh;
    eprintln!(
        "resolution {resolution}: flesh below half its volume at {} points, {:.1} mm³ at rest, \
         {:?}; smallest volume ratio {:.3}",
        crushed.points,
        crushed.rest_volume * 1e9,
        crushed.parts,
        crushed.smallest_volume_ratio
    );
    assert!(crushed.smallest_volume_ratio > 0.0 && crushed.smallest_volume_ratio < 0.5);
    assert_eq!(crushed.parts.values().sum::<usize>(), crushed.points);
    if resolution == 1.0 {
        let most = crushed.parts.iter().max_by_key(|(_, n)| **n).unwrap().0;
        assert_eq!(most, "little", "{:?}", crushed.parts);
    }
    // The pulps pressed into the palm: the solve warns once, the little finger's crushed flesh
    // first.
    let warned: Vec<&String> = held
        .report
        .warnings
        .iter()
        .filter(|w| w.contains("crushed below half its volume"))
        .collect();
    assert_eq!(warned.len(), 1, "{:?}", held.report.warnings);
    let first = crushed.warned_parts()[0];
    assert_eq!(first.0, "little", "{:?}", crushed.part_volumes);
    assert!(warned[0].contains(": little "), "{}", warned[0]);
    eprintln!("{}", warned[0]);
    // Every bone's reaction for the refinement study (docs/hand.md, "Self-contact").
    let mut bones: Vec<(&String, f64)> = last.bones.iter().map(|(n, b)| (n, b.magnitude)).collect();
    bones.sort_by(|a, b| b.1.total_cmp(&a.1));
    eprintln!("resolution {resolution}, bone reactions (N): {bones:.3?}");
    largest
}

/// The refinement study's third mesh: the shipped full fist at resolution 2 (about 4.4 GB and
/// 1 h 40 min on two cores; run by hand with `cargo test --release --test suite -- --ignored
/// at_resolution_2`): it closes, its skin crosses itself nowhere, its flesh keeps its volume to
/// 2 % and is nowhere inside out, its bones balance.
/// Measured 2026-12-06: it closes (1 h 38 min, 4.4 GB; volume −1.75 %), its largest bone
/// reaction 12.452 N (the little metacarpal) against 10.210 and 10.990 N at 1 and 1.5 — growing,
/// not converging (docs/hand.md, "Self-contact").
#[test]
#[ignore = "about 1 h 40 min and 4.4 GB: the refinement study's resolution 2, run by hand"]
fn the_shipped_full_fist_closes_at_resolution_2() {
    let largest = full_fist_closes(2.0, 0.02, false);
    eprintln!("largest bone reaction at resolution 2: {largest:.3} N");
}

/// The nested refinement study's second mesh: the shipped full fist on the resolution-1 hand with
/// every cell split into 2 × 2 × 2 (as many cells as resolution 2's lattice, 1.3× as long; run
/// by hand with `cargo test --release --test suite -- --ignored fist_split_2`): the same checks
/// as at resolution 2. Measured 2026-12-07, alone: passed in 2 h 09 min 44 s, 3.89 GB; its
/// largest bone reaction 9.810 N (the little metacarpal) against 10.210 N unsplit, −3.9 %, the
/// fist's first nested step (docs/hand.md, "Nested refinement"; both before that day's change of
/// the self-contact's neighbourhood, with which the unsplit fist reads 10.239 N).
#[test]
#[ignore = "about 2 h 10 min and 3.9 GB: the nested refinement study's second mesh, run by hand"]
fn the_shipped_full_fist_split_2() {
    let largest = full_fist_split_closes(1.0, 2, 0.02, false);
    eprintln!("largest bone reaction at resolution 1 split 2: {largest:.3} N");
}

/// The little finger's part of the full fist (MCP 88°, PIP 105°, DIP 70°, the other digits at
/// rest; its pulp pressed into the palm, the fist's largest reaction on its metacarpal) on the
/// hand of `resolution` with every cell split into `subdivisions`³, self-contact on: it closes,
/// its bones balance, its flesh keeps its volume to 1 %. The bones' reactions at the end, N, and
/// the skin's crossings of itself (on the palmar side, anywhere).
fn little_fist_split(resolution: f64, subdivisions: usize) -> (Vec<(String, f64)>, (usize, usize)) {
    let text = format!(
        "[solver]\nmax_step_deg = 10.0\nself_contact = true\n\n\
         [[material]]\nname = \"flesh\"\nyoung = 5.0e4\npoisson = 0.45\ndensity = 1050.0\n\n\
         [[body]]\nname = \"hand\"\nmaterial = \"flesh\"\nshape = {{ hand = {{ side = \
         \"right\", resolution = {resolution}, subdivisions = {subdivisions} }} }}\n\n\
         [[keyframe]]\ntime = 1.0\npose = {{ \"little.mcp.flex\" = 88, \"little.pip\" = 105, \
         \"little.dip\" = 70 }}\n"
    );
    let scene = prehensile::scene::Scene::parse(&text, "little-fist.toml").unwrap();
    let held = prehensile::headless::solve_scene(&scene, "little-fist.toml")
        .unwrap_or_else(|e| panic!("split {subdivisions}: {e}"));
    let last = held.report.frames.last().unwrap();
    let hand = &last.hands["hand"];
    for (joint, angle) in [
        ("little.mcp.flex", 88.0),
        ("little.pip", 105.0),
        ("little.dip", 70.0),
    ] {
        assert!(
            (hand.pose[joint] - angle).abs() < 1e-9,
            "{joint}: {}°",
            hand.pose[joint]
        );
    }
    let mut bones: Vec<(String, f64)> = hand
        .bones
        .iter()
        .map(|(n, b)| (n.clone(), b.magnitude))
        .collect();
    bones.sort_by(|a, b| b.1.total_cmp(&a.1));
    // One keyframe: the shared reading of a folded hand's frame 1.
    let Fold {
        crease, all, sum, ..
    } = fold(&held);
    eprintln!(
        "resolution {resolution} split {subdivisions}: {:.3?}; press {:.3} N; volume {:+.3} %; \
         Σ bones {sum:.1e} N",
        &bones[..4],
        hand.self_contact.as_ref().map_or(0.0, |c| c.force),
        100.0 * hand.volume_change
    );
    assert!(sum < 1e-7 * bones[0].1, "Σ bones {sum} N");
    assert!(hand.volume_change.abs() < 0.01);
    let crossings = (crease, all);
    eprintln!("split {subdivisions}: skin triangle pairs crossing {crossings:?}");
    (bones, crossings)
}

/// The nested refinement of the fist's largest reactions, on the little finger's part of it at
/// resolution 0.75 split 1, 2, 3 (its third mesh as costly as resolution 2.25's lattice; run by
/// hand with `cargo test --release --test suite -- --ignored little_fist`): the skin crosses
/// itself on none of the three; its distal phalanx's and its metacarpal's reactions (the
/// largest two) fall monotonically at an observed order of about 1, toward a limit the finest
/// is within a quarter of (docs/hand.md, "Nested refinement": the numbers; passed before and
/// after 2026-12-07's change of the self-contact's neighbourhood, the last time on 2026-12-08:
/// orders 1.39 and 1.00, 48 min beside another solve).
#[test]
#[ignore = "about 55 min and 2.5 GB: the nested refinement of the fist's largest reactions, run by hand"]
fn the_little_fist_s_largest_reactions_converge_nested() {
    use prehensile::util::convergence::{convergence, Convergence};
    let runs = [1, 2, 3].map(|n| little_fist_split(0.75, n));
    // The skin crosses itself nowhere on any of the three (on the unsplit mesh it did at 3
    // palmar pairs until 2026-12-07, when a point's neighbourhood still reached a facet past
    // its radius).
    for (k, (_, crossings)) in runs.iter().enumerate() {
        assert_eq!(
            *crossings,
            (0, 0),
            "split {}: the skin crosses itself",
            k + 1
        );
    }
    let runs = runs.map(|(bones, _)| bones);
    let h = [1.0, 0.5, 1.0 / 3.0];
    for bone in ["little.distal", "little.metacarpal"] {
        let f = [0, 1, 2].map(|k| runs[k].iter().find(|b| b.0 == bone).unwrap().1);
        assert!(f[0] > f[1] && f[1] > f[2], "{bone}: {f:.4?} N, not falling");
        match convergence(h, f) {
            Convergence::Order { order, limit } => {
                eprintln!("{bone}: {f:.4?} N, order {order:.2}, limit {limit:.4} N");
                assert!((0.5..3.0).contains(&order), "{bone}: order {order:.2}");
                assert!(
                    (f[2] - limit).abs() < 0.25 * limit,
                    "{bone}: limit {limit:.4} N"
                );
            }
            other => panic!("{bone}: {f:.4?} N: {other:?}"),
        }
    }
}

/// The shipped full fist's two keyframes (the four fingers, then the thumb folding over) asked
/// as one. With the active set of point-on-facet rows (before 2026-12-05) its straight path did
/// not settle — the thumb folding over fingers still closing — and the keyframe went in two
/// stages, the fingers first and the thumb after them, ending where the two keyframes end. With
/// the barrier the straight path closes: the same pose, the bones balanced, the flesh's volume
/// and the skin inside its own flesh as after the two keyframes (a path of its own: the joints
/// all at once), the largest bone reaction within a tenth of theirs. (The staged fallback is
/// still tried where the straight path fails; with the flesh kept from being crushed inside
/// out, issue 16's full fist, its thumb across, closes in one keyframe too.)
#[test]
fn the_shipped_full_fist_closes_in_one_keyframe_as_in_two() {
    // The simple form's: the anatomical hand's (the shipped scene's) closed along its straight
    // path with the active set already.
    let text = crate::common::with_hand_form(
        &std::fs::read_to_string("assets/scenes/hand-full-fist.toml").unwrap(),
        "simple",
    );
    let two = prehensile::scene::Scene::parse(&text, "hand-full-fist.toml").unwrap();
    let mut one = two.clone();
    let thumb = one.keyframe.pop().unwrap().pose;
    one.keyframe[0].pose.extend(thumb);
    let solve = |scene: &prehensile::scene::Scene| {
        prehensile::headless::solve_scene(scene, "hand-full-fist.toml")
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let (one, two) = (solve(&one), solve(&two));
    let a = &one.report.frames.last().unwrap().hands["hand"];
    let b = &two.report.frames.last().unwrap().hands["hand"];
    assert!(!a.motion.thumb_after_fingers && !b.motion.thumb_after_fingers);
    assert_eq!(a.pose, b.pose);
    let largest = |h: &prehensile::export::report::HandReport| {
        h.bones.values().map(|r| r.magnitude).fold(0.0, f64::max)
    };
    let (la, largest) = (largest(a), largest(b));
    eprintln!(
        "one keyframe: largest bone reaction {la:.4} N, volume {:+.3} %, skin inside {}; two: \
         {largest:.4} N, {:+.3} %, {}",
        100.0 * a.volume_change,
        a.skin_overlap.vertices,
        100.0 * b.volume_change,
        b.skin_overlap.vertices
    );
    assert!(Vector3::from(a.bone_reaction_sum).norm() < 1e-7 * la);
    assert!((la - largest).abs() < 0.1 * largest, "{la} / {largest} N");
    assert!((a.volume_change - b.volume_change).abs() < 2e-3);
    assert!(a.skin_overlap.vertices <= 2 * b.skin_overlap.vertices.max(50));
}

/// The shipped full fist at resolution 1, against the same scene without self-contact (the
/// flesh loses about 1.5 % of its volume: the creases pressed shut, the little finger's pulp
/// squeezed against the palm; bound 2 %). Its largest bone reaction under refinement is the
/// ignored test below (20 minutes).
#[test]
fn the_shipped_full_fist_closes_at_resolution_1() {
    let largest = full_fist_closes(1.0, 0.02, true);
    // The little finger's pulp squeezed against its metacarpal (10.210 N measured).
    assert!(largest > 5.0 && largest < 20.0, "{largest} N");
}

/// The shipped full fist at resolutions 1 and 1.5, each against the same scene without
/// self-contact (about 20 minutes on two cores: run by hand with `cargo test --release --test
/// suite -- --ignored resolutions_1_and_1_5`). The largest bone reaction (the little
/// finger's metacarpal) changes by less than 10 % between them (10.210 → 10.990 N measured,
/// 7.1 %; with the little finger at 95° / 60°, the index metacarpal's then, 9.337 → 10.337 N,
/// 10.7 %) — but at resolution 2 it is 12.452 N: it does not converge, moved by the press of the
/// little finger's pulp, crushed to less than half its volume between its bones, and from 1.5 to
/// 2 by the flexion's flesh across the joints (docs/hand.md, "What moves it, taken apart").
#[test]
#[ignore = "about 20 minutes: the refinement study's resolutions 1 and 1.5, run by hand"]
fn the_shipped_full_fist_largest_bone_reaction_at_resolutions_1_and_1_5() {
    let coarse = full_fist_closes(1.0, 0.02, true);
    let fine = full_fist_closes(1.5, 0.02, true);
    eprintln!("largest bone reaction: {coarse:.3} N at resolution 1, {fine:.3} N at 1.5");
    assert!((fine - coarse).abs() < 0.1 * fine, "{coarse} → {fine} N");
}

/// The user's path of the nested refinement (`subdivisions` in a scene's hand): the index PIP
/// flexed to 110° with self-contact on the resolution-1 hand, as meshed and with every cell
/// split into 2 × 2 × 2. Split, it folds as the lattice does: the skin crosses itself nowhere,
/// the press reaches the bones, which balance, the flesh keeps its volume; and its largest
/// bone reaction falls towards the limit of the nested series (measured 2026-12-07: 4.864 /
/// 3.882 / 3.589 N split 1 / 2 / 3, an observed order of 1.19 and a limit of 3.12 N;
/// docs/hand.md, "Nested refinement"), where the lattice of resolution 1.5 read more than that
/// of 1.
#[test]
fn a_split_hand_folds_its_crease_without_crossing_it_and_its_reaction_falls() {
    let read = |subdivisions: usize| {
        let text = format!(
            "[solver]\nself_contact = true\n\n[[material]]\nname = \"flesh\"\nyoung = 5.0e4\n\
             poisson = 0.45\ndensity = 1050.0\n\n[[body]]\nname = \"hand\"\n\
             material = \"flesh\"\n\
             shape = {{ hand = {{ side = \"right\", subdivisions = {subdivisions} }} }}\n\n\
             [[keyframe]]\ntime = 1.0\npose = {{ \"index.pip\" = 110.0 }}\n"
        );
        let solved = solve_fist(&text).unwrap_or_else(|e| panic!("split {subdivisions}: {e}"));
        let hand = solved.model.bodies[0].hand.as_deref().expect("a hand");
        assert_eq!(hand.subdivisions, subdivisions);
        let report = &solved.report.frames[1].hands["hand"];
        let Fold {
            crease,
            all,
            press,
            sum,
            largest,
        } = fold(&solved);
        eprintln!(
            "split {subdivisions}: {} cells; crossings {crease} / {all}; press {:.3} N; volume \
             {:+.3} %; largest bone {largest:.3} N, Σ {sum:.2e} N",
            hand.flesh.mesh.cells.len(),
            press.force,
            100.0 * report.volume_change,
        );
        assert_eq!(report.pose["index.pip"], 110.0);
        assert_eq!((crease, all), (0, 0), "split {subdivisions}");
        assert!(press.force > 1.0, "split {subdivisions}: {press:?}");
        assert!(
            report.volume_change.abs() < 2e-3,
            "{}",
            report.volume_change
        );
        assert!(sum < 1e-6 * largest, "split {subdivisions}: Σ {sum} N");
        (hand.flesh.mesh.cells.len(), largest)
    };
    let (cells1, coarse) = read(1);
    let (cells2, fine) = read(2);
    assert_eq!(cells2, 8 * cells1);
    assert!(
        fine < coarse && fine > 0.75 * coarse,
        "largest bone reaction {coarse:.3} N split 1, {fine:.3} N split 2"
    );
}
