//! The bodies: each shape meshed (or a hand model built), its elements checked, joined into one
//! mesh with its boundary facets, size, volume and (after the regions) mass; a hand's pose and
//! bone thresholds.

use super::check::list;
use super::hand_gltf::read_rigged_hand;
use super::materials::find_material;
use super::memory_estimate::fits_in_memory;
use super::names::shown;
use super::shapes::build_shape;
use super::BodyModel;
use crate::fem::hex8::{cell_volume, relative_min_jacobian};
use crate::fem::Material;
use crate::hand::{HandForm, HandModel, HandSize, Skeleton, SkinShape};
use crate::mesh::{aspect_ratio, boundary_facets, Facet, Mesh};
use crate::scene::{HandSizeDef, Placement, Scene, Shape};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use std::path::Path;
use std::sync::Arc;

/// Farthest a placement may move a hand, m (a scene is a few metres across; beyond this the
/// coordinates lose the precision the contact needs).
const MAX_PLACEMENT: f64 = 1.0e3;

/// The rigid motion `placement` gives the built-in hand (built in its own frame: x from the
/// wrist to the finger tips, y to the thumb of a right hand, z dorsal): turned (Euler angles in
/// degrees, about x, then y, then z, as an imported rig's) and moved. Its size is `size`'s.
fn builtin_placement(placement: &Placement) -> Result<Isometry3<f64>, String> {
    if placement.scale != 1.0 {
        return Err(format!(
            "the built-in hand is sized by `size` (an ANSUR II percentile, or {{ length, breadth }} \
             in metres), not `placement.scale` ({})",
            placement.scale
        ));
    }
    let t = placement.translation;
    if !t.iter().all(|x| x.is_finite() && x.abs() <= MAX_PLACEMENT) {
        return Err(format!(
            "`placement.translation` must be finite and within {MAX_PLACEMENT} m of the origin, \
             got {t:?}"
        ));
    }
    let r = placement.rotation;
    super::check::rotation(&r)?;
    let [rx, ry, rz] = r.map(f64::to_radians);
    Ok(Isometry3::from_parts(
        Translation3::from(Vector3::from(t)),
        UnitQuaternion::from_euler_angles(rx, ry, rz),
    ))
}

/// Largest ratio of an element's longest edge to its shortest: the stiffness along and across
/// such an element differ by about its square (a shell wall of 10⁻¹⁰ m on a 35 mm ball, ≈ 10⁸,
/// failed its factorization as if it could move freely; 10⁶ still solves).
const MAX_ASPECT: f64 = 1.0e6;

/// Smallest element a scene can hold, m: below it the volumes (size³) underflow toward zero
/// and the scene is not in metres.
const MIN_ELEMENT: f64 = 1.0e-9;

/// A hand's `subdivisions` (1, the lattice as it is, when absent), refused outside
/// 1 ..= [`crate::hand::MAX_SUBDIVISIONS`] before anything is read or meshed.
fn hand_subdivisions(subdivisions: Option<usize>) -> Result<usize, String> {
    let n = subdivisions.unwrap_or(1);
    if (1..=crate::hand::MAX_SUBDIVISIONS).contains(&n) {
        Ok(n)
    } else {
        Err(crate::hand::MeshingError::Subdivisions(n).to_string())
    }
}

/// A body's nodes within [`MAX_PLACEMENT`] of the origin and its elements at least
/// [`MIN_ELEMENT`] across (their longest edge).
fn check_extent(mesh: &Mesh) -> Result<(), String> {
    if let Some((n, p)) = mesh
        .nodes
        .iter()
        .enumerate()
        .find(|(_, p)| !p.iter().all(|x| x.abs() <= MAX_PLACEMENT))
    {
        return Err(format!(
            "node {n} lies at [{}] m, beyond {MAX_PLACEMENT} m from the origin: the scene is in \
             metres (a hand is about 0.2 m long)",
            p.iter()
                .map(|&x| crate::util::readable(x))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    for c in 0..mesh.cells.len() {
        let corners = mesh.cell_coords(c);
        let size = corners
            .iter()
            .flat_map(|a| corners.iter().map(move |b| (a - b).norm()))
            .fold(0.0, f64::max);
        if size.is_nan() || size < MIN_ELEMENT {
            return Err(format!(
                "element {c} is {} m across, smaller than {} m: the scene is in metres \
                 (a hand is about 0.2 m long)",
                crate::util::readable(size),
                crate::util::readable(MIN_ELEMENT)
            ));
        }
    }
    Ok(())
}

/// All bodies meshed one after the other.
pub struct Bodies {
    /// All bodies' meshes, one after the other.
    pub mesh: Mesh,
    /// Bodies (mass 0 until [`set_masses`], none floating yet).
    pub bodies: Vec<BodyModel>,
    /// Material index of each cell (the body's material, before the regions).
    pub cell_material: Vec<usize>,
    /// Body index of each cell.
    pub cell_body: Vec<usize>,
}

/// Builds the bodies of the scene, in its order, each checked to fit in the memory
/// (`max_memory`, and whether the nonlinear tier keeps its element states) before it is processed.
pub fn bodies(
    scene: &Scene,
    memory: (Option<u64>, bool),
    dir: &Path,
) -> Result<Bodies, (String, String)> {
    if scene.body.is_empty() {
        return Err(("body".into(), "the scene defines no [[body]]".into()));
    }
    let mut mesh = Mesh::default();
    let mut bodies: Vec<BodyModel> = Vec::new();
    let mut cell_material = Vec::new();
    let mut cell_body = Vec::new();
    for (i, b) in scene.body.iter().enumerate() {
        let field = format!("body \"{}\" (body[{i}])", shown(&b.name));
        super::names::named("body", &b.name).map_err(|m| (field.clone(), m))?;
        if bodies.iter().any(|o| o.name == b.name) {
            return Err((field, "a body of this name is defined twice".into()));
        }
        let material = find_material(scene, &b.material, format!("{field}.material"))?;
        let hand = match &b.shape {
            Shape::Hand {
                side,
                resolution,
                subdivisions,
                gltf: None,
                bones,
                placement,
                size,
                form,
            } => {
                let field = format!("{field}.shape.hand");
                let form = match form.as_deref() {
                    None => HandForm::default(),
                    Some(name) => HandForm::from_name(name).ok_or_else(|| {
                        (
                            format!("{field}.form"),
                            format!(
                                "unknown hand form \"{}\": the forms are \"simple\" and \
                                 \"anatomical\"",
                                shown(name)
                            ),
                        )
                    })?,
                };
                if bones.is_some() {
                    return Err((
                        field,
                        "`bones` is for a hand read from `gltf`; the built-in hand's joints are \
                         its own"
                            .into(),
                    ));
                }
                let motion = placement
                    .as_ref()
                    .map(builtin_placement)
                    .transpose()
                    .map_err(|e| (format!("{field}.placement"), e))?;
                let size = size
                    .as_ref()
                    .map(|size| hand_size(size).map_err(|e| (format!("{field}.size"), e)))
                    .transpose()?;
                let split = hand_subdivisions(*subdivisions)
                    .map_err(|e| (format!("{field}.subdivisions"), e))?;
                let built = match (size, form) {
                    (None, HandForm::Simple) => HandModel::build_nested(
                        Skeleton::new((*side).into()),
                        SkinShape::new((*side).into()),
                        *resolution,
                        split,
                        memory.0,
                        Vector3::zeros(),
                    ),
                    (size, form) => HandModel::built_in_nested(
                        (*side).into(),
                        size,
                        form,
                        *resolution,
                        split,
                        memory.0,
                    ),
                };
                let built = built.map_err(|e| (field, e.to_string()))?;
                Some(Arc::new(match motion {
                    Some(motion) => built.placed(&motion),
                    None => built,
                }))
            }
            Shape::Hand {
                size: Some(_),
                gltf: Some(_),
                ..
            } => {
                return Err((
                    format!("{field}.shape.hand.size"),
                    "a hand read from `gltf` has its own size; scale it with `placement.scale`"
                        .into(),
                ))
            }
            Shape::Hand {
                form: Some(_),
                gltf: Some(_),
                ..
            } => {
                return Err((
                    format!("{field}.shape.hand.form"),
                    "a hand read from `gltf` has its own form (its skin mesh); `form` is the \
                     built-in hand's"
                        .into(),
                ))
            }
            Shape::Hand {
                side,
                resolution,
                subdivisions,
                gltf: Some(file),
                bones,
                placement,
                ..
            } => {
                let split = hand_subdivisions(*subdivisions)
                    .map_err(|e| (format!("{field}.shape.hand.subdivisions"), e))?;
                let field = format!("{field}.shape.hand.gltf");
                let rig = read_rigged_hand(
                    &dir.join(file),
                    (*side).into(),
                    &bones.clone().unwrap_or_default(),
                    &placement.clone().unwrap_or_default(),
                )
                .map_err(|e| (field.clone(), e))?;
                Some(Arc::new(
                    HandModel::from_rig_within((*side).into(), &rig, *resolution, split, memory.0)
                        .map_err(|e| (field, format!("\"{}\": {e}", shown(file))))?,
                ))
            }
            _ => {
                if b.pose.is_some() {
                    return Err((
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
                .map_err(|e| (format!("{field}.pose"), e.to_string()))?,
            None => Vec::new(),
        };
        let body_mesh = match &hand {
            Some(h) => h.flesh.mesh.clone(),
            None => build_shape(&b.shape).map_err(|(sub, m)| (format!("{field}.shape{sub}"), m))?,
        };
        fits_in_memory(
            mesh.node_count().saturating_add(body_mesh.node_count()),
            mesh.cell_count().saturating_add(body_mesh.cell_count()),
            body_mesh.cell_count(),
            memory,
            &field,
        )?;
        check_extent(&body_mesh).map_err(|m| (format!("{field}.shape"), m))?;
        for (c, _) in body_mesh.cells.iter().enumerate() {
            let corners = body_mesh.cell_coords(c);
            let rel = relative_min_jacobian(&corners);
            if rel.is_nan() || rel <= 1e-12 {
                return Err((
                    format!("{field}.shape"),
                    format!(
                        "element {c} is inverted or has zero volume (smallest det J / size³ = \
                         {rel:.3e})"
                    ),
                ));
            }
            let aspect = aspect_ratio(&corners);
            if aspect.is_nan() || aspect > MAX_ASPECT {
                return Err((
                    format!("{field}.shape"),
                    format!(
                        "element {c} is {} times longer than it is thick (at most {}): its \
                         stiffness along and across differs by the square of that, beyond what \
                         double precision solves; make the part thicker, or its cells less \
                         flat (more cells along it: a box's or a shell's `cells`)",
                        crate::util::readable(aspect),
                        crate::util::readable(MAX_ASPECT)
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
        let facets: Vec<Facet> = facets
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
        let quads: Vec<[usize; 4]> = facets.iter().map(|f| f.nodes).collect();
        let exterior = crate::contact::exterior_quads(&quads, &mesh.nodes);
        let volume: f64 = (0..body_mesh.cell_count())
            .map(|c| cell_volume(&body_mesh.cell_coords(c)))
            .sum();
        bodies.push(BodyModel {
            name: b.name.clone(),
            shape: b.shape.clone(),
            nodes: node_offset..node_offset + body_mesh.node_count(),
            cells: cell_offset..cell_offset + body_mesh.cell_count(),
            facets,
            exterior,
            size: (hi - lo).max(),
            volume,
            mass: 0.0,
            thresholds: match &hand {
                Some(h) => thresholds(h, b.bone_thresholds.as_ref())
                    .map_err(|m| (format!("{field}.bone_thresholds"), m))?,
                None => {
                    if b.bone_thresholds.is_some() {
                        return Err((
                            format!("{field}.bone_thresholds"),
                            "only a hand has bones".into(),
                        ));
                    }
                    Vec::new()
                }
            },
            skin_overlap: hand.as_deref().map(super::SkinOverlapCheck::new),
            hand,
            initial_angles,
            floating: false,
        });
        cell_material.extend(std::iter::repeat_n(material, body_mesh.cell_count()));
        cell_body.extend(std::iter::repeat_n(i, body_mesh.cell_count()));
    }
    Ok(Bodies {
        mesh,
        bodies,
        cell_material,
        cell_body,
    })
}

/// The index of the body `name`; `field` names the reference in the error.
pub fn find_body(
    bodies: &[BodyModel],
    name: &str,
    field: String,
) -> Result<usize, (String, String)> {
    bodies.iter().position(|b| b.name == name).ok_or_else(|| {
        let known: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
        (
            field,
            format!(
                "no body named \"{}\" (defined: {})",
                shown(name),
                list(&known)
            ),
        )
    })
}

/// Sets the mass of every body from the final material of each cell.
pub fn set_masses(bodies: &mut [BodyModel], mesh: &Mesh, cell_materials: &[Material]) {
    for b in bodies {
        b.mass = b
            .cells
            .clone()
            .map(|c| cell_materials[c].density * cell_volume(&mesh.cell_coords(c)))
            .sum();
    }
}

/// A cell of every node (`usize::MAX` for a node of no cell).
pub fn node_cells(mesh: &Mesh) -> Vec<usize> {
    let mut node_cell = vec![usize::MAX; mesh.node_count()];
    for (c, cell) in mesh.cells.iter().enumerate().rev() {
        for &n in cell {
            node_cell[n] = c;
        }
    }
    node_cell
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
                "no bone \"{}\"; the bones are {}",
                shown(name),
                hand.skeleton.bone_names()
            )
        })?;
        if !(value.is_finite() && value > 0.0) {
            return Err(format!(
                "\"{}\": a threshold is a force > 0 N, got {value}",
                shown(name)
            ));
        }
        out[b] = value;
    }
    Ok(out)
}

/// The size a scene asks of the built-in hand (the scene's `size`, the CLI's `--size`).
pub fn hand_size(size: &HandSizeDef) -> Result<HandSize, String> {
    match size {
        HandSizeDef::Percentile(name) => HandSize::percentile(name).ok_or_else(|| {
            format!(
                "unknown percentile \"{}\"; ANSUR II percentiles are {}",
                shown(name),
                HandSize::percentile_names()
            )
        }),
        HandSizeDef::Measured { length, breadth } => Ok(match breadth {
            Some(breadth) => HandSize {
                length: *length,
                breadth: *breadth,
            },
            None => HandSize::of_length(*length),
        }),
    }
}
