//! Malformed scene files are refused with an error naming the file and the field or element at
//! fault (issue 19, "Hardening").
//!
//! Every `tests/malformed/*.toml` is solved by the real command line, `prehensile solve FILE
//! --out DIR`, in a child process with a time limit and (on Linux) a 4 GiB address-space limit,
//! so that a scene which would overflow a size check and allocate without bound fails here
//! instead of taking the machine down. Each file starts with one or more `# expect: TEXT` lines;
//! the run must exit with a non-zero code (not a signal, not a panic, not the time limit), its
//! stderr must hold the file's name and every expected text, and nothing may be written to
//! `--out`. All the cases that fail are reported together.

mod common;

use common::limited::{signal, solve_limited, toml_files, trimmed, written, Ending};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// Longest a case may run before it is killed.
const TIME_LIMIT: Duration = Duration::from_secs(20);

/// Address space allowed to a case (Linux only).
const ADDRESS_SPACE_LIMIT: u64 = 4 << 30;

/// The corpus, sorted by name.
fn corpus() -> Vec<PathBuf> {
    toml_files("tests/malformed")
}

/// The texts of the `# expect:` lines.
fn expectations(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("# expect:"))
        .map(|e| e.trim().to_string())
        .filter(|e| !e.is_empty())
        .collect()
}

/// Checks one case; the problems found (empty when it passes).
fn check(scene: &Path, work: &Path) -> Vec<String> {
    let name = scene.file_name().unwrap().to_string_lossy().to_string();
    let text = match fs::read_to_string(scene) {
        Ok(t) => t,
        Err(e) => return vec![format!("cannot read the case: {e}")],
    };
    let expected = expectations(&text);
    let mut problems = Vec::new();
    if expected.is_empty() {
        problems.push("has no `# expect:` line".to_string());
    }
    let case_dir = work.join(name.trim_end_matches(".toml"));
    let _ = fs::remove_dir_all(&case_dir);
    fs::create_dir_all(&case_dir).expect("case folder");
    let out = case_dir.join("out");
    let stderr_file = case_dir.join("stderr.txt");
    let (ending, elapsed) =
        match solve_limited(scene, &out, &stderr_file, TIME_LIMIT, ADDRESS_SPACE_LIMIT) {
            Ok(r) => r,
            Err(e) => return vec![format!("cannot run prehensile: {e}")],
        };
    let stderr = String::from_utf8_lossy(&fs::read(&stderr_file).unwrap_or_default()).to_string();
    let status = match &ending {
        Ending::TimedOut => format!("killed after {:.1} s (time limit)", elapsed.as_secs_f64()),
        Ending::Exited(s) => match (s.code(), signal(s)) {
            (Some(c), _) => format!("exit code {c}"),
            (None, Some(sig)) => format!("killed by signal {sig}"),
            (None, None) => format!("{s}"),
        },
    };
    match &ending {
        Ending::TimedOut => {
            problems.push(format!("did not finish within {} s", TIME_LIMIT.as_secs()))
        }
        Ending::Exited(s) => match s.code() {
            Some(0) => problems.push("was accepted (exit code 0)".to_string()),
            Some(_) => {}
            None => problems.push(format!("did not exit by itself ({status})")),
        },
    }
    if stderr.contains("panicked at") {
        problems.push("panicked".to_string());
    }
    if !stderr.contains(&name) {
        problems.push(format!("stderr does not name the file {name:?}"));
    }
    for e in &expected {
        if !stderr.contains(e.as_str()) {
            problems.push(format!("stderr lacks {e:?}"));
        }
    }
    let files = written(&out);
    if !files.is_empty() {
        problems.push(format!("wrote into --out: {}", files.join(", ")));
    }
    if !problems.is_empty() {
        problems.push(format!("{status}; stderr: {}", trimmed(&stderr, 600)));
    }
    problems
}

#[test]
fn malformed_scenes_are_refused_naming_file_and_field() {
    let files = corpus();
    assert!(
        files.len() >= 60,
        "tests/malformed holds {} scenes, expected at least 60",
        files.len()
    );
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("malformed_scenes");
    let _ = fs::remove_dir_all(&work);
    fs::create_dir_all(&work).expect("work folder");

    let next = AtomicUsize::new(0);
    let failures: Mutex<Vec<(String, Vec<String>)>> = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                let Some(scene) = files.get(i) else { break };
                let problems = check(scene, &work);
                if !problems.is_empty() {
                    let name = scene.file_name().unwrap().to_string_lossy().to_string();
                    failures.lock().unwrap().push((name, problems));
                }
            });
        }
    });

    let mut failures = failures.into_inner().unwrap();
    failures.sort();
    let report: String = failures
        .iter()
        .map(|(name, problems)| format!("\n- {name}\n    {}", problems.join("\n    ")))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} malformed scenes were not refused as expected:{report}",
        failures.len(),
        files.len()
    );
}
