//! `prehensile bench` through the real binary: every numeric option out of range is refused as
//! the arguments are parsed (clap's exit 2, naming the option and its range), never a panic or
//! an abort after minutes of work (found by a hostile-input probe); and the benches' library
//! entries return an error for what cannot be built or solved instead of panicking.

use prehensile::fem::solve::FillOrdering;
use std::process::Command;

fn bench(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg("bench")
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn numbers_out_of_range_are_refused_naming_the_option_and_its_range() {
    let cases: &[(&[&str], &str, &str)] = &[
        (
            &["solver", "--sizes", "0", "--repeats", "1"],
            "--sizes",
            "from 1 to 170",
        ),
        (
            &["solver", "--sizes", "100000", "--repeats", "1"],
            "--sizes",
            "from 1 to 170",
        ),
        (
            &["solver", "--sizes", "2", "--repeats", "0"],
            "--repeats",
            "at least 1",
        ),
        (
            &["elements", "--resolutions", "0"],
            "--resolutions",
            "from 1 to 16",
        ),
        (
            &["elements", "--resolutions", "100000"],
            "--resolutions",
            "from 1 to 16",
        ),
        (
            &["hand", "--resolutions", "0"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (
            &["hand", "--resolutions", "nan"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (
            &["hand", "--resolutions", "99"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (
            &["hand", "--whole-limit", "nan"],
            "--whole-limit",
            "not a finite number",
        ),
        (
            &["grasp", "--resolutions", "1,5"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (
            &["self-contact", "--resolutions", "0"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (
            &["gentle", "--resolutions", "inf"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (&["contact", "--friction=-1"], "--friction", "at least 0"),
        (
            &["contact", "--friction", "nan"],
            "--friction",
            "at least 0",
        ),
        (
            &["render", "--frames", "1", "--spheres", "0"],
            "--spheres",
            "from 1 to 1000",
        ),
        (&["render", "--frames", "0"], "--frames", "at least 1"),
        (&["viewer", "--changes", "0"], "--changes", "at least 1"),
        (
            &["flexion-refinement", "--offsets", "0"],
            "--offsets",
            "from 1 to 6",
        ),
        (
            &["flexion-refinement", "--offsets", "7"],
            "--offsets",
            "from 1 to 6",
        ),
        (
            &["flexion-refinement", "--resolutions", "5"],
            "--resolutions",
            "from 0.5 to 4",
        ),
        (
            &["flexion-refinement", "--angles", "nan"],
            "--angles",
            "not a finite number",
        ),
    ];
    for (args, option, range) in cases {
        let t = std::time::Instant::now();
        let run = bench(args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(option), "{args:?}: {stderr}");
        assert!(stderr.contains(range), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        // Refused as parsed: no bench started (each prints its heading first).
        assert!(run.stdout.is_empty(), "{args:?}");
        assert!(t.elapsed().as_secs_f64() < 10.0, "{args:?}");
    }
}

/// The smallest sizes in range run and print their table.
#[test]
fn the_smallest_sizes_run() {
    for args in [
        &["solver", "--sizes", "1,2", "--repeats", "1"][..],
        &["elements", "--resolutions", "1"][..],
    ] {
        let run = bench(args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{args:?}: {stderr}");
        let table = String::from_utf8_lossy(&run.stdout);
        assert!(table.contains("|---|"), "{args:?}: {table}");
    }
}

/// `bench self-contact --nonlinear` at the coarsest hand: both creases fold to 110° with the
/// skin kept out of itself (the barrier's pairs and force in the table) and without it; the
/// largest bone reaction and the flesh's change of volume are read.
#[test]
fn the_nonlinear_self_contact_bench_folds_both_creases() {
    let run = bench(&["self-contact", "--nonlinear", "--resolutions", "0.5"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let table = String::from_utf8_lossy(&run.stdout);
    assert!(table.contains("the nonlinear tier"), "{table}");
    let rows: Vec<Vec<&str>> = table
        .lines()
        .filter(|l| l.starts_with("| index"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    assert_eq!(rows.len(), 4, "{table}");
    for row in &rows {
        assert!(!row[5].starts_with("stopped"), "{table}");
        let (points, force): (usize, f64) = (row[7].parse().unwrap(), row[8].parse().unwrap());
        // The flesh keeps its volume to 2 %; the skin pressed on itself presses on the bones.
        // (Without it the coarsest hand reads 0.000 N: at resolution 0.5 no flesh spans the
        // PIP, docs/hand.md "Forms".)
        let (bone, volume): (f64, f64) = (row[9].parse().unwrap(), row[10].parse().unwrap());
        // The flesh crushed below half its volume, mm³ at rest: a number, none where nothing
        // presses (measured at 0.5: 49 and 55 mm³ with self-contact, 0 without).
        let crushed: f64 = row[11].parse().unwrap();
        assert!((0.0..1e4).contains(&crushed), "{table}");
        assert!(
            (0.0..100.0).contains(&bone) && volume.abs() < 2.0,
            "{table}"
        );
        if row[3] == "on" {
            assert!(points > 0 && force > 0.0 && bone > 0.1, "{table}");
        } else {
            assert!(points == 0 && force == 0.0, "{table}");
        }
    }
}

/// Called as a library, a size that cannot be built is an error naming it, not a panic.
#[test]
fn the_library_entries_return_errors() {
    let e = prehensile::bench::solver::solver_rows(&[0], FillOrdering::Auto, 1).unwrap_err();
    assert!(format!("{e:#}").contains("--sizes 0"), "{e:#}");
    let e = prehensile::bench::elements::element_rows(&[0]).unwrap_err();
    assert!(format!("{e:#}").contains("--resolutions 0"), "{e:#}");
    for bad in [0.0, f64::NAN, 99.0] {
        let e = prehensile::bench::hand::hand_rows(&[bad], 0.0).unwrap_err();
        let text = format!("{e:#}");
        assert!(
            text.contains("resolution must be a number between 0.5 and 4"),
            "{text}"
        );
    }
}

/// `bench flexion-refinement` at coarse hands: the table of the means and their observed order,
/// coarse to fine whatever the order asked, no NaN or infinity; an angle beyond the joint's range stops it naming the joint (exit 1, not a panic).
/// Through the library: a small flexion's reaction is proportional to its angle (1° and 2°
/// within 2 %: the corotated increments are linear in a small turn), and none at 0°.
#[test]
fn the_flexion_refinement_bench_reads_the_reactions_and_their_order() {
    let run = bench(&[
        "flexion-refinement",
        "--angles",
        "10",
        "--resolutions",
        "1,0.75,1.25,1",
        "--offsets",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let table = String::from_utf8_lossy(&run.stdout);
    // Coarse to fine, each resolution once, whatever the order asked.
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| 10° |")).collect();
    let expected = [
        "| 10° | 0.75 |",
        "| 10° | 1 |",
        "| 10° | 1.25 |",
        "| 10° | 0.75, 1, 1.25 |",
    ];
    assert_eq!(rows.len(), expected.len(), "{table}");
    for (row, r) in rows.iter().zip(expected) {
        assert!(row.starts_with(r), "{r}: {table}");
    }
    assert!(!table.contains("NaN") && !table.contains("inf"), "{table}");
    let run = bench(&[
        "flexion-refinement",
        "--angles",
        "120",
        "--resolutions",
        "0.5",
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("index.pip") && stderr.contains("--angles 120"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");

    use prehensile::bench::flexion_refinement::refinement_rows;
    let rows = refinement_rows(&[0.0, 1.0, 2.0], &[1.0], 1).unwrap();
    let f: Vec<f64> = rows.iter().map(|r| r.mean()).collect();
    assert_eq!(f[0], 0.0, "{f:?}");
    assert!(f[1] > 0.0, "{f:?}");
    assert!((f[2] / f[1] - 2.0).abs() < 0.04, "{f:?}");
}
