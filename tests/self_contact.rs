//! Self-contact of the hand's skin in the flexion increments (issue 16, experimental:
//! `[solver] self_contact = true`). The middle finger adducted against the ring finger (middle
//! MCP abduction 0 → −5°, 1° increments, the whole hand by FEM, resolution 1): its skin presses on
//! the ring's and does not enter it, the ring's bones feel the press, and the hand's bones
//! balance — the contact forces are internal to the hand.

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

const FLESH: Material = Material {
    young: 5.0e4,
    poisson: 0.45,
    density: 1050.0,
};

/// The middle MCP abducted to `angle` from rest in 1° increments, with or without self-contact.
fn adducted(angle: f64, self_contact: bool) -> (HandState, KeyframeStats) {
    let hand = hand();
    let mut stepper = Flexion::new(
        hand,
        "hand",
        vec![FLESH; hand.flesh.mesh.cells.len()],
        FlexionSettings {
            max_step_deg: 1.0,
            region: FleshRegion::Whole,
            self_contact: self_contact.then(ContactSettings::default),
            ..Default::default()
        },
        FillOrdering::NestedDissection,
    );
    let mut state = HandState::rest(hand);
    let pose: Pose = [("middle.mcp.abd".to_string(), angle)]
        .into_iter()
        .collect();
    let target = hand.skeleton.apply_pose(&state.angles, &pose).unwrap();
    let stats = stepper
        .move_to(&mut state, &target)
        .unwrap_or_else(|e| panic!("middle MCP abduction {angle}°: {e}"));
    (state, stats)
}

/// The digit (1 thumb … 5 little, 0 palm) whose bone leads skin vertex `v`'s heaviest node.
fn digit_of_vertex(v: usize) -> usize {
    let hand = hand();
    let node = hand
        .contact_skin
        .terms(v)
        .fold(
            (0, f64::NEG_INFINITY),
            |a, (n, w)| if w > a.1 { (n, w) } else { a },
        )
        .0;
    let bone = hand.weights.weights[node][0].0;
    hand.skeleton.bones[bone].digit.map_or(0, |d| d + 1)
}

/// How deep the middle finger's skin went into the ring finger: the largest distance from the
/// ring's skin of a middle skin vertex inside it (generalised winding number of the ring's open
/// skin tube > ½), mm.
fn middle_inside_ring_mm(state: &HandState) -> f64 {
    let hand = hand();
    let skin = &hand.contact_skin;
    let positions = skin.positions(&state.positions);
    let digit: Vec<usize> = (0..skin.vertex_count()).map(digit_of_vertex).collect();
    let ring: Vec<[usize; 3]> = skin
        .triangles()
        .into_iter()
        .map(|t| t.map(|v| v as usize))
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
    let (free, free_stats) = adducted(-5.0, false);
    let (held, stats) = adducted(-5.0, true);
    let ring_bones: Vec<usize> = (0..hand.skeleton.bones.len())
        .filter(|&b| hand.skeleton.bones[b].name.starts_with("ring."))
        .collect();
    let ring_reaction = |s: &HandState| -> Vector3<f64> {
        let r = s.bone_reactions(hand);
        ring_bones.iter().map(|&b| r[b]).sum()
    };
    let free_depth = middle_inside_ring_mm(&free);
    let held_depth = middle_inside_ring_mm(&held);
    let total: Vector3<f64> = held.bone_reactions(hand).iter().sum();
    eprintln!(
        "without self-contact: middle {free_depth:.3} mm inside the ring, ring bones {:.4} N; \
         with: {held_depth:.3} mm, {} contacts, {:.4} N, ring bones {:.4} N, Σ bones {:.2e} N; \
         {} / {} factorizations",
        ring_reaction(&free).norm(),
        stats.self_contacts,
        stats.self_contact_force,
        ring_reaction(&held).norm(),
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
    let press = ring_reaction(&held).norm();
    assert!(
        press > 0.5 * stats.self_contact_force && press > 10.0 * ring_reaction(&free).norm(),
        "ring bones {press} N for a press of {} N",
        stats.self_contact_force
    );
    // Action and reaction: the contact forces are internal, the bones balance.
    assert!(
        total.norm() < 1e-6 * stats.self_contact_force,
        "Σ bone reactions {total}"
    );
}
