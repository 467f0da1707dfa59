//! The exports of a solved grasp, read back by independent readers.
//!
//! The VTU files are binary by default (zlib-compressed blocks in the appended section): read
//! back by meshio, from Python (Debian's python3-meshio, which `.ci/run` installs), they hold
//! the solver's numbers to 1e-12 (bit for bit, in fact), and `--vtu ascii` writes the same
//! numbers as text. `animation.glb` passes the Khronos glTF validator (the npm package
//! `gltf-validator` under node, which `.ci/run` installs) with no error, and its frames —
//! read with the `gltf` crate, base plus morph target — are the VTU files' displaced points to
//! 1e-6 m.

use crate::common;

use prehensile::export::vtu_grid::VtuEncoding;
use prehensile::headless::{solve_scene_file, write_solved, write_solved_as, Solved};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The Python that has meshio (Debian's, where pyenv may shadow it).
fn python() -> &'static str {
    for p in ["/usr/bin/python3", "python3"] {
        if Command::new(p)
            .args(["-c", "import meshio"])
            .output()
            .is_ok_and(|o| o.status.success())
        {
            return p;
        }
    }
    panic!("no Python with meshio: apt-get install python3-meshio (.ci/run installs it)");
}

/// The finger press solved once, written binary and ASCII: (solved, folder).
fn written() -> &'static (Solved, PathBuf) {
    static WRITTEN: OnceLock<(Solved, PathBuf)> = OnceLock::new();
    WRITTEN.get_or_init(|| {
        let solved = solve_scene_file(Path::new("assets/scenes/finger-press-ball.toml")).unwrap();
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("exports");
        let _ = std::fs::remove_dir_all(&dir);
        write_solved(&solved, &dir.join("binary")).unwrap();
        write_solved_as(&solved, &dir.join("ascii"), VtuEncoding::Ascii).unwrap();
        (solved, dir)
    })
}

#[test]
fn binary_vtu_read_by_meshio_holds_the_solved_numbers() {
    let (solved, dir) = written();
    let (binary, ascii) = (dir.join("binary"), dir.join("ascii"));
    let last = solved.frames.len() - 1;
    let frame = &solved.frames[last];
    let hand = &frame.hands[0];
    // What the files must hold: the mesh, the frame's displacements and bone reactions.
    let expected = serde_json::json!({
        "points": solved.model.mesh.nodes.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>(),
        "displacement": frame.solution.displacement.chunks(3).collect::<Vec<_>>(),
        "cells": solved.model.mesh.cell_count(),
        "reactions": hand.bone_reactions.iter().map(|r| [r.x, r.y, r.z]).collect::<Vec<_>>(),
    });
    std::fs::write(dir.join("expected.json"), expected.to_string()).unwrap();
    let script = format!(
        r#"
import json, sys, meshio, numpy as np
e = json.load(open("{dir}/expected.json"))
worst = 0.0
def check(a, b, what):
    global worst
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, (what, a.shape, b.shape)
    d = float(np.max(np.abs(a - b))) if a.size else 0.0
    worst = max(worst, d)
    assert d <= 1e-12, (what, d)
for kind in ["binary", "ascii"]:
    m = meshio.read("{dir}/%s/frame_{last:04}.vtu" % kind)
    check(m.points, e["points"], kind + " points")
    check(m.point_data["displacement"], e["displacement"], kind + " displacement")
    assert len(m.cells[0].data) == e["cells"], kind
    assert all(np.isfinite(v).all() for v in m.point_data.values())
    bones = meshio.read("{dir}/%s/bones_{last:04}.vtu" % kind)
    ids = bones.cell_data["bone_id"][0]
    r = bones.cell_data["reaction"][0]
    for b, want in enumerate(e["reactions"]):
        rows = r[ids == b]
        if len(rows):
            check(rows, np.tile(want, (len(rows), 1)), kind + " bone %d" % b)
    skin = meshio.read("{dir}/%s/skin_{last:04}.vtu" % kind)
    assert skin.cells[0].type == "quad" and np.isfinite(skin.point_data["contact_pressure"]).all()
    assert skin.point_data["contact_pressure"].max() > 0, kind
    # Over 3.2 mm patches: area-weighted means of the vertices' pressures, so positive where
    # they are and never above their peak.
    patch = skin.point_data["contact_patch_pressure"]
    assert np.isfinite(patch).all() and (patch >= 0).all(), kind
    assert 0 < patch.max() <= skin.point_data["contact_pressure"].max() * (1 + 1e-12), kind
print("largest difference", worst)
"#,
        dir = dir.display()
    );
    let out = Command::new(python())
        .args(["-c", &script])
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    println!("{stdout}{stderr}");
    assert!(out.status.success(), "meshio check failed: {stderr}");
    // Binary is the smaller file, and the ASCII one is text.
    let size = |p: &Path| std::fs::metadata(p).unwrap().len();
    let name = format!("frame_{last:04}.vtu");
    let (b, a) = (size(&binary.join(&name)), size(&ascii.join(&name)));
    println!("frame VTU: binary {b} B, ASCII {a} B");
    assert!(b * 2 < a, "{b} {a}");
    assert!(std::str::from_utf8(&std::fs::read(ascii.join(&name)).unwrap()).is_ok());
    // And the tests' own reader agrees with the ASCII writer's text.
    let decoded = common::vtu::text(&binary.join(&name));
    let text = std::fs::read_to_string(ascii.join(&name)).unwrap();
    let numbers = |t: &str| -> Vec<f64> {
        t.split("<DataArray")
            .skip(1)
            .flat_map(|a| {
                let body = &a[a.find('>').unwrap() + 1..a.find("</DataArray>").unwrap()];
                body.split_whitespace()
                    .map(|x| x.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    assert_eq!(numbers(&decoded), numbers(&text));
}

/// The numbers of the array `name` (or the points, `None`) of an ASCII VTU text.
fn vtu_array(text: &str, name: Option<&str>) -> Vec<f64> {
    let start = match name {
        Some(n) => text.find(&format!("Name=\"{n}\"")).unwrap(),
        None => text.find("<Points>").unwrap(),
    };
    let rest = &text[start..];
    let body = &rest[rest.find('>').unwrap() + 1..];
    let body = match name {
        Some(_) => body,
        None => &body[body.find('>').unwrap() + 1..],
    };
    body[..body.find("</DataArray>").unwrap()]
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

#[test]
fn animation_glb_is_valid_and_its_frames_are_the_vtu_frames() {
    let (solved, dir) = written();
    let path = dir.join("binary").join("animation.glb");
    // The Khronos validator: no error (nor warning).
    let validation = common::gltf_validator::validate_glb(&path);
    let report = validation.report;
    assert!(validation.passed, "{report}");
    assert!(report.contains("\"errors\":0,\"warnings\":0"), "{report}");

    // Read back with the gltf crate: each surface's frame k is its base plus target k.
    let gltf = gltf::Gltf::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let blob = gltf.blob.clone().unwrap();
    let frames = solved.frames.len();
    let times: Vec<f64> = solved.report.frames.iter().map(|f| f.time).collect();
    let animation = gltf.animations().next().expect("an animation");
    let sampler_times: Vec<f32> = animation
        .channels()
        .next()
        .unwrap()
        .reader(|_| Some(&blob[..]))
        .read_inputs()
        .unwrap()
        .collect();
    assert_eq!(sampler_times.len(), frames);
    for (a, b) in sampler_times.iter().zip(&times) {
        assert!((*a as f64 - b).abs() < 1e-6);
    }
    let names: Vec<String> = gltf
        .meshes()
        .map(|m| m.name().unwrap().to_string())
        .collect();
    assert!(names.iter().any(|n| n == "hand_skin"), "{names:?}");
    assert!(names.iter().any(|n| n == "hand_index.distal"), "{names:?}");
    assert_eq!(animation.channels().count(), names.len());
    let ball = gltf
        .meshes()
        .find(|m| m.name() == Some("ball"))
        .expect("the ball");
    let primitive = ball.primitives().next().unwrap();
    let reader = primitive.reader(|_| Some(&blob[..]));
    let base: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    let targets: Vec<Vec<[f32; 3]>> = reader
        .read_morph_targets()
        .map(|(p, _, _)| p.unwrap().collect())
        .collect();
    assert_eq!(targets.len(), frames - 1);
    assert!(
        reader.read_colors(0).is_some(),
        "the ball touched: its pressure as colour"
    );
    // The ball's boundary nodes, in the order the export numbers them (first appearance).
    let body = solved
        .model
        .bodies
        .iter()
        .find(|b| b.name == "ball")
        .unwrap();
    let mut order = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for f in &body.facets {
        for n in f.nodes {
            if seen.insert(n) {
                order.push(n);
            }
        }
    }
    assert_eq!(order.len(), base.len());
    let mut worst = 0.0f64;
    let mut moved = 0.0f64;
    for k in 0..frames {
        let vtu = common::vtu::text(&dir.join("binary").join(format!("frame_{k:04}.vtu")));
        let (points, u) = (vtu_array(&vtu, None), vtu_array(&vtu, Some("displacement")));
        for (i, &n) in order.iter().enumerate() {
            for c in 0..3 {
                let mut g = base[i][c] as f64;
                if k > 0 {
                    g += targets[k - 1][i][c] as f64;
                }
                let want = points[3 * n + c] + u[3 * n + c];
                worst = worst.max((g - want).abs());
                moved = moved.max(u[3 * n + c].abs());
            }
        }
    }
    println!("glTF frames against the VTU frames: largest difference {worst:.2e} m (ball moves {moved:.2e} m)");
    assert!(worst < 1e-6, "{worst}");
    assert!(moved > 1e-4);
}
