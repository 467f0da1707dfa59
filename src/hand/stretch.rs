//! The map that stretches the built-in hand to another size (`size.rs`): about the middle of the
//! wrist cut, along the hand by one factor, across and through it by another.

use super::anatomy::PALM;
use nalgebra::Vector3;

/// The map from the reference hand to a hand of another size: p ↦ w + S (p − w), w the middle
/// of the wrist cut, S = diag(length ratio, breadth ratio, breadth ratio).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stretch {
    /// S's diagonal.
    pub scale: Vector3<f64>,
}

impl Stretch {
    /// The reference hand's own size.
    pub const IDENTITY: Stretch = Stretch {
        scale: Vector3::new(1.0, 1.0, 1.0),
    };

    /// Stretched by `along` the hand (x) and by `across` it and through it (y, z).
    pub fn new(along: f64, across: f64) -> Stretch {
        Stretch {
            scale: Vector3::new(along, across, across),
        }
    }

    fn origin() -> Vector3<f64> {
        Vector3::new(PALM.wrist_x, 0.0, 0.0)
    }

    /// A reference point's place in the stretched hand.
    pub fn apply(&self, p: &Vector3<f64>) -> Vector3<f64> {
        Stretch::origin() + (p - Stretch::origin()).component_mul(&self.scale)
    }

    /// A stretched point's place in the reference hand.
    pub fn inverse(&self, p: &Vector3<f64>) -> Vector3<f64> {
        Stretch::origin() + (p - Stretch::origin()).component_div(&self.scale)
    }

    /// How a radius across a bone or a finger scales.
    pub fn radial(&self) -> f64 {
        self.scale.y
    }

    /// A factor that keeps a reference signed distance a bound of the stretched one near the
    /// surface (the smallest stretch).
    pub fn distance(&self) -> f64 {
        self.scale.min()
    }
}
