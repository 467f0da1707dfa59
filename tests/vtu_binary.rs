//! The VTU files are binary by default (zlib-compressed blocks in the appended section): read
//! back by an independent reader — meshio, from Python (Debian's python3-meshio, which
//! `.ci/run` installs) — they hold the solver's numbers to 1e-12 (bit for bit, in fact), and
//! `--vtu ascii` writes the same numbers as text.

mod common;

use prehensile::export::vtu_grid::VtuEncoding;
use prehensile::headless::{solve_scene_file, write_solved, write_solved_as};
use std::path::Path;
use std::process::Command;

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

#[test]
fn binary_vtu_read_by_meshio_holds_the_solved_numbers() {
    let solved = solve_scene_file(Path::new("assets/scenes/finger-press-ball.toml")).unwrap();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("vtu_binary");
    let _ = std::fs::remove_dir_all(&dir);
    let (binary, ascii) = (dir.join("binary"), dir.join("ascii"));
    write_solved(&solved, &binary).unwrap();
    write_solved_as(&solved, &ascii, VtuEncoding::Ascii).unwrap();
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
