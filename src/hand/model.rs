//! A built hand: skeleton, meshed flesh, display skin, skinning weights. Fixed for a scene; the
//! pose and the flesh positions are state.

use super::embed::Reach;
use super::form::HandForm;
use super::lattice::{mesh_flesh_offset, FleshMesh, MeshingError};
use super::rig::RigJoints;
use super::shape::SkinShape;
use super::size::HandSize;
use super::skeleton::{Side, Skeleton};
use super::skin::DisplaySkin;
use super::skinning::SkinningWeights;
use super::stretch::Stretch;
use super::subdivide::{subdivide, MAX_SUBDIVISIONS};
use nalgebra::Vector3;

/// Catmull–Clark levels of the display skin.
pub const SKIN_LEVELS: usize = 2;

/// Catmull–Clark levels of the contact skin: the same smooth skin as the display's, sampled at
/// the flesh lattice's resolution (one vertex per skin lattice point), so that contact costs no
/// more rows than the lattice's own skin nodes would.
pub const CONTACT_SKIN_LEVELS: usize = 0;

/// Everything about a hand that does not change with its pose.
#[derive(Clone, Debug)]
pub struct HandModel {
    /// Bones and joints.
    pub skeleton: Skeleton,
    /// The simulation mesh of the flesh (rest pose), with bone attachments.
    pub flesh: FleshMesh,
    /// The smooth display skin embedded in the flesh.
    pub skin: DisplaySkin,
    /// The contact surface: the smooth skin at the lattice's resolution, embedded in the flesh
    /// like the display skin (its vertices on the skin's shape at rest).
    pub contact_skin: DisplaySkin,
    /// Skinning weights of every flesh node.
    pub weights: SkinningWeights,
    /// The resolution it was meshed at.
    pub resolution: f64,
    /// How many times each edge of that lattice's cells was split ([`super::subdivide`]; 1 = not
    /// split).
    pub subdivisions: usize,
    /// What building it changed of its input that the user should be told (an imported rig's
    /// joint found outside its finger and moved into it); empty for the built-in hand.
    pub mended: Vec<String>,
}

impl HandModel {
    /// Builds the built-in hand's simple form ([`HandForm::Simple`]: the benches' and the
    /// library's tests' hand; a scene's default is [`HandForm::Anatomical`], through
    /// [`HandModel::built_in`]) of the given side at `resolution` (1 = default).
    pub fn new(side: Side, resolution: f64) -> Result<HandModel, MeshingError> {
        HandModel::new_within(side, resolution, None)
    }

    /// [`HandModel::new`] refused when meshing it would take more than `max_memory` bytes (or
    /// what the machine has free: [`super::lattice::check_memory`]).
    pub fn new_within(
        side: Side,
        resolution: f64,
        max_memory: Option<u64>,
    ) -> Result<HandModel, MeshingError> {
        HandModel::build(
            Skeleton::new(side),
            SkinShape::new(side),
            resolution,
            max_memory,
        )
    }

    /// [`HandModel::new_within`] for a hand of `size` (the built-in anatomy stretched to it),
    /// refused, naming the number, for a size that is not a human hand's.
    pub fn sized(
        side: Side,
        size: HandSize,
        resolution: f64,
        max_memory: Option<u64>,
    ) -> Result<HandModel, MeshingError> {
        HandModel::built_in(side, Some(size), HandForm::Simple, resolution, max_memory)
    }

    /// The built-in hand of `form` ([`HandForm`]), of `size` (its own when `None`), refused,
    /// naming the number, for a size that is not a human hand's.
    pub fn built_in(
        side: Side,
        size: Option<HandSize>,
        form: HandForm,
        resolution: f64,
        max_memory: Option<u64>,
    ) -> Result<HandModel, MeshingError> {
        HandModel::built_in_nested(side, size, form, resolution, 1, max_memory)
    }

    /// [`HandModel::built_in`] with every cell of its lattice split into `subdivisions`³
    /// ([`super::subdivide`]: the nested refinement, whose hand stays that of the lattice).
    pub fn built_in_nested(
        side: Side,
        size: Option<HandSize>,
        form: HandForm,
        resolution: f64,
        subdivisions: usize,
        max_memory: Option<u64>,
    ) -> Result<HandModel, MeshingError> {
        let stretch = match size {
            Some(size) => {
                size.check().map_err(MeshingError::Size)?;
                size.stretch()
            }
            None => Stretch::IDENTITY,
        };
        let mut skeleton = Skeleton::from_joints(side, &RigJoints::builtin_form(stretch, form));
        skeleton.set_rest("thumb.cmc.abd", form.thumb_rest_abduction_deg());
        HandModel::build_nested(
            skeleton,
            SkinShape::sized(side, stretch, form),
            resolution,
            subdivisions,
            max_memory,
            Vector3::zeros(),
        )
    }

    /// The hand of `skeleton` inside the skin `shape` (both in the hand's frame), meshed at
    /// `resolution`, refused when meshing it would take more than `max_memory` bytes (or what
    /// the machine has free).
    pub fn build(
        skeleton: Skeleton,
        shape: SkinShape,
        resolution: f64,
        max_memory: Option<u64>,
    ) -> Result<HandModel, MeshingError> {
        HandModel::build_offset(skeleton, shape, resolution, max_memory, Vector3::zeros())
    }

    /// [`HandModel::build`] with the flesh lattice moved by `lattice_offset`
    /// ([`super::lattice::mesh_flesh_offset`]).
    pub fn build_offset(
        skeleton: Skeleton,
        shape: SkinShape,
        resolution: f64,
        max_memory: Option<u64>,
        lattice_offset: Vector3<f64>,
    ) -> Result<HandModel, MeshingError> {
        HandModel::build_nested(skeleton, shape, resolution, 1, max_memory, lattice_offset)
    }

    /// [`HandModel::build_offset`] with every cell of the lattice split into `subdivisions`³
    /// ([`super::subdivide`]); the display skin takes a Catmull–Clark level less where its
    /// control net is split in two or more (two levels fewer from four), so that it stays about
    /// as fine as the unsplit hand's.
    pub fn build_nested(
        skeleton: Skeleton,
        shape: SkinShape,
        resolution: f64,
        subdivisions: usize,
        max_memory: Option<u64>,
        lattice_offset: Vector3<f64>,
    ) -> Result<HandModel, MeshingError> {
        if !(1..=MAX_SUBDIVISIONS).contains(&subdivisions) {
            return Err(MeshingError::Subdivisions(subdivisions));
        }
        super::lattice::check_memory(&skeleton, &shape, resolution, subdivisions, max_memory)?;
        let lattice = mesh_flesh_offset(&skeleton, &shape, resolution, lattice_offset)?;
        let flesh = subdivide(lattice, subdivisions, &skeleton);
        let skin_levels = SKIN_LEVELS.saturating_sub(subdivisions.ilog2() as usize);
        let embedded = |levels, reach| {
            DisplaySkin::embedded(
                &flesh.display_quads,
                &flesh.display_vertices,
                &flesh.display_cells,
                (&flesh.mesh, subdivisions),
                levels,
                reach,
                |p| shape.project(p),
            )
        };
        let mut skin = embedded(skin_levels, Reach::Nearest);
        // The contact skin keeps its vertices within reach of their own cells: placed exactly
        // on the skin, the 106 (of 6 560) it pulls in by up to 4.2 mm on the backs and creases
        // of the fingers made the fist's self-contact fail to settle (ring PIP 41°), the folded
        // PIP crease invert a cell at 90.6°, and the pad's press into the soft ball stop at
        // 71 % of its way (measured 2026-11-27; docs/hand.md).
        let contact_skin = embedded(CONTACT_SKIN_LEVELS, Reach::OwnCell);
        // The display skin moves with what the contact holds (`skin_follow.rs`).
        skin.follow(
            contact_skin.clone(),
            (
                &flesh.display_quads,
                flesh.display_vertices.len(),
                skin_levels,
            ),
            &flesh.mesh.nodes,
        );
        let weights = SkinningWeights::new(&skeleton, &flesh.mesh.nodes, &flesh.node_bone);
        Ok(HandModel {
            skeleton,
            flesh,
            skin,
            contact_skin,
            weights,
            resolution,
            subdivisions,
            mended: Vec::new(),
        })
    }

    /// Nodes attached to bone `b`.
    pub fn bone_nodes(&self, b: usize) -> Vec<usize> {
        (0..self.flesh.node_bone.len())
            .filter(|&n| self.flesh.node_bone[n] == Some(b))
            .collect()
    }
}
