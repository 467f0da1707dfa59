//! A model with one body let go of: what a grasp against gravity is tested on (issue 17).
//!
//! The scene holds the object where the hand closes on it (a stand, or an obstacle it rests
//! on); whether the grip holds it is asked of the same bodies with nothing else holding the
//! object: its prescribed displacements freed, obstacles no longer touching it, and the body
//! floating (weak ground springs, `solve::stabilize`, checked to carry nothing after the
//! solve). Everything else — meshes, loads (its weight), materials, hands — is the model's.

use super::Model;
use crate::fem::DofPartition;

impl Model {
    /// This model with body `object` held by nothing but the hands' contact.
    pub fn released(&self, object: usize) -> Model {
        let mut model = self.clone();
        let nodes = model.bodies[object].nodes.clone();
        let mut mask = model.partition.prescribed.clone();
        for d in 3 * nodes.start..3 * nodes.end {
            mask[d] = false;
            model.prescribed[d] = 0.0;
        }
        model.partition = DofPartition::new(mask);
        model.constraints.retain(|c| c.body != object);
        model.contact_candidates.retain(|n| !nodes.contains(n));
        model.bodies[object].floating = true;
        model
    }

    /// Whether anything but the hands holds body `object`: a prescribed displacement on it, or
    /// an obstacle it may touch.
    pub fn supports(&self, object: usize) -> bool {
        let nodes = &self.bodies[object].nodes;
        (3 * nodes.start..3 * nodes.end).any(|d| self.partition.prescribed[d])
            || (!self.obstacles.is_empty()
                && self.contact_candidates.iter().any(|n| nodes.contains(n)))
    }
}
