//! Kernel: the hand — anatomy, skeleton and pose, bone shapes, flesh lattice, skin, skinning.
//! May import the mesh and fem kernels and util only.
//!
//! The synthetic hand: anatomy, skeleton and pose, the skin's shape, the meshed flesh around the
//! bones, the smooth display skin, geometric skinning (the fast path), and the preshapes and closing
//! synergies a hand grasps by itself with (`synergy.rs`).

pub mod anatomy;
mod bone_mesh;
mod embed;
mod form;
mod imported;
mod lattice;
mod mesh_skin;
mod model;
mod posed;
mod poses;
mod rig;
pub mod rig_names;
mod shape;
pub mod size;
mod skeleton;
mod skin;
mod skin_follow;
mod skinning;
mod stretch;
mod subdivide;
pub mod synergy;

pub use bone_mesh::{bone_surface, TriangleSurface};
pub use form::HandForm;
pub use imported::{RigError, RiggedHand};
pub use lattice::{
    mesh_flesh, mesh_flesh_offset, FleshMesh, MeshingError, BASE_SPACING, RESOLUTIONS,
};
pub use mesh_skin::{Located, MeshSkin, SkinMeshError};
pub use model::{HandModel, CONTACT_SKIN_LEVELS, SKIN_LEVELS};
pub use poses::{four_finger_fist, full_fist, thumb_over_fist};
pub use rig::RigJoints;
pub use shape::{BuiltinSkin, SkinShape};
pub use size::HandSize;
pub use skeleton::{
    cup_radius, digit_of, long_bone_radius, relative_motion, Bone, BoneShape, JointDof, Pose,
    PoseError, Side, Skeleton,
};
pub use skin::DisplaySkin;
pub use skinning::{Blend, SkinningWeights};
pub use stretch::Stretch;
pub use subdivide::{subdivide, MAX_SUBDIVISIONS};
