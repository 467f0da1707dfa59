//! What the solve of one frame produces: displacements, reactions, stresses, contact, and the
//! state of every hand.

use super::hand::KeyframeStats;
use super::outcome::Overload;
use crate::contact::ContactSummary;
use crate::fem::solve::Solution;
use crate::fem::stress::StressField;

/// The state after solving one frame.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Displacements and reactions.
    pub solution: Solution,
    /// Stresses (empty while `stress_pending`).
    pub stress: StressField,
    /// Stresses not computed yet, and by which rule: a contact step along a motion, or a
    /// correction at a pose, is mostly a state on the way to the next, so only the frame a
    /// keyframe ends with gets its stresses (`solve::frame_stress`; the viewer's draft at the
    /// pose only where it draws them). `None`: `stress` is the frame's.
    pub stress_pending: Option<PendingStress>,
    /// Time spent assembling K, ms.
    pub assembly_ms: f64,
    /// Time spent on stresses, ms.
    pub stress_ms: f64,
    /// The hands' state (empty without hands).
    pub hands: Vec<HandFrame>,
    /// Contact against the obstacles (None without obstacles).
    pub contact: Option<ContactSummary>,
}

/// How a frame's stresses are to be computed, once it is the frame kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PendingStress {
    /// The static frame with the hands composed into it (src/solve/compose.rs).
    Composed,
    /// A contact step's frame (src/solve/grasp.rs): the other bodies turned where the step
    /// corotated them (`objects_turned`).
    Contact {
        /// Whether the other bodies' strain is rotation-free (corotated about a carried state).
        objects_turned: bool,
    },
}

/// A hand in a frame.
#[derive(Clone, Debug)]
pub struct HandFrame {
    /// The body.
    pub body: usize,
    /// Joint angles, degrees.
    pub angles: Vec<f64>,
    /// Flesh node positions, m.
    pub positions: Vec<nalgebra::Vector3<f64>>,
    /// What the contact step added to each flesh node's position over the flexed pose, m (empty
    /// without contact): the flexed pose is `positions` less this.
    pub contact_displacement: Vec<nalgebra::Vector3<f64>>,
    /// What the contact step added to each flesh node's reaction, N (empty without contact):
    /// the flexion's reactions are `reaction` less this.
    pub contact_reaction: Vec<nalgebra::Vector3<f64>>,
    /// Reaction of every bone (sum of R_u over its nodes, equation (8)), N.
    pub bone_reactions: Vec<nalgebra::Vector3<f64>>,
    /// Accumulated reaction at every flesh node, N.
    pub reaction: Vec<nalgebra::Vector3<f64>>,
    /// Normal force of the skin's contact with itself at each contact-skin vertex, N (see
    /// `HandState::self_contact`; empty without).
    pub self_contact: Vec<f64>,
    /// Flesh volume, m³.
    pub volume: f64,
    /// What reaching this frame's pose cost.
    pub stats: KeyframeStats,
    /// Contact force on the flesh following each bone, N (zero without contact).
    pub contact_force: Vec<nalgebra::Vector3<f64>>,
    /// Bones whose reaction overruns their muscle force threshold: the grasp is not realisable.
    pub overloads: Vec<Overload>,
    /// What a grasp keyframe found (the gentlest grip), for the frame it ends in.
    pub grasp: Option<super::GraspOutcome>,
}

impl HandFrame {
    /// Whether its skin presses on itself anywhere (`self_contact`).
    pub fn presses_itself(&self) -> bool {
        self.self_contact.iter().any(|&f| f > 0.0)
    }

    /// The contact force on each digit's flesh (thumb first: `hand::synergy::DIGITS`), N: its
    /// bones' `contact_force` summed (the carpus's left out). `skeleton` is this hand's.
    pub fn contact_force_by_digit(
        &self,
        skeleton: &crate::hand::Skeleton,
    ) -> [nalgebra::Vector3<f64>; 5] {
        let mut on = [nalgebra::Vector3::zeros(); 5];
        for (bone, f) in skeleton.bones.iter().zip(&self.contact_force) {
            if let Some(d) = bone.digit {
                on[d] += f;
            }
        }
        on
    }
}
