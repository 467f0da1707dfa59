//! The viewer as a program: without a display it says so in one line and names the headless
//! commands; under Xvfb the real window opens, solves the default scene and its screenshot is
//! not blank. Xvfb must be installed (`.ci/run` installs it): without it the smoke test fails.
//! Also the real physics behind the solver thread: a stale job is cancelled between
//! increments, and the next one goes on from where it stopped.

use prehensile::app::jobs::{Failure, Job, Solution, Target};
use prehensile::app::physics::Physics;
use prehensile::app::worker::{Cancel, Solve};
use prehensile::present::VisualOptions;
use prehensile::scene::{Scene, DEFAULT_SCENE};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::AtomicU64;
use std::sync::Arc;
use std::time::{Duration, Instant};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_prehensile"));
    c.env("NODEVICE_SELECT", "1");
    c
}

#[test]
fn without_a_display_it_says_so_in_one_line() {
    let out = bin()
        .arg("view")
        .arg("assets/scenes/hand-and-ball.toml")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].contains("no display"), "{err}");
    assert!(lines[0].contains("prehensile solve") && lines[0].contains("prehensile render"));
    assert!(!err.contains("panicked"));
    // With no subcommand too.
    let out = bin()
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(String::from_utf8_lossy(&out.stderr).lines().count(), 1);
}

#[test]
fn help_lists_the_viewer_and_the_headless_commands() {
    let out = bin().arg("--help").output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    for cmd in ["view", "solve", "render", "bench"] {
        assert!(
            text.lines().any(|l| l.trim_start().starts_with(cmd)),
            "{cmd} missing from:\n{text}"
        );
    }
}

struct Child(std::process::Child);

impl Drop for Child {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts Xvfb on a free display number; fails the test when Xvfb is not installed.
fn xvfb() -> (Child, String) {
    let found = std::env::var_os("PATH")
        .map(|p| std::env::split_paths(&p).any(|d| d.join("Xvfb").is_file()))
        .unwrap_or(false);
    assert!(
        found,
        "Xvfb is not installed: the window smoke test needs it (Debian: apt-get install xvfb; \
         .ci/run installs it)"
    );
    for n in 90..120 {
        // A display is taken while its lock names a live server (a killed Xvfb leaves its lock
        // and socket behind; Xvfb itself replaces a stale lock).
        let lock = std::fs::read_to_string(format!("/tmp/.X{n}-lock")).ok();
        let alive = lock
            .as_deref()
            .is_some_and(|pid| Path::new(&format!("/proc/{}", pid.trim())).exists());
        if alive || (lock.is_none() && Path::new(&format!("/tmp/.X11-unix/X{n}")).exists()) {
            continue;
        }
        if lock.is_some() {
            // Stale: its socket would look like the new server's.
            let _ = std::fs::remove_file(format!("/tmp/.X11-unix/X{n}"));
            let _ = std::fs::remove_file(format!("/tmp/.X{n}-lock"));
        }
        let display = format!(":{n}");
        let child = Command::new("Xvfb")
            .args([&display, "-screen", "0", "1600x900x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb starts");
        let child = Child(child);
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(10) {
            if Path::new(&format!("/tmp/.X11-unix/X{n}")).exists() {
                return (child, display);
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    panic!("Xvfb did not start on any display from :90 to :119");
}

#[test]
fn the_window_opens_under_xvfb_and_shows_the_default_scene() {
    let (_xvfb, display) = xvfb();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("viewer-smoke");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join("window.png");
    let mut child = Child(
        bin()
            .args(["view", "--screenshot"])
            .arg(&shot)
            .args([
                "--exit-after-frames",
                "20000",
                "--width",
                "1280",
                "--height",
                "800",
            ])
            .env("DISPLAY", &display)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.0.try_wait().unwrap() {
            break s;
        }
        assert!(
            start.elapsed() < Duration::from_secs(240),
            "the viewer did not close within 240 s"
        );
        std::thread::sleep(Duration::from_millis(100));
    };
    let mut err = String::new();
    if let Some(mut e) = child.0.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut err);
    }
    assert!(status.success(), "viewer failed: {status}\n{err}");
    let image = image::open(&shot)
        .unwrap_or_else(|e| panic!("no screenshot {}: {e}\n{err}", shot.display()))
        .to_rgba8();
    assert!(
        image.width() >= 1000 && image.height() >= 600,
        "{:?}",
        image.dimensions()
    );
    // Not blank: many distinct colours, and the middle of the window (the 3D view) varies.
    let mut colours = std::collections::HashSet::new();
    for p in image.pixels() {
        colours.insert([p[0] >> 2, p[1] >> 2, p[2] >> 2]);
    }
    assert!(colours.len() > 500, "{} colours", colours.len());
    let (w, h) = image.dimensions();
    let lum: Vec<f64> = (h / 4..3 * h / 4)
        .flat_map(|y| (w / 3..2 * w / 3).map(move |x| (x, y)))
        .map(|(x, y)| {
            let p = image.get_pixel(x, y);
            0.3 * p[0] as f64 + 0.59 * p[1] as f64 + 0.11 * p[2] as f64
        })
        .collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    let sd = (lum.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / lum.len() as f64).sqrt();
    assert!(sd > 10.0, "the 3D view looks flat: sd {sd:.1}");
}

#[test]
fn a_stale_job_is_cancelled_between_increments_and_the_next_goes_on() {
    let scene = Arc::new(Scene::parse(DEFAULT_SCENE, "default").unwrap());
    let hands = prehensile::app::pose::hands_of(&scene);
    let pip = hands[0]
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == "index.pip")
        .unwrap();
    let mut target = hands[0].skeleton.rest_angles();
    target[pip] = 60.0;
    let job = |version: u64, target: &[f64]| Job {
        version,
        scene: scene.clone(),
        scene_revision: 1,
        visual: VisualOptions::default(),
        target: Target::Pose {
            pose: vec![(hands[0].body, target.to_vec())],
            start: None,
        },
        ahead: Default::default(),
    };
    let mut physics = Physics::new();
    let run = |physics: &mut Physics, job: &Job, cancel: &Cancel| {
        let mut out: Vec<Result<Solution, Failure>> = Vec::new();
        physics.run(job, cancel, &mut |r| out.push(r));
        out
    };
    // A newer version (2) exists: job 1 stops at its first increment.
    let latest = Arc::new(AtomicU64::new(2));
    let out = run(
        &mut physics,
        &job(1, &target),
        &Cancel::new(latest.clone(), 1),
    );
    assert!(matches!(out.as_slice(), [Err(Failure::Cancelled)]));
    let out = run(&mut physics, &job(2, &target), &Cancel::new(latest, 2));
    let [Ok(solution)] = out.as_slice() else {
        panic!("one frame")
    };
    let hand = &solution.frame.hands[0];
    assert_eq!(hand.angles[pip], 60.0);
    assert!(hand.stats.increments_taken >= 6, "60° in steps of 10°");
    assert!(!solution.draw_list.surfaces.is_empty());
    // The next pose goes on from there: 60° → 70° is one increment. A preview of it (the hand
    // moved there by skinning from the frame at 60°: the scene has a ball) comes first.
    target[pip] = 70.0;
    let next = job(3, &target);
    let out = run(
        &mut physics,
        &next,
        &Cancel::new(Arc::new(AtomicU64::new(3)), 3),
    );
    let [Ok(preview), Ok(solution)] = out.as_slice() else {
        panic!("a preview, then the frame")
    };
    assert!(preview.preview && !solution.preview);
    assert_eq!(preview.frame.hands[0].angles[pip], 70.0);
    assert_eq!(solution.frame.hands[0].stats.increments_taken, 1);
}
