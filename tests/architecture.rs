//! The layout of `src/` is the data flow (docs/architecture.md): each folder may import only the
//! folders below it, and no two files of a folder import each other in a circle. Read from the
//! source text, so a new `use` that breaks the layering fails here before it spreads.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Each folder of `src/` and the folders it may import (besides itself).
const ALLOWED: &[(&str, &[&str])] = &[
    ("util", &[]),
    ("mesh", &["util"]),
    ("fem", &["mesh", "util"]),
    ("contact", &["mesh", "fem", "util"]),
    ("hand", &["mesh", "fem", "util"]),
    ("scene", &["util"]),
    ("render", &["util"]),
    (
        "model",
        &["scene", "mesh", "fem", "contact", "hand", "util"],
    ),
    (
        "state",
        &["model", "mesh", "fem", "contact", "hand", "util"],
    ),
    (
        "solve",
        &["model", "state", "mesh", "fem", "contact", "hand", "util"],
    ),
    (
        "present",
        &[
            "render", "model", "state", "mesh", "fem", "contact", "hand", "util",
        ],
    ),
    (
        "export",
        &["model", "state", "mesh", "fem", "contact", "hand", "util"],
    ),
    (
        "headless",
        &[
            "export", "present", "render", "solve", "state", "model", "scene", "mesh", "fem",
            "contact", "hand", "util",
        ],
    ),
    (
        "app",
        &[
            "headless", "export", "present", "render", "solve", "state", "model", "scene", "mesh",
            "fem", "contact", "hand", "util",
        ],
    ),
    (
        "bench",
        &[
            "app", "headless", "export", "present", "render", "solve", "state", "model", "scene",
            "mesh", "fem", "contact", "hand", "util",
        ],
    ),
    (
        "cli",
        &[
            "bench", "app", "headless", "export", "present", "render", "solve", "state", "model",
            "scene", "mesh", "fem", "contact", "hand", "util",
        ],
    ),
];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The source without comments and without `#[cfg(test)]` modules (tests may reach further).
fn code(text: &str) -> String {
    let without_tests = match text.find("#[cfg(test)]\nmod tests") {
        Some(i) => &text[..i],
        None => text,
    };
    without_tests
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every `crate::NAME` a text refers to.
fn crate_folders(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = text;
    while let Some(i) = rest.find("crate::") {
        let before = rest[..i].chars().last();
        rest = &rest[i + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        out.insert(name);
    }
    out
}

/// The top folder of a file under `src/` (`None` for `lib.rs` and `main.rs`).
fn folder_of(path: &Path) -> Option<String> {
    let rel = path.strip_prefix(src()).unwrap();
    let mut parts = rel.components();
    let first = parts.next()?.as_os_str().to_string_lossy().to_string();
    parts.next().map(|_| first)
}

#[test]
fn every_folder_imports_only_the_folders_below_it() {
    let allowed: BTreeMap<&str, &[&str]> = ALLOWED.iter().copied().collect();
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut violations = Vec::new();
    let mut seen = BTreeSet::new();
    for file in &files {
        let Some(folder) = folder_of(file) else {
            continue;
        };
        seen.insert(folder.clone());
        let Some(may) = allowed.get(folder.as_str()) else {
            violations.push(format!(
                "{}: folder `{folder}` has no place in the layering (add it to ALLOWED and to \
                 docs/architecture.md)",
                file.display()
            ));
            continue;
        };
        for used in crate_folders(&code(&std::fs::read_to_string(file).unwrap())) {
            if used != folder && !may.contains(&used.as_str()) {
                violations.push(format!(
                    "{}: `{folder}` imports `crate::{used}`",
                    file.strip_prefix(src()).unwrap().display()
                ));
            }
        }
    }
    assert!(violations.is_empty(), "{}", violations.join("\n"));
    // Loose files at `src/` other than lib.rs and main.rs are not allowed either.
    let loose: Vec<_> = std::fs::read_dir(src())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .filter(|p| !["lib.rs", "main.rs"].contains(&p.file_name().unwrap().to_str().unwrap()))
        .collect();
    assert!(loose.is_empty(), "loose files at src/: {loose:?}");
    assert!(seen.len() >= 15, "folders found: {seen:?}");
}

#[test]
fn the_kernels_and_the_scene_reach_nothing_above_them() {
    // The rule that matters most, spelled out: a kernel (or the scene file's types) that imported
    // the orchestration, presentation or a front-end would fail here even if ALLOWED drifted.
    let above = [
        "model", "solve", "state", "present", "render", "export", "headless", "app", "bench", "cli",
    ];
    for kernel in ["mesh", "fem", "contact", "hand", "scene"] {
        let mut files = Vec::new();
        rust_files(&src().join(kernel), &mut files);
        assert!(!files.is_empty(), "{kernel}/ is missing");
        for file in files {
            let used = crate_folders(&code(&std::fs::read_to_string(&file).unwrap()));
            let bad: Vec<_> = used
                .iter()
                .filter(|u| above.contains(&u.as_str()))
                .collect();
            assert!(bad.is_empty(), "{}: imports {bad:?}", file.display());
        }
    }
}

/// The files of one folder (not its `mod.rs`) that a file names through `super::FILE` or
/// `crate::FOLDER::FILE`.
fn sibling_uses(text: &str, folder: &str, siblings: &BTreeSet<String>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for prefix in ["super::".to_string(), format!("crate::{folder}::")] {
        let mut rest = text;
        while let Some(i) = rest.find(&prefix) {
            rest = &rest[i + prefix.len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if siblings.contains(&name) {
                out.insert(name);
            }
        }
    }
    out
}

#[test]
fn no_two_files_of_a_folder_import_each_other_in_a_circle() {
    let mut cycles = Vec::new();
    for (folder, _) in ALLOWED {
        let dir = src().join(folder);
        let mut files = Vec::new();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "rs") && !path.ends_with("mod.rs") {
                files.push(path);
            }
        }
        let names: BTreeSet<String> = files
            .iter()
            .map(|p| p.file_stem().unwrap().to_string_lossy().to_string())
            .collect();
        let edges: BTreeMap<String, BTreeSet<String>> = files
            .iter()
            .map(|p| {
                let name = p.file_stem().unwrap().to_string_lossy().to_string();
                let mut used =
                    sibling_uses(&code(&std::fs::read_to_string(p).unwrap()), folder, &names);
                used.remove(&name);
                (name, used)
            })
            .collect();
        // Depth-first search for a back edge.
        fn visit(
            n: &str,
            edges: &BTreeMap<String, BTreeSet<String>>,
            state: &mut BTreeMap<String, u8>,
            path: &mut Vec<String>,
            out: &mut Vec<String>,
        ) {
            state.insert(n.to_string(), 1);
            path.push(n.to_string());
            for m in &edges[n] {
                match state.get(m.as_str()).copied().unwrap_or(0) {
                    0 => visit(m, edges, state, path, out),
                    1 => {
                        let start = path.iter().position(|p| p == m).unwrap();
                        out.push(format!("{}: {} → {m}", "", path[start..].join(" → ")));
                    }
                    _ => {}
                }
            }
            path.pop();
            state.insert(n.to_string(), 2);
        }
        let mut state = BTreeMap::new();
        for n in edges.keys() {
            if state.get(n.as_str()).copied().unwrap_or(0) == 0 {
                let mut found = Vec::new();
                visit(n, &edges, &mut state, &mut Vec::new(), &mut found);
                cycles.extend(found.into_iter().map(|c| format!("{folder}/{c}")));
            }
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

/// Every test file is a module of the one test binary (`tests/suite.rs`, `autotests = false`):
/// a file it does not name would never run.
#[test]
fn every_test_file_is_named_in_the_suite() {
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let suite = std::fs::read_to_string(tests.join("suite.rs")).unwrap();
    let named: BTreeSet<String> = code(&suite)
        .lines()
        .filter_map(|l| l.trim().strip_prefix("mod "))
        .map(|m| m.trim_end_matches(';').trim().to_string())
        .collect();
    let mut files = BTreeSet::new();
    for entry in std::fs::read_dir(&tests).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let file = path.extension().is_some_and(|e| e == "rs") && name != "suite";
        if file || path.join("mod.rs").exists() {
            files.insert(name);
        }
    }
    let missing: Vec<_> = files.difference(&named).collect();
    assert!(
        missing.is_empty(),
        "tests/suite.rs does not name {missing:?}"
    );
    let absent: Vec<_> = named.difference(&files).collect();
    assert!(
        absent.is_empty(),
        "tests/suite.rs names {absent:?}, not in tests/"
    );
}
