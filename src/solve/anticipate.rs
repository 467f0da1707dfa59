//! The keyframes a user may ask next, flexed ahead while the solver has nothing to do (issue 20:
//! a pose preset from the pose shown to a converged grasp within 1.5 s). A preset moves every
//! joint of the hand: its flexion is the whole hand's, knot after knot (≈ 150–200 ms each at
//! resolution 1 on two cores), and was most of a preset's time. The knots of each keyframe that
//! may come next are flexed from the state it would start from and kept
//! ([`super::knot_memo::KnotMemo`]); the keyframe, when asked, takes them instead of flexing them
//! ([`super::driver::flex_hand`]): the same computation from the same state, so the same result.
//! Its contact steps are solved as before.

use super::driver::{flex_hand, flexion_path, moving_hands, Posed, SolvedAhead, Workspace};
use super::flexion::CancelCheck;
use super::knot_memo::{same_bits, same_points, same_state, KnotMemo};
use super::path::{flex_ahead, Parts};
use super::SimError;
use crate::model::Model;
use crate::state::{Frame, HandState};

/// The most keyframes kept solved ahead (the viewer has four presets).
const SOLVED_AHEAD: usize = 4;

impl Workspace {
    /// Flexes ahead the knots of the keyframes from `posed` to each of `poses` (joint angles by
    /// hand body; in the order given, each to its end unless a knot fails), keeping them for
    /// the keyframe that asks for them; knots kept from another start are forgotten first.
    /// `cancel` is asked in every increment: once it answers `true`, the rest is left. Returns
    /// the knots kept. Poses naming a body that is not a posed hand are passed over.
    pub fn anticipate(
        &mut self,
        model: &Model,
        posed: &Posed,
        poses: &[Vec<(usize, Vec<f64>)>],
        cancel: Option<&CancelCheck>,
    ) -> usize {
        for (_, c) in &mut self.caches {
            c.knots.clear();
        }
        self.solved_ahead.clear();
        let stopped = || cancel.is_some_and(|c| c());
        let mut kept = 0;
        for targets in poses {
            let known = targets.iter().all(|(b, to)| {
                posed.hands.iter().any(|h| {
                    h.body == *b
                        && h.state.angles.len() == to.len()
                        && model.bodies[*b].hand.is_some()
                })
            });
            if !known || stopped() {
                continue;
            }
            let moving = moving_hands(posed, targets);
            let path = flexion_path(model, posed, &moving, false);
            let plan = path.knots_to_flex();
            let mut full = false;
            let mut flex = |body: usize, state: HandState, angles: &[f64], parts: Parts| {
                if full || stopped() {
                    return Err(SimError::Cancelled);
                }
                let from = state.clone();
                let reached = flex_hand(
                    (model, &mut self.caches, cancel),
                    body,
                    state,
                    angles,
                    parts,
                );
                if let Ok(r) = &reached {
                    let caches = self.caches.iter_mut().find(|(cb, _)| *cb == body);
                    let memo = &mut caches.expect("flex_hand puts its caches back").1.knots;
                    if r.1.knots_flexed_ahead == 0 {
                        if memo.put((&from, angles, parts.0, parts.1), r) {
                            kept += 1;
                        } else {
                            full = true;
                        }
                    }
                }
                reached
            };
            // The knots go to a receiver held until all are flexed (`flex_ahead` stops when
            // none listens).
            let (to_path, knots) = std::sync::mpsc::channel();
            flex_ahead(plan, &mut flex, to_path);
            drop(knots);
            if full {
                break;
            }
        }
        kept
    }
}

impl Workspace {
    /// Solves ahead the keyframe from `posed` to `targets` (its flexion taken from knots flexed
    /// ahead where [`Workspace::anticipate`] kept them) and keeps its frame for when it is asked
    /// ([`Workspace::take_solved_ahead`] from the same hands and contact, to the same targets): the
    /// workspace goes on from where it was, as if it had not been solved. Returns whether it was
    /// kept: not where the keyframe fails, is cancelled (`cancel`), would not fit the memory
    /// kept for it, or an object is being let go of.
    pub fn solve_ahead(
        &mut self,
        model: &Model,
        posed: &Posed,
        targets: &[(usize, Vec<f64>)],
        cancel: Option<&CancelCheck>,
    ) -> bool {
        let Some(carried) = self.contact.carried() else {
            return false;
        };
        if self.solved_ahead.len() >= SOLVED_AHEAD || self.solved_for(posed, targets).is_some() {
            return false;
        }
        let mut to = posed.clone();
        let solved = self.move_hands(model, &mut to, targets, cancel);
        let carried_on = self.contact.carried();
        self.contact.restore(carried.clone());
        let (Ok(frame), Some(carried_on)) = (solved, carried_on) else {
            return false;
        };
        let kept: usize = self.solved_ahead.iter().map(|s| s.bytes()).sum();
        let solved = SolvedAhead {
            from: (posed.clone(), carried),
            targets: targets.to_vec(),
            to: (to, carried_on),
            frame,
        };
        if kept.saturating_add(solved.bytes()) > KnotMemo::BUDGET {
            return false;
        }
        self.solved_ahead.push(solved);
        true
    }

    /// Whether the keyframe from `posed` to `targets` was solved ahead.
    pub fn has_solved_ahead(&self, posed: &Posed, targets: &[(usize, Vec<f64>)]) -> bool {
        self.solved_for(posed, targets).is_some()
    }

    /// The index of the keyframe solved ahead from `posed` (and the contact carried now) to
    /// `targets`.
    fn solved_for(&self, posed: &Posed, targets: &[(usize, Vec<f64>)]) -> Option<usize> {
        let carried = self.contact.carried()?;
        self.solved_ahead.iter().position(|s| {
            s.targets.len() == targets.len()
                && s.targets
                    .iter()
                    .zip(targets)
                    .all(|((a, x), (b, y))| a == b && same_bits(x, y))
                && s.from.1 == carried
                && same_posed(&s.from.0, posed)
        })
    }

    /// The frame of the keyframe from `posed` to `targets` if it was solved ahead (and kept
    /// no longer): `posed` and the contact carried go on from where it ended, as if
    /// [`Workspace::move_hands`] had solved it now.
    pub fn take_solved_ahead(
        &mut self,
        posed: &mut Posed,
        targets: &[(usize, Vec<f64>)],
    ) -> Option<Frame> {
        let i = self.solved_for(posed, targets)?;
        let SolvedAhead {
            to: (to, carried),
            mut frame,
            ..
        } = self.solved_ahead.swap_remove(i);
        *posed = to;
        self.contact.restore(carried);
        for hand in &mut frame.hands {
            hand.stats.solved_ahead = true;
        }
        Some(frame)
    }
}

impl SolvedAhead {
    /// The memory it holds, bytes (its vectors, roughly: the frame's per-dof fields and
    /// stresses, the hands' states twice).
    fn bytes(&self) -> usize {
        let hands = |p: &Posed| {
            p.hands
                .iter()
                .map(|h| 48 * h.state.positions.len() + 96 * h.frame.positions.len())
                .sum::<usize>()
                + 8 * p.contact.as_ref().map_or(0, Vec::len)
        };
        let dofs = self.frame.solution.displacement.len();
        hands(&self.from.0) + hands(&self.to.0) + 8 * 24 * dofs
    }
}

/// Whether `a` and `b` hold the same hands, bit for bit, and carry the same contact.
fn same_posed(a: &Posed, b: &Posed) -> bool {
    let contact = match (&a.contact, &b.contact) {
        (None, None) => true,
        (Some(x), Some(y)) => same_bits(x, y),
        _ => false,
    };
    contact
        && a.hands.len() == b.hands.len()
        && a.hands.iter().zip(&b.hands).all(|(x, y)| {
            x.body == y.body
                && same_state(&x.state, &y.state)
                && same_points(&x.frame.positions, &y.frame.positions)
                && same_points(&x.frame.contact_displacement, &y.frame.contact_displacement)
        })
}

#[cfg(test)]
mod tests {
    use crate::scene::{Scene, DEFAULT_SCENE};
    use crate::solve::{Posed, Workspace};

    /// The default scene's Power-grasp-like keyframe (index and middle closing on the ball)
    /// solved after its knots were flexed ahead gives the frame it gives without: every knot
    /// taken, the bone reactions and the contact force the same to round-off.
    #[test]
    fn a_keyframe_flexed_ahead_solves_to_the_same_frame() {
        let scene = Scene::parse(DEFAULT_SCENE, "default").unwrap();
        let model = crate::model::Model::build(&scene, "default").unwrap();
        let hand = model.bodies.iter().position(|b| b.hand.is_some()).unwrap();
        let skeleton = &model.bodies[hand].hand.as_ref().unwrap().skeleton;
        let mut target = skeleton.rest_angles();
        for (d, a) in skeleton.dofs.iter().zip(target.iter_mut()) {
            if d.name.ends_with(".pip") || d.name.ends_with(".flex") {
                *a = 20.0;
            }
        }
        let targets = vec![(hand, target)];
        let solve = |ahead: bool| {
            let mut workspace = Workspace::new(&model).unwrap();
            let mut posed = Posed::rest(&model);
            let kept = if ahead {
                workspace.anticipate(&model, &posed, std::slice::from_ref(&targets), None)
            } else {
                0
            };
            let frame = workspace
                .move_hands(&model, &mut posed, &targets, None)
                .unwrap();
            (kept, frame)
        };
        let (none, plain) = solve(false);
        let (kept, ahead) = solve(true);
        assert_eq!(none, 0);
        // 20° in knots of `max_step_deg` (10°): two.
        assert_eq!(kept, 2, "knots kept");
        let (h0, h1) = (&plain.hands[0], &ahead.hands[0]);
        assert_eq!(h1.stats.knots_flexed_ahead, 2);
        assert_eq!(h0.stats.knots_flexed_ahead, 0);
        assert_eq!(
            h1.stats.factorizations, 0,
            "no factorization of the flexion"
        );
        assert!(h0.stats.factorizations > 0);
        let (r0, r1) = (&h0.bone_reactions, &h1.bone_reactions);
        let largest = r0.iter().map(|r| r.norm()).fold(0.0, f64::max);
        assert!(largest > 0.0);
        for (a, b) in r0.iter().zip(r1) {
            assert!((a - b).norm() <= 1e-9 * largest, "{a} against {b}");
        }
        let apart = h0
            .positions
            .iter()
            .zip(&h1.positions)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(apart <= 1e-12, "the flesh {apart} m apart");
    }
}
