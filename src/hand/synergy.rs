//! Preshapes and closing synergies: how a hand closes on an object by itself (the gentlest grip,
//! issue 17).
//!
//! A preshape opens the digits that will grasp and sets the others aside; each grasping digit
//! then closes along one synergy, its joints coupled — a finger's MCP, PIP and DIP flexing
//! together (the flexor tendons couple them), the thumb's CMC flexing and abducting into
//! opposition while its MCP and IP flex — from its open angles to its closed ones, as one
//! parameter s from 0 to 1.

use super::skeleton::Pose;

/// Digits in the order of the hand's parts: thumb, index, middle, ring, little.
pub const DIGITS: [&str; 5] = ["thumb", "index", "middle", "ring", "little"];

/// A named preshape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preshape {
    /// Every digit wraps the object.
    Power,
    /// Thumb and index pads.
    Pinch,
    /// Thumb, index and middle.
    Tripod,
}

impl Preshape {
    /// Every named preshape.
    pub const ALL: [Preshape; 3] = [Preshape::Power, Preshape::Pinch, Preshape::Tripod];

    /// Its name in a scene file.
    pub fn name(self) -> &'static str {
        match self {
            Preshape::Power => "power",
            Preshape::Pinch => "pinch",
            Preshape::Tripod => "tripod",
        }
    }

    /// The preshape named `name`, if any.
    pub fn from_name(name: &str) -> Option<Preshape> {
        Preshape::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Which digits grasp (in [`DIGITS`] order).
    pub fn grasping(self) -> [bool; 5] {
        match self {
            Preshape::Power => [true; 5],
            Preshape::Pinch => [true, true, false, false, false],
            Preshape::Tripod => [true, true, true, false, false],
        }
    }

    /// The preshape's angles, degrees: the grasping digits open (their synergies at s = 0), the
    /// others curled out of the way (they would touch first in a pinch otherwise).
    pub fn pose(self) -> Pose {
        let grasping = self.grasping();
        let mut pose = Pose::new();
        for (d, digit) in DIGITS.iter().enumerate() {
            let angles = if grasping[d] {
                open(self, digit)
            } else {
                tucked(self, digit)
            };
            for (joint, angle) in angles {
                pose.insert(joint, angle);
            }
        }
        if self == Preshape::Pinch {
            // The index turned a little towards the middle finger, as its pad meets the
            // thumb's.
            pose.insert("index.mcp.abd".into(), PINCH_INDEX_ABDUCTION);
        }
        if self == Preshape::Tripod {
            // The index and middle pads side by side, facing the thumb's.
            pose.insert("index.mcp.abd".into(), TRIPOD_ABDUCTION.0);
            pose.insert("middle.mcp.abd".into(), TRIPOD_ABDUCTION.1);
        }
        pose
    }
}

/// The index's MCP abduction in the pinch, degrees (towards the middle finger).
const PINCH_INDEX_ABDUCTION: f64 = -15.0;

/// The index's and the middle's MCP abduction in the tripod, degrees (positive: radial, towards
/// the thumb's side).
const TRIPOD_ABDUCTION: (f64, f64) = (0.0, 10.0);

/// A grasping digit's synergy at rest: its open angles (s = 0).
pub fn open(preshape: Preshape, digit: &str) -> Vec<(String, f64)> {
    synergy(preshape, digit)
        .into_iter()
        .map(|(j, a, _)| (j, a))
        .collect()
}

/// A digit folded out of the way of a pinch (a fist's angles, short of the limits).
fn tucked(preshape: Preshape, digit: &str) -> Vec<(String, f64)> {
    if digit == "thumb" {
        return open(preshape, digit);
    }
    vec![
        (format!("{digit}.mcp.flex"), 70.0),
        (format!("{digit}.pip"), 90.0),
        (format!("{digit}.dip"), 50.0),
    ]
}

/// A digit's closing synergy in a preshape: (joint, open angle, closed angle), degrees.
///
/// Wrapping (power): fingers flex MCP, PIP and DIP together from slightly bent to near
/// a fist's (88°, 105°, 70° at the limits' edge: the full fist is reached without a crushed
/// cell, `hand::full_fist`); the thumb opens in wide palmar abduction (60°, the CMC's flexion
/// −10°: out of the palm's plane, in front of the index) and wraps the object from the side
/// opposite the fingertips, abducting to 70° while its MCP and IP flex (60°, 30°) — Kapandji's
/// spherical grip, the thumb's pulp and the fingers' on either side of the object. Measured on
/// the default scene's ball (the skin's shape carried by the bones): the thumb first meets it on
/// the wrist's side below its equator, its normal force pointing (0.71, −0.54, 0.44) — towards
/// the fingertips and up, against the fingers' (−0.95, ±0.2, 0.2); the old synergy (abducting
/// 35 → 45°, flexing across the palm 0 → 35°) met it on its side, (−0.01, −0.98, −0.17), and
/// nothing opposed the fingertips pushing the ball towards the wrist: a palm-down power grasp
/// could not hold a free ball (tests/let_go.rs).
///
/// Pinch (pulp to pulp): the thumb pronated into opposition (`thumb.cmc.rot`) and the index
/// close their pads on each other, facing: along the whole synergy the pads' normals lie within
/// 16° of the line between them (13° … 1° as it opens), their distance going from 45 mm open
/// to 15 mm closed, the point between them moving by less than 16 mm — the line between two
/// poses found by minimising the pads' angle to that line at 45 and 15 mm apart with a ball's
/// room between them (the skin's shape on the bones; `tests/pinch.rs` holds a free ball so).
///
/// Tripod (since 2026-11-29; the three-jaw chuck): the pinch's thumb and index, the index
/// straight ahead (no abduction) and the middle finger closing along the index's pinch synergy,
/// turned 10° towards it, its pad beside the index's: an object between the two fingers' pads
/// is met by all three (before, the tripod closed the power grasp's wrapping thumb, which never
/// met a ball the fingers' pads held).
pub fn synergy(preshape: Preshape, digit: &str) -> Vec<(String, f64, f64)> {
    let j = |name: &str| format!("{digit}.{name}");
    if matches!(preshape, Preshape::Pinch | Preshape::Tripod) {
        // The tripod's middle finger closes along the index's pinch synergy (its own joints).
        let along = match (preshape, digit) {
            (Preshape::Tripod, "middle") => "index",
            _ => digit,
        };
        match along {
            "thumb" => {
                return vec![
                    (j("cmc.abd"), 54.5, 37.0),
                    (j("cmc.flex"), 13.0, 30.5),
                    (j("cmc.rot"), 56.5, 44.5),
                    (j("mcp"), 5.0, -5.0),
                    (j("ip"), -15.0, -20.0),
                ]
            }
            "index" => {
                return vec![
                    (j("mcp.flex"), 49.0, 34.0),
                    (j("pip"), 31.0, 72.0),
                    (j("dip"), 0.0, -10.0),
                ]
            }
            _ => {}
        }
    }
    if digit == "thumb" {
        vec![
            (j("cmc.abd"), 60.0, 70.0),
            (j("cmc.flex"), -10.0, -5.0),
            (j("mcp"), 0.0, 60.0),
            (j("ip"), 0.0, 30.0),
        ]
    } else {
        vec![
            (j("mcp.flex"), 10.0, 85.0),
            (j("pip"), 10.0, 100.0),
            (j("dip"), 5.0, 65.0),
        ]
    }
}

/// The largest joint turn of `digit`'s synergy from open to closed, degrees: one unit of its
/// parameter s.
pub fn span(preshape: Preshape, digit: &str) -> f64 {
    synergy(preshape, digit)
        .iter()
        .map(|(_, a, b)| (b - a).abs())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::{Side, Skeleton};

    #[test]
    fn preshapes_and_synergies_lie_within_the_joint_limits() {
        let s = Skeleton::new(Side::Right);
        for p in Preshape::ALL {
            assert_eq!(Preshape::from_name(p.name()), Some(p));
            s.apply_pose(&s.rest_angles(), &p.pose())
                .unwrap_or_else(|e| panic!("{}: {e}", p.name()));
        }
        for p in Preshape::ALL {
            for digit in DIGITS {
                let closed: Pose = synergy(p, digit)
                    .into_iter()
                    .map(|(j, _, b)| (j, b))
                    .collect();
                s.apply_pose(&s.rest_angles(), &closed)
                    .unwrap_or_else(|e| panic!("{digit}: {e}"));
                assert!(span(p, digit) > 0.0);
            }
        }
        assert_eq!(Preshape::from_name("fist"), None);
    }
}
