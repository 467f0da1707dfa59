//! The `render` command end to end: PNG output, `--all`, and clear errors (never a panic) when
//! there is no adapter or the overlay cannot be drawn.

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_prehensile"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("render-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn writes_a_png_of_the_asked_size_and_names_the_adapter() {
    let dir = scratch("one");
    let out = dir.join("ball.png");
    let run = bin()
        .args([
            "render",
            "assets/scenes/default.toml",
            "--width",
            "200",
            "--height",
            "120",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("adapter: "), "{stderr}");
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (200, 120));
    // Nothing but the image is left in the folder (the write went through a temporary file).
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
}

#[test]
fn all_frames_go_into_a_folder() {
    let dir = scratch("all");
    let run = bin()
        .args([
            "render",
            "assets/scenes/block-press.toml",
            "--all",
            "--width",
            "64",
            "--height",
            "48",
            "--overlay",
            "forces",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(dir.join("frame_0000.png").is_file());
}

#[test]
fn no_adapter_is_a_clear_error() {
    // Vulkan only, with the loader pointed at no driver: nothing to render with.
    let run = bin()
        .args([
            "render",
            "assets/scenes/default.toml",
            "--out",
            "unused.png",
        ])
        .env("WGPU_BACKEND", "vulkan")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no graphics adapter found"), "{stderr}");
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn pressure_without_contact_is_a_clear_error() {
    let run = bin()
        .args([
            "render",
            "assets/scenes/default.toml",
            "--overlay",
            "pressure",
            "--out",
            "unused.png",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no contact in this scene"), "{stderr}");
}

/// The pressure overlay of a frame out of contact, in a scene whose hand reaches the ball later:
/// the frame is drawn with zero pressure (the legend from 0), not refused. (The viewer takes the
/// same path when the overlay stays on while the hand lets go.)
#[test]
fn pressure_on_a_frame_out_of_contact_is_drawn_as_zero() {
    let dir = scratch("zero-pressure");
    let out = dir.join("open.png");
    let run = bin()
        .args([
            "render",
            "assets/scenes/hand-and-ball.toml",
            "--frame",
            "0",
            "--overlay",
            "pressure",
            "--width",
            "160",
            "--height",
            "90",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let image = image::open(&out).unwrap();
    assert_eq!((image.width(), image.height()), (160, 90));
}

/// A display option that cannot be drawn is the option's error, named, before any solve:
/// `--scale nan` used to be told "the scene has nothing to draw", `--skin-opacity nan` drew a
/// white hand with exit 0.
#[test]
fn display_options_that_cannot_be_drawn_are_named() {
    for (option, value, text) in [
        ("--scale", "nan", "--scale NaN"),
        ("--scale", "inf", "--scale inf"),
        ("--skin-opacity", "nan", "--skin-opacity NaN"),
        ("--skin-opacity", "1.5", "--skin-opacity 1.5"),
        // Out of the documented range (0 to 1000): 1e30 drew only the sky and the legend, with
        // exit 0.
        ("--scale", "1e30", "--scale 1.000e30"),
        ("--scale", "-1", "--scale -1"),
        ("--scale", "1001", "between 0 (undeformed) and 1000"),
    ] {
        let run = bin()
            .args([
                "render",
                "assets/scenes/block-press.toml",
                &format!("{option}={value}"),
                "--out",
                "unused.png",
            ])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{option} {value}: {stderr}");
        assert!(stderr.contains(text), "{option} {value}: {stderr}");
        assert!(
            !stderr.contains("adapter: "),
            "refused before the solve: {stderr}"
        );
    }
}

/// An image larger than the adapter reads back at once (here 12 000² pixels, 576 MB against
/// lavapipe's 268 MB buffer), an --out that is not a PNG and an --all folder that is a file are
/// refused before the scene is solved (the hand scene would take seconds), each naming what to
/// change; nothing is written.
#[test]
fn sizes_and_outputs_that_cannot_be_written_are_refused_before_the_solve() {
    let dir = scratch("refused");
    let a_file = dir.join("a-file");
    std::fs::write(&a_file, b"kept").unwrap();
    let big = dir.join("big.png");
    let jpg = dir.join("frame.jpg");
    let cases: [(Vec<String>, &str); 3] = [
        (
            vec![
                "--width".into(),
                "12000".into(),
                "--height".into(),
                "12000".into(),
                "--out".into(),
                big.display().to_string(),
            ],
            "render a smaller image",
        ),
        (
            vec!["--out".into(), jpg.display().to_string()],
            "name the file .png",
        ),
        (
            vec!["--all".into(), "--out".into(), a_file.display().to_string()],
            "this is a file",
        ),
    ];
    for (args, text) in cases {
        let t = std::time::Instant::now();
        let run = bin()
            .args(["render", "assets/scenes/finger-press-ball.toml"])
            .args(&args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(text), "{args:?}: {stderr}");
        // The adapter is named once the scene is solved and drawn: refused before that.
        assert!(!stderr.contains("adapter: "), "{args:?}: {stderr}");
        println!("{args:?}: refused in {:.2} s", t.elapsed().as_secs_f64());
    }
    assert!(!big.exists() && !jpg.exists());
    assert_eq!(std::fs::read(&a_file).unwrap(), b"kept");
}

/// `--all` into a folder an earlier, longer run wrote: the folder ends holding exactly the new
/// frames (frame_0002.png of the three-frame run is gone), as `solve` replaces its own outputs;
/// files that are no rendered frame (the user's, a solve's report) stay.
#[test]
fn all_frames_replace_an_earlier_longer_run() {
    let dir = scratch("stale");
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    std::fs::write(dir.join("report.json"), "{}").unwrap();
    std::fs::write(dir.join("frame_0000.vtu"), "a solve's").unwrap();
    let render = |scene: &str| {
        let run = bin()
            .args(["render", scene, "--all", "--width", "48", "--height", "32"])
            .arg("--out")
            .arg(&dir)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{scene}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
    };
    let frames = || {
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".png"))
            .collect();
        names.sort();
        names
    };
    render("assets/scenes/finger-press-ball.toml");
    assert_eq!(
        frames(),
        ["frame_0000.png", "frame_0001.png", "frame_0002.png"]
    );
    render("assets/scenes/block-press.toml");
    assert_eq!(frames(), ["frame_0000.png"], "the stale frames are gone");
    assert_eq!(std::fs::read(dir.join("notes.txt")).unwrap(), b"mine");
    assert_eq!(std::fs::read(dir.join("report.json")).unwrap(), b"{}");
    assert_eq!(
        std::fs::read(dir.join("frame_0000.vtu")).unwrap(),
        b"a solve's"
    );
    let image = image::open(dir.join("frame_0000.png")).unwrap();
    assert_eq!((image.width(), image.height()), (48, 32));
}

/// `--out` naming a folder without `--all`: refused before the scene is solved (it rendered for
/// seconds first), saying so once.
#[test]
fn a_folder_as_the_png_is_refused_before_the_solve() {
    let dir = scratch("folder-out");
    let run = bin()
        .args(["render", "assets/scenes/finger-press-ball.toml", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.matches("this is a folder").count(), 1, "{stderr}");
    assert!(stderr.contains("--all"), "{stderr}");
    assert!(
        !stderr.contains("adapter: "),
        "refused before the solve: {stderr}"
    );
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}
