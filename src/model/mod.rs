//! The immutable model built from a scene: meshes, materials, bodies, constraints, loads, probes,
//! obstacles, keyframes and settings. Imports the scene and the kernels (mesh, fem, contact, hand).

mod bodies;
mod build;
mod cameras;
mod check;
mod constraints;
mod convert;
mod flexion_settings;
mod gas;
mod gltf_checks;
mod grasp;
mod hand_gltf;
mod input_warnings;
mod keyframes;
mod loads;
mod materials;
mod memory_estimate;
mod names;
mod obstacles;
mod probes;
mod refinement;
mod regions;
mod release;
mod select;
mod settings;
mod shapes;
mod skin_overlap;
mod supports;
mod tier;

pub use bodies::hand_size;
pub use flexion_settings::{FleshMethod, FleshRegion, FlexionScheme, FlexionSettings};
pub use gas::{GasCavity, STANDARD_AMBIENT};
pub use grasp::{grasp_keyframe, ClosingJoint, GraspModel, HoldTarget, DEFAULT_MARGIN};
pub use names::shown;
pub use refinement::DEFAULT_SIZE_OF_RADIUS;
pub use skin_overlap::SkinOverlapCheck;
pub use tier::{Tier, STEP_WARNING_DEG};

use crate::contact::{ContactSettings, Obstacle};
use crate::fem::assembly::StiffnessPattern;
use crate::fem::solve::FillOrdering;
use crate::fem::{DofPartition, Material};
use crate::hand::HandModel;
use crate::mesh::{Facet, Mesh};
use crate::scene::Shape;
use nalgebra::Vector3;
use std::ops::Range;
use std::sync::Arc;

/// One body: a contiguous range of nodes and cells of the model's mesh.
#[derive(Clone, Debug)]
pub struct BodyModel {
    /// Its name in the scene.
    pub name: String,
    /// Its shape as given.
    pub shape: Shape,
    /// Its nodes.
    pub nodes: Range<usize>,
    /// Its cells.
    pub cells: Range<usize>,
    /// Its boundary facets (global node indices).
    pub facets: Vec<Facet>,
    /// The nodes of the facets skin meets: the pieces of the boundary enclosing its material,
    /// without the walls of cavities inside it (`contact::exterior_quads`).
    pub exterior: Vec<[usize; 4]>,
    /// Longest edge of its bounding box, m.
    pub size: f64,
    /// Volume, m³.
    pub volume: f64,
    /// Mass, kg.
    pub mass: f64,
    /// The hand, for a hand body (its flesh is this body's mesh).
    pub hand: Option<Arc<HandModel>>,
    /// A hand's check for its skin inside its own flesh (from its rest geometry); `None` for
    /// other bodies.
    pub skin_overlap: Option<SkinOverlapCheck>,
    /// A hand's joint angles at time 0 (its `pose`), degrees; empty for other bodies.
    pub initial_angles: Vec<f64>,
    /// A hand's muscle force threshold of every bone, N; empty for other bodies.
    pub thresholds: Vec<f64>,
    /// Held by nothing but contact (no prescribed displacement): stabilised by weak ground
    /// springs, and checked to be held after the solve.
    pub floating: bool,
}

impl BodyModel {
    /// The inner and outer radii of a hollow ball (`shell`), m; `None` for any other shape.
    pub fn shell_radii(&self) -> Option<(f64, f64)> {
        match self.shape {
            Shape::Shell {
                inner_radius,
                outer_radius,
                ..
            } => Some((inner_radius, outer_radius)),
            _ => None,
        }
    }
}

/// A keyframe: the full joint angles of one hand at a time.
#[derive(Clone, Debug)]
pub struct KeyframeModel {
    /// Time, s.
    pub time: f64,
    /// The hand body.
    pub body: usize,
    /// All its joint angles, degrees (joints the keyframe does not name keep their previous
    /// angle); for a grasp, where its digits start closing (the preshape).
    pub angles: Vec<f64>,
    /// The hand closes on an object by itself from `angles` (a grasp keyframe).
    pub grasp: Option<Box<GraspModel>>,
}

/// A named set of prescribed dofs.
#[derive(Clone, Debug)]
pub struct ConstraintModel {
    /// Name (report key).
    pub name: String,
    /// Index of the body.
    pub body: usize,
    /// The dofs it prescribes (a dof prescribed by an earlier constraint is not repeated).
    pub dofs: Vec<usize>,
}

/// A load as applied.
#[derive(Clone, Debug)]
pub struct LoadModel {
    /// Name (given, or `load[i]`).
    pub name: String,
    /// Index of the body.
    pub body: usize,
    /// The total force it applies, N.
    pub total: Vector3<f64>,
    /// A pressure (Pa) and the facets it acts on: it follows them where they turn (the
    /// contact steps of a corotated tier apply it to the deformed surface).
    pub pressure: Option<(f64, Vec<Facet>)>,
}

/// A probed node.
#[derive(Clone, Debug)]
pub struct ProbeModel {
    /// Name (report key).
    pub name: String,
    /// Index of the body.
    pub body: usize,
    /// The requested point.
    pub point: Vector3<f64>,
    /// The nearest node of the body.
    pub node: usize,
}

/// Coulomb friction: the default μ, and (name, name, μ) by pair of materials or obstacles.
pub type FrictionTable = (f64, Vec<(String, String, f64)>);

/// The compiled scene.
#[derive(Clone, Debug)]
pub struct Model {
    /// All bodies' meshes, one after the other.
    pub mesh: Mesh,
    /// Bodies.
    pub bodies: Vec<BodyModel>,
    /// Material names.
    pub material_names: Vec<String>,
    /// Material index of each cell.
    pub cell_material: Vec<usize>,
    /// Material of each cell (expanded, for assembly).
    pub cell_materials: Vec<Material>,
    /// Body index of each cell.
    pub cell_body: Vec<usize>,
    /// Constraints.
    pub constraints: Vec<ConstraintModel>,
    /// Loads.
    pub loads: Vec<LoadModel>,
    /// The gas cavity, when a pressure load is one (`gas = true`): its pressure follows its
    /// volume, and the load vector holds it at its rest pressure.
    pub gas: Option<GasCavity>,
    /// Total gravity force, N.
    pub gravity_total: Vector3<f64>,
    /// The gravitational acceleration (`[world] gravity`), m/s².
    pub gravity: Option<Vector3<f64>>,
    /// Probes.
    pub probes: Vec<ProbeModel>,
    /// Which dofs are prescribed.
    pub partition: DofPartition,
    /// Prescribed values U_k (zero at free dofs).
    pub prescribed: Vec<f64>,
    /// The load vector R (body forces, pressure, point forces).
    pub load_vector: Vec<f64>,
    /// Sparsity pattern of K.
    pub pattern: Arc<StiffnessPattern>,
    /// Fill-reducing ordering.
    pub ordering: FillOrdering,
    /// How hands move between poses.
    pub flexion: FlexionSettings,
    /// Keyframes in time order.
    pub keyframes: Vec<KeyframeModel>,
    /// The scene's named cameras (validated).
    pub cameras: Vec<crate::scene::CameraDef>,
    /// Rigid obstacles, by name.
    pub obstacles: Vec<(String, Obstacle)>,
    /// Nodes that may touch the obstacles: the boundary nodes of every body but hands.
    pub contact_candidates: Vec<usize>,
    /// Contact iteration settings.
    pub contact: ContactSettings,
    /// Radius around the contact within which hand flesh is solved with it, m.
    pub contact_region: f64,
    /// Coulomb friction: the default μ and (name, name, μ) by pair of materials or obstacles.
    pub friction: FrictionTable,
    /// A cell of every node.
    pub node_cell: Vec<usize>,
    /// Element of the linear static solve (`[solver] element`).
    pub element: crate::fem::ElementKind,
    /// The bodies other than hands are solved at large strain by Newton (`[solver] tier =
    /// "nonlinear"`), not by one linear solve.
    pub nonlinear_statics: bool,
    /// The memory a solve may take, bytes (`[solver] max_memory`; `None`: what the machine has
    /// free).
    pub max_memory: Option<u64>,
    /// Warnings about the input found while building: a nearly incompressible material on an
    /// element that locks, a point far from its body.
    pub input_warnings: Vec<String>,
}

impl Model {
    /// Whether the other bodies of a contact step are corotated about the displacements the
    /// motion carries (every tier that turns the flesh's elements too; not the linear one).
    pub fn corotates_objects(&self) -> bool {
        self.flexion.scheme != FlexionScheme::Linear
    }

    /// Warnings about the settings (the model is usable; `report.json` lists them), derived from
    /// the model.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = self.input_warnings.clone();
        out.extend(settings::warnings(
            self.nonlinear_statics,
            &self.flexion,
            &self.bodies,
        ));
        out
    }

    /// A cell that contains node `n`.
    pub fn node_cell(&self, n: usize) -> Option<usize> {
        self.node_cell.get(n).copied().filter(|&c| c != usize::MAX)
    }

    /// The name of material `m` ("" when out of range).
    pub fn material_name(&self, m: usize) -> &str {
        self.material_names.get(m).map_or("", |s| s.as_str())
    }

    /// Coulomb coefficient between two materials (or a material and an obstacle).
    pub fn friction_between(&self, a: &str, b: &str) -> f64 {
        self.friction
            .1
            .iter()
            .find(|(x, y, _)| (x == a && y == b) || (x == b && y == a))
            .map_or(self.friction.0, |p| p.2)
    }

    /// Index of the body that owns node `n`.
    pub fn body_of_node(&self, n: usize) -> usize {
        self.bodies
            .iter()
            .position(|b| b.nodes.contains(&n))
            .unwrap_or(0)
    }
}
