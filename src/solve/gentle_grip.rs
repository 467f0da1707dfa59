//! The gentlest grip that holds (issue 17; the paper: the grip "is as gentle as possible without
//! letting go of the ball"): a grasp keyframe closes the hand on an object by itself.
//!
//! 1. The hand moves to the preshape (an ordinary keyframe's motion).
//! 2. Each grasping digit closes along its synergy (`hand::synergy`) until its skin first meets
//!    the object: found on the skin the bones carry (skinning), against the object's surface
//!    where the preshape's frame leaves it, by a scan in sixteenths of the synergy and a
//!    bisection of the first interval that meets. A digit that never meets closes fully.
//! 3. The touching digits close on together, each by the same angle θ of its synergy's largest
//!    joint past its first contact, and every pose is solved by FEM (the keyframe driver, from
//!    the last pose solved: the grip tightens monotonically). θ doubles from 1° until the grip
//!    holds the object as asked, then the last interval is narrowed (regula falsi towards the
//!    hold asked where both ends have a measure, bisection otherwise) down to 1/32 of a
//!    degree, or until the hold is met within 5 %: the least closing that holds, the least
//!    effort of the muscles along the synergy. Where the grip at first contact already passes
//!    what is asked by more than that (the FEM's flesh meets the object before the skin the
//!    bones carry does), the interval from the preshape (θ < 0) to first contact is bisected.
//! 4. It holds when the contact forces on the object, taken as a rigid body with nothing else
//!    holding it, can balance its weight with friction to spare by the margin
//!    (`contact::hold_margin`), or press it with the grip force asked. A bone past its
//!    threshold, a pose the solver cannot reach, or a synergy closed to its end without a hold
//!    end the search with the best grip found and `held = false`, and why.

use super::driver::{Posed, Workspace};
use super::error::SimError;
use super::let_go::Release;
use crate::hand::synergy::DIGITS;
use crate::model::{GraspModel, HoldTarget, KeyframeModel, Model};
use crate::state::outcome::Overload;
use crate::state::{grip, Frame, GraspOutcome, GripTrial};
use nalgebra::Vector3;
use parry3d_f64::math::Vec3;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

/// The first trial's closing past first contact, degrees.
const FIRST_THETA: f64 = 1.0;

/// The search stops when the interval is this narrow, degrees (a pinch's pads press ≈ 0.8 N
/// more per degree on the 38 mm ball of `tests/pinch.rs`)…
const THETA_TOLERANCE: f64 = 1.0 / 32.0;

/// …or when the hold is met within this share of what is asked.
const HOLD_TOLERANCE: f64 = 0.05;

/// Poses solved by FEM at most.
const MAX_TRIALS: usize = 16;

/// A pose tried: its closing, frame, where it left the hands, and what its grip achieves.
#[derive(Clone)]
struct Trial {
    theta: f64,
    frame: Frame,
    posed: Posed,
    /// The sum of the normal forces on the object, N.
    grip: f64,
    /// The friction margin against the weight (gravity holds; 0 otherwise).
    margin: f64,
    /// A gravity hold: how far the object moved when let go of, m, or why the hand does not
    /// hold it (`None`: nothing touched it, or a force hold).
    released: Option<Result<f64, String>>,
}

impl Trial {
    /// The first of hand `body`'s bones past its threshold in this pose.
    fn overload(&self, body: usize) -> Option<Overload> {
        self.frame
            .hands
            .iter()
            .find(|h| h.body == body)
            .and_then(|h| h.overloads.first().cloned())
    }
}

impl Workspace {
    /// Solves the grasp keyframe `key` (it has a `grasp`): the hand moves to the preshape, then
    /// closes on the object to the gentlest grip that holds it (module documentation). The
    /// frame returned carries the outcome in its hand's `grasp`; `posed` is left in its pose.
    pub fn close_grip(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        key: &KeyframeModel,
        cancel: Option<&super::CancelCheck>,
    ) -> Result<Frame, SimError> {
        let mut frame = self.close_from_preshape(model, posed, key, cancel)?;
        let hand = frame.hands.iter_mut().find(|h| h.body == key.body);
        if let Some(g) = hand.and_then(|h| h.grasp.as_mut()) {
            let skeleton = &model.bodies[key.body]
                .hand
                .as_deref()
                .expect("a grasp keyframe poses a hand")
                .skeleton;
            g.preshape_pose = skeleton.pose_of(&key.angles);
        }
        Ok(frame)
    }

    /// [`Workspace::close_grip`] but for the outcome's preshape pose.
    fn close_from_preshape(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        key: &KeyframeModel,
        cancel: Option<&super::CancelCheck>,
    ) -> Result<Frame, SimError> {
        let grasp = key.grasp.as_deref().expect("a grasp keyframe");
        let body = key.body;
        let preshape = self.move_hands(model, posed, &[(body, key.angles.clone())], cancel)?;
        let object = Surface::of(model, &preshape, grasp.object);
        let hand = model.bodies[body]
            .hand
            .as_deref()
            .expect("a grasp keyframe poses a hand");
        // Each closing digit's synergy parameter at first contact (None: it never meets; a pose
        // judged as posed closes none).
        let first: Vec<Option<f64>> = grasp
            .digits
            .iter()
            .map(|(d, joints)| {
                grasp
                    .close
                    .then(|| first_contact(model, body, hand, &key.angles, *d, joints, &object))
                    .flatten()
            })
            .collect();
        // Each digit's synergy in degrees of its largest joint turn (from the angles it starts
        // at: a preshape adjusted by the keyframe's pose turns less or more).
        let spans: Vec<f64> = grasp
            .digits
            .iter()
            .map(|(_, joints)| {
                joints
                    .iter()
                    .map(|j| (j.closed - j.open).abs())
                    .fold(0.0, f64::max)
            })
            .collect();
        let angles_at = |theta: f64| -> Vec<f64> {
            let mut angles = key.angles.clone();
            for (((_, joints), s), span) in grasp.digits.iter().zip(&first).zip(&spans) {
                let s = match s {
                    Some(s) if *span > 0.0 => (s + theta / span).clamp(0.0, 1.0),
                    _ => 1.0,
                };
                for j in joints {
                    angles[j.dof] = j.open + s * (j.closed - j.open);
                }
            }
            angles
        };
        let touching: Vec<String> = grasp
            .digits
            .iter()
            .zip(&first)
            .filter(|(_, s)| s.is_some())
            .map(|((d, _), _)| DIGITS[*d].to_string())
            .collect();
        // The largest closing any touching digit can take.
        let theta_max = first
            .iter()
            .zip(&spans)
            .filter_map(|(s, span)| s.map(|s| (1.0 - s) * span))
            .fold(0.0, f64::max);
        // Back to the preshape: the closing at which every touching digit is open again.
        let theta_open = -first
            .iter()
            .zip(&spans)
            .filter_map(|(s, span)| s.map(|s| s * span))
            .fold(0.0, f64::max);

        // A gravity hold is judged with the object let go of (`let_go`): its supports freed,
        // held by the hand alone, the digits' forces balancing among themselves and its weight.
        let release = match grasp.hold {
            HoldTarget::Gravity { .. } => {
                Some(std::cell::RefCell::new(Release::new(model, grasp.object)?))
            }
            HoldTarget::Force(_) => None,
        };
        // A pose solved (`frame`, the hands where `posed` leaves them, the contacts `holding`
        // held by its last step) as a trial: its grip, and for a gravity hold the frame let go
        // of, the friction margin its contacts achieve there (`contact::hold_margin`) and how
        // far the object moved (0 margin where the hand does not hold it).
        let judge = |theta: f64,
                     frame: Frame,
                     posed: Posed,
                     holding: &[usize]|
         -> Result<Trial, SimError> {
            let touching = grip(model, &frame, body, grasp.object).normal_force > 0.0;
            let (frame, released) = match (&release, grasp.hold) {
                (Some(r), HoldTarget::Gravity { .. }) if touching => {
                    let l = r.borrow_mut().let_go(
                        (&frame, &posed, holding),
                        (body, grasp.object),
                        cancel,
                    );
                    match l {
                        Ok(l) => (l.frame, Some(Ok(l.drift.norm()))),
                        Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                        Err(e) => (frame, Some(Err(super::let_go::not_held(&e)))),
                    }
                }
                _ => (frame, None),
            };
            let g = grip(model, &frame, body, grasp.object);
            let margin = match (grasp.hold, &released) {
                (HoldTarget::Gravity { weight }, Some(Ok(_))) => {
                    g.margin(&weight, model.bodies[grasp.object].size)
                }
                _ => 0.0,
            };
            Ok(Trial {
                theta,
                frame,
                posed,
                grip: g.normal_force,
                margin,
                released,
            })
        };
        let count = std::cell::Cell::new(0);
        let search = std::cell::RefCell::new(Vec::new());
        let solve = |ws: &mut Workspace, from: &Posed, theta: f64| -> Result<Trial, SimError> {
            count.set(count.get() + 1);
            let mut p = from.clone();
            let frame = ws.move_hands(model, &mut p, &[(body, angles_at(theta))], cancel)?;
            let t = judge(theta, frame, p, &ws.contact.held)?;
            search.borrow_mut().push(GripTrial {
                closing_deg: theta,
                grip: t.grip,
                margin: t.margin,
                within_thresholds: t.overload(body).is_none(),
            });
            Ok(t)
        };
        // What a hold is measured by (the friction margin let go of, or the grip), and what
        // is asked of it.
        let measure = |t: &Trial| match grasp.hold {
            HoldTarget::Gravity { .. } => t.margin,
            HoldTarget::Force(_) => t.grip,
        };
        let target = match grasp.hold {
            HoldTarget::Gravity { .. } => grasp.margin,
            HoldTarget::Force(f) => f,
        };
        let holds = |t: &Trial| measure(t) >= target;
        let close_enough = |t: &Trial| measure(t) <= target * (1.0 + HOLD_TOLERANCE);
        let overloaded = |t: &Trial| t.overload(body);

        // The preshape (every touching digit open: θ at its most negative) and what it grips.
        let start = judge(
            theta_open,
            preshape,
            posed.clone(),
            &self.contact.held.clone(),
        )?;
        let preshape_grip = start.grip;
        // An animator's own grasp (`close = false`): the pose as posed is the grip, judged.
        if !grasp.close {
            let start = Trial {
                theta: 0.0,
                ..start
            };
            search.borrow_mut().push(GripTrial {
                closing_deg: 0.0,
                grip: start.grip,
                margin: start.margin,
                within_thresholds: start.overload(body).is_none(),
            });
            let reason = short_as_posed(model, (body, grasp), &start, overloaded(&start));
            let touching = digits_touching(model, &start.frame, body);
            return self.finish(
                model,
                posed,
                (body, grasp),
                start,
                &touching,
                (1, search.take(), preshape_grip),
                reason,
            );
        }
        let mut lo = if touching.is_empty() {
            start.clone()
        } else {
            match solve(self, &start.posed, 0.0) {
                Ok(t) => t,
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(e) => {
                    return self.finish(
                        model,
                        posed,
                        (body, grasp),
                        start,
                        &touching,
                        (count.get(), search.take(), preshape_grip),
                        Some(format!(
                            "the digits could not be closed to their first contact: {e}"
                        )),
                    )
                }
            }
        };
        // No grip to search for: no digit touches, a bone past its threshold at first contact
        // (the closing only adds to the reactions), or no friction for a hold against gravity
        // (whatever the grip).
        let early = touching
            .is_empty()
            .then(|| {
                "no digit reaches the object along its synergy: move the object into the hand, \
                 or the hand to it"
                    .to_string()
            })
            .or_else(|| overloaded(&lo).map(|o| overloaded_at_first_contact(&o)))
            .or_else(|| {
                matches!(grasp.hold, HoldTarget::Gravity { .. })
                    .then(|| frictionless(model, body, grasp.object))
                    .flatten()
            });
        if let Some(reason) = early {
            return self.finish(
                model,
                posed,
                (body, grasp),
                lo,
                &touching,
                (count.get(), search.take(), preshape_grip),
                Some(reason),
            );
        }
        // The firmest grip within the bones' thresholds that does not hold; the least closing
        // that holds within them; the least closing past a bone's threshold.
        let mut best = lo.clone();
        let mut hi: Option<Trial> = None;
        let mut ceiling: Option<(Overload, Trial)> = None;
        let mut stop: Option<String> = None;
        // Sorts a pose solved into lo, hi or the ceiling.
        let mut sort = |t: Trial,
                        lo: &mut Trial,
                        hi: &mut Option<Trial>,
                        ceiling: &mut Option<(Overload, Trial)>| {
            if let Some(o) = overloaded(&t) {
                *ceiling = Some((o, t));
            } else if holds(&t) {
                *hi = Some(t);
            } else {
                // (Equal measures, as where nothing holds the object let go of: the firmest.)
                if measure(&t) > measure(&best)
                    || (measure(&t) == measure(&best) && t.grip > best.grip)
                {
                    best = t.clone();
                }
                *lo = t;
            }
        };
        if holds(&lo) {
            hi = Some(lo.clone());
            // First contact is found on the skin the bones carry; the flesh's FEM can press
            // harder there already (the power preshape: 0.075 N where 0.05 N were asked). Then
            // the search bisects back towards the preshape (θ < 0). Where the preshape itself
            // holds (posed into the object: the pinch preshape's thumb, 13.4 N where 3 N were
            // asked), nothing along the synergies is gentler: it is the grip.
            if !close_enough(&lo) && theta_open < 0.0 {
                if holds(&start) {
                    hi = Some(start.clone());
                } else {
                    lo = start.clone();
                }
            }
        }
        // Bracket: double θ until the grip holds or a bone gives out.
        let mut theta = FIRST_THETA;
        while hi.is_none() && ceiling.is_none() && stop.is_none() {
            if lo.theta >= theta_max {
                stop = Some(format!(
                    "the digits closed to the end of their synergies ({:.1}° past first contact) \
                     without holding it",
                    lo.theta,
                ));
                break;
            }
            if count.get() >= MAX_TRIALS {
                stop = Some(format!("no hold within {MAX_TRIALS} poses"));
                break;
            }
            let next = theta.min(theta_max);
            match solve(self, &lo.posed, next) {
                Ok(t) => sort(t, &mut lo, &mut hi, &mut ceiling),
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(e) => {
                    stop = Some(format!(
                        "closing further to {next:.1}° past first contact failed: {e}"
                    ))
                }
            }
            theta *= 2.0;
        }
        // Bisect: the least closing that holds, below the least that overloads a bone.
        loop {
            let upper = match (&hi, &ceiling) {
                (Some(h), _) if close_enough(h) => break,
                (Some(h), _) => h.theta,
                (None, Some((_, c))) => c.theta,
                (None, None) => break,
            };
            if upper - lo.theta <= THETA_TOLERANCE || count.get() >= MAX_TRIALS {
                break;
            }
            let mid = match &hi {
                Some(h) => next_closing(lo.theta, measure(&lo), h.theta, measure(h), target),
                None => 0.5 * (lo.theta + upper),
            };
            match solve(self, &lo.posed, mid) {
                Ok(t) => sort(t, &mut lo, &mut hi, &mut ceiling),
                Err(SimError::Cancelled) => return Err(SimError::Cancelled),
                Err(_) => break,
            }
        }
        if let Some(hi) = hi {
            return self.finish(
                model,
                posed,
                (body, grasp),
                hi,
                &touching,
                (count.get(), search.take(), preshape_grip),
                None,
            );
        }
        // Not held: the firmest grip found within the bones' thresholds, and why.
        let reason = match ceiling {
            Some((o, _)) => overload_reason(&o, grasp, &best),
            None => format!(
                "{}; {}",
                stop.unwrap_or_else(|| "the search ended without a hold".into()),
                firmest(model, grasp, body, &best)
            ),
        };
        self.finish(
            model,
            posed,
            (body, grasp),
            best,
            &touching,
            (count.get(), search.take(), preshape_grip),
            Some(reason),
        )
    }

    /// The frame of the grip `trial` with its outcome; `posed` left where it is.
    #[allow(clippy::too_many_arguments)]
    fn finish(
        &mut self,
        model: &Model,
        posed: &mut Posed,
        (hand, grasp): (usize, &GraspModel),
        trial: Trial,
        touching: &[String],
        (trials, search, preshape_grip): (usize, Vec<GripTrial>, f64),
        reason: Option<String>,
    ) -> Result<Frame, SimError> {
        let Trial {
            theta,
            mut frame,
            posed: p,
            grip,
            margin,
            released,
        } = trial;
        *posed = p;
        let drift = released.as_ref().and_then(|r| r.as_ref().ok().copied());
        let held = reason.is_none()
            && match grasp.hold {
                HoldTarget::Gravity { .. } => drift.is_some() && margin >= grasp.margin,
                HoldTarget::Force(f) => grip >= f,
            };
        let reason = match (held, reason) {
            (true, _) => None,
            (false, Some(r)) => Some(r),
            (false, None) => Some("the search ended without a hold".into()),
        };
        let body = model.bodies[grasp.object].name.clone();
        if let Some(h) = frame.hands.iter_mut().find(|h| h.body == hand) {
            let skeleton = &model.bodies[h.body]
                .hand
                .as_deref()
                .expect("a hand")
                .skeleton;
            h.grasp = Some(GraspOutcome {
                object: body,
                preshape: grasp.preshape.clone(),
                held,
                pose: skeleton.pose_of(&h.angles),
                preshape_pose: std::collections::BTreeMap::new(),
                margin,
                margin_target: matches!(grasp.hold, HoldTarget::Gravity { .. })
                    .then_some(grasp.margin),
                grip,
                force_target: match grasp.hold {
                    HoldTarget::Force(f) => Some(f),
                    HoldTarget::Gravity { .. } => None,
                },
                closing_deg: theta,
                preshape_grip,
                drift,
                digits_touching: touching.to_vec(),
                trials,
                search,
                reason,
                closed: grasp.close,
            });
        }
        Ok(frame)
    }
}

/// Why no grip stays within the thresholds: bone `o` is past its threshold at first contact.
fn overloaded_at_first_contact(o: &Overload) -> String {
    format!(
        "at first contact, before any grip, bone {} already bears {:.3} N, past its threshold of \
         {} N: no grip stays within the thresholds (raise it: bone_thresholds on the hand)",
        o.bone,
        o.reaction,
        crate::util::number::readable(o.threshold)
    )
}

/// Why the pose `t` judged as posed (`close = false`) does not hold (`None`: it holds): a bone
/// past its threshold (`overload`), nothing touched, no friction, the object not held let go
/// of, or a margin or grip short of what is asked.
fn short_as_posed(
    model: &Model,
    (hand, grasp): (usize, &GraspModel),
    t: &Trial,
    overload: Option<Overload>,
) -> Option<String> {
    const CLOSE: &str = "close the digits further, or leave out close = false and the hand closes \
                         to the gentlest grip that holds";
    if let Some(o) = overload {
        return Some(format!(
            "as posed, bone {} bears {:.3} N, past its threshold of {} N: open the digits that \
             press it, or raise the threshold (bone_thresholds on the hand)",
            o.bone,
            o.reaction,
            crate::util::number::readable(o.threshold)
        ));
    }
    if t.grip <= 0.0 {
        return Some(format!("as posed, no digit touches the object: {CLOSE}"));
    }
    match grasp.hold {
        HoldTarget::Gravity { .. } => {
            if let Some(why) = frictionless(model, hand, grasp.object) {
                return Some(why);
            }
            match &t.released {
                Some(Err(why)) => Some(format!("as posed, {why}: {CLOSE}")),
                _ if t.margin < grasp.margin => Some(format!(
                    "as posed, the grip of {:.3} N holds with a margin of {:.2}, short of the {} \
                     asked: {CLOSE}",
                    t.grip,
                    t.margin,
                    crate::util::number::readable(grasp.margin)
                )),
                _ => None,
            }
        }
        HoldTarget::Force(f) if t.grip < f => Some(format!(
            "as posed, the grip is {:.3} N, {:.3} N short of the {} N asked: {CLOSE}",
            t.grip,
            f - t.grip,
            crate::util::number::readable(f)
        )),
        HoldTarget::Force(_) => None,
    }
}

/// The digits of the hand `body` whose bones bear contact forces in `frame`, thumb first.
fn digits_touching(model: &Model, frame: &Frame, body: usize) -> Vec<String> {
    let Some(hand) = frame.hands.iter().find(|h| h.body == body) else {
        return Vec::new();
    };
    let skeleton = &model.bodies[body]
        .hand
        .as_deref()
        .expect("a grasp keyframe poses a hand")
        .skeleton;
    let on = hand.contact_force_by_digit(skeleton);
    DIGITS
        .iter()
        .zip(on)
        .filter(|(_, f)| f.norm() > 0.0)
        .map(|(d, _)| d.to_string())
        .collect()
}

/// Why a bone's overload stops the grip: the bone, its reaction and threshold, and the force
/// the hold still misses from `t`, the firmest grip within the thresholds.
fn overload_reason(o: &Overload, grasp: &GraspModel, t: &Trial) -> String {
    let missing = match grasp.hold {
        HoldTarget::Force(f) => (f - t.grip).max(0.0),
        // The grip needed grows about as the margin asked over the margin achieved.
        HoldTarget::Gravity { .. } if t.margin > 0.0 => {
            (t.grip * (grasp.margin / t.margin - 1.0)).max(0.0)
        }
        HoldTarget::Gravity { .. } => f64::NAN,
    };
    let missing = match (&grasp.hold, &t.released) {
        _ if missing.is_finite() => format!("about {missing:.2} N more grip"),
        // Let go of, the grip does not hold the object at all: what it would have to take.
        (HoldTarget::Gravity { weight }, Some(Err(why))) => format!(
            "a grip that holds its {:.2} N weight ({why})",
            weight.norm()
        ),
        _ => "a grip its contacts cannot give".into(),
    };
    format!(
        "closing further, bone {} would bear {:.3} N, past its threshold of {} N; the firmest \
         grip within the thresholds (shown), {:.2} N at {:.1}° past first contact (margin \
         {:.2}), misses {missing}",
        o.bone,
        o.reaction,
        crate::util::number::readable(o.threshold),
        t.grip,
        t.theta,
        t.margin
    )
}

/// The object's surface where a frame leaves it, for the skin's signed distance to it.
struct Surface {
    mesh: Option<TriMesh>,
}

impl Surface {
    fn of(model: &Model, frame: &Frame, object: usize) -> Surface {
        let u = &frame.solution.displacement;
        let b = &model.bodies[object];
        let mut index = std::collections::HashMap::new();
        let mut points = Vec::new();
        let mut triangles = Vec::new();
        let mut id = |n: usize, points: &mut Vec<Vec3>| -> u32 {
            *index.entry(n).or_insert_with(|| {
                let p = model.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
                points.push(Vec3::new(p.x, p.y, p.z));
                (points.len() - 1) as u32
            })
        };
        for q in &b.exterior {
            let v = q.map(|n| id(n, &mut points));
            triangles.push([v[0], v[1], v[2]]);
            triangles.push([v[0], v[2], v[3]]);
        }
        Surface {
            mesh: TriMesh::with_flags(points, triangles, TriMeshFlags::ORIENTED).ok(),
        }
    }

    /// Signed distance from `p` (negative inside), m; infinite without a surface.
    fn distance(&self, p: &Vector3<f64>) -> f64 {
        let Some(mesh) = &self.mesh else {
            return f64::INFINITY;
        };
        let proj = mesh.project_local_point(Vec3::new(p.x, p.y, p.z), false);
        let q = proj.point;
        let d = ((q.x - p.x).powi(2) + (q.y - p.y).powi(2) + (q.z - p.z).powi(2)).sqrt();
        if proj.is_inside {
            -d
        } else {
            d
        }
    }
}

/// The synergy parameter at which digit `digit`'s skin first meets the object, closing from
/// `angles` along `joints`; `None` when it never does.
fn first_contact(
    model: &Model,
    body: usize,
    hand: &crate::hand::HandModel,
    angles: &[f64],
    digit: usize,
    joints: &[crate::model::ClosingJoint],
    object: &Surface,
) -> Option<f64> {
    let skeleton = &hand.skeleton;
    let skin = &hand.contact_skin;
    let rest = &hand.flesh.mesh.nodes;
    // The digit's skin points: those whose heaviest node follows a phalanx of the digit most
    // (not its metacarpal: a finger's is in the palm, the thumb's under the thenar eminence,
    // which lie on the object before the digit closes at all).
    let bone_of = |n: usize| {
        hand.weights.weights[n]
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|w| w.0)
    };
    let points: Vec<usize> = (0..skin.vertex_count())
        .filter(|&v| {
            let heaviest = skin
                .terms(v)
                .max_by(|a, b| a.1.total_cmp(&b.1))
                .map(|t| t.0);
            heaviest.and_then(bone_of).is_some_and(|b| {
                let bone = &skeleton.bones[b];
                bone.digit == Some(digit) && !bone.name.ends_with(".metacarpal")
            })
        })
        .collect();
    if points.is_empty() {
        return None;
    }
    // The hand's flesh in the model's frame is its rest mesh (the scene places the hand).
    debug_assert_eq!(rest.len(), model.bodies[body].nodes.len());
    let gap = |s: f64| -> f64 {
        let mut a = angles.to_vec();
        for j in joints {
            a[j.dof] = j.open + s * (j.closed - j.open);
        }
        let transforms = skeleton.transforms(&a);
        let mut flesh = rest.clone();
        hand.weights.apply(
            model.flexion.blend,
            &transforms,
            rest,
            0..rest.len(),
            &mut flesh,
        );
        points
            .iter()
            .map(|&v| {
                let p: Vector3<f64> = skin.terms(v).map(|(n, w)| flesh[n] * w).sum();
                object.distance(&p)
            })
            .fold(f64::INFINITY, f64::min)
    };
    if gap(0.0) <= 0.0 {
        return Some(0.0);
    }
    const SCAN: usize = 16;
    let mut before = 0.0;
    for k in 1..=SCAN {
        let s = k as f64 / SCAN as f64;
        if gap(s) <= 0.0 {
            let (mut a, mut b) = (before, s);
            for _ in 0..12 {
                let m = 0.5 * (a + b);
                if gap(m) <= 0.0 {
                    b = m;
                } else {
                    a = m;
                }
            }
            return Some(b);
        }
        before = s;
    }
    None
}

/// The firmest grip found, `t`, in words: how far it is from what was asked, and for a gravity
/// hold what keeps it short — the grip's normal forces do not balance among themselves, so
/// friction must take their resultant as well as the weight: however hard the digits press,
/// the margin stays where their geometry puts it.
fn firmest(model: &Model, grasp: &GraspModel, body: usize, t: &Trial) -> String {
    let weight = match grasp.hold {
        HoldTarget::Force(f) => {
            return format!(
                "the firmest grip found (shown), {:.2} N at {:.1}° past first contact, is {:.2} N \
                 short of the {f} N asked",
                t.grip,
                t.theta,
                (f - t.grip).max(0.0)
            )
        }
        HoldTarget::Gravity { weight } => weight,
    };
    let g = grip(model, &t.frame, body, grasp.object);
    let resultant: Vector3<f64> = g.contacts.iter().map(|c| c.inward * c.normal_force).sum();
    let found = format!(
        "the best grip found (shown), {:.2} N at {:.1}° past first contact, holds with a margin \
         of {:.2} against the {:.2} asked",
        t.grip, t.theta, t.margin, grasp.margin
    );
    let why = match &t.released {
        Some(Err(why)) => format!("; {why}"),
        _ => String::new(),
    };
    // What friction alone would need: the digits' normal forces balancing among themselves (a
    // pinch), friction carries the weight with the margin, μ·Σλ ≥ margin·|W|. A hand cradling
    // the object under it needs less; no grip holds with less where nothing is under it.
    let (mu, _, _) = friction(model, body, grasp.object);
    let needed = (mu > 0.0).then(|| grasp.margin * weight.norm() / mu);
    let alone = if let Some(needed) = needed.filter(|&n| n > t.grip) {
        format!(
            "; held by friction alone (μ = {}), its {:.2} N weight asks a grip of at least \
             margin·weight/μ = {needed:.2} N, {:.2} N more than the best found ({})",
            crate::util::number::readable(mu),
            weight.norm(),
            needed - t.grip,
            most_loaded(model, body, &t.frame)
        )
    } else {
        String::new()
    };
    let told = if resultant.norm() > weight.norm() {
        format!(
            "{found}: the digits' normal forces leave {:.2} N unbalanced, pushing the object \
             against what supports it, and friction would have to take that as well as its \
             {:.2} N weight; place the object between opposing digits, the thumb against the \
             fingers",
            resultant.norm(),
            weight.norm()
        )
    } else {
        found
    };
    format!("{told}{alone}{why}")
}

/// The bone of hand `body` nearest its threshold in `frame`, in words: how far the grip is
/// from what the muscles can give.
fn most_loaded(model: &Model, body: usize, frame: &Frame) -> String {
    let Some(hand) = frame.hands.iter().find(|h| h.body == body) else {
        return "no bone loaded".into();
    };
    let skeleton = &model.bodies[body]
        .hand
        .as_deref()
        .expect("a grasp keyframe poses a hand")
        .skeleton;
    let thresholds = &model.bodies[body].thresholds;
    let share = |b: usize| hand.bone_reactions[b].norm() / thresholds[b];
    match (0..skeleton.bones.len())
        .filter(|&b| thresholds[b] > 0.0)
        .max_by(|&a, &b| share(a).total_cmp(&share(b)))
    {
        Some(b) => format!(
            "no bone at its threshold: the nearest, {}, bears {:.2} N of its {} N",
            skeleton.bones[b].name,
            hand.bone_reactions[b].norm(),
            crate::util::number::readable(thresholds[b])
        ),
        None => "no bone loaded".into(),
    }
}

/// Why no grip holds body `object` against gravity in the hand `hand`'s contacts, if no pair of
/// their materials has friction (`[[region]]`s may give either body several).
fn frictionless(model: &Model, hand: usize, object: usize) -> Option<String> {
    let (mu, a, b) = friction(model, hand, object);
    (mu <= 0.0).then(|| {
        format!(
            "there is no friction between \"{a}\" and \"{b}\" (μ = 0): no grip holds an \
             object against gravity without it; set [[friction]] between = [\"{a}\", \"{b}\"] \
             (skin on rubber: μ ≈ 0.8), or give force = N for a target grip"
        )
    })
}

/// The largest friction coefficient between a material of body `hand` and one of body `object`
/// (`[[region]]`s may give either body several), and the pair's names (the first pair where
/// none has friction).
fn friction(model: &Model, hand: usize, object: usize) -> (f64, &str, &str) {
    let materials = |b: usize| {
        let mut m: Vec<&str> = model.bodies[b]
            .cells
            .clone()
            .map(|c| model.material_name(model.cell_material[c]))
            .collect();
        m.sort_unstable();
        m.dedup();
        m
    };
    let (ours, theirs) = (materials(hand), materials(object));
    let mut best = (0.0, ours[0], theirs[0]);
    for a in &ours {
        for b in &theirs {
            let mu = model.friction_between(a, b);
            if mu > best.0 {
                best = (mu, a, b);
            }
        }
    }
    best
}

/// The next closing to try between `lo` (measure `m_lo`, short of `target`) and `hi` (measure
/// `m_hi`, holding), degrees: where the line between them reaches the middle of the accepted
/// window [target, target·(1 + HOLD_TOLERANCE)] when `lo` has a measure of its own (the grip,
/// or a margin let go of), kept an eighth of the interval from either end (regula falsi,
/// safeguarded); the middle otherwise (a pose the hand did not hold let go of has no margin).
fn next_closing(lo: f64, m_lo: f64, hi: f64, m_hi: f64, target: f64) -> f64 {
    let w = hi - lo;
    if m_lo > 0.0 && m_hi > m_lo {
        let aim = target * (1.0 + 0.5 * HOLD_TOLERANCE);
        let t = lo + (aim - m_lo) / (m_hi - m_lo) * w;
        t.clamp(lo + w / 8.0, hi - w / 8.0)
    } else {
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::next_closing;

    #[test]
    fn the_next_closing_aims_at_the_accepted_window_and_keeps_off_the_ends() {
        // A grip linear in the closing, 0.2 N at 1°, 1.0 N at 2°, 0.6 N asked: the line reaches
        // the window's middle (0.615 N) at 1.519 ° (within a rounding of 1e-12).
        let t = next_closing(1.0, 0.2, 2.0, 1.0, 0.6);
        assert!((t - (1.0 + (0.6 * 1.025 - 0.2) / 0.8)).abs() < 1e-12, "{t}");
        // Near an end, an eighth of the interval away from it.
        assert_eq!(next_closing(1.0, 0.59, 2.0, 5.0, 0.6), 1.125);
        assert_eq!(next_closing(1.0, 0.2, 2.0, 0.6, 0.6), 1.875);
        // No measure at the lower end (not held let go of): the middle.
        assert_eq!(next_closing(1.0, 0.0, 2.0, 1.0, 0.6), 1.5);
    }
}
