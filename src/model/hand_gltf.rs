//! A rigged hand read from a glTF 2.0 file (.glb, or .gltf with its buffers beside it or embedded):
//! its skin mesh in the rest pose, its joints by name, turned from glTF's Y-up to the scene's
//! Z-up as Blender's importer does ((x, y, z) → (x, −z, y)), then placed (scale, rotation,
//! translation) where the scene says.

use super::gltf_checks::{check_accessor, check_chains, check_hierarchy};
use crate::hand::rig_names::{joint_keys, normalized, recognise, Convention, CONVENTIONS};
use crate::hand::{RiggedHand, Side};
use crate::scene::Placement;
use crate::util::gltf_axes::from_gltf_axes;
use crate::util::shown;
use gltf::accessor::{DataType, Dimensions};
use nalgebra::{Matrix4, Rotation3, Vector3, Vector4};
use std::collections::BTreeMap;
use std::path::Path;

/// The largest glTF file (or buffer beside it) read, bytes: a rigged hand's skin and skeleton
/// are a few megabytes.
const MAX_GLTF_BYTES: u64 = 1_000_000_000;

/// The rig in `path` for a hand of `side`: joints named in `bones` (joint key → node name) or
/// recognised by their names, the skin mesh posed at rest, placed by `placement`. Errors name
/// the file and what is wrong in it.
pub fn read_rigged_hand(
    path: &Path,
    side: Side,
    bones: &BTreeMap<String, String>,
    placement: &Placement,
) -> Result<RiggedHand, String> {
    let file = path.display();
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !(placement.scale.is_finite() && placement.scale > 0.0) {
        return Err(format!(
            "`placement.scale` must be a positive number, got {}",
            placement.scale
        ));
    }
    if !finite(&placement.translation) {
        return Err("`placement.translation` must be finite numbers".into());
    }
    super::check::rotation(&placement.rotation)?;
    let bytes = crate::util::read::read_at_most(path, MAX_GLTF_BYTES)
        .map_err(|e| format!("cannot read \"{file}\": {e}"))?;
    let gltf = gltf::Gltf::from_slice(&bytes)
        .map_err(|e| format!("\"{file}\" is not a glTF 2.0 file: {e}"))?;
    let buffers = buffers(&gltf, path)?;
    let name = file.to_string();
    check_hierarchy(&gltf.document, &name)?;
    let world = world_matrices(&gltf.document);

    // The joints.
    let keys = joint_keys();
    if let Some(bad) = bones.keys().find(|k| !keys.contains(k)) {
        return Err(format!(
            "`bones` names \"{bad}\", which is not a joint of the hand; the joints are: {}",
            keys.join(", ")
        ));
    }
    let names: Vec<(usize, String)> = gltf
        .document
        .nodes()
        .filter_map(|n| n.name().map(|s| (n.index(), s.to_string())))
        .collect();
    // Each name escaped and cut, at most 40 of them (a rig may have hundreds of nodes).
    let found = || {
        let mut list: Vec<String> = names.iter().take(40).map(|(_, s)| shown(s)).collect();
        if names.len() > 40 {
            list.push(format!("… and {} more", names.len() - 40));
        }
        list.join(", ")
    };
    // Nodes of one name: a skin's joint is taken before a node no skin is bound to; two
    // candidates alike are refused (the first of them was taken, silently).
    let skin_joints: std::collections::BTreeSet<usize> = gltf
        .document
        .skins()
        .flat_map(|s| s.joints().map(|j| j.index()).collect::<Vec<_>>())
        .collect();
    let pick = |key: &str, candidates: Vec<usize>| -> Result<Option<usize>, String> {
        let bound: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|n| skin_joints.contains(n))
            .collect();
        let among = if bound.is_empty() { candidates } else { bound };
        match among.as_slice() {
            [] => Ok(None),
            [n] => Ok(Some(*n)),
            [a, b, ..] => {
                let named = |n: &usize| {
                    let s = names.iter().find(|(m, _)| m == n).map_or("", |(_, s)| s);
                    format!("node {n} (\"{s}\")")
                };
                Err(format!(
                    "\"{file}\": {} and {} are both named as the joint {key}{}: rename one of \
                     them (a file of two such hands: export the one hand alone)",
                    named(a),
                    named(b),
                    if skin_joints.contains(a) {
                        ", and both are joints of a skin"
                    } else {
                        ""
                    }
                ))
            }
        }
    };
    let mut joint_node: BTreeMap<String, usize> = BTreeMap::new();
    for (key, name) in bones {
        let candidates: Vec<usize> = names
            .iter()
            .filter(|(_, s)| s == name || normalized(s) == normalized(name))
            .map(|(n, _)| *n)
            .collect();
        let Some(n) = pick(key, candidates)? else {
            return Err(format!(
                "`bones.\"{}\"` names the node \"{}\", which \"{file}\" does not have; its \
                 nodes are: {}",
                shown(key),
                shown(name),
                found()
            ));
        };
        if let Some((other, _)) = joint_node.iter().find(|(_, &m)| m == n) {
            return Err(format!(
                "`bones` names the node \"{}\" for both \"{}\" and \"{}\": each \
                 joint is a node of its own",
                shown(name),
                shown(other),
                shown(key)
            ));
        }
        joint_node.insert(key.clone(), n);
    }
    // The others by name, in the convention that recognises the most of them.
    let recognised: Vec<(usize, Convention, String)> = names
        .iter()
        .filter_map(|(n, s)| recognise(s, side).map(|(c, key)| (*n, c, key)))
        .collect();
    let best = CONVENTIONS
        .iter()
        .map(|&c| {
            recognised
                .iter()
                .filter(|(_, conv, _)| *conv == c)
                .map(|(n, _, key)| (key.clone(), *n))
                .collect::<Vec<_>>()
        })
        .max_by_key(|hits| hits.len())
        .unwrap_or_default();
    let mut by_key: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (key, n) in best {
        by_key.entry(key).or_default().push(n);
    }
    for (key, candidates) in by_key {
        if joint_node.contains_key(&key) {
            continue;
        }
        if let Some(n) = pick(&key, candidates)? {
            joint_node.insert(key, n);
        }
    }
    let place = placed(placement);
    let mut rig = RiggedHand::default();
    for (key, n) in &joint_node {
        let m = world[*n];
        rig.joints.insert(
            key.clone(),
            place(Vector3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)])),
        );
    }
    let node_name = |key: &str| {
        joint_node
            .get(key)
            .and_then(|&n| names.iter().find(|(m, _)| *m == n))
            .map_or(String::new(), |(_, s)| s.clone())
    };
    check_chains(&rig.joints, &node_name, &name)?;
    let missing: Vec<&String> = keys
        .iter()
        .filter(|k| crate::hand::rig_names::required(k) && !rig.joints.contains_key(*k))
        .collect();
    if !missing.is_empty() {
        let side_name = format!("{side:?}").to_lowercase();
        return Err(format!(
            "\"{file}\" has no node for the joints {} of a {side_name} hand (by the Mixamo, Rigify, \
             MakeHuman or Unreal names, or `bones`); name them in `bones = {{ \"{}\" = \"<node>\", \
             … }}`; its nodes are: {}",
            missing.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", "),
            missing[0],
            found()
        ));
    }

    // The skin: the mesh of the node skinned to the most of these joints (or, unskinned, the
    // one with the most vertices), posed at rest.
    let joint_nodes: Vec<usize> = joint_node.values().copied().collect();
    let candidate = gltf
        .document
        .nodes()
        .filter(|n| n.mesh().is_some())
        .max_by_key(|n| {
            let shared = n
                .skin()
                .map(|s| {
                    s.joints()
                        .filter(|j| joint_nodes.contains(&j.index()))
                        .count()
                })
                .unwrap_or(0);
            let vertices: usize = n
                .mesh()
                .unwrap()
                .primitives()
                .filter_map(|p| p.get(&gltf::Semantic::Positions).map(|a| a.count()))
                .sum();
            (shared, vertices)
        })
        .ok_or_else(|| format!("\"{file}\" has no mesh: the hand's skin is needed"))?;
    let mesh = candidate.mesh().unwrap();
    let mesh_name = mesh.name().unwrap_or("");
    // Morph targets at a weight other than 0 are part of the rest shape, which is read
    // without them.
    if let Some(w) = mesh.weights().filter(|w| w.iter().any(|&x| x != 0.0)) {
        return Err(format!(
            "\"{file}\": mesh \"{mesh_name}\" rests with its morph targets at weights {w:?}, \
             which the hand does not apply: apply them to the mesh (Blender: apply the shape \
             keys) or set their weights to 0 before exporting"
        ));
    }
    let skin = candidate.skin();
    if let Some(s) = &skin {
        if let Some(ibm) = s.inverse_bind_matrices() {
            check_accessor(
                &ibm,
                "the skin's inverse bind matrices",
                &[(DataType::F32, Dimensions::Mat4)],
                &buffers,
                &name,
            )?;
            let joints = s.joints().count();
            if ibm.count() < joints {
                return Err(format!(
                    "\"{file}\": the skin's inverse bind matrices (accessor {}) are {} for its {joints} \
                     joints",
                    ibm.index(),
                    ibm.count()
                ));
            }
        }
    }
    // Skinning matrices at rest: joint world × inverse bind.
    let skinning: Option<Vec<Matrix4<f64>>> = skin.as_ref().map(|s| {
        let ibm: Vec<Matrix4<f64>> = match s
            .reader(|b| buffers.get(b.index()).map(|v| &v[..]))
            .read_inverse_bind_matrices()
        {
            Some(m) => m.map(|m| matrix(&m)).collect(),
            None => vec![Matrix4::identity(); s.joints().count()],
        };
        s.joints()
            .zip(ibm)
            .map(|(j, ibm)| world[j.index()] * ibm)
            .collect()
    });
    let node_world = world[candidate.index()];
    for (p, primitive) in mesh.primitives().enumerate() {
        if primitive.mode() != gltf::mesh::Mode::Triangles {
            return Err(format!(
                "\"{file}\": mesh \"{}\" primitive {p} is {:?}, not triangles",
                mesh.name().unwrap_or(""),
                primitive.mode()
            ));
        }
        let what = |semantic: &str| format!("{semantic} of mesh \"{mesh_name}\" primitive {p}");
        let Some(position_accessor) = primitive.get(&gltf::Semantic::Positions) else {
            continue;
        };
        check_accessor(
            &position_accessor,
            &what("POSITION"),
            &[(DataType::F32, Dimensions::Vec3)],
            &buffers,
            &name,
        )?;
        if let Some(a) = primitive.get(&gltf::Semantic::Joints(0)) {
            let types = [DataType::U8, DataType::U16].map(|d| (d, Dimensions::Vec4));
            check_accessor(&a, &what("JOINTS_0"), &types, &buffers, &name)?;
        }
        if let Some(a) = primitive.get(&gltf::Semantic::Weights(0)) {
            let types = [DataType::F32, DataType::U8, DataType::U16].map(|d| (d, Dimensions::Vec4));
            check_accessor(&a, &what("WEIGHTS_0"), &types, &buffers, &name)?;
        }
        if let Some(a) = primitive.indices() {
            let types =
                [DataType::U8, DataType::U16, DataType::U32].map(|d| (d, Dimensions::Scalar));
            check_accessor(&a, &what("indices"), &types, &buffers, &name)?;
        }
        let reader = primitive.reader(|b| buffers.get(b.index()).map(|v| &v[..]));
        let Some(positions) = reader.read_positions() else {
            return Err(format!(
                "\"{file}\": the {} (accessor {}) cannot be read",
                what("POSITION"),
                position_accessor.index()
            ));
        };
        let positions: Vec<[f32; 3]> = positions.collect();
        let joints: Option<Vec<[u16; 4]>> = reader.read_joints(0).map(|j| j.into_u16().collect());
        let weights: Option<Vec<[f32; 4]>> = reader.read_weights(0).map(|w| w.into_f32().collect());
        let base = rig.vertices.len() as u32;
        for (v, q) in positions.iter().enumerate() {
            let local = Vector4::new(q[0] as f64, q[1] as f64, q[2] as f64, 1.0);
            let at = match (&skinning, &joints, &weights) {
                (Some(m), Some(j), Some(w)) => {
                    let mut sum = Vector4::zeros();
                    let mut total = 0.0;
                    for k in 0..4 {
                        let wk = w[v][k] as f64;
                        if wk > 0.0 {
                            let Some(mk) = m.get(j[v][k] as usize) else {
                                return Err(format!(
                                    "\"{file}\": vertex {v} of mesh \"{}\" is bound to joint {} \
                                     of a skin of {} joints",
                                    mesh.name().unwrap_or(""),
                                    j[v][k],
                                    m.len()
                                ));
                            };
                            sum += mk * local * wk;
                            total += wk;
                        }
                    }
                    if total > 0.0 {
                        sum / total
                    } else {
                        node_world * local
                    }
                }
                _ => node_world * local,
            };
            rig.vertices.push(place(Vector3::new(at.x, at.y, at.z)));
        }
        let count = positions.len() as u32;
        let indices: Vec<u32> = match (reader.read_indices(), primitive.indices()) {
            (Some(i), _) => i.into_u32().collect(),
            (None, None) => (0..count).collect(),
            (None, Some(a)) => {
                return Err(format!(
                    "\"{file}\": the {} (accessor {}) cannot be read",
                    what("indices"),
                    a.index()
                ))
            }
        };
        if let Some(bad) = indices.iter().find(|&&i| i >= count) {
            return Err(format!(
                "\"{file}\": mesh \"{}\" primitive {p} has index {bad} of {count} vertices",
                mesh.name().unwrap_or("")
            ));
        }
        rig.triangles.extend(
            indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    if rig.triangles.is_empty() {
        return Err(format!(
            "\"{file}\": mesh \"{}\" has no triangles",
            mesh.name().unwrap_or("")
        ));
    }
    Ok(rig)
}

/// The buffers' bytes: the GLB's own chunk, files beside the glTF, or embedded base64 data.
fn buffers(gltf: &gltf::Gltf, path: &Path) -> Result<Vec<Vec<u8>>, String> {
    let file = path.display();
    gltf.document
        .buffers()
        .map(|b| match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| format!("\"{file}\": buffer {} has no binary chunk", b.index())),
            gltf::buffer::Source::Uri(uri) => {
                if let Some(data) = uri.strip_prefix("data:") {
                    let encoded = data.split_once(";base64,").map(|(_, d)| d).ok_or_else(|| {
                        format!(
                            "\"{file}\": buffer {} is a data URI without base64",
                            b.index()
                        )
                    })?;
                    base64::decode(encoded)
                        .map_err(|e| format!("\"{file}\": buffer {}: {e}", b.index()))
                } else {
                    // A URI reference: "my%20hand.bin" is the file "my hand.bin".
                    let decoded = percent_encoding::percent_decode_str(uri).decode_utf8_lossy();
                    let beside = path
                        .parent()
                        .unwrap_or(Path::new("."))
                        .join(decoded.as_ref());
                    crate::util::read::read_at_most(&beside, MAX_GLTF_BYTES).map_err(|e| {
                        format!(
                            "\"{file}\": cannot read its buffer \"{}\": {e}",
                            beside.display()
                        )
                    })
                }
            }
        })
        .collect()
}

fn matrix(m: &[[f32; 4]; 4]) -> Matrix4<f64> {
    // glTF matrices are column-major: m[column][row].
    Matrix4::from_fn(|r, c| m[c][r] as f64)
}

/// Every node's world matrix (rest pose), from the scenes' roots down.
fn world_matrices(doc: &gltf::Document) -> Vec<Matrix4<f64>> {
    let mut world = vec![Matrix4::identity(); doc.nodes().count()];
    let mut is_child = vec![false; world.len()];
    for n in doc.nodes() {
        for c in n.children() {
            is_child[c.index()] = true;
        }
    }
    let mut stack: Vec<(gltf::Node, Matrix4<f64>)> = doc
        .nodes()
        .filter(|n| !is_child[n.index()])
        .map(|n| (n, Matrix4::identity()))
        .collect();
    while let Some((n, parent)) = stack.pop() {
        let m = parent * matrix(&n.transform().matrix());
        world[n.index()] = m;
        for c in n.children() {
            stack.push((c, m));
        }
    }
    world
}

/// glTF (Y-up) to the scene (Z-up), then the placement: scaled, turned (Euler XYZ, degrees, as
/// Blender's), moved.
fn placed(placement: &Placement) -> impl Fn(Vector3<f64>) -> Vector3<f64> {
    let [rx, ry, rz] = placement.rotation.map(f64::to_radians);
    let rotation = Rotation3::from_euler_angles(rx, ry, rz);
    let translation = Vector3::from(placement.translation);
    let scale = placement.scale;
    move |p: Vector3<f64>| rotation * (from_gltf_axes(&p) * scale) + translation
}
