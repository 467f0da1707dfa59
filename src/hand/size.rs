//! The built-in hand's size. ANSUR II (C. C. Gordon et al., "2012 Anthropometric Survey of U.S.
//! Army Personnel: Methods and Summary Statistics", NATICK/TR-15/007, 2014; public data of
//! 4 082 men and 1 986 women) measures a hand by its length, from the wrist crease (the stylion
//! line) to the tip of the middle finger, and its breadth across the metacarpal heads, index to
//! little finger. The anatomy tables (`anatomy.rs`) describe one hand; a scene asks for another
//! by these two numbers or by an ANSUR II percentile, and the whole hand — joints, bones and
//! skin — is stretched to it about the middle of the wrist cut: along the hand (x) by the
//! length, across it and through it (y, z) by the breadth.

use super::anatomy::{FINGERS, PALM};
use super::shape::BuiltinSkin;
use super::skeleton::Side;
use super::stretch::Stretch;
use nalgebra::Vector3;
use std::sync::OnceLock;

/// A hand's length and breadth as ANSUR II measures them, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandSize {
    /// Wrist crease to the tip of the middle finger, m.
    pub length: f64,
    /// Across the metacarpal heads, index to little finger, m.
    pub breadth: f64,
}

/// ANSUR II percentiles of hand length and breadth, mm, computed from its public data
/// (linear interpolation between order statistics): sex, percentile, length, breadth.
pub const ANSUR_II: [(&str, u32, f64, f64); 6] = [
    ("female", 5, 165.0, 72.0),
    ("female", 50, 180.0, 78.0),
    ("female", 95, 199.0, 85.0),
    ("male", 5, 177.0, 81.0),
    ("male", 50, 193.0, 88.0),
    ("male", 95, 210.0, 96.0),
];

/// The [`ANSUR_II`] row named `name` (`"female-50"`, …).
pub fn ansur_ii(name: &str) -> Option<(&'static str, u32, f64, f64)> {
    ANSUR_II
        .iter()
        .find(|(sex, p, _, _)| format!("{sex}-{p}") == name)
        .copied()
}

/// Accepted hand lengths, m: from a small child's to beyond the largest adult's.
pub const LENGTH_RANGE: (f64, f64) = (0.10, 0.30);

/// Accepted ratios of breadth to length (ANSUR II's 5th–95th percentiles span 0.40–0.51).
pub const SHAPE_RANGE: (f64, f64) = (0.30, 0.65);

impl HandSize {
    /// The built-in anatomy's own size, measured on its skin.
    pub fn reference() -> HandSize {
        static REFERENCE: OnceLock<HandSize> = OnceLock::new();
        *REFERENCE.get_or_init(|| measure(&BuiltinSkin::new(Side::Right)))
    }

    /// An ANSUR II percentile by name: `"female-5"`, `"female-50"`, `"female-95"`, `"male-5"`,
    /// `"male-50"`, `"male-95"`.
    pub fn percentile(name: &str) -> Option<HandSize> {
        ansur_ii(name).map(|(_, _, length, breadth)| HandSize {
            length: length * 1e-3,
            breadth: breadth * 1e-3,
        })
    }

    /// The names [`HandSize::percentile`] knows, for an error message.
    pub fn percentile_names() -> String {
        ANSUR_II
            .iter()
            .map(|(sex, p, _, _)| format!("\"{sex}-{p}\""))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// A hand `length` long, its breadth in the reference hand's proportion.
    pub fn of_length(length: f64) -> HandSize {
        let r = HandSize::reference();
        HandSize {
            length,
            breadth: length * r.breadth / r.length,
        }
    }

    /// The stretch from the anatomy tables' hand to this size.
    pub fn stretch(&self) -> Stretch {
        let r = HandSize::reference();
        Stretch::new(self.length / r.length, self.breadth / r.breadth)
    }

    /// Refuses a size that is not a human hand's, naming the number.
    pub fn check(&self) -> Result<(), String> {
        let (lo, hi) = LENGTH_RANGE;
        if !(lo..=hi).contains(&self.length) {
            return Err(format!(
                "the hand's length must be between {lo} and {hi} m (wrist crease to the middle \
                 finger's tip), got {}",
                self.length
            ));
        }
        let ratio = self.breadth / self.length;
        let (lo, hi) = SHAPE_RANGE;
        if !self.breadth.is_finite() || !(lo..=hi).contains(&ratio) {
            return Err(format!(
                "the hand's breadth must be between {lo} and {hi} times its length ({:.3} to \
                 {:.3} m for {} m), got {}",
                lo * self.length,
                hi * self.length,
                self.length,
                self.breadth
            ));
        }
        Ok(())
    }
}

/// The length and breadth of a built-in skin, as ANSUR II measures them: from the wrist cut to
/// the farthest point of the middle finger along x; across the hand (y) at its widest over the
/// metacarpal heads and through the palm's thickness, as calipers close on it.
pub fn measure(skin: &BuiltinSkin) -> HandSize {
    // Probed in a right hand's frame (a left hand's skin is its mirror in y).
    let flip = skin.side() == Side::Left;
    let inside = |p: Vector3<f64>| {
        let p = if flip {
            Vector3::new(p.x, -p.y, p.z)
        } else {
            p
        };
        skin.distance(&p) < 0.0
    };
    // Crossing of the skin between an outside point `out` and an inside point `inn`.
    let crossing = |mut out: Vector3<f64>, mut inn: Vector3<f64>| {
        for _ in 0..60 {
            let mid = (out + inn) / 2.0;
            if inside(mid) {
                inn = mid;
            } else {
                out = mid;
            }
        }
        (out + inn) / 2.0
    };
    let (lo, hi) = skin.bounds();
    let lo_y = if flip { -hi.y } else { lo.y };
    let stretch = skin.stretch();
    let middle = &FINGERS[1];
    let y_mid = middle.mcp[1];
    // The middle finger's axis is 1.4 mm palmar of its bones (shape.rs): search its tip there.
    let tip = (0..=40)
        .map(|k| {
            let z = -0.004 + 0.0002 * k as f64;
            let inn = stretch.apply(&Vector3::new(middle.mcp[0], y_mid, z));
            let out = Vector3::new(hi.x + 0.01, inn.y, inn.z);
            if inside(inn) {
                crossing(out, inn).x
            } else {
                f64::NEG_INFINITY
            }
        })
        .fold(f64::NEG_INFINITY, f64::max);
    let (index, little) = (&FINGERS[0], &FINGERS[3]);
    // Inwards from beyond the index and the little finger, at the widest across the palm's
    // thickness and over the metacarpal heads (from 12 mm short of the little finger's
    // knuckle to the index's), as calipers measure it; the thumb lies palmar, out of the way.
    let beyond_index = stretch
        .apply(&Vector3::new(0.0, index.mcp[1] + 0.025, 0.0))
        .y;
    let middle_line = (index.mcp[1] + little.mcp[1]) / 2.0;
    let (mut radial, mut ulnar) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..=20 {
        let span = index.mcp[0] - little.mcp[0] + 0.012;
        let x = little.mcp[0] - 0.012 + span * i as f64 / 20.0;
        for k in 0..=40 {
            let z = -0.012 + 0.0005 * k as f64;
            let centre = stretch.apply(&Vector3::new(x, middle_line, z));
            if inside(centre) {
                let out = Vector3::new(centre.x, beyond_index, centre.z);
                radial = radial.max(crossing(out, centre).y);
                let out = Vector3::new(centre.x, lo_y - 0.01, centre.z);
                ulnar = ulnar.min(crossing(out, centre).y);
            }
        }
    }
    let wrist = stretch.apply(&Vector3::new(PALM.wrist_x, 0.0, 0.0)).x;
    HandSize {
        length: tip - wrist,
        breadth: radial - ulnar,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stretched_skin_measures_the_size_it_was_stretched_to() {
        let reference = HandSize::reference();
        // The anatomy tables' hand is an adult's, within ANSUR II's range of men and women.
        assert!((0.165..0.210).contains(&reference.length), "{reference:?}");
        assert!((0.072..0.096).contains(&reference.breadth), "{reference:?}");
        for name in ["female-5", "male-95"] {
            let size = HandSize::percentile(name).unwrap();
            size.check().unwrap();
            for side in [Side::Right, Side::Left] {
                let got = measure(&BuiltinSkin::sized(
                    side,
                    size.stretch(),
                    crate::hand::HandForm::Simple,
                ));
                assert!(
                    (got.length - size.length).abs() < 1e-5
                        && (got.breadth - size.breadth).abs() < 1e-5,
                    "{name} {side:?}: asked {size:?}, measured {got:?}"
                );
            }
        }
    }

    #[test]
    fn a_size_that_is_not_a_hands_is_refused_naming_the_number() {
        for (size, word) in [
            ((0.5, 0.2), "length"),
            ((f64::NAN, 0.08), "length"),
            ((0.18, 0.02), "breadth"),
            ((0.18, f64::INFINITY), "breadth"),
        ] {
            let e = HandSize {
                length: size.0,
                breadth: size.1,
            }
            .check()
            .unwrap_err();
            assert!(e.contains(word), "{e}");
        }
        assert_eq!(HandSize::percentile("male-40"), None);
        assert!(HandSize::percentile_names().contains("\"female-50\""));
    }
}
