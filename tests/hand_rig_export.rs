//! The built-in hand exported as a rigged glTF 2.0 binary (`export::hand_rig`), read back by
//! independent readers: the `gltf` crate (joint nodes named per convention at the skeleton's
//! joints, the skin's vertices, volume and weights), the Khronos validator (no error, no
//! warning) and Blender 3.4 (an armature of the convention's bones deforming the mesh; run when
//! `blender` is on PATH).

use crate::common;

use nalgebra::{Matrix4, Vector3};
use prehensile::export::hand_rig::{from_gltf_axes, write_hand_rig};
use prehensile::export::rig_mesh::{RigOptions, RigSkin};
use prehensile::hand::anatomy::PALM;
use prehensile::hand::rig_names::{joint_keys, node_name, Convention, CONVENTIONS};
use prehensile::hand::{HandModel, Side};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, OnceLock};

/// The hands at resolution 0.75 (right, left).
fn hand(side: Side) -> &'static HandModel {
    static RIGHT: OnceLock<HandModel> = OnceLock::new();
    static LEFT: OnceLock<HandModel> = OnceLock::new();
    let cell = if side == Side::Right { &RIGHT } else { &LEFT };
    cell.get_or_init(|| HandModel::new(side, 0.75).unwrap())
}

/// The file of `hand(side)` in `convention` with `options`, written once (the tests share it).
fn written(side: Side, convention: Convention, options: RigOptions) -> PathBuf {
    static WRITTEN: Mutex<BTreeSet<PathBuf>> = Mutex::new(BTreeSet::new());
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hand_rig");
    let path = dir.join(format!(
        "{side:?}-{convention:?}-{}-{:?}.glb",
        if options.open_wrist { "open" } else { "closed" },
        options.skin
    ));
    let mut done = WRITTEN.lock().unwrap();
    if done.insert(path.clone()) {
        write_hand_rig(&path, hand(side), convention, &options).unwrap();
    }
    path
}

const CLOSED: RigOptions = RigOptions {
    open_wrist: false,
    skin: RigSkin::Display,
};
const OPEN: RigOptions = RigOptions {
    open_wrist: true,
    skin: RigSkin::Display,
};
const SMALL: RigOptions = RigOptions {
    open_wrist: false,
    skin: RigSkin::Contact,
};

/// The skeleton's joint `key` (hand frame), read off the bones here: the wrist at the carpus's
/// start, a tip at the end of the distal bone, any other joint at the start of its bone.
fn expected_joint(hand: &HandModel, key: &str) -> Vector3<f64> {
    let s = &hand.skeleton;
    let bone = |name: &str| &s.bones[s.bone_index(name).unwrap()];
    match key {
        "wrist" => bone("carpus").start,
        _ if key.ends_with(".tip") => bone(&key.replace(".tip", ".distal")).end,
        _ => bone(key).start,
    }
}

/// A file read back: its joint nodes (name → world position in the hand frame, f64 sums of
/// the f32 translations, and the parent's name), and the skinned mesh.
struct ReadBack {
    joints: BTreeMap<String, (Vector3<f64>, Option<String>)>,
    /// The skin's joint names in its order, and each one's inverse bind matrix.
    skin_joints: Vec<(String, Matrix4<f64>)>,
    positions: Vec<Vector3<f64>>,
    normals: Vec<Vector3<f64>>,
    triangles: Vec<[usize; 3]>,
    joints_of: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
}

fn read_back(path: &Path) -> ReadBack {
    let gltf = gltf::Gltf::from_slice(&std::fs::read(path).unwrap()).unwrap();
    let blob = gltf.blob.clone().unwrap();
    let nodes: Vec<gltf::Node> = gltf.nodes().collect();
    let mut parent: HashMap<usize, usize> = HashMap::new();
    for n in &nodes {
        for c in n.children() {
            parent.insert(c.index(), n.index());
        }
    }
    let world = |mut i: usize| {
        let mut w = Vector3::zeros();
        loop {
            let (t, r, s) = nodes[i].transform().decomposed();
            assert_eq!(
                (r, s),
                ([0.0, 0.0, 0.0, 1.0], [1.0; 3]),
                "translations only"
            );
            w += Vector3::from(t.map(f64::from));
            match parent.get(&i) {
                Some(&p) => i = p,
                None => return from_gltf_axes(&w),
            }
        }
    };
    let mesh_node = nodes.iter().find(|n| n.mesh().is_some()).unwrap();
    assert!(
        !parent.contains_key(&mesh_node.index()),
        "the skinned mesh is a root"
    );
    let skin = mesh_node.skin().expect("a glTF skin");
    let joints = skin
        .joints()
        .map(|j| {
            let p = parent
                .get(&j.index())
                .map(|&p| nodes[p].name().unwrap().to_string());
            (j.name().unwrap().to_string(), (world(j.index()), p))
        })
        .collect();
    let ibm: Vec<Matrix4<f64>> = skin
        .reader(|_| Some(&blob[..]))
        .read_inverse_bind_matrices()
        .unwrap()
        .map(|m| Matrix4::from_fn(|r, c| m[c][r] as f64))
        .collect();
    let skin_joints = skin
        .joints()
        .zip(ibm)
        .map(|(j, m)| (j.name().unwrap().to_string(), m))
        .collect();
    let primitive = mesh_node.mesh().unwrap().primitives().next().unwrap();
    let reader = primitive.reader(|_| Some(&blob[..]));
    let v3 = |p: [f32; 3]| from_gltf_axes(&Vector3::from(p.map(f64::from)));
    let indices: Vec<usize> = reader
        .read_indices()
        .unwrap()
        .into_u32()
        .map(|i| i as usize)
        .collect();
    ReadBack {
        joints,
        skin_joints,
        positions: reader.read_positions().unwrap().map(v3).collect(),
        normals: reader.read_normals().unwrap().map(v3).collect(),
        triangles: indices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect(),
        joints_of: reader.read_joints(0).unwrap().into_u16().collect(),
        weights: reader.read_weights(0).unwrap().into_f32().collect(),
    }
}

/// The volume the triangles enclose (divergence theorem: Σ a·(b × c) / 6), m³.
fn volume(positions: &[Vector3<f64>], triangles: &[[usize; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v]);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum()
}

/// The edges used by one triangle only (sorted vertex pairs).
fn boundary_edges(triangles: &[[usize; 3]]) -> Vec<(usize, usize)> {
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    for t in triangles {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut edges: Vec<_> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|(e, _)| e)
        .collect();
    edges.sort();
    edges
}

#[test]
fn every_named_joint_is_a_node_at_the_skeletons_joint() {
    let mut worst = 0.0f64;
    for (side, convention, options) in CONVENTIONS
        .iter()
        .map(|&c| (Side::Right, c, SMALL))
        .chain([(Side::Left, Convention::Rigify, SMALL)])
    {
        let hand = hand(side);
        let back = read_back(&written(side, convention, options));
        let named: Vec<(String, String)> = joint_keys()
            .into_iter()
            .filter_map(|k| node_name(convention, side, &k).map(|n| (k, n)))
            .collect();
        assert_eq!(
            back.joints.len(),
            named.len(),
            "{convention:?}: joint count"
        );
        for (key, name) in &named {
            let (world, parent) = back
                .joints
                .get(name)
                .unwrap_or_else(|| panic!("{convention:?} {side:?}: no node {name}"));
            let error = (world - expected_joint(hand, key)).norm();
            worst = worst.max(error);
            assert!(error < 1e-8, "{name}: {error:e} m off the skeleton's {key}");
            // Its parent: the digit's previous named joint, else the wrist.
            let (digit, _) = key.split_once('.').unwrap_or((key, ""));
            let expected_parent = named
                .iter()
                .take_while(|(k, _)| k != key)
                .filter(|(k, _)| k.starts_with(&format!("{digit}.")))
                .last()
                .or_else(|| (key != "wrist").then_some(&named[0]))
                .map(|(_, n)| n.clone());
            assert_eq!(parent, &expected_parent, "{name}'s parent");
        }
        // Each inverse bind matrix undoes its joint's rest position (glTF axes).
        for (name, ibm) in &back.skin_joints {
            let p = back.joints[name].0;
            let g = Vector3::new(p.x, p.z, -p.y);
            let m = ibm * Matrix4::new_translation(&g);
            assert!((m - Matrix4::identity()).abs().max() < 1e-8, "{name}: {m}");
        }
    }
    println!("joints: largest distance from the skeleton's {worst:.2e} m (f32 translations)");
    // The named joints by convention, as written: Mixamo with tips and no finger metacarpals.
    let mixamo = read_back(&written(Side::Right, Convention::Mixamo, SMALL));
    assert_eq!(mixamo.joints.len(), 21);
    assert_eq!(
        mixamo.joints["mixamorig:RightHandIndex1"].1.as_deref(),
        Some("mixamorig:RightHand")
    );
    let unreal = read_back(&written(Side::Right, Convention::Unreal, SMALL));
    assert_eq!(unreal.joints.len(), 20);
    assert_eq!(
        unreal.joints["index_01_r"].1.as_deref(),
        Some("index_metacarpal_r")
    );
}

#[test]
fn the_closed_skin_is_the_display_skin_with_its_volume_and_weights() {
    let hand = hand(Side::Right);
    let back = read_back(&written(Side::Right, Convention::Mixamo, CLOSED));
    let skin = hand.skin.positions(&hand.flesh.mesh.nodes);
    assert_eq!(back.positions.len(), hand.skin.vertex_count());
    let gap = back
        .positions
        .iter()
        .zip(&skin)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    assert!(gap < 2e-8, "vertices {gap:e} m from the skin's");
    assert!(boundary_edges(&back.triangles).is_empty(), "closed");
    let direct: Vec<[usize; 3]> = hand.skin.triangle_indices();
    let (v_file, v_skin) = (
        volume(&back.positions, &back.triangles),
        volume(&skin, &direct),
    );
    println!(
        "volume: file {:.6} ml, display skin {:.6} ml",
        v_file * 1e6,
        v_skin * 1e6
    );
    assert!(v_skin > 150e-6 && v_skin < 500e-6, "a hand's volume");
    assert!((v_file - v_skin).abs() < 1e-6 * v_skin);
    // Normals: unit, within 120° of the triangles around them but for folds of the skin (at
    // resolution 0.75 stretched triangles up to 10 mm long folded in the webs between the
    // fingers: 0.22 % of the area; 0.02 % at resolution 1), a small share of its area. 90° is
    // passed at sharp edges (the wrist's rim). Inverted normals would fail on all of it,
    // random ones on a third.
    assert!(back.normals.iter().all(|n| (n.norm() - 1.0).abs() < 1e-6));
    let (mut folded, mut folded_area, mut total_area) = (0, 0.0, 0.0);
    for t in &back.triangles {
        let [a, b, c] = t.map(|v| back.positions[v]);
        let n = (b - a).cross(&(c - a));
        total_area += n.norm() / 2.0;
        let opposed = t
            .iter()
            .filter(|&&v| back.normals[v].dot(&n) < -0.5 * n.norm())
            .count();
        if opposed > 0 {
            folded += opposed;
            folded_area += n.norm() / 2.0;
        }
    }
    println!(
        "normals over 120° from their triangle: {folded} of {} corners, in triangles of \
         {:.4} % of the skin's {:.1} cm²",
        3 * back.triangles.len(),
        100.0 * folded_area / total_area,
        total_area * 1e4
    );
    assert!(folded_area < 5e-3 * total_area);
    // Weights: non-negative, summing to one; the index fingertip moves with the index's distal
    // joint, the middle of the palm with the wrist.
    let names: Vec<&str> = back.skin_joints.iter().map(|(n, _)| n.as_str()).collect();
    let mut worst = 0.0f64;
    for w in &back.weights {
        assert!(w.iter().all(|&x| x >= 0.0));
        worst = worst.max((w.iter().map(|&x| x as f64).sum::<f64>() - 1.0).abs());
    }
    println!("weights: largest |Σw − 1| = {worst:.1e}");
    assert!(worst < 1e-6);
    let weight_of = |v: usize, name: &str| -> f64 {
        (0..4)
            .filter(|&k| names[back.joints_of[v][k] as usize] == name)
            .map(|k| back.weights[v][k] as f64)
            .sum()
    };
    let near = |p: Vector3<f64>| {
        (0..back.positions.len())
            .min_by(|&a, &b| {
                (back.positions[a] - p)
                    .norm()
                    .total_cmp(&(back.positions[b] - p).norm())
            })
            .unwrap()
    };
    let tip = near(expected_joint(hand, "index.tip") + Vector3::new(0.01, 0.0, 0.0));
    let palm =
        near((expected_joint(hand, "wrist") + expected_joint(hand, "middle.proximal")) / 2.0);
    println!(
        "index tip vertex: {:.3} on Index3; palm vertex: {:.3} on the wrist",
        weight_of(tip, "mixamorig:RightHandIndex3"),
        weight_of(palm, "mixamorig:RightHand")
    );
    assert!(weight_of(tip, "mixamorig:RightHandIndex3") > 0.99);
    assert!(weight_of(palm, "mixamorig:RightHand") > 0.99);
}

#[test]
fn the_open_wrist_leaves_one_boundary_loop_on_the_wrist_plane() {
    let hand = hand(Side::Right);
    let back = read_back(&written(Side::Right, Convention::Rigify, OPEN));
    let skin = hand.skin.positions(&hand.flesh.mesh.nodes);
    let on_plane = |p: &Vector3<f64>| (p.x - PALM.wrist_x).abs() < 1e-6;
    // The skin's vertices that are gone all lay on the wrist plane (matched by their f32
    // position, as the file holds them).
    let key = |p: &Vector3<f64>| [p.x, p.y, p.z].map(|x| (x as f32).to_bits());
    let in_file: BTreeSet<_> = back.positions.iter().map(key).collect();
    let gone: Vec<&Vector3<f64>> = skin.iter().filter(|p| !in_file.contains(&key(p))).collect();
    println!(
        "open wrist: {} of the skin's {} vertices ({} gone)",
        back.positions.len(),
        skin.len(),
        gone.len()
    );
    assert!(!gone.is_empty());
    assert!(
        gone.iter().all(|p| on_plane(p)),
        "only the cut's vertices go"
    );
    assert_eq!(back.positions.len() + gone.len(), skin.len());
    // One loop: every boundary vertex on two boundary edges, walked round once.
    let edges = boundary_edges(&back.triangles);
    let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(a, b) in &edges {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    assert!(next.values().all(|n| n.len() == 2), "a simple loop");
    let start = edges[0].0;
    let (mut previous, mut at) = (start, next[&start][0]);
    let mut walk = vec![start];
    while at != start {
        let n = &next[&at];
        let step = if n[0] == previous { n[1] } else { n[0] };
        walk.push(at);
        (previous, at) = (at, step);
    }
    println!(
        "boundary: one loop of {} edges ({} in all)",
        walk.len(),
        edges.len()
    );
    assert_eq!(walk.len(), edges.len(), "one loop");
    let off = walk
        .iter()
        .map(|&v| (back.positions[v].x - PALM.wrist_x).abs())
        .fold(0.0, f64::max);
    println!("boundary: at most {off:.2e} m off the wrist plane");
    assert!(off < 1e-6);
    // What went is the cut the loop bounds: the area taken out is the loop's (shoelace, in the
    // plane).
    let area = |p: &[Vector3<f64>], t: &[[usize; 3]]| -> f64 {
        t.iter()
            .map(|t| (p[t[1]] - p[t[0]]).cross(&(p[t[2]] - p[t[0]])).norm() / 2.0)
            .sum()
    };
    let direct: Vec<[usize; 3]> = hand.skin.triangle_indices();
    let taken = area(&skin, &direct) - area(&back.positions, &back.triangles);
    let loop_area = (0..walk.len())
        .map(|i| {
            let (a, b) = (
                back.positions[walk[i]],
                back.positions[walk[(i + 1) % walk.len()]],
            );
            (a.y * b.z - b.y * a.z) / 2.0
        })
        .sum::<f64>()
        .abs();
    println!(
        "wrist cut: {:.3} mm² taken out, {:.3} mm² inside the loop",
        taken * 1e6,
        loop_area * 1e6
    );
    assert!(
        loop_area > 500e-6 && loop_area < 5000e-6,
        "a wrist's section"
    );
    assert!((taken - loop_area).abs() < 1e-3 * loop_area);
    // The wrist plane closes what is left: the volume about a point on it is the closed skin's.
    let closed = read_back(&written(Side::Right, Convention::Rigify, CLOSED));
    let c = Vector3::new(PALM.wrist_x, 0.0, 0.0);
    let about = |p: &[Vector3<f64>]| p.iter().map(|x| x - c).collect::<Vec<_>>();
    let open_volume = volume(&about(&back.positions), &back.triangles);
    let closed_volume = volume(&about(&closed.positions), &closed.triangles);
    println!(
        "volume about the wrist plane: open {:.6} ml, closed {:.6} ml",
        open_volume * 1e6,
        closed_volume * 1e6
    );
    assert!((open_volume - closed_volume).abs() < 1e-6 * closed_volume);
}

#[test]
fn the_khronos_validator_finds_no_error() {
    for path in [
        written(Side::Right, Convention::Mixamo, CLOSED),
        written(Side::Right, Convention::Rigify, OPEN),
        written(Side::Left, Convention::MakeHuman, SMALL),
        written(Side::Right, Convention::Unreal, SMALL),
    ] {
        let validation = common::gltf_validator::validate_glb(&path);
        let report = validation.report;
        assert!(validation.passed, "{report}");
        assert!(report.contains("\"errors\":0,\"warnings\":0"), "{report}");
    }
}

#[test]
fn blender_imports_an_armature_of_the_conventions_bones_deforming_the_mesh() {
    if Command::new("blender").arg("--version").output().is_err() {
        println!("skipped: no `blender` on PATH (apt-get install blender)");
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/import_rig_in_blender.py");
    for (side, convention, options) in [
        (Side::Right, Convention::Mixamo, OPEN),
        (Side::Left, Convention::Unreal, SMALL),
    ] {
        let path = written(side, convention, options);
        let back = read_back(&path);
        let out = Command::new("blender")
            .args(["-b", "--factory-startup", "-P"])
            .arg(&script)
            .arg("--")
            .arg(&path)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout
            .lines()
            .find_map(|l| l.strip_prefix("RIG_JSON "))
            .unwrap_or_else(|| panic!("{stdout}{}", String::from_utf8_lossy(&out.stderr)));
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        let armatures = v["armatures"].as_array().unwrap();
        assert_eq!(armatures.len(), 1, "one armature");
        let bones: BTreeMap<String, (Vector3<f64>, Option<String>)> = armatures[0]["bones"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| {
                let h: Vec<f64> = serde_json::from_value(b["head"].clone()).unwrap();
                (
                    b["name"].as_str().unwrap().to_string(),
                    (
                        Vector3::new(h[0], h[1], h[2]),
                        b["parent"].as_str().map(str::to_string),
                    ),
                )
            })
            .collect();
        let names: Vec<&String> = bones.keys().collect();
        let expected: Vec<&String> = back.joints.keys().collect();
        assert_eq!(
            names, expected,
            "{convention:?}: the bones are the joint nodes"
        );
        let hand = hand(side);
        let mut worst = 0.0f64;
        for key in joint_keys() {
            if let Some(name) = node_name(convention, side, &key) {
                let (head, parent) = &bones[&name];
                assert_eq!(parent, &back.joints[&name].1, "{name}'s parent bone");
                worst = worst.max((head - expected_joint(hand, &key)).norm());
            }
        }
        let mesh = &v["meshes"][0];
        let lo: Vec<f64> = serde_json::from_value(mesh["min"].clone()).unwrap();
        let hi: Vec<f64> = serde_json::from_value(mesh["max"].clone()).unwrap();
        let (mut min, mut max) = (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN));
        for p in &back.positions {
            min = min.inf(p);
            max = max.sup(p);
        }
        let box_gap = (Vector3::from_vec(lo) - min)
            .abs()
            .max()
            .max((Vector3::from_vec(hi) - max).abs().max());
        println!(
            "Blender, {convention:?} {side:?}: {} bones, heads within {worst:.1e} m of the \
             skeleton's joints; mesh of {} vertices, box within {box_gap:.1e} m of the file's \
             (Z-up); turning every bone 20° moves the skin up to {:.1} mm",
            bones.len(),
            mesh["vertices"],
            mesh["deformed_max"].as_f64().unwrap() * 1e3
        );
        assert!(
            worst < 1e-6,
            "bone heads at the joints, in the hand's Z-up frame"
        );
        assert!(box_gap < 1e-6, "the mesh in the hand's Z-up frame");
        assert_eq!(
            mesh["vertices"].as_u64().unwrap() as usize,
            back.positions.len()
        );
        // Blender's importer validates the mesh, which keeps one of two triangles on the same
        // three vertices: a fold of the contact skin onto itself where two lattice quads meet
        // along two edges (2 of 7 176 in the left hand's at resolution 0.75; none at 1).
        let distinct: std::collections::HashSet<[usize; 3]> = back
            .triangles
            .iter()
            .map(|t| {
                let mut t = *t;
                t.sort_unstable();
                t
            })
            .collect();
        assert!(
            back.triangles.len() - distinct.len() <= back.triangles.len() / 1000,
            "{} triangles repeat another's vertices",
            back.triangles.len() - distinct.len()
        );
        assert_eq!(mesh["polygons"].as_u64().unwrap() as usize, distinct.len());
        assert_eq!(
            mesh["armature"], armatures[0]["name"],
            "deformed by the armature"
        );
        assert!(mesh["deformed_max"].as_f64().unwrap() > 0.01);
    }
}

#[test]
fn the_command_line_writes_the_file_whole_and_refuses_a_bad_resolution() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hand_rig_cli");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("left.glb");
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_prehensile"))
            .arg("export-hand")
            .args(args)
            .output()
            .unwrap()
    };
    let ok = run(&[
        "--out",
        out.to_str().unwrap(),
        "--side",
        "left",
        "--resolution",
        "0.75",
        "--convention",
        "makehuman",
        "--open-wrist",
        "--contact-skin",
    ]);
    let said = String::from_utf8_lossy(&ok.stdout).to_string();
    println!("{said}");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(
        said.contains("20 joints (MakeHuman names, wrist.L"),
        "{said}"
    );
    // Only the file: the temporary one renamed into place.
    let files: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(files.len(), 1);
    let back = read_back(&out);
    assert!(back.joints.contains_key("finger2-1.L"));
    assert_eq!(back.joints.len(), 20);
    assert!(!boundary_edges(&back.triangles).is_empty(), "open");
    // A resolution out of range: exit 1 naming it; nothing written.
    let bad = run(&[
        "--out",
        dir.join("bad.glb").to_str().unwrap(),
        "--resolution",
        "0.2",
    ]);
    let error = String::from_utf8_lossy(&bad.stderr).to_string();
    assert_eq!(bad.status.code(), Some(1), "{error}");
    assert!(
        error.contains("--resolution: resolution must be a number between 0.5 and 4, got 0.2"),
        "{error}"
    );
    assert!(!dir.join("bad.glb").exists());
    // An --out that is a folder or not named .glb: refused before the hand is built (which
    // took 1.7 s first), the cause said once (it was told twice).
    let folder = dir.join("folder.glb");
    std::fs::create_dir_all(&folder).unwrap();
    let gltf = dir.join("hand.gltf");
    for (out, text) in [
        (&folder, "this is a folder; give the .glb file's path"),
        (
            &gltf,
            "export-hand writes binary glTF (.glb); name the file .glb",
        ),
    ] {
        let t = std::time::Instant::now();
        let bad = run(&["--out", out.to_str().unwrap()]);
        let error = String::from_utf8_lossy(&bad.stderr).to_string();
        assert_eq!(bad.status.code(), Some(1), "{error}");
        assert!(error.contains("--out"), "{error}");
        assert_eq!(error.matches(text).count(), 1, "{error}");
        println!(
            "{}: refused in {:.2} s",
            out.display(),
            t.elapsed().as_secs_f64()
        );
    }
    assert!(folder.is_dir() && !gltf.exists());
    // A write that fails once the hand is built (a file where a folder must be): its cause told
    // once.
    let under_a_file = out.join("hand.glb");
    let bad = run(&[
        "--out",
        under_a_file.to_str().unwrap(),
        "--resolution",
        "0.5",
        "--contact-skin",
    ]);
    let error = String::from_utf8_lossy(&bad.stderr).to_string();
    assert_eq!(bad.status.code(), Some(1), "{error}");
    assert_eq!(error.matches("cannot write").count(), 1, "{error}");
    assert_eq!(error.matches("(os error").count(), 1, "{error}");
    // Any case of .glb is a .glb.
    let upper = dir.join("upper.GLB");
    let ok = run(&[
        "--out",
        upper.to_str().unwrap(),
        "--resolution",
        "0.5",
        "--contact-skin",
    ]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(upper.is_file());
    let unknown = run(&["--out", "x.glb", "--convention", "blender"]);
    assert_eq!(unknown.status.code(), Some(2), "clap's usage error");
    // A hand of the 50th-percentile woman: her hand length from the wrist's cut to the middle
    // finger's tip (the smooth skin follows the skin's shape to a fraction of a millimetre).
    let sized = dir.join("female.glb");
    let ok = run(&[
        "--out",
        sized.to_str().unwrap(),
        "--size",
        "female-50",
        "--resolution",
        "0.75",
        "--contact-skin",
    ]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let back = read_back(&sized);
    let (lo, hi) = back
        .positions
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.x), hi.max(p.x))
        });
    assert!(
        ((hi - lo) - 0.180).abs() < 1.5e-3,
        "hand length {} m",
        hi - lo
    );
    for (size, says) in [
        (
            "male-40",
            "is neither a length in metres nor an ANSUR II percentile",
        ),
        ("1.9", "the hand's length must be between 0.1 and 0.3 m"),
    ] {
        let bad = run(&[
            "--out",
            dir.join("bad.glb").to_str().unwrap(),
            "--size",
            size,
        ]);
        let error = String::from_utf8_lossy(&bad.stderr).to_string();
        assert_eq!(bad.status.code(), Some(1), "{error}");
        assert!(error.contains("--size") && error.contains(says), "{error}");
        assert!(!dir.join("bad.glb").exists());
    }
}
