//! Letting go of the object a grasp closed on (issue 17, `hold = "gravity"`): each pose of the
//! gentlest grip's search, solved with the object held as the scene holds it (a stand, an
//! obstacle), is solved again with the object held by nothing but the hand
//! (`Model::released`): its supports freed, its weight on,
//! friction at every contact, starting from the held state (contacts held there stick where
//! they were: incremental Coulomb friction). The object settles into the grip — the digits'
//! normal forces, which the stand balanced, now balance among themselves and the weight — or
//! the solve finds that nothing holds it (its stabilising springs would carry its load:
//! `stabilize::check_held`), settled again from where each solve left it (the springs anchored
//! there). How far it moves on release, its drift, is measured.

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
        // contacts' stiffness, ≈ 10⁻²); sliding out, about as much every time.
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
        let mut anchor = held.solution.displacement.clone();
        let mut last = f64::INFINITY;
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
            match self
                .workspace
                .contact
                .unheld
                .as_mut()
                .and_then(Option::take)
            {
                None => {
                    let drift = centre(&frame.solution.displacement) - start;
                    return Ok(LetGo { frame, drift });
                }
                Some(e) if moved > SETTLED * last => return Err(SimError::Contact(e)),
                Some(_) => {
                    last = moved;
                    anchor = frame.solution.displacement.clone();
                }
            }
        }
        Err(SimError::Contact(crate::contact::ContactError::NotHeld {
            body: self.model.bodies[object].name.clone(),
            held: 0.0,
            motion: format!("still moves {last:.3e} m after {SETTLES} settles"),
            place: String::new(),
        }))
    }
}

/// Settles of an object let go of at most.
const SETTLES: usize = 12;

/// A settle that moves the object more than this share of the one before: it slides out.
const SETTLED: f64 = 0.5;

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
