//! A hand built from an animator's rig: its skin mesh and its joints (scene frame, m).
//!
//! The hand's own frame is found from the rig: x along the fingers' proximal phalanges, z the
//! dorsal normal of the plane of x and the knuckle line (index MCP to little MCP; the side decides
//! which way is dorsal), the origin at the wrist joint; then turned as the built-in hand's own
//! axes are turned from the frame the same rule finds on its skeleton (`BuiltinFrame`). In that
//! frame the hand is built as the built-in one is — the skin's mesh as its shape, the flesh
//! lattice, the display and contact skins — and the whole model is then placed back where the rig
//! is. The lattice's lines are laid from the skeleton, not from the skin's bounds: through the
//! point that sits, from the wrist joint and scaled by the hand's size, where the built-in hand's
//! lattice anchor sits from its wrist. So a thumb resting lower, a longer forearm stump or a
//! ring on a finger do not move where the lattice cuts the joints' creases (a bone's reaction
//! depends on that: ±23 % at resolution 1, docs/hand.md), and the built-in hand taken as a rig
//! is meshed on its own lattice.
//!
//! Real rigs are imperfect, and the joints are taken as hints: a joint near the back (or the
//! front) of a finger, or outside it, is moved to 42 % of the finger's thickness from the back
//! along the dorsal normal (where the built-in hand's joints are); the tips are where the skin
//! ends along the last phalanx, less the pulp beyond the bone; finger metacarpals a rig lacks
//! start a third of the way from the wrist to the knuckle; bones are as thick as the built-in
//! hand's in proportion to the flesh around them (`SHAFT_OF_FLESH`). A skin cut short of the
//! wrist (a forearm stump) moves the wrist's cut and the carpus distal with it.

use super::anatomy::{DIGITS, THUMB};
use super::mesh_skin::{Located, MeshSkin, SkinMeshError};
use super::model::HandModel;
use super::rig::RigJoints;
use super::rig_names::{joint_keys, required};
use super::shape::{BuiltinSkin, SkinShape};
use super::skeleton::{Side, Skeleton};
use super::MeshingError;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use std::collections::BTreeMap;

/// A rig as read from a file, in the scene's frame.
#[derive(Clone, Debug, Default)]
pub struct RiggedHand {
    /// Joint positions by joint key (`rig_names::joint_keys`), m.
    pub joints: BTreeMap<String, Vector3<f64>>,
    /// Skin mesh vertices, m.
    pub vertices: Vec<Vector3<f64>>,
    /// Skin mesh triangles.
    pub triangles: Vec<[u32; 3]>,
}

/// Why a rig cannot be a hand.
#[derive(Debug, thiserror::Error)]
pub enum RigError {
    /// Joints it must have and has not.
    #[error("the rig has no joint for {}", .0.join(", "))]
    MissingJoints(Vec<String>),
    /// Joints that coincide, so no frame or bone can be made from them.
    #[error("the rig's joints \"{0}\" and \"{1}\" are at the same place")]
    Coincident(String, String),
    /// Not the size of a hand.
    #[error(
        "the hand is {length_m:.3} m long from the wrist to the middle finger's tip joint: glTF \
         lengths are metres (set the placement's `scale`, e.g. 0.01 for a rig in centimetres)"
    )]
    Size {
        /// Its length, m.
        length_m: f64,
    },
    /// The skin mesh.
    #[error("skin mesh: {0} (scene coordinates)")]
    Skin(#[from] SkinMeshError),
    /// A joint with no finger around it.
    #[error(
        "joint \"{key}\" at {at} is not inside the skin, nor is any of the finger along its dorsal \
         normal: is the skin the rig's, and `side` right?"
    )]
    JointOutside {
        /// The joint.
        key: String,
        /// Where it is (scene).
        at: Located,
    },
    /// The skin ends too near the knuckles.
    #[error(
        "the skin mesh ends {short_mm:.1} mm short of the wrist, too near the knuckles to hold \
         the carpal bones: export the hand with some forearm"
    )]
    Stump {
        /// How far distal of the wrist joint the skin ends, mm.
        short_mm: f64,
    },
    /// The palm's thickness says the rig is of the other side.
    #[error(
        "as a {side} hand the rig's palm would be {back_mm:.1} mm thick behind the metacarpals and \
         {front_mm:.1} mm in front of them (a palm is thicker in front): is it a hand of the \
         other side? {MIRRORED_ADVICE}"
    )]
    Side {
        /// The side asked for.
        side: String,
        /// Flesh behind the metacarpals (dorsal for that side), mm.
        back_mm: f64,
        /// Flesh in front (palmar for that side), mm.
        front_mm: f64,
    },
    /// The thumb on the back of the hand: the rig is the other side's geometry under this side's
    /// names.
    #[error(
        "as a {side} hand the rig's thumb lies {behind_mm:.1} mm behind the plane of its knuckles, \
         on the back of the hand (a thumb rests in front of the palm): the rig is a hand of the \
         other side, or mirrored (a negative scale on one of its nodes), or its digits' names are \
         swapped. {MIRRORED_ADVICE}"
    )]
    Mirrored {
        /// The side asked for.
        side: String,
        /// How far behind the knuckles' plane the thumb's last joint lies, mm.
        behind_mm: f64,
    },
    /// The thumb on the little finger's side of the index finger.
    #[error(
        "the rig's thumb MCP joint lies {across_mm:.1} mm on the little finger's side of the index \
         finger's MCP joint (a thumb is beside the index finger): are the digits' joints named \
         for other digits? Name each digit's nodes for its own digit"
    )]
    ThumbAcross {
        /// How far towards the little finger of the index MCP the thumb's MCP lies, mm.
        across_mm: f64,
    },
    /// A skin reaching far beyond a hand.
    #[error(
        "the skin mesh reaches {reach_mm:.1} mm from the wrist joint, at {at}, {times:.1} times \
         the hand's length ({length_mm:.1} mm from the wrist to the middle finger's tip): a stray \
         vertex, or more than a hand in the mesh. Mend the vertex, or export the hand's skin \
         alone (a forearm is cut at the wrist)"
    )]
    Reach {
        /// The skin's point farthest from the wrist (scene).
        at: Located,
        /// How far it is from the wrist joint, mm.
        reach_mm: f64,
        /// The hand's length, mm.
        length_mm: f64,
        /// Their ratio.
        times: f64,
    },
    /// A lattice too large for the memory.
    #[error(
        "the hand's lattice at this resolution would span {cells:.3e} cells; a resolution of \
         {resolution:.2} or less fits"
    )]
    TooFine {
        /// Lattice cells over the skin's bounds.
        cells: f64,
        /// The largest resolution that fits.
        resolution: f64,
    },
    /// The lattice.
    #[error("{0}")]
    Meshing(#[from] MeshingError),
}

/// Shaft radius over the distance from the bone's axis to the skin at its middle, per bone of a
/// digit (metacarpal first): the built-in hand's ratios (its bones against its skin), so that an
/// imported hand's bones fill its fingers as the built-in hand's fill its own.
const SHAFT_OF_FLESH: [[f64; 4]; 2] = [[0.40, 0.41, 0.39, 0.0], [0.32, 0.475, 0.453, 0.426]];

/// What to do with a rig whose geometry is the other side's: the side is read from its nodes'
/// names, so renaming alone or setting `side` alone does not fix it.
const MIRRORED_ADVICE: &str = "A rig's side is read from its node names: undo the mirroring \
     (a scale of -1 on a node), or give a left hand a left hand's node names and `side = \"left\"` \
     (a right hand likewise)";

/// How far behind the knuckles' plane, over the wrist-to-knuckle length, the thumb's last joint
/// may lie before the rig is taken for the other side's (the built-in hand's thumb lies 15 mm
/// (simple form) and 40 mm (anatomical) in front of it, 0.15 and 0.41 of that length; a thumb in
/// the palm's plane, as some rigs rest it, lies on it).
const THUMB_BEHIND: f64 = 0.05;

/// How far to the little finger's side of the index MCP, over the wrist-to-knuckle length, the
/// thumb's MCP may lie (the built-in hand's lies 24 mm (simple) and 21 mm (anatomical), 0.25 and
/// 0.22 of that length, on the thumb's side).
const THUMB_ACROSS: f64 = 0.1;

/// How far the skin (distal of the wrist's cut) may reach from the wrist joint, over the hand's
/// length from the wrist to the middle finger's tip (the built-in hand's skin reaches 1.02 times
/// it; fingers spread, a thumb abducted, a palm turned by the rig's rest pose stay well within 2).
const MAX_REACH: f64 = 2.0;

/// The most lattice cells (inside the skin or not) an imported hand's flesh is meshed from:
/// four times the built-in hand's box at resolution 4 (≈ 4 M).
const MAX_LATTICE: f64 = 1.6e7;

/// Flesh beyond the end of the distal phalanx at the built-in hand's size, m.
const TIP_PAD: f64 = 0.0035;

/// How far outside its finger's skin a rig's joint may lie, at the built-in hand's size, before
/// its move into the finger is told, m.
const OUTSIDE_TOLD: f64 = 0.001;

/// Where a joint sits across its finger: its distance from the back over the finger's thickness.
const JOINT_DEPTH: f64 = 0.42;

/// The built-in hand's length from the wrist joint to the middle finger's MCP, about, m (the
/// imported hand's heuristics scale by it; its size is measured against the exact length,
/// `BuiltinFrame::wrist_to_middle_mcp`).
const WRIST_TO_MIDDLE_MCP: f64 = 0.0974;

impl HandModel {
    /// The hand of `side` whose skin and joints are `rig`, meshed at `resolution`.
    pub fn from_rig(side: Side, rig: &RiggedHand, resolution: f64) -> Result<HandModel, RigError> {
        HandModel::from_rig_within(side, rig, resolution, 1, None)
    }

    /// [`HandModel::from_rig`] with every cell of its lattice split into `subdivisions`³
    /// ([`super::subdivide`]: the nested refinement, whose hand stays that of the lattice),
    /// refused when meshing it would take more than `max_memory` bytes (or what the machine
    /// has free).
    pub fn from_rig_within(
        side: Side,
        rig: &RiggedHand,
        resolution: f64,
        subdivisions: usize,
        max_memory: Option<u64>,
    ) -> Result<HandModel, RigError> {
        let missing: Vec<String> = joint_keys()
            .into_iter()
            .filter(|k| required(k) && !rig.joints.contains_key(k))
            .collect();
        if !missing.is_empty() {
            return Err(RigError::MissingJoints(missing));
        }
        let reference = BuiltinFrame::of(side);
        let found = hand_frame(side, &rig.joints)?;
        let frame = Isometry3::from_parts(found.translation, found.rotation * reference.turn);
        let to_hand = frame.inverse();
        let joint = |k: &str| {
            rig.joints
                .get(k)
                .map(|p| to_hand * nalgebra::Point3::from(*p))
                .map(|p| p.coords)
        };
        let scale = joint("middle.proximal").unwrap().norm() / reference.wrist_to_middle_mcp;
        let tip_len = (joint("middle.proximal").unwrap() - joint("middle.distal").unwrap()).norm();
        let length = joint("middle.distal").unwrap().x + tip_len * 0.4;
        if !(0.08..=0.4).contains(&length) {
            return Err(RigError::Size { length_m: length });
        }
        check_chirality(side, &joint, scale)?;
        let vertices: Vec<Vector3<f64>> = rig
            .vertices
            .iter()
            .map(|p| (to_hand * nalgebra::Point3::from(*p)).coords)
            .collect();
        let to_scene = |p: Vector3<f64>| (frame * nalgebra::Point3::from(p)).coords;
        let (skin, cut) = cut_skin(&vertices, &rig.triangles, scale)
            .map_err(|e| e.map_skin(|err| err.mapped(to_scene)))?;
        let wrist = joint("wrist").unwrap();
        check_side(
            &skin,
            side,
            (joint("middle.proximal").unwrap() + wrist) / 2.0,
            scale,
        )?;
        let (far, reach) = skin.farthest_from(&wrist);
        if reach > MAX_REACH * length {
            return Err(RigError::Reach {
                at: Located(to_scene(far)),
                reach_mm: reach * 1e3,
                length_mm: length * 1e3,
                times: reach / length,
            });
        }
        check_lattice(&skin, resolution)?;

        // Joints in the hand frame, of a right hand (a left one mirrored in y).
        let mirror = |p: Vector3<f64>| match side {
            Side::Right => p,
            Side::Left => Vector3::new(p.x, -p.y, p.z),
        };
        let mut digits: [Vec<Vector3<f64>>; 5] = Default::default();
        let mut moved = Vec::new();
        for (d, name) in DIGITS.iter().enumerate() {
            digits[d] =
                digit_joints(&skin, d, name, &joint, scale, &mut moved).map_err(|(key, p)| {
                    RigError::JointOutside {
                        key,
                        at: Located(to_scene(p)),
                    }
                })?;
        }
        let mended: Vec<String> = moved
            .into_iter()
            .map(|(key, from, to, outside)| {
                format!(
                    "the rig's joint \"{key}\" at {} lies {:.1} mm outside its finger's skin: \
                     taken {:.1} mm from there, inside the finger at {} (is the joint where the \
                     rig's finger bends?)",
                    Located(to_scene(from)),
                    outside * 1e3,
                    (to - from).norm() * 1e3,
                    Located(to_scene(to)),
                )
            })
            .collect();
        let shafts = digits
            .clone()
            .map(|points| shafts_of(&skin, &points, scale));
        let (centre, half) = carpus(&digits, wrist, cut, scale);
        let joints = RigJoints {
            carpus: (mirror(centre), half, UnitQuaternion::identity()),
            digits: digits.map(|points| points.into_iter().map(mirror).collect()),
            shafts,
            thumb_pronation_deg: THUMB.pronation_deg,
        };
        let skeleton = Skeleton::from_joints(side, &joints);
        let skin = skin.with_lattice_anchor(reference.anchor * scale);
        let hand = HandModel::build_nested(
            skeleton,
            SkinShape::Mesh(Box::new(skin)),
            resolution,
            subdivisions,
            max_memory,
            Vector3::zeros(),
        )?;
        let mut hand = hand.placed(&frame);
        hand.mended = mended;
        Ok(hand)
    }

    /// The hand moved rigidly by `motion` (from its own frame to the scene's).
    pub fn placed(mut self, motion: &Isometry3<f64>) -> HandModel {
        let p = |v: &mut Vector3<f64>| *v = (motion * nalgebra::Point3::from(*v)).coords;
        for bone in &mut self.skeleton.bones {
            p(&mut bone.start);
            p(&mut bone.end);
            if let Some((c, _)) = &mut bone.cup {
                p(c);
            }
            if let super::BoneShape::Block { axes, .. } = &mut bone.shape {
                *axes = motion.rotation * *axes;
            }
        }
        for dof in &mut self.skeleton.dofs {
            p(&mut dof.center);
            dof.axis = motion.rotation * dof.axis;
        }
        self.flesh.mesh.nodes.iter_mut().for_each(p);
        self.flesh.display_vertices.iter_mut().for_each(p);
        self
    }
}

impl RigError {
    /// The error with its skin-mesh error mapped by `f`.
    fn map_skin(self, f: impl FnOnce(SkinMeshError) -> SkinMeshError) -> RigError {
        match self {
            RigError::Skin(e) => RigError::Skin(f(e)),
            other => other,
        }
    }
}

/// The skin of `triangles` over `vertices` (hand frame) cut at the wrist, 4 mm proximal of the
/// wrist joint at the built-in hand's size, or just distal of a forearm stump's rim; and the cut's
/// x.
fn cut_skin(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
    scale: f64,
) -> Result<(MeshSkin, f64), RigError> {
    let cut = -0.004 * scale;
    // Sheets that graze each other are let be: fingers modelled touching overlap a little
    // (the built-in hand's own display skin crosses itself up to 2.4 mm deep where the ring
    // and little fingers touch, at resolution 0.75), and change which cells are flesh only
    // in that sliver; a finger through another or through the palm goes deeper than a
    // quarter of a finger's thickness (4 mm at the built-in hand's size).
    let tolerance = 0.004 * scale;
    match MeshSkin::new(vertices, triangles, cut, tolerance) {
        Err(SkinMeshError::Hole {
            at,
            reach_x,
            across_mm,
            ..
        }) if at.0.x < 0.6 * WRIST_TO_MIDDLE_MCP * scale
            && across_mm > 250.0 * WRIST_TO_MIDDLE_MCP * scale =>
        {
            // An opening across the proximal 60 % of the palm (wider than a quarter of the
            // wrist-to-knuckle length) is the end of a forearm stump that stops distal of the
            // cut: cut distal of its rim.
            let cut = reach_x + 0.001 * scale;
            if cut > 0.2 * WRIST_TO_MIDDLE_MCP * scale {
                return Err(RigError::Stump {
                    short_mm: reach_x * 1000.0,
                });
            }
            Ok((MeshSkin::new(vertices, triangles, cut, tolerance)?, cut))
        }
        other => Ok((other?, cut)),
    }
}

/// The side: the palm is thicker in front of the metacarpals than behind them (the built-in
/// hand: 15 mm against 11 mm at `mid`, midway from the wrist to the knuckles); a rig of the other
/// side has its front where this side's back is.
fn check_side(skin: &MeshSkin, side: Side, mid: Vector3<f64>, scale: f64) -> Result<(), RigError> {
    if let (Some(back), Some(front)) = (
        skin.ray(&mid, &Vector3::z(), 0.1 * scale),
        skin.ray(&mid, &-Vector3::z(), 0.1 * scale),
    ) {
        if back > 1.15 * front {
            return Err(RigError::Side {
                side: format!("{side:?}").to_lowercase(),
                back_mm: back * 1e3,
                front_mm: front * 1e3,
            });
        }
    }
    Ok(())
}

/// The rig's handedness from its skeleton alone: the thumb rests in front of the palm, not on
/// its back, and beside the index finger, not beyond it. A rig of the other side's geometry under
/// this side's names (a left hand renamed, or any rig under a negative scale) would otherwise be
/// built with its palm taken for its back, and flex backwards; the palm's thickness
/// (`check_side`) does not tell the anatomical hand's sides apart.
fn check_chirality(
    side: Side,
    joint: &impl Fn(&str) -> Option<Vector3<f64>>,
    scale: f64,
) -> Result<(), RigError> {
    let j = |k: &str| joint(k).expect("the required joints are there");
    let length = WRIST_TO_MIDDLE_MCP * scale;
    // Towards the thumb: +y for a right hand, -y for a left one (the hand frame is a right
    // hand's mirrored).
    let towards_thumb = match side {
        Side::Right => 1.0,
        Side::Left => -1.0,
    };
    let across = towards_thumb * (j("index.proximal").y - j("thumb.proximal").y);
    if across > THUMB_ACROSS * length {
        return Err(RigError::ThumbAcross {
            across_mm: across * 1e3,
        });
    }
    let knuckles_z = (j("index.proximal").z + j("little.proximal").z) / 2.0;
    let behind = j("thumb.distal").z - knuckles_z;
    if behind > THUMB_BEHIND * length {
        return Err(RigError::Mirrored {
            side: format!("{side:?}").to_lowercase(),
            behind_mm: behind * 1e3,
        });
    }
    Ok(())
}

/// The lattice over the skin's bounds, refused before it is allocated when it is more than four
/// times the built-in hand's at resolution 4.
fn check_lattice(skin: &MeshSkin, resolution: f64) -> Result<(), RigError> {
    let (lo, hi) = skin.bounds();
    let cells = |resolution: f64| -> f64 {
        let h = super::BASE_SPACING / resolution;
        (hi - lo).iter().map(|e| (e / h).ceil() + 1.0).product()
    };
    let lattice = cells(resolution);
    if lattice > MAX_LATTICE {
        // The largest resolution that fits, by bisection on the count itself (a cube-root guess
        // can miss: the count is of whole cells).
        let (mut fits, mut not) = (0.0, resolution);
        for _ in 0..50 {
            let mid = (fits + not) / 2.0;
            if cells(mid) <= MAX_LATTICE {
                fits = mid;
            } else {
                not = mid;
            }
        }
        return Err(RigError::TooFine {
            cells: lattice,
            resolution: (fits * 100.0).floor() / 100.0,
        });
    }
    Ok(())
}

/// Digit `d`'s joint points (hand frame) from its carpometacarpal joint to its tip: the rig's
/// joints (`joint`), a missing finger metacarpal a third of the way from the wrist to the
/// knuckle, the others centred in their finger, the tip where the skin ends along the last
/// phalanx less the pulp. A joint with no finger around it is an error: its key and where it is.
fn digit_joints(
    skin: &MeshSkin,
    d: usize,
    name: &str,
    joint: &impl Fn(&str) -> Option<Vector3<f64>>,
    scale: f64,
    moved: &mut Vec<(String, Vector3<f64>, Vector3<f64>, f64)>,
) -> Result<Vec<Vector3<f64>>, (String, Vector3<f64>)> {
    let wrist = joint("wrist").unwrap();
    let parts: &[&str] = if d == 0 {
        &["metacarpal", "proximal", "distal"]
    } else {
        &["metacarpal", "proximal", "middle", "distal"]
    };
    let mut points: Vec<Vector3<f64>> = Vec::new();
    for part in parts {
        let key = format!("{name}.{part}");
        let p = match joint(&key) {
            Some(p) => p,
            // A finger metacarpal the rig lacks.
            None => wrist + (joint(&format!("{name}.proximal")).unwrap() - wrist) / 3.0,
        };
        // The CMC joints sit in the palm; the others are centred in their finger.
        let p = if *part == "metacarpal" {
            p
        } else {
            let previous = points.last().copied().unwrap_or(wrist);
            let q = centred(skin, p, p - previous, scale).ok_or((key.clone(), p))?;
            // A joint outside its finger by more than a millimetre (at the built-in hand's
            // size) is told: a rig's joints sit inside their fingers.
            let outside = skin.distance(&p);
            if outside > OUTSIDE_TOLD * scale {
                moved.push((key, p, q, outside));
            }
            q
        };
        points.push(p);
    }
    let last = points[points.len() - 1];
    let dir = match joint(&format!("{name}.tip")) {
        Some(t) if (t - last).norm() > 1e-6 => (t - last).normalize(),
        _ => (last - points[points.len() - 2]).normalize(),
    };
    let reach = skin.ray(&last, &dir, 0.1 * scale).unwrap_or(0.0);
    points.push(last + dir * (reach - TIP_PAD * scale).max(0.3 * reach));
    Ok(points)
}

/// The shaft radius of each bone between consecutive `points` of a digit (thumb: four points),
/// from the flesh around its middle ([`SHAFT_OF_FLESH`]), m.
fn shafts_of(skin: &MeshSkin, points: &[Vector3<f64>], scale: f64) -> Vec<f64> {
    let kind = usize::from(points.len() != 4);
    (0..points.len() - 1)
        .map(|k| {
            let mid = (points[k] + points[k + 1]) / 2.0;
            let flesh = -skin.distance(&mid);
            (SHAFT_OF_FLESH[kind][k.min(3)] * flesh.max(0.0)).max(0.0005 * scale)
        })
        .collect()
}

/// The carpus block (centre, half extents; hand frame): from the wrist (or just distal of the
/// cut) to the finger metacarpals' bases, as wide as they spread.
fn carpus(
    digits: &[Vec<Vector3<f64>>; 5],
    wrist: Vector3<f64>,
    cut: f64,
    scale: f64,
) -> (Vector3<f64>, [f64; 3]) {
    let bases: Vec<Vector3<f64>> = (1..5).map(|d| digits[d][0]).collect();
    let x0 = wrist.x.max(cut + 0.002 * scale);
    let x1 = bases.iter().map(|b| b.x).fold(f64::INFINITY, f64::min) - 0.001 * scale;
    let (y0, y1) = bases
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.y), b.max(p.y))
        });
    let z = bases.iter().map(|b| b.z).sum::<f64>() / 4.0 - 0.002 * scale;
    let half = [
        ((x1 - x0) / 2.0).max(0.004 * scale),
        (y1 - y0) / 2.0 + 0.005 * scale,
        0.0055 * scale,
    ];
    (Vector3::new((x0 + x1) / 2.0, (y0 + y1) / 2.0, z), half)
}

/// How the built-in hand's own axes and lattice sit in the frame [`hand_frame`] finds on its
/// skeleton at rest.
struct BuiltinFrame {
    /// From the found frame's axes to the built-in hand's (a rotation applied in the found frame).
    turn: UnitQuaternion<f64>,
    /// The built-in hand's lattice anchor from its wrist joint, in its own axes (a right hand's
    /// frame, as lattice anchors are), m.
    anchor: Vector3<f64>,
    /// Its length from the wrist joint to the middle finger's MCP, m ([`WRIST_TO_MIDDLE_MCP`]
    /// exactly: an imported hand's size is measured against it, so that the built-in hand taken
    /// as a rig is of size 1 to round-off and meshed on the built-in hand's lattice).
    wrist_to_middle_mcp: f64,
}

impl BuiltinFrame {
    fn of(side: Side) -> BuiltinFrame {
        let skeleton = Skeleton::new(side);
        let joints: BTreeMap<String, Vector3<f64>> = joint_keys()
            .into_iter()
            .filter_map(|k| skeleton.joint_point(&k).map(|p| (k, p)))
            .collect();
        let found = hand_frame(side, &joints).expect("the built-in skeleton has a frame");
        let wrist = joints["wrist"];
        // Anchors are in a right hand's frame: a left hand's wrist mirrored back in y (the
        // built-in left hand is the right one mirrored).
        let wrist_right = match side {
            Side::Right => wrist,
            Side::Left => Vector3::new(wrist.x, -wrist.y, wrist.z),
        };
        BuiltinFrame {
            turn: found.rotation.inverse(),
            anchor: BuiltinSkin::lattice_anchor() - wrist_right,
            wrist_to_middle_mcp: (joints["middle.proximal"] - wrist).norm(),
        }
    }
}

/// The hand's frame in the scene: origin at the wrist joint, x along the fingers' proximal
/// phalanges, z dorsal.
fn hand_frame(
    side: Side,
    joints: &BTreeMap<String, Vector3<f64>>,
) -> Result<Isometry3<f64>, RigError> {
    let j = |k: &str| joints[k];
    let mut x = Vector3::zeros();
    for f in &DIGITS[1..] {
        let (a, b) = (format!("{f}.proximal"), format!("{f}.middle"));
        if (j(&b) - j(&a)).norm() < 1e-9 {
            return Err(RigError::Coincident(a, b));
        }
        x += (j(&b) - j(&a)).normalize();
    }
    let across = j("index.proximal") - j("little.proximal");
    let z = match side {
        Side::Right => x.cross(&across),
        Side::Left => across.cross(&x),
    };
    if x.norm() < 1e-9 || z.norm() < 1e-12 {
        return Err(RigError::Coincident(
            "index.proximal".into(),
            "little.proximal".into(),
        ));
    }
    let x = x.normalize();
    let z = z.normalize();
    let y = z.cross(&x);
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
        Matrix3::from_columns(&[x, y, z]),
    ));
    Ok(Isometry3::from_parts(
        Translation3::from(j("wrist")),
        rotation,
    ))
}

/// `p` moved along the dorsal normal of its bone (`along`: the bone's direction) to
/// [`JOINT_DEPTH`] of the finger's thickness from its back, when it lies outside the finger or
/// nearer its back or front than a quarter of its thickness; `None` when no finger is found
/// within 3 cm along that normal.
fn centred(
    skin: &MeshSkin,
    p: Vector3<f64>,
    along: Vector3<f64>,
    scale: f64,
) -> Option<Vector3<f64>> {
    let z = Vector3::z();
    let d = along.try_normalize(1e-12).unwrap_or(Vector3::x());
    let n = (z - d * z.dot(&d)).try_normalize(1e-9).unwrap_or(z);
    let reach = 0.03 * scale;
    // The interval [a, b] of the line p + t·n inside the skin nearest p.
    let (a, b) = if skin.distance(&p) < 0.0 {
        (-skin.ray(&p, &-n, reach)?, skin.ray(&p, &n, reach)?)
    } else {
        let mut best: Option<(f64, f64)> = None;
        for s in [1.0, -1.0] {
            let dir = n * s;
            if let Some(t) = skin.ray(&p, &dir, reach) {
                let inside = p + dir * (t + 1e-7);
                if let Some(u) = skin.ray(&inside, &dir, reach) {
                    let (lo, hi) = if s > 0.0 { (t, t + u) } else { (-(t + u), -t) };
                    if best.is_none_or(|(bl, bh)| lo.abs().min(hi.abs()) < bl.abs().min(bh.abs())) {
                        best = Some((lo, hi));
                    }
                }
            }
        }
        best?
    };
    let thickness = b - a;
    if a < -0.25 * thickness && b > 0.25 * thickness {
        return Some(p);
    }
    Some(p + n * (b - JOINT_DEPTH * thickness))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::BoneShape;

    #[test]
    fn the_shaft_ratios_are_the_builtin_hands() {
        let skeleton = Skeleton::new(Side::Right);
        let skin = SkinShape::new(Side::Right);
        for (d, name) in DIGITS.iter().enumerate() {
            let parts: &[&str] = if d == 0 {
                &["metacarpal", "proximal", "distal"]
            } else {
                &["metacarpal", "proximal", "middle", "distal"]
            };
            for (k, part) in parts.iter().enumerate() {
                let bone = &skeleton.bones[skeleton.bone_index(&format!("{name}.{part}")).unwrap()];
                let BoneShape::Long { shaft, .. } = bone.shape else {
                    panic!()
                };
                let flesh = -skin.distance(&((bone.start + bone.end) / 2.0));
                let table = SHAFT_OF_FLESH[usize::from(d > 0)][k];
                let ratio = shaft / flesh;
                assert!(
                    (ratio / table - 1.0).abs() < 0.12,
                    "{name}.{part}: {ratio:.3} against {table}"
                );
            }
        }
    }
}
