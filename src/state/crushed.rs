//! Flesh crushed past what flesh bears: the Gauss points of a hand's flesh that have lost more
//! than half their volume (volume ratio q = det J / det J₀ below
//! [`CRUSH_ONSET`](crate::fem::crush_barrier::CRUSH_ONSET)). Flesh, nearly incompressible,
//! flows aside rather than lose volume; the linear increments' flesh is held there only by the
//! barrier on its volume (`fem::crush_barrier`), and what the bones squeezing it feel depends on
//! how finely the squeeze is meshed (docs/hand.md, "Self-contact", "What moves it").

use super::outcome::{node_bone, part_of_bone, PARTS};
use crate::fem::crush_barrier::CRUSH_ONSET;
use crate::fem::hex8::{gauss_derivatives, jacobian};
use crate::hand::HandModel;
use nalgebra::Vector3;
use serde::Serialize;
use std::collections::BTreeMap;

/// Where a hand's flesh is crushed to less than half its volume.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CrushedFlesh {
    /// Gauss points (eight a cell) below half their rest volume.
    pub points: usize,
    /// Their rest volume, m³ (each point a cell's share: det J₀ at the point, weight 1).
    pub rest_volume: f64,
    /// The smallest volume ratio over every Gauss point of the flesh (1 at rest; below 0.5
    /// where crushed, negative where a point is inside out, 0 where a position is not finite).
    pub smallest_volume_ratio: f64,
    /// How many points per part of the hand (`palm`, `thumb` … `little`: the part of the bone
    /// most of the cell's nodes follow, as the report's other parts — a finger's metacarpal is
    /// the finger's); parts with none left out.
    pub parts: BTreeMap<String, usize>,
    /// Their rest volume per part, m³ (the parts of `parts`).
    pub part_volumes: BTreeMap<String, f64>,
}

/// Crushed flesh a part may hold, rest volume, before the solve warns (0.1 cm³, a cube of
/// 4.6 mm). Measured (docs/hand.md, "Self-contact", "What moves it, taken apart") at hand resolutions 1 / 1.5 /
/// 2, the whole hand's: the little finger's pulp on the palm (MCP 88°, PIP 90°, DIP 50°) 30 / 29 /
/// 39 mm³ (its creases; what the press adds to its bones holds within 5 % a step), the index PIP
/// at 110° 24 / 37 / 34 mm³, either without self-contact at most 59 mm³; the little finger's pulp
/// pressed into the palm (105°, 70°, the shipped fist's) 505 / 439 / 401 mm³, where what the
/// bones feel does not settle. A rest volume, not a count of points: the same squeeze at every
/// resolution.
pub const CRUSH_WARNING_VOLUME: f64 = 1.0e-7;

impl CrushedFlesh {
    /// The parts holding more than [`CRUSH_WARNING_VOLUME`] of crushed flesh and how much (m³),
    /// the most first.
    pub fn warned_parts(&self) -> Vec<(&str, f64)> {
        let mut out: Vec<(&str, f64)> = self
            .part_volumes
            .iter()
            .filter(|(_, &v)| v > CRUSH_WARNING_VOLUME)
            .map(|(p, &v)| (p.as_str(), v))
            .collect();
        out.sort_by(|a, b| b.1.total_cmp(&a.1));
        out
    }
}

/// The crushed flesh of `hand` with its flesh nodes at `positions` (m). A cell inside out at
/// rest (none in a built hand) is skipped.
pub fn crushed_flesh(hand: &HandModel, positions: &[Vector3<f64>]) -> CrushedFlesh {
    let mesh = &hand.flesh.mesh;
    let mut out = CrushedFlesh {
        smallest_volume_ratio: 1.0,
        ..Default::default()
    };
    for (c, cell) in mesh.cells.iter().enumerate() {
        let rest = gauss_determinants(&mesh.cell_coords(c));
        let now = gauss_determinants(&cell.map(|n| positions[n]));
        let (mut crushed, mut volume) = (0, 0.0);
        for (det0, det) in rest.into_iter().zip(now) {
            if det0.is_nan() || det0 <= 0.0 {
                continue;
            }
            let q = det / det0;
            // A position not finite counts as crushed flat: it is not flesh that holds.
            let q = if q.is_finite() { q } else { 0.0 };
            out.smallest_volume_ratio = out.smallest_volume_ratio.min(q);
            if q < CRUSH_ONSET {
                crushed += 1;
                volume += det0;
            }
        }
        if crushed > 0 {
            let part = PARTS[cell_part(hand, c)];
            out.points += crushed;
            out.rest_volume += volume;
            *out.parts.entry(part.to_string()).or_default() += crushed;
            *out.part_volumes.entry(part.to_string()).or_default() += volume;
        }
    }
    out
}

/// Flesh that a contact's press turned inside out: the flesh near a contact is solved
/// linearised about the hand's pose (small strain in the press), and a press deeper than that
/// follows passes cells through zero volume while the force stays the small strain's, where
/// real flesh, nearly incompressible, stiffens without bound. The Gauss point turned the most,
/// and how many are.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InsideOut {
    /// Gauss points (eight a cell) the press turned inside out.
    pub points: usize,
    /// The flesh cell of the one turned the most, numbered within the hand.
    pub cell: usize,
    /// Its volume ratio (≤ 0), against rest.
    pub ratio: f64,
    /// Its part of the hand (as [`CrushedFlesh::parts`]).
    pub part: &'static str,
    /// The cell's centre at rest, mm.
    pub rest_position_mm: [f64; 3],
}

impl InsideOut {
    /// The part of the point turned the most, as a user names it ("index finger", "thumb",
    /// "palm").
    pub fn part_named(&self) -> &'static str {
        match self.part {
            "index" => "index finger",
            "middle" => "middle finger",
            "ring" => "ring finger",
            "little" => "little finger",
            other => other,
        }
    }
}

/// Where the press of a contact step turned `hand`'s flesh inside out: the Gauss point with the
/// smallest volume ratio among those at or below 0 with its flesh nodes at `positions` and
/// above 0 in the flexed pose (`positions` less `contact_displacement`, the step's own
/// displacement of each node; an empty one: no contact), over the cells the step moved.
/// Flesh the flexion left crushed is the flexion's to tell (`crushed_flesh`); positions not
/// finite are the solve's error (`SimError::NonFinite`), not looked at here.
pub fn pressed_inside_out(
    hand: &HandModel,
    positions: &[Vector3<f64>],
    contact_displacement: &[Vector3<f64>],
) -> Option<InsideOut> {
    let mesh = &hand.flesh.mesh;
    let nodes = mesh.nodes.len();
    if contact_displacement.len() != nodes || positions.len() != nodes {
        return None;
    }
    let (mut points, mut worst) = (0, None::<(usize, f64)>);
    for (c, cell) in mesh.cells.iter().enumerate() {
        if cell
            .iter()
            .all(|&n| contact_displacement[n] == Vector3::zeros())
        {
            continue;
        }
        let rest = gauss_determinants(&mesh.cell_coords(c));
        let now = gauss_determinants(&cell.map(|n| positions[n]));
        let flexed = gauss_determinants(&cell.map(|n| positions[n] - contact_displacement[n]));
        for g in 0..8 {
            let det0 = rest[g];
            if det0.is_nan() || det0 <= 0.0 {
                continue;
            }
            let q = now[g] / det0;
            if !q.is_finite() || q > 0.0 || flexed[g] / det0 <= 0.0 {
                continue;
            }
            points += 1;
            if worst.is_none_or(|(_, w)| q < w) {
                worst = Some((c, q));
            }
        }
    }
    worst.map(|(cell, ratio)| {
        let centre = mesh.cell_coords(cell).iter().sum::<Vector3<f64>>() / 8.0 * 1e3;
        InsideOut {
            points,
            cell,
            ratio,
            part: PARTS[cell_part(hand, cell)],
            rest_position_mm: [centre.x, centre.y, centre.z],
        }
    })
}

/// det J at the eight Gauss points of a cell with corners `x` (each point's volume, weight 1).
fn gauss_determinants(x: &[Vector3<f64>; 8]) -> [f64; 8] {
    gauss_derivatives().map(|dn| jacobian(x, &dn).determinant())
}

/// Index into [`PARTS`] of flesh cell `c`: the part of the bone most of its nodes follow (their
/// attachment, or their heaviest skinning weight); a tie goes to the part listed first.
fn cell_part(hand: &HandModel, c: usize) -> usize {
    let mut votes = [0usize; PARTS.len()];
    for &n in &hand.flesh.mesh.cells[c] {
        votes[part_of_bone(hand, node_bone(hand, n))] += 1;
    }
    (0..PARTS.len()).fold(0, |best, p| if votes[p] > votes[best] { p } else { best })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::Side;

    /// The built hand at rest has nothing crushed; a uniform squeeze of the whole flesh by s
    /// along z crushes every point when s < ½ and none when s > ½, its ratio s exactly (det J
    /// scales by s), their rest volume the flesh's.
    #[test]
    fn a_uniform_squeeze_crushes_every_point_below_half() {
        let hand = HandModel::new(Side::Right, 0.5).unwrap();
        let mesh = &hand.flesh.mesh;
        let at_rest = crushed_flesh(&hand, &mesh.nodes);
        assert_eq!(at_rest.points, 0);
        assert!((at_rest.smallest_volume_ratio - 1.0).abs() < 1e-12);
        let volume = crate::state::HandState::rest(&hand).flesh_volume(&hand);
        let squeezed = |s: f64| {
            let nodes: Vec<Vector3<f64>> = mesh
                .nodes
                .iter()
                .map(|p| Vector3::new(p.x, p.y, s * p.z))
                .collect();
            crushed_flesh(&hand, &nodes)
        };
        let light = squeezed(0.55);
        assert_eq!(light.points, 0);
        assert!((light.smallest_volume_ratio - 0.55).abs() < 1e-9);
        let hard = squeezed(0.4);
        assert_eq!(hard.points, 8 * mesh.cells.len());
        assert!((hard.smallest_volume_ratio - 0.4).abs() < 1e-9);
        assert!((hard.rest_volume - volume).abs() < 1e-12 * volume);
        assert_eq!(hard.parts.values().sum::<usize>(), hard.points);
        let by_part: f64 = hard.part_volumes.values().sum();
        assert!((by_part - volume).abs() < 1e-12 * volume);
        assert_eq!(
            hard.part_volumes.keys().collect::<Vec<_>>(),
            hard.parts.keys().collect::<Vec<_>>()
        );
        // Every part of a whole hand squeezed flat holds far more than the warning's volume:
        // all warned, the most first.
        let warned = hard.warned_parts();
        assert_eq!(warned.len(), 6, "{warned:?}");
        assert!(warned.windows(2).all(|w| w[0].1 >= w[1].1), "{warned:?}");
        assert!(light.warned_parts().is_empty());
        assert_eq!(hard.parts.len(), 6, "{:?}", hard.parts);
        // The cells' parts follow their nodes' bones, as the report's other parts: a finger's
        // metacarpal's flesh (the lattice's palm) is the finger's, the carpus's the palm's.
        let metacarpal = hand.skeleton.bone_index("little.metacarpal").unwrap();
        let carpus = hand.skeleton.bone_index("carpus").unwrap();
        let all_on = |c: usize, b: usize| mesh.cells[c].iter().all(|&n| node_bone(&hand, n) == b);
        let on_metacarpal: Vec<usize> = (0..mesh.cells.len())
            .filter(|&c| all_on(c, metacarpal))
            .collect();
        assert!(!on_metacarpal.is_empty());
        for &c in &on_metacarpal {
            assert_eq!(cell_part(&hand, c), 5, "cell {c}");
        }
        assert!(on_metacarpal
            .iter()
            .any(|&c| hand.flesh.cell_digit[c].is_none()));
        let on_carpus = (0..mesh.cells.len()).find(|&c| all_on(c, carpus)).unwrap();
        assert_eq!(cell_part(&hand, on_carpus), 0);
        // The little finger's distal phalanx's flesh squeezed alone (its nodes not on the bone
        // pulled four fifths of the way to the bone's distal end): only the little finger's part.
        let distal = hand.skeleton.bone_index("little.distal").unwrap();
        let cells: Vec<usize> = (0..mesh.cells.len())
            .filter(|&c| mesh.cells[c].iter().all(|&n| node_bone(&hand, n) == distal))
            .collect();
        assert!(!cells.is_empty());
        let mut pulled = mesh.nodes.clone();
        let tip = hand.skeleton.bones[distal].end;
        for &c in &cells {
            for &n in &mesh.cells[c] {
                if hand.flesh.node_bone[n].is_none() {
                    pulled[n] = tip + 0.2 * (mesh.nodes[n] - tip);
                }
            }
        }
        let pulp = crushed_flesh(&hand, &pulled);
        assert!(pulp.points > 0);
        // The pulp squeezed so is warned of, alone: 795 mm³ of it at rest at resolution 0.5,
        // over the warning's 100.
        let pulp_volume = pulp.part_volumes["little"];
        assert!((pulp_volume - pulp.rest_volume).abs() < 1e-15);
        assert!(pulp_volume > CRUSH_WARNING_VOLUME, "{pulp_volume:e} m³");
        assert_eq!(pulp.warned_parts(), [("little", pulp_volume)]);
        assert_eq!(
            pulp.parts.keys().collect::<Vec<_>>(),
            ["little"],
            "{:?}",
            pulp.parts
        );
        // A position not finite is not flesh that holds.
        let mut broken = mesh.nodes.clone();
        broken[mesh.cells[0][0]].x = f64::NAN;
        let broken = crushed_flesh(&hand, &broken);
        assert!(broken.points > 0 && broken.smallest_volume_ratio == 0.0);
    }

    /// A press that mirrors the whole flesh through a plane (z → −z/2) turns every Gauss point
    /// inside out at −½ exactly; the same positions reached by a flexion already inside out
    /// (the contact adding a hair) are the flexion's, not the press's; without contact, none.
    #[test]
    fn a_press_that_mirrors_the_flesh_turns_every_point_inside_out() {
        let hand = HandModel::new(Side::Right, 0.5).unwrap();
        let mesh = &hand.flesh.mesh;
        // The flesh's positions with z scaled by `s`, and what the press moved each node.
        let pressed_along_z = |s: f64| -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
            let moved: Vec<Vector3<f64>> = mesh
                .nodes
                .iter()
                .map(|p| Vector3::new(p.x, p.y, s * p.z))
                .collect();
            let by = moved.iter().zip(&mesh.nodes).map(|(m, r)| m - r).collect();
            (moved, by)
        };
        let (mirrored, pressed) = pressed_along_z(-0.5);
        let turned = pressed_inside_out(&hand, &mirrored, &pressed).unwrap();
        assert_eq!(turned.points, 8 * mesh.cells.len());
        assert!((turned.ratio + 0.5).abs() < 1e-9, "{}", turned.ratio);
        let centre = mesh.cell_coords(turned.cell).iter().sum::<Vector3<f64>>() / 8.0 * 1e3;
        assert_eq!(turned.rest_position_mm, [centre.x, centre.y, centre.z]);
        assert_eq!(turned.part, PARTS[cell_part(&hand, turned.cell)]);
        let hair = vec![Vector3::new(1e-9, 0.0, 0.0); mesh.nodes.len()];
        assert_eq!(pressed_inside_out(&hand, &mirrored, &hair), None);
        assert_eq!(pressed_inside_out(&hand, &mirrored, &[]), None);
        // A press that squeezes without turning: none.
        let (squeezed, pressed) = pressed_along_z(0.1);
        assert_eq!(pressed_inside_out(&hand, &squeezed, &pressed), None);
    }
}
