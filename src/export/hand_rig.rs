//! The built-in hand as a rigged glTF 2.0 binary (`.glb`), as an animator's hand arrives from
//! Blender, Mixamo or MakeHuman: the skin at rest, a skeleton of joint nodes named in one of the
//! common conventions (`hand::rig_names`), and a glTF skin (joints, inverse bind matrices,
//! JOINTS_0 / WEIGHTS_0) so that the skeleton deforms the mesh. The fixture of the glTF import.
//!
//! Joints: `wrist` (the carpus's start) → each digit's metacarpal (where the convention names
//! one; else the proximal is the wrist's child) → proximal → middle → distal → tip (where the
//! convention names it); each at the start of its bone, the tip at the end of the distal bone.
//! Nodes carry translations only (from their parent; no rotation). glTF is Y-up and the hand
//! frame Z-up: positions, normals and translations go (x, y, z) → (x, z, −y), as Blender's
//! exporter writes them, so that its importer turns them back exactly. glTF holds f32: a joint's
//! position is within half a unit of f32's last place of its own translation (each translation
//! is rounded from the exact position less the parent's rounded one; errors do not accumulate).

use super::glb::GlbBuilder;
use super::png::write_bytes_atomic;
use super::rig_mesh::{rig_mesh, RigMesh};
pub use super::rig_mesh::{RigOptions, RigSkin};
use crate::hand::rig_names::{joint_keys, node_name, Convention};
use crate::hand::{HandModel, Skeleton};
pub use crate::util::gltf_axes::{from_gltf_axes, to_gltf_axes};
use gltf_json as json;
use json::validation::Checked::Valid;
use nalgebra::Vector3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A joint of the exported skeleton.
#[derive(Clone, Debug, PartialEq)]
pub struct RigJoint {
    /// Its joint key (`wrist`, `index.proximal`, `index.tip`, …; `hand::rig_names`).
    pub key: String,
    /// Its node name in the convention.
    pub name: String,
    /// The joint it hangs from (an index into the joints), `None` for the wrist.
    pub parent: Option<usize>,
    /// Its rest position in the hand frame (Z-up), m.
    pub position: Vector3<f64>,
}

/// Why the rigged hand cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum RigError {
    /// The skeleton lacks a bone a joint key needs.
    #[error("the hand's skeleton has no bone \"{bone}\" for joint \"{key}\"")]
    MissingBone {
        /// The joint key.
        key: String,
        /// The bone looked for.
        bone: String,
    },
    /// The file would exceed glTF's 4 GiB.
    #[error("the rigged hand would take {0} bytes, beyond glTF's 4 GiB limit")]
    TooLarge(usize),
    /// The file could not be written. (The cause is told in the message, not as the error's
    /// source: a chain printed whole, `{:#}`, would tell it twice.)
    #[error("cannot write {path}: {cause}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        cause: std::io::Error,
    },
}

/// The rest position of joint `key` in `skeleton` ([`Skeleton::joint_point`]).
pub fn joint_position(skeleton: &Skeleton, key: &str) -> Result<Vector3<f64>, RigError> {
    skeleton
        .joint_point(key)
        .ok_or_else(|| RigError::MissingBone {
            key: key.to_string(),
            bone: Skeleton::joint_bone(key).0,
        })
}

/// The joints `convention` names for `hand`, parents before children, in `joint_keys` order.
pub fn rig_joints(hand: &HandModel, convention: Convention) -> Result<Vec<RigJoint>, RigError> {
    let side = hand.skeleton.side;
    let mut joints: Vec<RigJoint> = Vec::new();
    for key in joint_keys() {
        let Some(name) = node_name(convention, side, &key) else {
            continue;
        };
        // The last joint of the same digit before it, else the wrist.
        let digit = key.split_once('.').map(|(d, _)| d);
        let parent = joints
            .iter()
            .rposition(|j| j.key.split_once('.').map(|(d, _)| d) == digit)
            .or(if key == "wrist" { None } else { Some(0) });
        joints.push(RigJoint {
            position: joint_position(&hand.skeleton, &key)?,
            key,
            name,
            parent,
        });
    }
    Ok(joints)
}

/// For each bone of `skeleton`, the joint that moves it: the joint at its start (the wrist for
/// the carpus), or its parent bone's where the convention has no joint there (Mixamo's finger
/// metacarpals move with the wrist).
pub fn bone_joints(skeleton: &Skeleton, joints: &[RigJoint]) -> Vec<usize> {
    let mut out = vec![0; skeleton.bones.len()];
    for (b, bone) in skeleton.bones.iter().enumerate() {
        let key = if bone.parent.is_none() {
            "wrist"
        } else {
            bone.name.as_str()
        };
        out[b] = match joints.iter().position(|j| j.key == key) {
            Some(j) => j,
            None => bone.parent.map_or(0, |p| out[p]),
        };
    }
    out
}

/// The `.glb` bytes of `hand` rigged in `convention`, with the skin `options` ask for.
pub fn hand_rig_glb(
    hand: &HandModel,
    convention: Convention,
    options: &RigOptions,
) -> Result<Vec<u8>, RigError> {
    let joints = rig_joints(hand, convention)?;
    let mesh = rig_mesh(hand, options, &bone_joints(&hand.skeleton, &joints));
    let mut b = GlbBuilder::new();
    // Translations rounded to f32 from the exact position less the parent's rounded one.
    let mut world: Vec<Vector3<f64>> = Vec::with_capacity(joints.len());
    let mut translations = Vec::with_capacity(joints.len());
    for j in &joints {
        let parent = j.parent.map_or(Vector3::zeros(), |p| world[p]);
        let t = (to_gltf_axes(&j.position) - parent).map(|x| x as f32);
        world.push(parent + t.map(f64::from));
        translations.push(t);
    }
    for (i, j) in joints.iter().enumerate() {
        let children: Vec<json::Index<json::Node>> = (0..joints.len())
            .filter(|&c| joints[c].parent == Some(i))
            .map(|c| json::Index::new(c as u32))
            .collect();
        b.root.push(json::Node {
            name: Some(j.name.clone()),
            translation: Some(translations[i].into()),
            children: (!children.is_empty()).then_some(children),
            ..Default::default()
        });
    }
    // Inverse bind matrices (column-major): a translation by minus the joint's rest position.
    let matrices: Vec<f32> = world
        .iter()
        .flat_map(|w| {
            let mut m = [0.0f32; 16];
            for i in 0..4 {
                m[5 * i] = 1.0;
            }
            m[12] = -w.x as f32;
            m[13] = -w.y as f32;
            m[14] = -w.z as f32;
            m
        })
        .collect();
    let inverse_bind_matrices = b.floats(&matrices, json::accessor::Type::Mat4, false, None);
    let side = match hand.skeleton.side {
        crate::hand::Side::Right => "right",
        crate::hand::Side::Left => "left",
    };
    let skin = b.root.push(json::Skin {
        extensions: Default::default(),
        extras: Default::default(),
        inverse_bind_matrices: Some(inverse_bind_matrices),
        joints: (0..joints.len())
            .map(|i| json::Index::new(i as u32))
            .collect(),
        name: Some(format!("hand_{side}_rig")),
        skeleton: Some(json::Index::new(0)),
    });
    let primitive = skin_primitive(&mut b, &mesh);
    let mesh_index = b.root.push(json::Mesh {
        extensions: Default::default(),
        extras: Default::default(),
        name: Some(format!("hand_{side}")),
        primitives: vec![primitive],
        weights: None,
    });
    let mesh_node = b.root.push(json::Node {
        name: Some(format!("hand_{side}")),
        mesh: Some(mesh_index),
        skin: Some(skin),
        ..Default::default()
    });
    let scene = b.root.push(json::Scene {
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        nodes: vec![json::Index::new(0), mesh_node],
    });
    b.root.scene = Some(scene);
    b.finish().map_err(RigError::TooLarge)
}

/// The mesh's one primitive: positions, normals, joints and weights in glTF axes, f32.
fn skin_primitive(b: &mut GlbBuilder, mesh: &RigMesh) -> json::mesh::Primitive {
    use json::accessor::{ComponentType, Type};
    use json::mesh::Semantic;
    let target = Some(json::buffer::Target::ArrayBuffer);
    let flat = |v: &[Vector3<f64>]| -> Vec<f32> {
        v.iter()
            .flat_map(|p| {
                let g = to_gltf_axes(p);
                [g.x as f32, g.y as f32, g.z as f32]
            })
            .collect()
    };
    let mut attributes = BTreeMap::new();
    let positions = b.floats(&flat(&mesh.positions), Type::Vec3, true, target);
    attributes.insert(Valid(Semantic::Positions), positions);
    let normals = b.floats(&flat(&mesh.normals), Type::Vec3, false, target);
    attributes.insert(Valid(Semantic::Normals), normals);
    let joint_bytes: Vec<u8> = mesh.joints.iter().flat_map(|j| j.map(|e| e.0)).collect();
    let joints = b.integers(
        &joint_bytes,
        mesh.joints.len(),
        ComponentType::U8,
        Type::Vec4,
        target,
    );
    attributes.insert(Valid(Semantic::Joints(0)), joints);
    let weights: Vec<f32> = mesh.joints.iter().flat_map(f32_weights).collect();
    let weights = b.floats(&weights, Type::Vec4, false, target);
    attributes.insert(Valid(Semantic::Weights(0)), weights);
    json::mesh::Primitive {
        attributes,
        extensions: Default::default(),
        extras: Default::default(),
        indices: Some(b.triangles(&mesh.triangles)),
        material: None,
        mode: Valid(json::mesh::Mode::Triangles),
        targets: None,
    }
}

/// Four weights in f32 summing to one as closely as f32 holds it: the round-off put on the
/// largest.
fn f32_weights(joints: &[(u8, f64); 4]) -> [f32; 4] {
    let mut w = joints.map(|e| e.1 as f32);
    let rest: f32 = w[1..].iter().sum();
    w[0] = 1.0 - rest;
    w
}

/// Writes `hand` rigged in `convention` to `path` as a `.glb` (temporary file, then rename).
pub fn write_hand_rig(
    path: &Path,
    hand: &HandModel,
    convention: Convention,
    options: &RigOptions,
) -> Result<(), RigError> {
    let bytes = hand_rig_glb(hand, convention, options)?;
    write_bytes_atomic(path, &bytes).map_err(|cause| RigError::Io {
        path: path.to_path_buf(),
        cause,
    })
}
