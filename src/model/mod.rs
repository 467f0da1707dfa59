//! `Model::build`: from a scene to meshes, materials, prescribed dofs and the load vector.
//! Everything here is fixed for a frame; the solve produces the state.

mod convert;
mod flexion_settings;
mod select;
mod tier;

pub use flexion_settings::{FleshMethod, FleshRegion, FlexionScheme, FlexionSettings};
pub use tier::{Tier, STEP_WARNING_DEG};

use crate::contact::{ContactSettings, Obstacle, Relaxation};
use crate::fem::assembly::StiffnessPattern;
use crate::fem::hex8::{cell_volume, relative_min_jacobian};
use crate::fem::loads::{add_gravity, add_pressure, add_shared_force, add_traction};
use crate::fem::rigid::free_rigid_motions;
use crate::fem::solve::FillOrdering;
use crate::fem::{DofPartition, Material};
use crate::hand::HandModel;
use crate::mesh::{boundary_facets, box_mesh, shell_mesh, sphere_mesh, Facet, Mesh};
use crate::scene::{
    FarFromContact, FleshRegionName, ObstacleShape, OrderingName, RelaxationDef, Scene, SceneError,
    Shape, SolverSettings,
};
use nalgebra::Vector3;
use select::select;
use std::collections::HashMap;
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
    /// Longest edge of its bounding box, m.
    pub size: f64,
    /// Volume, m³.
    pub volume: f64,
    /// Mass, kg.
    pub mass: f64,
    /// The hand, for a hand body (its flesh is this body's mesh).
    pub hand: Option<Arc<HandModel>>,
    /// A hand's joint angles at time 0 (its `pose`), degrees; empty for other bodies.
    pub initial_angles: Vec<f64>,
    /// A hand's muscle force threshold of every bone, N; empty for other bodies.
    pub thresholds: Vec<f64>,
    /// Held by nothing but contact (no prescribed displacement): stabilised by weak ground
    /// springs, and checked to be held after the solve.
    pub floating: bool,
}

/// A keyframe: the full joint angles of one hand at a time.
#[derive(Clone, Debug)]
pub struct KeyframeModel {
    /// Time, s.
    pub time: f64,
    /// The hand body.
    pub body: usize,
    /// All its joint angles, degrees (joints the keyframe does not name keep their previous
    /// angle).
    pub angles: Vec<f64>,
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
#[derive(Debug)]
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
    /// Total gravity force, N.
    pub gravity_total: Vector3<f64>,
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
    /// Warnings about the settings (the model is usable; `report.json` lists them).
    pub warnings: Vec<String>,
    /// Element of the linear static solve (`[solver] element`).
    pub element: crate::fem::ElementKind,
    /// The bodies other than hands are solved at large strain by Newton (`[solver] tier =
    /// "nonlinear"`), not by one linear solve.
    pub nonlinear_statics: bool,
}

fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

impl Model {
    /// Builds the model; `file` names the scene in errors.
    pub fn build(scene: &Scene, file: &str) -> Result<Model, SceneError> {
        let err = |field: String, message: String| SceneError::invalid(file, field, message);

        // Materials.
        let mut material_index: HashMap<&str, usize> = HashMap::new();
        let mut materials = Vec::new();
        for (i, m) in scene.material.iter().enumerate() {
            let field = format!("material \"{}\" (material[{i}])", m.name);
            if material_index.insert(&m.name, i).is_some() {
                return Err(err(
                    field,
                    "a material of this name is defined twice".into(),
                ));
            }
            let mat = Material {
                young: m.young,
                poisson: m.poisson,
                density: m.density,
            };
            mat.check().map_err(|msg| err(field, msg))?;
            materials.push(mat);
        }
        let find_material = |name: &str, field: String| -> Result<usize, SceneError> {
            material_index.get(name).copied().ok_or_else(|| {
                let known: Vec<&str> = scene.material.iter().map(|m| m.name.as_str()).collect();
                err(
                    field,
                    format!("no material named \"{name}\" (defined: {})", list(&known)),
                )
            })
        };

        // Bodies.
        if scene.body.is_empty() {
            return Err(err("body".into(), "the scene defines no [[body]]".into()));
        }
        let mut mesh = Mesh::default();
        let mut bodies: Vec<BodyModel> = Vec::new();
        let mut cell_material = Vec::new();
        let mut cell_body = Vec::new();
        for (i, b) in scene.body.iter().enumerate() {
            let field = format!("body \"{}\" (body[{i}])", b.name);
            if bodies.iter().any(|o| o.name == b.name) {
                return Err(err(field, "a body of this name is defined twice".into()));
            }
            let material = find_material(&b.material, format!("{field}.material"))?;
            let hand = match &b.shape {
                Shape::Hand { side, resolution } => Some(Arc::new(
                    HandModel::new((*side).into(), *resolution)
                        .map_err(|e| err(format!("{field}.shape.hand"), e.to_string()))?,
                )),
                _ => {
                    if b.pose.is_some() {
                        return Err(err(
                            format!("{field}.pose"),
                            "only hand bodies have a pose".into(),
                        ));
                    }
                    None
                }
            };
            let initial_angles = match &hand {
                Some(hand) => hand
                    .skeleton
                    .apply_pose(
                        &hand.skeleton.rest_angles(),
                        &b.pose.clone().unwrap_or_default(),
                    )
                    .map_err(|e| err(format!("{field}.pose"), e.to_string()))?,
                None => Vec::new(),
            };
            let body_mesh = match &hand {
                Some(h) => h.flesh.mesh.clone(),
                None => build_shape(&b.shape).map_err(|m| err(format!("{field}.shape"), m))?,
            };
            for (c, _) in body_mesh.cells.iter().enumerate() {
                let rel = relative_min_jacobian(&body_mesh.cell_coords(c));
                if rel.is_nan() || rel <= 1e-12 {
                    return Err(err(
                        format!("{field}.shape"),
                        format!(
                            "element {c} is inverted or has zero volume (smallest det J / size³ = \
                             {rel:.3e})"
                        ),
                    ));
                }
            }
            let facets = match &hand {
                Some(h) => h
                    .flesh
                    .skin_quads
                    .iter()
                    .zip(&h.flesh.skin_cells)
                    .map(|(q, &cell)| Facet { nodes: *q, cell })
                    .collect(),
                None => boundary_facets(&body_mesh),
            };
            let (node_offset, cell_offset) = mesh.append(&body_mesh);
            let facets = facets
                .into_iter()
                .map(|f| Facet {
                    nodes: f.nodes.map(|n| n + node_offset),
                    cell: f.cell + cell_offset,
                })
                .collect();
            let mut lo = body_mesh.nodes[0];
            let mut hi = lo;
            for p in &body_mesh.nodes {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
            let volume: f64 = (0..body_mesh.cell_count())
                .map(|c| cell_volume(&body_mesh.cell_coords(c)))
                .sum();
            bodies.push(BodyModel {
                name: b.name.clone(),
                shape: b.shape.clone(),
                nodes: node_offset..node_offset + body_mesh.node_count(),
                cells: cell_offset..cell_offset + body_mesh.cell_count(),
                facets,
                size: (hi - lo).max(),
                volume,
                mass: 0.0,
                thresholds: match &hand {
                    Some(h) => thresholds(h, b.bone_thresholds.as_ref())
                        .map_err(|m| err(format!("{field}.bone_thresholds"), m))?,
                    None => {
                        if b.bone_thresholds.is_some() {
                            return Err(err(
                                format!("{field}.bone_thresholds"),
                                "only a hand has bones".into(),
                            ));
                        }
                        Vec::new()
                    }
                },
                hand,
                initial_angles,
                floating: false,
            });
            cell_material.extend(std::iter::repeat_n(material, body_mesh.cell_count()));
            cell_body.extend(std::iter::repeat_n(i, body_mesh.cell_count()));
        }
        let find_body = |name: &str, field: String| -> Result<usize, SceneError> {
            bodies.iter().position(|b| b.name == name).ok_or_else(|| {
                let known: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
                err(
                    field,
                    format!("no body named \"{name}\" (defined: {})", list(&known)),
                )
            })
        };

        // Regions of other materials.
        for (i, r) in scene.region.iter().enumerate() {
            let field = format!("region[{i}]");
            let b = find_body(&r.body, format!("{field}.body"))?;
            let m = find_material(&r.material, format!("{field}.material"))?;
            let sel = select(&bodies[b], &mesh, &r.selection)
                .map_err(|msg| err(format!("{field}.where"), msg))?;
            let mut chosen = vec![false; mesh.node_count()];
            for &n in &sel.nodes {
                chosen[n] = true;
            }
            let mut count = 0;
            for c in bodies[b].cells.clone() {
                if mesh.cells[c].iter().all(|&n| chosen[n]) {
                    cell_material[c] = m;
                    count += 1;
                }
            }
            if count == 0 {
                return Err(err(
                    format!("{field}.where"),
                    "contains no whole element of the body (a region takes the elements whose \
                     eight nodes are all selected)"
                        .into(),
                ));
            }
        }
        let cell_materials: Vec<Material> = cell_material.iter().map(|&m| materials[m]).collect();

        // Constraints.
        let dofs = 3 * mesh.node_count();
        let mut prescribed_mask = vec![false; dofs];
        let mut prescribed = vec![0.0; dofs];
        let mut owner = vec![usize::MAX; dofs];
        let mut constraints: Vec<ConstraintModel> = Vec::new();
        for (i, c) in scene.constraint.iter().enumerate() {
            let field = format!("constraint \"{}\" (constraint[{i}])", c.name);
            if constraints.iter().any(|o| o.name == c.name) {
                return Err(err(
                    field,
                    "a constraint of this name is defined twice".into(),
                ));
            }
            let b = find_body(&c.body, format!("{field}.body"))?;
            let sel = select(&bodies[b], &mesh, &c.selection)
                .map_err(|msg| err(format!("{field}.where"), msg))?;
            let components = c.displacement.components();
            if bodies[b].hand.is_some()
                && (!matches!(c.selection, crate::scene::Selection::Bone(_))
                    || components.iter().any(|v| *v != Some(0.0)))
            {
                return Err(err(
                    field,
                    "a hand moves with its skeleton (pose and keyframes): a constraint on a hand \
                     selects a bone (`where = { bone = \"index.distal\" }`) with `displacement = \
                     [0, 0, 0]`, and reports that bone's reaction under its name"
                        .into(),
                ));
            }
            if components.iter().all(Option::is_none) {
                return Err(err(
                    format!("{field}.displacement"),
                    "prescribes no component (give x, y or z)".into(),
                ));
            }
            if components.iter().flatten().any(|v| !v.is_finite()) {
                return Err(err(
                    format!("{field}.displacement"),
                    "is not a finite number".into(),
                ));
            }
            let mut own = Vec::new();
            for &n in &sel.nodes {
                for (axis, value) in components.iter().enumerate() {
                    let Some(value) = *value else { continue };
                    let d = 3 * n + axis;
                    if prescribed_mask[d] {
                        if (prescribed[d] - value).abs() > 1e-15 * (1.0 + value.abs()) {
                            return Err(err(
                                format!("{field}.displacement"),
                                format!(
                                    "node {} is already prescribed along {} by constraint \"{}\" \
                                     with another value ({} m against {} m)",
                                    n - bodies[b].nodes.start,
                                    ["x", "y", "z"][axis],
                                    constraints[owner[d]].name,
                                    prescribed[d],
                                    value
                                ),
                            ));
                        }
                        continue;
                    }
                    prescribed_mask[d] = true;
                    prescribed[d] = value;
                    owner[d] = constraints.len();
                    own.push(d);
                }
            }
            constraints.push(ConstraintModel {
                name: c.name.clone(),
                body: b,
                dofs: own,
            });
        }

        // A hand moves by its skeleton, solved increment by increment (sim::flexion); in the
        // static solve of the other bodies all its nodes are held where they are.
        for body in &bodies {
            if body.hand.is_some() {
                prescribed_mask[3 * body.nodes.start..3 * body.nodes.end].fill(true);
            }
        }

        // Loads.
        let mut load_vector = vec![0.0; dofs];
        let mut loads = Vec::new();
        for (i, l) in scene.load.iter().enumerate() {
            let name = l.name.clone().unwrap_or_else(|| format!("load[{i}]"));
            let field = format!("load \"{name}\" (load[{i}])");
            let b = find_body(&l.body, format!("{field}.body"))?;
            if bodies[b].hand.is_some() {
                return Err(err(
                    format!("{field}.body"),
                    "loads on a hand are not supported: the hand is driven by its skeleton".into(),
                ));
            }
            let sel = select(&bodies[b], &mesh, &l.selection)
                .map_err(|msg| err(format!("{field}.where"), msg))?;
            let kinds = [
                l.pressure.is_some(),
                l.traction.is_some(),
                l.force.is_some(),
            ];
            if kinds.iter().filter(|&&k| k).count() != 1 {
                return Err(err(
                    field,
                    "give exactly one of `pressure` (Pa), `traction` ([tx, ty, tz] Pa) and \
                     `force` ([fx, fy, fz] N)"
                        .into(),
                ));
            }
            let values: Vec<f64> = l
                .pressure
                .into_iter()
                .chain(l.traction.into_iter().flatten())
                .chain(l.force.into_iter().flatten())
                .collect();
            if !finite(&values) {
                return Err(err(
                    field,
                    "holds a value that is not a finite number".into(),
                ));
            }
            if l.force.is_none() && sel.facets.is_empty() {
                return Err(err(
                    format!("{field}.where"),
                    "selects no boundary facet, and a pressure or traction acts on facets (use \
                     a face, a surface or a box)"
                        .into(),
                ));
            }
            let total = if let Some(p) = l.pressure {
                add_pressure(&mut load_vector, &mesh, &sel.facets, p)
            } else if let Some(t) = l.traction {
                add_traction(&mut load_vector, &mesh, &sel.facets, &Vector3::from(t))
            } else {
                let f = Vector3::from(l.force.unwrap());
                add_shared_force(&mut load_vector, &sel.nodes, &f);
                f
            };
            loads.push(LoadModel {
                name,
                body: b,
                total,
            });
        }
        let mut gravity_total = Vector3::zeros();
        if let Some(g) = scene.world.gravity {
            if !finite(&g) {
                return Err(err("world.gravity".into(), "is not a finite vector".into()));
            }
            // The weight of a hand's flesh (a few newtons at most, held by its bones) is not
            // modelled: the hand moves by its skeleton.
            for body in bodies.iter().filter(|b| b.hand.is_none()) {
                gravity_total += add_gravity(
                    &mut load_vector,
                    &mesh,
                    &cell_materials,
                    body.cells.clone(),
                    &Vector3::from(g),
                )
                .map_err(|e| {
                    err(
                        "world.gravity".into(),
                        format!("element {} is inverted", e.cell),
                    )
                })?;
            }
        }

        // Probes.
        let mut probes = Vec::new();
        for (i, p) in scene.probe.iter().enumerate() {
            let field = format!("probe \"{}\" (probe[{i}])", p.name);
            if probes.iter().any(|o: &ProbeModel| o.name == p.name) {
                return Err(err(field, "a probe of this name is defined twice".into()));
            }
            if !finite(&p.point) {
                return Err(err(
                    format!("{field}.point"),
                    "is not a finite point".into(),
                ));
            }
            let b = find_body(&p.body, format!("{field}.body"))?;
            let sel = select(&bodies[b], &mesh, &crate::scene::Selection::Point(p.point))
                .map_err(|msg| err(format!("{field}.point"), msg))?;
            probes.push(ProbeModel {
                name: p.name.clone(),
                body: b,
                point: Vector3::from(p.point),
                node: sel.nodes[0],
            });
        }

        // Every piece of every body must be held against rigid motion, or (a body with no
        // support at all, in a scene with obstacles or hands) be held by contact.
        let mut floating = Vec::new();
        let (piece, pieces) = mesh.connected_pieces();
        let mut piece_nodes: Vec<Vec<usize>> = vec![Vec::new(); pieces];
        for (n, &p) in piece.iter().enumerate() {
            piece_nodes[p].push(n);
        }
        for (b, body) in bodies.iter().enumerate() {
            let mut body_pieces: Vec<usize> = body.nodes.clone().map(|n| piece[n]).collect();
            body_pieces.sort_unstable();
            body_pieces.dedup();
            for (k, &p) in body_pieces.iter().enumerate() {
                let free = free_rigid_motions(&piece_nodes[p], &mesh.nodes, |d| prescribed_mask[d]);
                let untouched = body
                    .nodes
                    .clone()
                    .all(|n| (0..3).all(|a| !prescribed_mask[3 * n + a]));
                let holders = !scene.obstacle.is_empty() || bodies.iter().any(|o| o.hand.is_some());
                if !free.is_empty()
                    && untouched
                    && body_pieces.len() == 1
                    && holders
                    && body.hand.is_none()
                {
                    floating.push(b);
                    continue;
                }
                if !free.is_empty() {
                    let which = if body_pieces.len() > 1 {
                        format!(
                            " (piece {} of {}, {} nodes)",
                            k + 1,
                            body_pieces.len(),
                            piece_nodes[p].len()
                        )
                    } else {
                        String::new()
                    };
                    return Err(err(
                        format!("body \"{}\" (body[{b}])", body.name),
                        format!(
                            "is free to move rigidly{which}: the constraints leave {} free; \
                             prescribe more displacements on it",
                            list(&free.iter().map(String::as_str).collect::<Vec<_>>())
                        ),
                    ));
                }
            }
        }

        for &b in &floating {
            bodies[b].floating = true;
        }
        let flexion = flexion_settings(&scene.solver).map_err(|(f, m)| err(f, m))?;
        let keyframes = keyframes(scene, &bodies).map_err(|(f, m)| err(f, m))?;
        let has_hand = bodies.iter().any(|b| b.hand.is_some());
        let mut warnings = tier::flexion_warnings(&flexion, has_hand);
        let has_object = bodies.iter().any(|b| b.hand.is_none());
        warnings.extend(tier::nonlinear_contact_warning(
            scene.solver.tier,
            has_hand,
            has_object,
        ));
        for (i, c) in scene.camera.iter().enumerate() {
            let field = format!("camera \"{}\" (camera[{i}])", c.name);
            if scene.camera[..i].iter().any(|o| o.name == c.name) {
                return Err(err(field, "a camera of this name is defined twice".into()));
            }
            let (eye, target, up) = (
                Vector3::from(c.eye),
                Vector3::from(c.target),
                Vector3::from(c.up),
            );
            if !(finite(&c.eye) && finite(&c.target) && finite(&c.up)) {
                return Err(err(field, "eye, target and up must be finite".into()));
            }
            if (eye - target).norm() < 1e-9 || up.cross(&(eye - target)).norm() < 1e-12 {
                return Err(err(
                    field,
                    "eye must differ from target, and up must not be along the view".into(),
                ));
            }
            if !(1.0..=170.0).contains(&c.fov_deg) {
                return Err(err(
                    format!("{field}.fov_deg"),
                    format!("must be between 1 and 170 degrees, got {}", c.fov_deg),
                ));
            }
        }
        let cameras = scene.camera.clone();

        // Rigid obstacles and the nodes that may touch them.
        let mut obstacles = Vec::new();
        for (i, o) in scene.obstacle.iter().enumerate() {
            let field = format!("obstacle \"{}\" (obstacle[{i}])", o.name);
            if scene.obstacle[..i].iter().any(|p| p.name == o.name) {
                return Err(err(
                    field,
                    "an obstacle of this name is defined twice".into(),
                ));
            }
            let obstacle = match &o.shape {
                ObstacleShape::Plane { point, normal } => {
                    let n = Vector3::from(*normal);
                    if !(finite(point) && finite(normal)) || n.norm() < 1e-12 {
                        return Err(err(
                            format!("{field}.shape.plane"),
                            "needs a finite point and a non-zero finite normal".into(),
                        ));
                    }
                    Obstacle::Plane {
                        point: Vector3::from(*point),
                        normal: n.normalize(),
                    }
                }
                ObstacleShape::Sphere { center, radius } => {
                    if !(finite(center) && radius.is_finite() && *radius > 0.0) {
                        return Err(err(
                            format!("{field}.shape.sphere"),
                            format!("needs a finite center and a radius > 0 (radius = {radius})"),
                        ));
                    }
                    Obstacle::Sphere {
                        center: Vector3::from(*center),
                        radius: *radius,
                    }
                }
            };
            obstacles.push((o.name.clone(), obstacle));
        }
        let mut contact_candidates: Vec<usize> = bodies
            .iter()
            .filter(|b| b.hand.is_none())
            .flat_map(|b| b.facets.iter().flat_map(|f| f.nodes))
            .collect();
        contact_candidates.sort_unstable();
        contact_candidates.dedup();
        let largest = bodies.iter().map(|b| b.size).fold(0.0, f64::max);
        let contact = contact_settings(&scene.solver, largest).map_err(|(f, m)| err(f, m))?;
        let contact_region = scene.solver.contact_region.unwrap_or(0.008);
        let friction = friction_table(scene).map_err(|(f, m)| err(f, m))?;
        let mut node_cell = vec![usize::MAX; mesh.node_count()];
        for (c, cell) in mesh.cells.iter().enumerate().rev() {
            for &n in cell {
                node_cell[n] = c;
            }
        }
        let ordering = match scene.solver.ordering {
            Some(OrderingName::Amd) => FillOrdering::Amd,
            _ => FillOrdering::NestedDissection,
        };
        for b in &mut bodies {
            b.mass = b
                .cells
                .clone()
                .map(|c| cell_materials[c].density * cell_volume(&mesh.cell_coords(c)))
                .sum();
        }
        let pattern = Arc::new(StiffnessPattern::new(&mesh));
        Ok(Model {
            mesh,
            bodies,
            material_names: scene.material.iter().map(|m| m.name.clone()).collect(),
            cell_material,
            cell_materials,
            cell_body,
            constraints,
            loads,
            gravity_total,
            probes,
            partition: DofPartition::new(prescribed_mask),
            prescribed,
            load_vector,
            pattern,
            ordering,
            flexion,
            keyframes,
            cameras,
            obstacles,
            contact_candidates,
            contact,
            contact_region,
            friction,
            node_cell,
            warnings,
            element: scene.solver.element.unwrap_or_default().into(),
            nonlinear_statics: scene.solver.tier == Some(crate::scene::TierName::Nonlinear),
        })
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

/// The muscle force thresholds of a hand's bones: the defaults, overridden by name.
fn thresholds(
    hand: &HandModel,
    given: Option<&std::collections::BTreeMap<String, f64>>,
) -> Result<Vec<f64>, String> {
    let bones = &hand.skeleton.bones;
    let mut out: Vec<f64> = bones
        .iter()
        .map(|b| crate::hand::anatomy::bone_threshold(&b.name))
        .collect();
    for (name, &value) in given.into_iter().flatten() {
        let b = hand.skeleton.bone_index(name).ok_or_else(|| {
            format!(
                "no bone \"{name}\"; the bones are {}",
                hand.skeleton.bone_names()
            )
        })?;
        if !(value.is_finite() && value > 0.0) {
            return Err(format!(
                "\"{name}\": a threshold is a force > 0 N, got {value}"
            ));
        }
        out[b] = value;
    }
    Ok(out)
}

/// The contact settings of `[solver]`.
fn contact_settings(s: &SolverSettings, largest: f64) -> Result<ContactSettings, (String, String)> {
    let mut out = ContactSettings {
        tolerance: s.contact_tolerance.unwrap_or(1e-9 * largest),
        max_iterations: s.contact_max_iterations.unwrap_or(50),
        method: s.contact.unwrap_or_default().into(),
        pairs: s.contact_pairs.unwrap_or_default().into(),
        ..ContactSettings::default()
    };
    if !(out.tolerance.is_finite() && out.tolerance >= 0.0) {
        return Err((
            "solver.contact_tolerance".into(),
            format!("must be a length ≥ 0 m, got {}", out.tolerance),
        ));
    }
    if out.max_iterations == 0 {
        return Err((
            "solver.contact_max_iterations".into(),
            "must be at least 1".into(),
        ));
    }
    if let Some(c) = s.contact_change_tolerance {
        if !(c.is_finite() && c > 0.0) {
            return Err((
                "solver.contact_change_tolerance".into(),
                format!("must be a length > 0 m, got {c}"),
            ));
        }
        out.change_tolerance = c;
    }
    if let Some(d) = s.contact_search {
        if !(d.is_finite() && d > 0.0) {
            return Err((
                "solver.contact_search".into(),
                format!("must be a length > 0 m, got {d}"),
            ));
        }
        out.search_depth = d;
    }
    out.relaxation = match &s.contact_relaxation {
        None => Relaxation::Aitken,
        Some(RelaxationDef::Name(n)) if n == "aitken" => Relaxation::Aitken,
        Some(RelaxationDef::Factor(w)) if w.is_finite() && *w > 0.0 && *w <= 1.0 => {
            Relaxation::Fixed(*w)
        }
        Some(other) => {
            return Err((
                "solver.contact_relaxation".into(),
                format!("must be \"aitken\" or a factor in (0, 1], got {other:?}"),
            ))
        }
    };
    Ok(out)
}

/// The friction coefficients: `[solver] friction` and the `[[friction]]` pairs.
fn friction_table(scene: &Scene) -> Result<FrictionTable, (String, String)> {
    let default = scene.solver.friction.unwrap_or(0.0);
    if !(default.is_finite() && default >= 0.0) {
        return Err((
            "solver.friction".into(),
            format!("μ must be ≥ 0, got {default}"),
        ));
    }
    let mut pairs = Vec::new();
    for (i, f) in scene.friction.iter().enumerate() {
        let field = format!("friction[{i}]");
        for name in &f.between {
            let known = scene.material.iter().any(|m| &m.name == name)
                || scene.obstacle.iter().any(|o| &o.name == name);
            if !known {
                return Err((
                    format!("{field}.between"),
                    format!("\"{name}\" is neither a material nor an obstacle"),
                ));
            }
        }
        if !(f.mu.is_finite() && f.mu >= 0.0) {
            return Err((
                format!("{field}.mu"),
                format!("μ must be ≥ 0, got {}", f.mu),
            ));
        }
        pairs.push((f.between[0].clone(), f.between[1].clone(), f.mu));
    }
    Ok((default, pairs))
}

/// The flexion settings of `[solver]`.
fn flexion_settings(s: &SolverSettings) -> Result<FlexionSettings, (String, String)> {
    let mut out = FlexionSettings::default();
    if let Some(step) = s.max_step_deg {
        if !(step.is_finite() && step > 0.0 && step <= 45.0) {
            return Err((
                "solver.max_step_deg".into(),
                format!("must be in (0, 45] degrees, got {step}"),
            ));
        }
        out.max_step_deg = step;
    }
    if let Some(m) = s.flesh {
        out.methods = [m.into(); 6];
    }
    tier::apply_tier(s, &mut out)?;
    const PARTS: [&str; 6] = ["palm", "thumb", "index", "middle", "ring", "little"];
    for (name, &m) in &s.flesh_digits {
        let Some(i) = PARTS.iter().position(|p| p == name) else {
            return Err((
                format!("solver.flesh_digits.{name}"),
                format!("is not a part of the hand ({})", PARTS.join(", ")),
            ));
        };
        out.methods[i] = m.into();
    }
    let radius = s.flesh_region_radius.unwrap_or(0.012);
    if !(radius.is_finite() && radius > 0.0) {
        return Err((
            "solver.flesh_region_radius".into(),
            format!("must be a positive length in metres, got {radius}"),
        ));
    }
    out.region = match s.flesh_region {
        Some(FleshRegionName::Whole) => FleshRegion::Whole,
        _ => FleshRegion::Local { radius },
    };
    if let Some(b) = s.skinning {
        out.blend = b.into();
    }
    if let Some(v) = s.volumetric {
        out.volumetric = v.into();
    }
    let near = s.near_contact.unwrap_or(0.01);
    if !(near.is_finite() && near > 0.0) {
        return Err((
            "solver.near_contact".into(),
            format!("must be a positive distance in metres, got {near}"),
        ));
    }
    out.near_contact = match s.far_from_contact {
        Some(FarFromContact::Solve) => None,
        _ => Some(near),
    };
    if let Some(f) = s.flexion {
        out.scheme = f.into();
    }
    Ok(out)
}

/// The keyframes, validated: increasing times, an existing hand, known joints within limits.
fn keyframes(scene: &Scene, bodies: &[BodyModel]) -> Result<Vec<KeyframeModel>, (String, String)> {
    let hands: Vec<usize> = (0..bodies.len())
        .filter(|&b| bodies[b].hand.is_some())
        .collect();
    let mut angles: Vec<Vec<f64>> = bodies.iter().map(|b| b.initial_angles.clone()).collect();
    let mut out: Vec<KeyframeModel> = Vec::new();
    for (i, k) in scene.keyframe.iter().enumerate() {
        let field = format!("keyframe[{i}]");
        if !(k.time.is_finite() && k.time >= 0.0) {
            return Err((
                format!("{field}.time"),
                format!("must be a time ≥ 0 s, got {}", k.time),
            ));
        }
        if let Some(last) = out.last() {
            if k.time < last.time {
                return Err((
                    format!("{field}.time"),
                    format!(
                        "{} s comes before the previous keyframe's {} s: list keyframes in time order",
                        k.time, last.time
                    ),
                ));
            }
        }
        let body =
            match &k.body {
                Some(name) => {
                    let Some(b) = bodies.iter().position(|b| &b.name == name) else {
                        return Err((format!("{field}.body"), format!("no body named \"{name}\"")));
                    };
                    if bodies[b].hand.is_none() {
                        return Err((
                            format!("{field}.body"),
                            format!("body \"{name}\" is not a hand"),
                        ));
                    }
                    b
                }
                None => match hands.as_slice() {
                    [b] => *b,
                    [] => return Err((
                        field,
                        "the scene has no hand to pose (add a body with shape = { hand = { side \
                         = \"right\" } })"
                            .into(),
                    )),
                    _ => {
                        return Err((
                            format!("{field}.body"),
                            "the scene has several hands: name the one this keyframe poses".into(),
                        ))
                    }
                },
            };
        if out
            .last()
            .is_some_and(|l| l.time == k.time && l.body == body)
        {
            return Err((
                format!("{field}.time"),
                format!("a keyframe at {} s already poses this hand", k.time),
            ));
        }
        let hand = bodies[body].hand.as_ref().unwrap();
        angles[body] = hand
            .skeleton
            .apply_pose(&angles[body], &k.pose)
            .map_err(|e| (format!("{field}.pose"), e.to_string()))?;
        out.push(KeyframeModel {
            time: k.time,
            body,
            angles: angles[body].clone(),
        });
    }
    Ok(out)
}

fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}

/// Generates the mesh of a shape after checking its parameters.
fn build_shape(shape: &Shape) -> Result<Mesh, String> {
    const MAX_CELLS: usize = 5_000_000;
    match shape {
        Shape::Hand { .. } => Err("a hand is built by the hand module".into()),
        Shape::Mesh { nodes, cells } => {
            if nodes.is_empty() || cells.is_empty() {
                return Err("mesh needs at least one node and one cell".into());
            }
            if let Some(i) = nodes.iter().position(|p| !finite(p)) {
                return Err(format!("mesh node {i} is not a finite point"));
            }
            for (c, cell) in cells.iter().enumerate() {
                if let Some(&n) = cell.iter().find(|&&n| n >= nodes.len()) {
                    return Err(format!(
                        "mesh element {c} names node {n}, but there are {} nodes",
                        nodes.len()
                    ));
                }
            }
            Ok(Mesh {
                nodes: nodes.iter().map(|p| Vector3::from(*p)).collect(),
                cells: cells.clone(),
            })
        }
        Shape::Box { min, max, cells } => {
            if !finite(min) || !finite(max) {
                return Err("box min and max must be finite".into());
            }
            if (0..3).any(|i| max[i] <= min[i]) {
                return Err(format!(
                    "box max {max:?} must exceed min {min:?} on every axis"
                ));
            }
            if cells.contains(&0) {
                return Err(format!("box cells {cells:?} must all be at least 1"));
            }
            if cells.iter().product::<usize>() > MAX_CELLS {
                return Err(format!(
                    "box cells {cells:?} make more than {MAX_CELLS} elements"
                ));
            }
            Ok(box_mesh(Vector3::from(*min), Vector3::from(*max), *cells))
        }
        Shape::Sphere {
            center,
            radius,
            cells,
        } => {
            if !(finite(center) && radius.is_finite() && *radius > 0.0) {
                return Err(format!(
                    "sphere needs a finite center and a radius > 0 (radius = {radius})"
                ));
            }
            if *cells == 0 || cells.pow(3) > MAX_CELLS {
                return Err(format!(
                    "sphere cells = {cells} must be at least 1 and at most 170"
                ));
            }
            Ok(sphere_mesh(Vector3::from(*center), *radius, *cells))
        }
        Shape::Shell {
            center,
            inner_radius,
            outer_radius,
            cells,
            layers,
        } => {
            if !(finite(center) && inner_radius.is_finite() && *inner_radius > 0.0) {
                return Err(format!(
                    "shell needs a finite center and inner_radius > 0 (inner_radius = {inner_radius})"
                ));
            }
            if !(outer_radius.is_finite() && outer_radius > inner_radius) {
                return Err(format!(
                    "shell outer_radius = {outer_radius} must exceed inner_radius = {inner_radius}"
                ));
            }
            if *cells == 0 || *layers == 0 || 6 * cells * cells * layers > MAX_CELLS {
                return Err(format!(
                    "shell cells = {cells} and layers = {layers} must be at least 1 (and make at \
                     most {MAX_CELLS} elements)"
                ));
            }
            Ok(shell_mesh(
                Vector3::from(*center),
                *inner_radius,
                *outer_radius,
                *cells,
                *layers,
            ))
        }
    }
}
