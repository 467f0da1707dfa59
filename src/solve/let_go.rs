//! Letting go of the object a grasp closed on (issue 17, `hold = "gravity"`): each pose of the
//! gentlest grip's search, solved with the object held as the scene holds it (a stand, an
//! obstacle), is solved again with the object held by nothing but the hand
//! (`Model::released`): its supports freed, its weight on,
//! friction at every contact, starting from the held state (contacts held there stick where
//! they were: incremental Coulomb friction). The object settles into the grip — the digits'
//! normal forces, which the stand balanced, now balance among themselves and the weight — or
//! the solve finds that nothing holds it (its stabilising springs would carry its load:
//! `stabilize::check_held`), settled again from where each solve left it (the springs anchored
//! there). The springs' force is measured against the forces on the object — the larger of its
//! load and its contacts' summed force (`stabilize::check_held`). Held: a settle whose springs
//! carry at most 10⁻⁴ of them, or at most 10⁻³ once the settles no longer slow (the creep of
//! contacts at their cones, µm a settle). Sliding out: a settle that moves it more than half as
//! far as the one before, its springs carrying more than 10⁻². How far it moves on release, its
//! drift, is measured.

use super::driver::{Posed, Workspace};
use super::error::SimError;
use crate::model::Model;
use crate::state::Frame;
use nalgebra::Vector3;

/// The object let go of.
pub(super) struct LetGo {
    /// The frame with the object held by the hand alone.
    pub frame: Frame,
    /// How far the object's centre moved on release, m (its nodes' mean displacement).
    pub drift: Vector3<f64>,
}

/// The released model and what its solves keep between the poses of one grasp.
pub(super) struct Release {
    pub model: Model,
    workspace: Workspace,
}

impl Release {
    /// `model` with body `object` let go of.
    pub fn new(model: &Model, object: usize) -> Result<Release, SimError> {
        let model = model.released(object);
        let workspace = Workspace::new(&model)?;
        Ok(Release { model, workspace })
    }

    /// The grip `held` (a frame of the scene's model, the hands where `posed` leaves them, the
    /// contacts `holding` held by its last step) solved with the object let go of.
    pub fn let_go(
        &mut self,
        (held, posed, holding): (&Frame, &Posed, &[usize]),
        (hand, object): (usize, usize),
        cancel: Option<&super::CancelCheck>,
    ) -> Result<LetGo, SimError> {
        let mut p = posed.clone();
        let angles = p
            .hands
            .iter()
            .find(|h| h.body == hand)
            .expect("a grasp's hand is posed")
            .state
            .angles
            .clone();
        self.workspace.contact.held = holding.to_vec();
        // The springs that keep the object's stiffness regular rest where the last solve left
        // it, and a solve whose springs carry part of its load is not failed but settled
        // again from there: held, each settle moves it less (by the springs' over the
        // contacts' stiffness, ≈ 10⁻²) down to a floor of micrometres where the springs carry
        // ≈ 10⁻⁴ of the forces on it; sliding out, 0.4 mm to centimetres every time, the
        // springs carrying 1 % of them to all.
        self.workspace.contact.unheld = Some(None);
        let centre = |u: &[f64]| -> Vector3<f64> {
            let nodes = self.model.bodies[object].nodes.clone();
            let count = nodes.len().max(1) as f64;
            nodes
                .map(|n| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
                .sum::<Vector3<f64>>()
                / count
        };
        let start = centre(&held.solution.displacement);
        let stays = |frame: Frame| {
            let drift = centre(&frame.solution.displacement) - start;
            LetGo { frame, drift }
        };
        let mut anchor = held.solution.displacement.clone();
        let mut last = f64::INFINITY;
        let mut last_share = 0.0;
        let mut creeping = None;
        for _ in 0..SETTLES {
            self.workspace.contact.anchor = Some(anchor);
            let frame = self.workspace.move_hands(
                &self.model,
                &mut p,
                &[(hand, angles.clone())],
                cancel,
            )?;
            let moved = (centre(&frame.solution.displacement)
                - centre(self.workspace.contact.anchor.as_deref().unwrap_or_default()))
            .norm();
            let unheld = self
                .workspace
                .contact
                .unheld
                .as_mut()
                .and_then(Option::take);
            // The share of the forces on it (its load, or its contacts' summed force where
            // larger) the springs carried in this settle.
            let share = match &unheld {
                None => 0.0,
                Some(crate::contact::ContactError::NotHeld { held, .. }) => held / 100.0,
                Some(_) => 1.0,
            };
            let slowing = moved <= SETTLED * last;
            match unheld {
                None => return Ok(stays(frame)),
                // At the floor: the contacts carry all but a thousandth of the forces, and what
                // is left creeps on by micrometres a settle (the incremental friction's
                // contacts at their cones slip again each time the springs are re-anchored):
                // held, where it is.
                Some(_) if share <= FLOOR && !slowing => return Ok(stays(frame)),
                // A settle that moves it as far as the one before with its springs carrying
                // more than a hundredth of the forces: it slides out. (Between that and the
                // floor, a contact slipping again after the load moved onto it: settled again.)
                Some(e) if !slowing && share > SLIDING => return Err(SimError::Contact(e)),
                Some(_) => {
                    last = moved;
                    last_share = share;
                    anchor = frame.solution.displacement.clone();
                    creeping = (share <= FLOOR).then_some(frame);
                }
            }
        }
        if let Some(frame) = creeping {
            return Ok(stays(frame));
        }
        Err(SimError::Contact(crate::contact::ContactError::NotHeld {
            body: self.model.bodies[object].name.clone(),
            held: 100.0 * last_share,
            motion: format!("still moves {last:.3e} m after {SETTLES} settles"),
            place: String::new(),
        }))
    }
}

/// Settles of an object let go of at most.
const SETTLES: usize = 12;

/// A settle that moves the object more than this share of the one before no longer slows: it
/// slides out, or (its springs carrying at most [`FLOOR`] of the forces) it is held and creeps.
const SETTLED: f64 = 0.5;

/// The largest share of the forces on it (its load, or its contacts' summed force where
/// larger) the springs may carry in a settle that no longer slows for the object to be held
/// (measured, the power grasp's settles at hand resolution 1.25: 0.92, 0.20, 0.045, 0.014,
/// 0.018 %, moving 642, 142, 31, 9.8 and 12 µm; sliding out, 23–100 %, moving 12–28 mm each).
const FLOOR: f64 = 1e-3;

/// The share of the forces on it the springs carry, past which a settle that no longer slows
/// has the object slide out (at hand resolution 1.5 the same grasp's settles, held, rise once
/// in a while from ≈ 0.02 % to 0.1–0.2 % as a contact slips; sliding out, 1.2–100 %).
const SLIDING: f64 = 1e-2;

/// Why the object let go of is not held, in words (`error` from [`Release::let_go`]): where
/// nothing holds it, how much of its load and which way it moves (the advice of a scene's
/// unsupported body, "give it supports", is not what a grasp needs).
pub(super) fn not_held(error: &SimError) -> String {
    match error {
        SimError::Contact(crate::contact::ContactError::NotHeld { held, motion, .. }) => {
            let motion = motion
                .split(" before contact holds it")
                .next()
                .unwrap_or(motion);
            let motion = if motion.starts_with("moves") {
                format!("it {motion} out of the grip")
            } else {
                format!("it {motion}")
            };
            format!(
                "let go of, the hand does not hold it: {motion}, {held:.0} % of its load held \
                 by nothing"
            )
        }
        other => format!("let go of, its solve failed: {other}"),
    }
}
