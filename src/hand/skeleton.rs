//! The skeleton: rigid bones in a tree, joint angles (degrees) with anatomical limits, and forward
//! kinematics from a pose to one rigid motion per bone (rest frame → posed frame).

use super::anatomy::{limits, Limits, CONDYLE_RATIO, DIGITS, JOINT_GAP};
use super::rig::RigJoints;
use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use std::collections::BTreeMap;
use thiserror::Error;

/// Which hand.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Right hand (thumb towards +y).
    Right,
    /// Left hand (mirror image in y).
    Left,
}

/// The geometric kind of a bone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BoneShape {
    /// A long bone from `start` to `end`: shaft with condyles (wider heads) at both ends; a distal
    /// phalanx ends in a narrower tuft instead.
    Long {
        /// Shaft radius, m.
        shaft: f64,
        /// Is it a distal phalanx (tuft at the end)?
        distal: bool,
    },
    /// The carpus: a rounded block with these half extents, m, along its axes.
    Block {
        /// Half extents.
        half: [f64; 3],
        /// Rotation of the block's axes from the hand frame's (rest).
        axes: UnitQuaternion<f64>,
    },
}

/// One rigid bone.
#[derive(Clone, Debug)]
pub struct Bone {
    /// Name, e.g. `index.distal`.
    pub name: String,
    /// Digit (0 = thumb … 4 = little), `None` for the carpus.
    pub digit: Option<usize>,
    /// Parent bone, `None` for the root.
    pub parent: Option<usize>,
    /// Proximal joint centre (rest), m.
    pub start: Vector3<f64>,
    /// Distal end (rest), m.
    pub end: Vector3<f64>,
    /// Shape.
    pub shape: BoneShape,
    /// For a bone hinged on a long bone: the centre of the parent's head (the hinge) and the
    /// radius of the articular cup the base of this bone forms around that head.
    pub cup: Option<(Vector3<f64>, f64)>,
}

impl Bone {
    /// Signed distance from `p` (rest frame) to the bone's surface, m (negative inside).
    pub fn distance(&self, p: &Vector3<f64>) -> f64 {
        match self.shape {
            BoneShape::Block { half, axes } => {
                let c = (self.start + self.end) / 2.0;
                let r = 0.004;
                let q = (axes.inverse_transform_vector(&(p - c))).abs()
                    - (Vector3::from(half) - Vector3::repeat(r));
                q.sup(&Vector3::zeros()).norm() + q.max().min(0.0) - r
            }
            BoneShape::Long { shaft, distal } => {
                let axis = self.end - self.start;
                let len = axis.norm();
                let dir = axis / len;
                if let Some((c, inner)) = self.cup {
                    // A base cupped around the parent's head: a round cone from the hinge to
                    // the distal end, less the head (and joint space), on the distal side.
                    let r1 = long_bone_radius(1.0, shaft, distal);
                    let base = cup_radius(inner, shaft);
                    let b = self.end - dir * (JOINT_GAP + r1);
                    let l = (b - c).norm();
                    let s = (p - c).dot(&dir);
                    let t = (s / l).clamp(0.0, 1.0);
                    let along = (s / len).clamp(0.0, 1.0);
                    let r = if t <= 0.0 {
                        base
                    } else if t >= 1.0 {
                        r1
                    } else {
                        long_bone_radius(along, shaft, distal).max(base * (1.0 - t / 0.35))
                    };
                    let cone = (p - (c + dir * (t * l))).norm() - r;
                    return cone.max(-s).max(inner - (p - c).norm());
                }
                // The rounded ends stop at the joint spaces: the segment is inset by the end
                // radii, so neighbouring bones never overlap.
                let r0 = long_bone_radius(0.0, shaft, distal);
                let r1 = long_bone_radius(1.0, shaft, distal);
                let a = self.start + dir * (JOINT_GAP + r0);
                let l = (len - 2.0 * JOINT_GAP - r0 - r1).max(1e-6);
                let s = (p - a).dot(&dir);
                let t = (s / l).clamp(0.0, 1.0);
                let along = ((s + r0) / len).clamp(0.0, 1.0);
                let radius = long_bone_radius(along, shaft, distal);
                let r = if t <= 0.0 {
                    r0
                } else if t >= 1.0 {
                    r1
                } else {
                    radius
                };
                (p - (a + dir * (t * l))).norm() - r
            }
        }
    }

    /// Length of the bone (joint to joint), m.
    pub fn length(&self) -> f64 {
        (self.end - self.start).norm()
    }
}

/// Outer radius of a bone's base cupped around a head of radius `inner` (the cup's inner
/// radius), m: a shell of cortical bone about 0.5 mm thick, never narrower than the condyles.
pub fn cup_radius(inner: f64, shaft: f64) -> f64 {
    (inner + 0.0005).max(shaft * CONDYLE_RATIO)
}

/// Radius of a long bone at the fraction `t` of its length: condyles of [`CONDYLE_RATIO`] × the
/// shaft at the ends, blending into the shaft over a fifth of the length; a distal phalanx ends in
/// a tuft only slightly wider than its shaft.
pub fn long_bone_radius(t: f64, shaft: f64, distal: bool) -> f64 {
    let bump = |s: f64| {
        let s = (s / 0.22).clamp(0.0, 1.0);
        (1.0 - s) * (1.0 - s)
    };
    let head = shaft * CONDYLE_RATIO;
    let tail = if distal { shaft * 1.25 } else { head };
    shaft + (head - shaft) * bump(t) + (tail - shaft) * bump(1.0 - t)
}

/// One joint angle (degree of freedom): rotation of `bone` (and its descendants) about `axis`
/// through `center`, relative to its parent.
#[derive(Clone, Debug)]
pub struct JointDof {
    /// Name, e.g. `index.mcp.flex`.
    pub name: String,
    /// The bone it moves.
    pub bone: usize,
    /// Centre of rotation (rest), m.
    pub center: Vector3<f64>,
    /// Unit axis (rest frame); a positive angle is flexion (or abduction).
    pub axis: Unit<Vector3<f64>>,
    /// Range, degrees.
    pub limits: Limits,
    /// The angle at the skeleton's rest geometry, degrees (0 but for a rest pose that is not
    /// the joints' zero: the anatomical hand's thumb, `HandForm`). Angles are counted from the
    /// joints' zero; the bones move by the angle less this.
    pub rest: f64,
}

/// A pose: joint angles by name, in degrees. Joints not named keep their previous angle.
pub type Pose = BTreeMap<String, f64>;

/// What is wrong with a pose.
#[derive(Debug, Error, PartialEq)]
pub enum PoseError {
    /// No such joint.
    #[error(
        "there is no joint \"{}\"; the joints are: {known}",
        crate::util::shown(name)
    )]
    UnknownJoint {
        /// The name given.
        name: String,
        /// All joint names.
        known: String,
    },
    /// Outside the anatomical range.
    #[error(
        "joint \"{name}\": {}° is outside its range {min}° … {max}°",
        crate::util::readable(*angle)
    )]
    OutOfRange {
        /// The joint.
        name: String,
        /// The angle asked for.
        angle: f64,
        /// Smallest angle.
        min: f64,
        /// Largest angle.
        max: f64,
    },
}

/// The hand skeleton: 20 bones (the carpus, five metacarpals, fourteen phalanges) and 21 joint
/// angles.
#[derive(Clone, Debug)]
pub struct Skeleton {
    /// Which hand.
    pub side: Side,
    /// Bones, parents before children.
    pub bones: Vec<Bone>,
    /// Joint angles, in order of application (abduction before flexion at a joint).
    pub dofs: Vec<JointDof>,
}

impl Skeleton {
    /// The built-in adult hand skeleton.
    pub fn new(side: Side) -> Skeleton {
        Skeleton::from_joints(side, &RigJoints::builtin())
    }

    /// The skeleton of the hand whose joints are `joints` (a right hand's; a left hand is
    /// built as the right one, then mirrored in y): 20 bones, and 21 joint angles whose axes
    /// come from the bones' directions and the palm's dorsal normal (z): each finger flexes
    /// about z × its bone's direction and abducts about z; the thumb's CMC abducts about the
    /// axis normal to the thumb and to z, flexes about z's part normal to the thumb and turns
    /// about the metacarpal's own axis (opposition's pronation); its MCP and IP flex about the
    /// nail normal (z turned by the pronation about the thumb) × the bone.
    pub fn from_joints(side: Side, joints: &RigJoints) -> Skeleton {
        let mut bones: Vec<Bone> = Vec::new();
        let mut dofs = Vec::new();
        let z = Vector3::z();
        let (c, h, axes) = joints.carpus;
        let along = axes * Vector3::x() * h[0];
        bones.push(Bone {
            name: "carpus".into(),
            digit: None,
            parent: None,
            start: c - along,
            end: c + along,
            shape: BoneShape::Block { half: h, axes },
            cup: None,
        });
        let add_dof = |dofs: &mut Vec<JointDof>, name: String, bone, center, axis, limits| {
            dofs.push(JointDof {
                name,
                bone,
                center,
                axis: Unit::new_normalize(axis),
                limits,
                rest: 0.0,
            })
        };

        // Thumb: metacarpal (CMC: flexion across the palm, palmar abduction), proximal (MCP),
        // distal (IP).
        let p = joints.thumb_pronation_deg.to_radians();
        let thumb = &joints.digits[0];
        let names = ["metacarpal", "proximal", "distal"];
        for (k, name) in names.iter().enumerate() {
            let (start, end) = (thumb[k], thumb[k + 1]);
            let d = (end - start).normalize();
            let zp = (z - d * z.dot(&d)).normalize();
            let outward = zp.cross(&d).normalize();
            let nail = zp * p.cos() + outward * p.sin();
            let bone = bones.len();
            bones.push(Bone {
                name: format!("thumb.{name}"),
                digit: Some(0),
                parent: Some(if k == 0 { 0 } else { bone - 1 }),
                start,
                end,
                shape: BoneShape::Long {
                    shaft: joints.shafts[0][k],
                    distal: k == 2,
                },
                cup: None,
            });
            match k {
                0 => {
                    add_dof(
                        &mut dofs,
                        "thumb.cmc.abd".into(),
                        bone,
                        start,
                        outward,
                        limits::CMC_ABD,
                    );
                    add_dof(
                        &mut dofs,
                        "thumb.cmc.flex".into(),
                        bone,
                        start,
                        -zp,
                        limits::CMC_FLEX,
                    );
                    // Applied last, so about the metacarpal's own axis wherever the CMC's
                    // flexion and abduction have taken it. Positive is pronation: about −d, the
                    // nail turns from its sideways rest away from the palm and the pad towards
                    // the fingers' pads (right hand).
                    add_dof(
                        &mut dofs,
                        "thumb.cmc.rot".into(),
                        bone,
                        start,
                        -d,
                        limits::CMC_ROT,
                    );
                }
                1 => add_dof(
                    &mut dofs,
                    "thumb.mcp".into(),
                    bone,
                    start,
                    nail.cross(&d),
                    limits::THUMB_MCP,
                ),
                _ => add_dof(
                    &mut dofs,
                    "thumb.ip".into(),
                    bone,
                    start,
                    nail.cross(&d),
                    limits::THUMB_IP,
                ),
            }
        }

        // Fingers: metacarpal fixed to the carpus, then proximal (MCP abduction + flexion),
        // middle (PIP), distal (DIP).
        for digit in 1..5 {
            let name = DIGITS[digit];
            let points = &joints.digits[digit];
            let shafts = &joints.shafts[digit];
            let metacarpal = bones.len();
            bones.push(Bone {
                name: format!("{name}.metacarpal"),
                digit: Some(digit),
                parent: Some(0),
                start: points[0],
                end: points[1],
                shape: BoneShape::Long {
                    shaft: shafts[0],
                    distal: false,
                },
                cup: None,
            });
            let abd_axis = if name == "ring" || name == "little" {
                -z
            } else {
                z
            };
            for (k, part) in ["proximal", "middle", "distal"].iter().enumerate() {
                let (start, end) = (points[k + 1], points[k + 2]);
                let lateral = z.cross(&(end - start).normalize());
                let bone = bones.len();
                bones.push(Bone {
                    name: format!("{name}.{part}"),
                    digit: Some(digit),
                    parent: Some(if k == 0 { metacarpal } else { bone - 1 }),
                    start,
                    end,
                    shape: BoneShape::Long {
                        shaft: shafts[k + 1],
                        distal: k == 2,
                    },
                    cup: None,
                });
                match k {
                    0 => {
                        add_dof(
                            &mut dofs,
                            format!("{name}.mcp.abd"),
                            bone,
                            start,
                            abd_axis,
                            limits::MCP_ABD,
                        );
                        add_dof(
                            &mut dofs,
                            format!("{name}.mcp.flex"),
                            bone,
                            start,
                            lateral,
                            limits::MCP_FLEX,
                        );
                    }
                    1 => add_dof(
                        &mut dofs,
                        format!("{name}.pip"),
                        bone,
                        start,
                        lateral,
                        limits::PIP,
                    ),
                    _ => add_dof(
                        &mut dofs,
                        format!("{name}.dip"),
                        bone,
                        start,
                        lateral,
                        limits::DIP,
                    ),
                }
            }
        }
        // Joints turn about the centre of the proximal bone's head (its condyle), as real
        // hinges do, so that the joint space keeps its width as the joint flexes.
        // The child's base is cupped around that head, a joint space apart.
        for dof in &mut dofs {
            let parent = &bones[bones[dof.bone].parent.unwrap_or(0)];
            if let BoneShape::Long { shaft, distal } = parent.shape {
                let dir = (parent.end - parent.start).normalize();
                let head = long_bone_radius(1.0, shaft, distal);
                dof.center = parent.end - dir * (JOINT_GAP + head);
                let cup = (dof.center, head + 2.0 * JOINT_GAP);
                bones[dof.bone].cup = Some(cup);
            }
        }
        let mut skeleton = Skeleton { side, bones, dofs };
        if side == Side::Left {
            skeleton.mirror();
        }
        skeleton
    }

    /// Mirrors the (right) skeleton in y: points map to M·p, and a rotation axis a (an axial
    /// vector) to −M·a, so that the same angles give the mirrored motion.
    fn mirror(&mut self) {
        let m = |v: Vector3<f64>| Vector3::new(v.x, -v.y, v.z);
        for bone in &mut self.bones {
            bone.start = m(bone.start);
            bone.end = m(bone.end);
            bone.cup = bone.cup.map(|(c, r)| (m(c), r));
        }
        for dof in &mut self.dofs {
            dof.center = m(dof.center);
            dof.axis = Unit::new_normalize(-m(dof.axis.into_inner()));
        }
    }

    /// Index of the bone called `name`.
    pub fn bone_index(&self, name: &str) -> Option<usize> {
        self.bones.iter().position(|b| b.name == name)
    }

    /// The rest position of rig joint `key` ([`super::rig_names::joint_keys`]): `wrist` the
    /// carpus's start, `<digit>.tip` the end of the digit's distal bone, any other key the
    /// start of the bone of that name; `None` when the skeleton has no such bone.
    pub fn joint_point(&self, key: &str) -> Option<Vector3<f64>> {
        let (bone, tip) = Skeleton::joint_bone(key);
        let bone = &self.bones[self.bone_index(&bone)?];
        Some(if tip { bone.end } else { bone.start })
    }

    /// The bone whose start (or end, when the flag is set: a tip) is rig joint `key`.
    pub fn joint_bone(key: &str) -> (String, bool) {
        match key {
            "wrist" => ("carpus".to_string(), false),
            _ => match key.strip_suffix(".tip") {
                Some(digit) => (format!("{digit}.distal"), true),
                None => (key.to_string(), false),
            },
        }
    }

    /// Comma-separated bone names (for error messages).
    pub fn bone_names(&self) -> String {
        let names: Vec<&str> = self.bones.iter().map(|b| b.name.as_str()).collect();
        names.join(", ")
    }

    /// Joint angles of the rest pose, degrees (all zero but where the skeleton rests
    /// elsewhere: [`JointDof::rest`]).
    pub fn rest_angles(&self) -> Vec<f64> {
        self.dofs.iter().map(|d| d.rest).collect()
    }

    /// Sets joint `name`'s angle at the rest geometry, degrees ([`JointDof::rest`]).
    ///
    /// # Panics
    /// If there is no such joint, or the angle is outside its range.
    pub fn set_rest(&mut self, name: &str, angle: f64) {
        let dof = self
            .dofs
            .iter_mut()
            .find(|d| d.name == name)
            .unwrap_or_else(|| panic!("no joint {name}"));
        assert!(
            (dof.limits.min..=dof.limits.max).contains(&angle),
            "{name} rests at {angle}°, outside its range"
        );
        dof.rest = angle;
    }

    /// `angles` (one per dof, degrees) by joint name.
    pub fn pose_of(&self, angles: &[f64]) -> Pose {
        self.dofs
            .iter()
            .zip(angles)
            .map(|(d, a)| (d.name.clone(), *a))
            .collect()
    }

    /// `base` with the angles named in `pose` replaced; unknown names and angles outside their
    /// limits are errors.
    pub fn apply_pose(&self, base: &[f64], pose: &Pose) -> Result<Vec<f64>, PoseError> {
        let mut angles = base.to_vec();
        for (name, &angle) in pose {
            let Some(i) = self.dofs.iter().position(|d| &d.name == name) else {
                let known: Vec<&str> = self.dofs.iter().map(|d| d.name.as_str()).collect();
                return Err(PoseError::UnknownJoint {
                    name: name.clone(),
                    known: known.join(", "),
                });
            };
            let lim = self.dofs[i].limits;
            if !angle.is_finite() || angle < lim.min - 1e-9 || angle > lim.max + 1e-9 {
                return Err(PoseError::OutOfRange {
                    name: name.clone(),
                    angle,
                    min: lim.min,
                    max: lim.max,
                });
            }
            angles[i] = angle;
        }
        Ok(angles)
    }

    /// For each bone, the rigid motion taking it from where the angles `from` put it to where
    /// `to` put it (degrees, one per dof).
    pub fn motion(&self, from: &[f64], to: &[f64]) -> Vec<Isometry3<f64>> {
        relative_motion(&self.transforms(from), &self.transforms(to))
    }

    /// Forward kinematics: for each bone, the rigid motion taking its rest position to its
    /// position at `angles` (degrees, one per dof).
    pub fn transforms(&self, angles: &[f64]) -> Vec<Isometry3<f64>> {
        let mut local: Vec<Isometry3<f64>> = vec![Isometry3::identity(); self.bones.len()];
        for (dof, &angle) in self.dofs.iter().zip(angles) {
            let c = Translation3::from(dof.center);
            let r = UnitQuaternion::from_axis_angle(&dof.axis, (angle - dof.rest).to_radians());
            let about_center = c * Isometry3::from_parts(Translation3::identity(), r) * c.inverse();
            local[dof.bone] *= about_center;
        }
        let mut world = local.clone();
        for b in 0..self.bones.len() {
            if let Some(p) = self.bones[b].parent {
                world[b] = world[p] * local[b];
            }
        }
        world
    }

    /// Children of every bone.
    pub fn children(&self) -> Vec<Vec<usize>> {
        let mut children = vec![Vec::new(); self.bones.len()];
        for (b, bone) in self.bones.iter().enumerate() {
            if let Some(p) = bone.parent {
                children[p].push(b);
            }
        }
        children
    }

    /// Posed position of a rest point attached to bone `b`.
    pub fn posed(transforms: &[Isometry3<f64>], b: usize, rest: &Vector3<f64>) -> Vector3<f64> {
        (transforms[b] * Point3::from(*rest)).coords
    }
}

/// Bone by bone, the rigid motion from the placements `from` to the placements `to`
/// (to · from⁻¹).
pub fn relative_motion(from: &[Isometry3<f64>], to: &[Isometry3<f64>]) -> Vec<Isometry3<f64>> {
    to.iter().zip(from).map(|(t, f)| t * f.inverse()).collect()
}

/// The digit a joint belongs to ("thumb", "index", …): the part of its name before the first
/// dot.
pub fn digit_of(joint: &str) -> &str {
    joint.split('.').next().unwrap_or(joint)
}
