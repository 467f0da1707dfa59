//! Serde types of the scene file.

use super::names::{
    BlendName, ContactMethodName, ElementName, FleshMethodName, FlexionSchemeName, HandSide,
    PairSidesName, VolumetricName,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A whole scene.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// World settings (gravity).
    #[serde(default)]
    pub world: World,
    /// Solver settings.
    #[serde(default)]
    pub solver: SolverSettings,
    /// Named materials.
    #[serde(default)]
    pub material: Vec<MaterialDef>,
    /// Bodies.
    #[serde(default)]
    pub body: Vec<BodyDef>,
    /// Sub-regions of a body made of another material.
    #[serde(default)]
    pub region: Vec<RegionDef>,
    /// Prescribed displacements.
    #[serde(default)]
    pub constraint: Vec<ConstraintDef>,
    /// Loads.
    #[serde(default)]
    pub load: Vec<LoadDef>,
    /// Points whose displacement is reported.
    #[serde(default)]
    pub probe: Vec<ProbeDef>,
    /// Poses of hands at later times.
    #[serde(default)]
    pub keyframe: Vec<KeyframeDef>,
    /// Named cameras of this scene (beside the built-in presets).
    #[serde(default)]
    pub camera: Vec<CameraDef>,
    /// Rigid obstacles (a table, a rigid ball) that bodies may touch but not enter.
    #[serde(default)]
    pub obstacle: Vec<ObstacleDef>,
    /// Coulomb friction coefficients by pair of materials or obstacles.
    #[serde(default)]
    pub friction: Vec<FrictionDef>,
}

/// The friction coefficient between two materials (or a material and an obstacle).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FrictionDef {
    /// Two names: materials, or a material and an obstacle (order does not matter).
    pub between: Vec<String>,
    /// Coulomb coefficient μ ≥ 0: sliding starts when F_t ≥ μ·F_n.
    pub mu: f64,
}

/// `contact_relaxation`: `"quasi_newton"`, `"aitken"` or a fixed factor in (0, 1].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(
    untagged,
    expecting = "expected \"quasi_newton\", \"aitken\" or a factor in (0, 1]"
)]
pub enum RelaxationDef {
    /// A fixed factor ω.
    Factor(f64),
    /// A name (`"quasi_newton"`, `"aitken"`).
    Name(String),
}

/// `[[obstacle]]`: a rigid obstacle.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObstacleDef {
    /// Name (report key).
    pub name: String,
    /// Its geometry.
    pub shape: ObstacleShape,
}

/// Geometry of a rigid obstacle.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ObstacleShape {
    /// The half-space below a plane; bodies stay on the side the normal points to.
    Plane {
        /// A point of the plane, m.
        point: [f64; 3],
        /// Normal (normalised on reading), pointing out of the obstacle.
        normal: [f64; 3],
    },
    /// A rigid ball; bodies stay outside.
    Sphere {
        /// Centre, m.
        center: [f64; 3],
        /// Radius, m.
        radius: f64,
    },
}

/// `[[camera]]`: a named view of the scene.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraDef {
    /// Name, used by `--camera`.
    pub name: String,
    /// Eye position, m.
    pub eye: [f64; 3],
    /// Point looked at, m.
    pub target: [f64; 3],
    /// Up direction (default `[0, 0, 1]`).
    #[serde(default = "z_up")]
    pub up: [f64; 3],
    /// Vertical field of view, degrees (default 35).
    #[serde(default = "default_fov")]
    pub fov_deg: f64,
}

fn z_up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

fn default_fov() -> f64 {
    35.0
}

/// `[[keyframe]]`: a hand's pose at a time. Joints not named keep their previous angle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeDef {
    /// Time, s (keyframes in increasing time).
    pub time: f64,
    /// The hand body it poses (may be left out when the scene has one hand).
    #[serde(default)]
    pub body: Option<String>,
    /// Joint angles in degrees by name, e.g. `{ "index.pip" = 40 }` (may be left out in a
    /// grasp keyframe; there they adjust the preshape).
    #[serde(default)]
    pub pose: BTreeMap<String, f64>,
    /// The hand closes on an object by itself: the gentlest grip that holds it
    /// (docs/contact.md, "The gentlest grip").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grasp: Option<GraspDef>,
}

/// `grasp = { object = "ball", preshape = "power" }` in a keyframe.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GraspDef {
    /// The body grasped.
    pub object: String,
    /// `"power"` (default), `"pinch"` (thumb and index pads), `"tripod"` (thumb, index,
    /// middle), or a pose table where the digits start closing from (every digit closes).
    #[serde(default)]
    pub preshape: Option<PreshapeDef>,
    /// `"gravity"` (default): the grip must hold the object against the scene's gravity by
    /// friction, with `margin`, as if nothing else held it.
    #[serde(default)]
    pub hold: Option<String>,
    /// A target grip instead: the sum of the hand's normal contact forces on the object, N.
    #[serde(default)]
    pub force: Option<f64>,
    /// Safety factor on the friction the hold needs (default 1.5).
    #[serde(default)]
    pub margin: Option<f64>,
    /// `false`: the digits do not close; the pose as posed (the preshape adjusted by the
    /// keyframe's `pose`: an animator's own grasp) is solved and judged — does it hold, with
    /// what margin and grip. Default `true`: the hand closes to the gentlest grip that holds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub close: Option<bool>,
}

/// A grasp's preshape: a name or a pose table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "expected \"power\", \"pinch\", \"tripod\" or a pose table of joint angles in degrees"
)]
pub enum PreshapeDef {
    /// `"power"`, `"pinch"` or `"tripod"`.
    Named(String),
    /// Joint angles in degrees by name.
    Pose(BTreeMap<String, f64>),
}

/// `[world]`
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct World {
    /// Gravitational acceleration in m/s², e.g. `[0, 0, -9.81]`; none when absent.
    #[serde(default)]
    pub gravity: Option<[f64; 3]>,
}

/// `[solver]`
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSettings {
    /// Fill-reducing ordering for the sparse Cholesky: `"auto"` (default: whichever of the two
    /// fills less), `"nested_dissection"` or `"amd"`.
    #[serde(default)]
    pub ordering: Option<OrderingName>,
    /// Largest joint rotation per flexion increment, degrees (default 10).
    #[serde(default)]
    pub max_step_deg: Option<f64>,
    /// How hand flesh moves: `"fem"` (default) or `"skinning"`.
    #[serde(default)]
    pub flesh: Option<FleshMethodName>,
    /// Per-digit override of `flesh`: keys `palm`, `thumb`, `index`, `middle`, `ring`, `little`.
    #[serde(default)]
    pub flesh_digits: BTreeMap<String, FleshMethodName>,
    /// FEM region of a flexion increment: `"local"` (default: cells near moving joints) or
    /// `"whole"` (the whole hand).
    #[serde(default)]
    pub flesh_region: Option<FleshRegionName>,
    /// Radius of the local region around each moving joint, m (default 0.012).
    #[serde(default)]
    pub flesh_region_radius: Option<f64>,
    /// Skinning blend: `"dual_quaternion"` (default) or `"linear"`.
    #[serde(default)]
    pub skinning: Option<BlendName>,
    /// The parts of a hand (palm, thumb, fingers) that stay farther than `near_contact` from
    /// every other body over a keyframe: `"skinning"` (default: their flesh follows the bones,
    /// the FEM effort goes where contact is) or `"solve"` (solved like the rest).
    #[serde(default)]
    pub far_from_contact: Option<FarFromContact>,
    /// Distance under which a part of a hand counts as near contact, m (default 0.01).
    #[serde(default)]
    pub near_contact: Option<f64>,
    /// Penetration allowed at the end of the contact iteration, m (default 1e-9 × the largest
    /// body size).
    #[serde(default)]
    pub contact_tolerance: Option<f64>,
    /// Most contact iterations (default 50).
    #[serde(default)]
    pub contact_max_iterations: Option<usize>,
    /// Contact method: `"lagrange"` (default) or `"paper"`.
    #[serde(default)]
    pub contact: Option<ContactMethodName>,
    /// Relaxation of the paper's method's transferred forces.
    #[serde(default)]
    pub contact_relaxation: Option<RelaxationDef>,
    /// Convergence of the paper's method: largest displacement change between iterations, m.
    #[serde(default)]
    pub contact_change_tolerance: Option<f64>,
    /// Deepest penetration contact detection looks for, m.
    #[serde(default)]
    pub contact_search: Option<f64>,
    /// Which side is checked node against facet: `"skin_nodes"`, `"object_nodes"`, `"both"`.
    #[serde(default)]
    pub contact_pairs: Option<PairSidesName>,
    /// Radius around the contact within which hand flesh is solved with it, m (default 0.008).
    #[serde(default)]
    pub contact_region: Option<f64>,
    /// Whether a hand's skin is kept from passing through itself in the flexion increments
    /// (default false; experimental: docs/hand.md, "Self-contact").
    #[serde(default)]
    pub self_contact: Option<bool>,
    /// Default Coulomb friction coefficient of every contact (default 0).
    #[serde(default)]
    pub friction: Option<f64>,
    /// Flexion increments: `"corotational"` (default), `"updated_lagrangian"` (the paper's),
    /// `"linear"` or `"nonlinear"`.
    #[serde(default)]
    pub flexion: Option<FlexionSchemeName>,
    /// Speed against accuracy for the hands, in one key: `"skinning"`, `"linear"`,
    /// `"incremental"`, `"corotational"` or `"nonlinear"` (sets `flesh` and `flexion`).
    #[serde(default)]
    pub tier: Option<TierName>,
    /// Volumetric integration of the Neo-Hookean law of the nonlinear tier:
    /// `"mean_dilatation"` (default, free of volumetric locking) or `"full"` (2×2×2, locks as
    /// ν → ½).
    #[serde(default)]
    pub volumetric: Option<VolumetricName>,
    /// Element of the linear static solve: `"hex8"` (default) or `"incompatible_modes"`.
    #[serde(default)]
    pub element: Option<ElementName>,
    /// The memory a solve may take: bytes, or a string with a unit (`"8 GB"`, `"512 MiB"`);
    /// default: what the machine has free. A job that would need more is refused before it
    /// allocates.
    #[serde(default)]
    pub max_memory: Option<MemorySize>,
}

/// `[solver] max_memory`: a number of bytes, or a string with a unit.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(
    untagged,
    expecting = "expected a number of bytes or a size with its unit, e.g. \"8 GB\" or \"512 MiB\""
)]
pub enum MemorySize {
    /// Bytes.
    Bytes(f64),
    /// A number and a unit: B, kB, MB, GB, TB (powers of 1000) or KiB, MiB, GiB, TiB.
    Text(String),
}

/// `[solver] tier`: how the hands' flesh is solved, fastest first.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TierName {
    /// Geometric skinning, no mechanics (`flesh = "skinning"`).
    Skinning,
    /// Linear elasticity on the rest geometry, factored once (`flexion = "linear"`).
    Linear,
    /// The paper's updated-Lagrangian increments (`flexion = "updated_lagrangian"`).
    Incremental,
    /// Corotated increments (`flexion = "corotational"`, the default).
    Corotational,
    /// Large-strain hyperelasticity: Neo-Hookean flesh and bodies, Newton–Raphson
    /// (`flexion = "nonlinear"` for the hands).
    Nonlinear,
}

/// `[solver] far_from_contact`: what flexion does with the parts of a hand far from contact.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FarFromContact {
    /// Skinning: the FEM effort goes where contact is.
    Skinning,
    /// Solved by the scene's tier like the parts near contact.
    Solve,
}

/// Name of a flexion region.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FleshRegionName {
    /// Cells near moving joints.
    Local,
    /// Every cell.
    Whole,
}

/// Name of a fill-reducing ordering.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum OrderingName {
    /// Whichever of the two below leaves less fill in the factor (the default).
    Auto,
    /// Geometric nested dissection.
    NestedDissection,
    /// Approximate minimum degree.
    Amd,
}

/// `[[material]]`
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDef {
    /// Name used by bodies and regions.
    pub name: String,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Density, kg/m³.
    #[serde(default)]
    pub density: f64,
}

/// `[[body]]`
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    /// Unique name.
    pub name: String,
    /// Material of its cells (regions may override).
    pub material: String,
    /// Its geometry.
    pub shape: Shape,
    /// A hand's initial pose: joint angles in degrees by name (rest when absent).
    #[serde(default)]
    pub pose: Option<BTreeMap<String, f64>>,
    /// A hand's muscle force thresholds by bone (N), e.g. `{ "index.distal" = 20 }`, over the
    /// defaults from human finger strength.
    #[serde(default)]
    pub bone_thresholds: Option<BTreeMap<String, f64>>,
}

fn one() -> f64 {
    1.0
}

/// A body's geometry.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// An axis-aligned box.
    Box {
        /// Lower corner, m.
        min: [f64; 3],
        /// Upper corner, m.
        max: [f64; 3],
        /// Cells along x, y, z.
        cells: [usize; 3],
    },
    /// A solid ball.
    Sphere {
        /// Centre, m.
        center: [f64; 3],
        /// Radius, m.
        radius: f64,
        /// Cells across the diameter.
        cells: usize,
        /// Finer cells where the ball is touched (a graded mesh); uniform when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        refine: Option<Refine>,
    },
    /// A hollow ball (cubed sphere).
    Shell {
        /// Centre, m.
        center: [f64; 3],
        /// Inner radius, m.
        inner_radius: f64,
        /// Outer radius, m.
        outer_radius: f64,
        /// Cells along each edge of each of the six cube faces.
        cells: usize,
        /// Cells through the wall.
        layers: usize,
        /// Finer cells where the ball is touched (a graded mesh); uniform when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        refine: Option<Refine>,
    },
    /// The built-in hand: skeleton, bones and flesh, meshed at `resolution` (1 = default: 3.2 mm
    /// lattice, 1.6 mm on the finger-tip pads).
    Hand {
        /// `"right"` or `"left"`.
        side: HandSide,
        /// Mesh resolution (0.5 … 4).
        #[serde(default = "one")]
        resolution: f64,
        /// Every cell of the lattice split into n × n × n (1, the default, to 4): the nested
        /// refinement, which refines the finite elements of the hand meshed at `resolution`
        /// without meshing another (docs/hand.md, "Nested refinement"). The built-in hand's.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        subdivisions: Option<usize>,
        /// A rigged hand from a glTF 2.0 file (`.glb`, or `.gltf`), relative to the scene file:
        /// its skin and its joints instead of the built-in hand's (docs/hand.md, "Your own
        /// hand").
        #[serde(default, skip_serializing_if = "Option::is_none")]
        gltf: Option<String>,
        /// The rig's node at each joint, by joint key (`wrist`, `index.proximal` for the joint
        /// at the start of the index's proximal phalanx, …, `index.tip`), where the node names
        /// are not in one of the conventions recognised (Mixamo, Rigify, MakeHuman, Unreal).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        bones: Option<BTreeMap<String, String>>,
        /// Where the rig goes in the scene.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        placement: Option<Placement>,
        /// The built-in hand's size: an ANSUR II percentile (`"male-50"`, …) or
        /// `{ length, breadth }` in metres; the anatomy tables' own when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        size: Option<HandSizeDef>,
        /// The built-in hand's form: `"anatomical"` (the default: the thumb at its natural rest,
        /// the palm's arches and eminences, knuckles and pulps; docs/hand.md) or `"simple"`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        form: Option<String>,
    },
    /// An explicit mesh: node coordinates and 8-node cells (VTK order; repeat nodes for prisms
    /// and tetrahedra).
    Mesh {
        /// Node positions, m.
        nodes: Vec<[f64; 3]>,
        /// Cells as 0-based node indices.
        cells: Vec<[usize; 8]>,
    },
}

/// `size = "female-50"` or `size = { length = 0.18, breadth = 0.078 }`: the built-in hand's size
/// (`hand::size`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "expected an ANSUR II percentile such as \"male-50\" or { length = …, breadth = … } in metres"
)]
pub enum HandSizeDef {
    /// `"female-5"`, `"female-50"`, `"female-95"`, `"male-5"`, `"male-50"`, `"male-95"`.
    Percentile(String),
    /// Measured.
    Measured {
        /// Wrist crease to the tip of the middle finger, m.
        length: f64,
        /// Across the metacarpal heads, m; in the built-in hand's proportion when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        breadth: Option<f64>,
    },
}

/// `placement = { translation = [x, y, z], rotation = [rx, ry, rz], scale = 1 }`: an imported
/// rig, once turned from glTF's Y-up to the scene's Z-up, is scaled, turned (Euler angles in
/// degrees, X then Y then Z, as Blender's) and moved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// Translation, m.
    #[serde(default)]
    pub translation: [f64; 3],
    /// Rotation, degrees about x, y, z.
    #[serde(default)]
    pub rotation: [f64; 3],
    /// Scale (0.01 for a rig modelled in centimetres).
    #[serde(default = "one")]
    pub scale: f64,
}

impl Default for Placement {
    fn default() -> Placement {
        Placement {
            translation: [0.0; 3],
            rotation: [0.0; 3],
            scale: 1.0,
        }
    }
}

/// `refine = { toward = [x, y, z], size = 0.001 }`: a ball's mesh graded toward the point of its
/// surface nearest `toward` (on a shell, of the outer surface, or of the inner one when `toward`
/// lies in the cavity): cells of `size` there, growing by 1.25 from one to the next up to the
/// size that `cells` (and `layers`) give.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Refine {
    /// A point, m: the surface is refined where it is nearest this point (not the centre).
    pub toward: [f64; 3],
    /// The cells' size at the touched point, m; by default 1/32 of the touched surface's radius.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<f64>,
}

/// A selection of nodes (and of boundary facets) of one body.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Selection {
    /// A face of a box body: `x-`, `x+`, `y-`, `y+`, `z-`, `z+`.
    Face(String),
    /// `outer` (every body) or `inner` (a shell's cavity).
    Surface(String),
    /// The node nearest a point.
    Point([f64; 3]),
    /// The flesh nodes attached to a bone of a hand, e.g. `"index.distal"`.
    Bone(String),
    /// Nodes inside an axis-aligned box (facets with all their nodes inside).
    Box {
        /// Lower corner.
        min: [f64; 3],
        /// Upper corner.
        max: [f64; 3],
    },
}

/// `[[region]]`: cells of a body (all eight nodes selected) made of another material.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionDef {
    /// The body.
    pub body: String,
    /// The material of the region.
    pub material: String,
    /// Which cells.
    #[serde(rename = "where")]
    pub selection: Selection,
}

/// A prescribed displacement: all three components, or some of them.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(
    untagged,
    expecting = "expected [ux, uy, uz] in metres, or some components, e.g. { z = -0.001 }"
)]
pub enum DisplacementDef {
    /// `[ux, uy, uz]`
    All([f64; 3]),
    /// `{ x = .., z = .. }`: only the named components are prescribed.
    Some(Components),
}

/// Optional components.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Components {
    /// Along x, m.
    pub x: Option<f64>,
    /// Along y, m.
    pub y: Option<f64>,
    /// Along z, m.
    pub z: Option<f64>,
}

impl DisplacementDef {
    /// The prescribed components (None where free).
    pub fn components(&self) -> [Option<f64>; 3] {
        match self {
            DisplacementDef::All(u) => u.map(Some),
            DisplacementDef::Some(c) => [c.x, c.y, c.z],
        }
    }
}

/// `[[constraint]]`
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintDef {
    /// Unique name (the report's key).
    pub name: String,
    /// The body.
    pub body: String,
    /// Which nodes.
    #[serde(rename = "where")]
    pub selection: Selection,
    /// Prescribed displacement, m.
    pub displacement: DisplacementDef,
}

/// `[[load]]`: exactly one of `pressure`, `traction` and `force`; a pressure may be a gas
/// cavity's (`gas = true`).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadDef {
    /// Optional name.
    #[serde(default)]
    pub name: Option<String>,
    /// The body.
    pub body: String,
    /// Where it acts.
    #[serde(rename = "where")]
    pub selection: Selection,
    /// Pressure on the selected facets, Pa, pushing against their outward normal.
    #[serde(default)]
    pub pressure: Option<f64>,
    /// The pressure is that of a gas sealed in the cavity the selection encloses (isothermal:
    /// p·V constant in absolute pressure); `pressure` is then its gauge pressure when the cavity
    /// has the volume of the mesh as given.
    #[serde(default)]
    pub gas: bool,
    /// With `gas`: the absolute ambient pressure, Pa (101325 when not given).
    #[serde(default)]
    pub ambient: Option<f64>,
    /// Total force shared equally by the selected nodes, N.
    #[serde(default)]
    pub force: Option<[f64; 3]>,
    /// Uniform traction (force per unit area) on the selected facets, Pa.
    #[serde(default)]
    pub traction: Option<[f64; 3]>,
}

/// `[[probe]]`
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeDef {
    /// Unique name.
    pub name: String,
    /// The body.
    pub body: String,
    /// The point; the nearest node of the body is reported.
    pub point: [f64; 3],
}
