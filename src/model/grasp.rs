//! A grasp keyframe (`grasp = { object = "ball", preshape = "power" }`): the object, where the
//! digits start closing and where their synergies end, and what the grip must achieve.

use super::names::shown;
use super::BodyModel;
use crate::hand::synergy::{self, Preshape, DIGITS};
use crate::hand::Skeleton;
use crate::scene::{GraspDef, PreshapeDef};
use nalgebra::Vector3;

/// The default safety factor on the friction a hold needs (grip-force to load-force ratios of
/// human grasping stay 1.2–2 above the slip ratio, Westling & Johansson 1984).
pub const DEFAULT_MARGIN: f64 = 1.5;

/// The largest target grip force, N (beyond every bone's threshold).
const MAX_FORCE: f64 = 1e5;

/// What the grip must achieve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HoldTarget {
    /// Hold the object against its weight (N, the scene's gravity on its mass) by friction,
    /// with the margin.
    Gravity {
        /// The object's weight, N.
        weight: Vector3<f64>,
    },
    /// Press the object with this sum of normal forces, N.
    Force(f64),
}

/// One joint of a closing digit: where it starts and where its synergy ends, degrees.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosingJoint {
    /// The joint (index into the skeleton's dofs).
    pub dof: usize,
    /// Its angle where the closing starts (the keyframe's pose).
    pub open: f64,
    /// Its angle at the synergy's end.
    pub closed: f64,
}

/// A grasp keyframe's closing, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspModel {
    /// The body grasped.
    pub object: usize,
    /// The preshape's name (`"pose"` for a pose table).
    pub preshape: String,
    /// Each closing digit (index into [`DIGITS`]) and its joints.
    pub digits: Vec<(usize, Vec<ClosingJoint>)>,
    /// What the grip must achieve.
    pub hold: HoldTarget,
    /// Safety factor on friction (gravity holds).
    pub margin: f64,
    /// The digits close to the gentlest grip (`false`: the pose is judged as posed).
    pub close: bool,
}

/// The closing of `def` for the hand with `skeleton`, from the angles `angles` (the previous
/// keyframe's), which it sets to the preshape adjusted by the keyframe's own `pose`. `field`
/// names the keyframe in errors.
pub fn grasp(
    def: &GraspDef,
    pose: &crate::hand::Pose,
    keyframe: &str,
    bodies: &[BodyModel],
    gravity: Option<[f64; 3]>,
    skeleton: &Skeleton,
    angles: &mut Vec<f64>,
) -> Result<GraspModel, (String, String)> {
    let field = format!("{keyframe}.grasp");
    let Some(object) = bodies.iter().position(|b| b.name == def.object) else {
        let names: Vec<&str> = bodies
            .iter()
            .filter(|b| b.hand.is_none())
            .map(|b| b.name.as_str())
            .collect();
        return Err((
            format!("{field}.object"),
            format!(
                "no body named \"{}\" (bodies a hand can grasp: {})",
                shown(&def.object),
                super::check::list(&names)
            ),
        ));
    };
    if bodies[object].hand.is_some() {
        return Err((
            format!("{field}.object"),
            format!(
                "\"{}\" is a hand: a hand grasps an object",
                shown(&def.object)
            ),
        ));
    }
    // The preshape's name, the digits that grasp, its angles, and the synergies they close
    // along (a pose table closes every digit as the power grasp does).
    let (name, grasping, start, closing) = match &def.preshape {
        None => (
            "power".to_string(),
            Preshape::Power.grasping(),
            Preshape::Power.pose(),
            Preshape::Power,
        ),
        Some(PreshapeDef::Named(n)) => match Preshape::from_name(n) {
            Some(p) => (n.clone(), p.grasping(), p.pose(), p),
            None => {
                return Err((
                    format!("{field}.preshape"),
                    format!(
                        "unknown preshape \"{}\": use \"power\", \"pinch\", \"tripod\" or a pose \
                         table of joint angles",
                        shown(n)
                    ),
                ))
            }
        },
        Some(PreshapeDef::Pose(p)) => ("pose".to_string(), [true; 5], p.clone(), Preshape::Power),
    };
    *angles = skeleton
        .apply_pose(angles, &start)
        .map_err(|e| (format!("{field}.preshape"), e.to_string()))?;
    *angles = skeleton
        .apply_pose(angles, pose)
        .map_err(|e| (format!("{keyframe}.pose"), e.to_string()))?;
    let hold = match (def.hold.as_deref(), def.force) {
        (Some(_), Some(_)) => {
            return Err((
                format!("{field}.force"),
                "give either hold = \"gravity\" or force = N, not both".into(),
            ))
        }
        (Some(h), None) if h != "gravity" => {
            return Err((
                format!("{field}.hold"),
                format!(
                    "unknown hold \"{}\": use \"gravity\" (or force = N for a target grip)",
                    shown(h)
                ),
            ))
        }
        (_, Some(f)) => {
            if !(f.is_finite() && f > 0.0 && f <= MAX_FORCE) {
                return Err((
                    format!("{field}.force"),
                    format!(
                        "must be a grip force above 0 N and at most {MAX_FORCE:e} N, got {}",
                        crate::util::readable(f)
                    ),
                ));
            }
            HoldTarget::Force(f)
        }
        (_, None) => {
            let g = gravity.map(Vector3::from).unwrap_or_else(Vector3::zeros);
            if g == Vector3::zeros() {
                return Err((
                    format!("{field}.hold"),
                    "a grip holds against gravity, and the scene has none: add [world] gravity = \
                     [0, 0, -9.81], or give force = N for a target grip"
                        .into(),
                ));
            }
            HoldTarget::Gravity {
                weight: g * bodies[object].mass,
            }
        }
    };
    let margin = def.margin.unwrap_or(DEFAULT_MARGIN);
    if !(margin.is_finite() && (1.0..=100.0).contains(&margin)) {
        return Err((
            format!("{field}.margin"),
            format!(
                "must be a safety factor from 1 to 100, got {}",
                crate::util::readable(margin)
            ),
        ));
    }
    let dof = |joint: &str| skeleton.dofs.iter().position(|d| d.name == joint);
    let digits = (0..DIGITS.len())
        .filter(|&d| grasping[d])
        .map(|d| {
            let joints = synergy::synergy(closing, DIGITS[d])
                .into_iter()
                .filter_map(|(joint, _, closed)| {
                    let i = dof(&joint)?;
                    let limits = skeleton.dofs[i].limits;
                    Some(ClosingJoint {
                        dof: i,
                        open: angles[i],
                        closed: closed.clamp(limits.min, limits.max),
                    })
                })
                .collect();
            (d, joints)
        })
        .collect();
    Ok(GraspModel {
        object,
        preshape: name,
        digits,
        hold,
        margin,
        close: def.close.unwrap_or(true),
    })
}

/// A grasp asked for at run time (the viewer's Grasp button): the keyframe that closes hand
/// body `body` of `model`, from its angles `from`, as `def` asks. Errors name the field of
/// `def` at fault.
pub fn grasp_keyframe(
    model: &super::Model,
    body: usize,
    from: &[f64],
    def: &GraspDef,
) -> Result<super::KeyframeModel, String> {
    let hand = model.bodies[body]
        .hand
        .as_deref()
        .ok_or_else(|| format!("body \"{}\" is not a hand", shown(&model.bodies[body].name)))?;
    let mut angles = from.to_vec();
    let grasp = grasp(
        def,
        &crate::hand::Pose::new(),
        "grasp",
        &model.bodies,
        model.gravity.map(|g| [g.x, g.y, g.z]),
        &hand.skeleton,
        &mut angles,
    )
    .map_err(|(field, message)| format!("{field}: {message}"))?;
    Ok(super::KeyframeModel {
        time: 0.0,
        body,
        angles,
        grasp: Some(Box::new(grasp)),
    })
}
