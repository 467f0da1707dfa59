//! `prehensile bench accuracy`: its library functions measure what they claim. The cantilever's
//! errors fall with the mesh at the rate of the elements, incompatible modes beat the standard
//! hex8 on the coarse beam, the tables carry a row per variant and resolution with finite
//! numbers, tiers the solver refuses are recorded with its reason, the hand measure is zero
//! between identical solutions and not between tiers, and the plot and document are written.

use nalgebra::Vector3;
use prehensile::bench::accuracy::{
    doc_text, merged_text, plot_png, problem_rows, problem_table, run_scene, Embedding,
    HandReference, Machine, Outcome, ProblemId, Results, Row, Variant, GUIDANCE_BEGIN,
    GUIDANCE_END,
};
use prehensile::mesh::box_mesh;
use prehensile::scene::ElementName;
use prehensile::scene::TierName;

fn quiet(_: &str) {}

fn cantilever_rows() -> Vec<Row> {
    let variants = [
        Variant::new(TierName::Linear),
        Variant {
            element: ElementName::IncompatibleModes,
            ..Variant::new(TierName::Linear)
        },
        Variant::new(TierName::Nonlinear),
        Variant::new(TierName::Skinning),
        Variant::new(TierName::Corotational),
    ];
    variants
        .iter()
        .flat_map(|v| problem_rows(ProblemId::Cantilever, v, false, None, &mut quiet))
        .collect()
}

/// The plotted errors of a variant's rows, coarsest first.
fn errors(rows: &[Row], v: &Variant) -> Vec<f64> {
    rows.iter()
        .filter(|r| &r.variant == v)
        .map(|r| r.error().expect("measured"))
        .collect()
}

#[test]
fn cantilever_errors_fall_with_the_mesh_and_incompatible_modes_do_not_lock() {
    let rows = cantilever_rows();
    let hex8 = errors(&rows, &Variant::new(TierName::Linear));
    let incompatible = errors(
        &rows,
        &Variant {
            element: ElementName::IncompatibleModes,
            ..Variant::new(TierName::Linear)
        },
    );
    let nonlinear = errors(&rows, &Variant::new(TierName::Nonlinear));
    println!("tip errors (%), k = 1, 2, 4: hex8 {hex8:?}, incompatible {incompatible:?}, nonlinear {nonlinear:?}");
    // Shear locking of the fully integrated hex8: about a third of the deflection missing with
    // one element through the thickness, and the error falls by more than 2.5 per halving.
    assert!(hex8[0] > 30.0 && hex8[0] < 40.0, "{hex8:?}");
    assert!(
        hex8[0] / hex8[1] > 2.5 && hex8[1] / hex8[2] > 2.5,
        "{hex8:?}"
    );
    // Incompatible modes reproduce bending on the coarse beam: ten times closer than hex8.
    assert!(
        incompatible[0] * 10.0 < hex8[0],
        "{incompatible:?} vs {hex8:?}"
    );
    // Every element converges; the last per cent is the 3D beam against Timoshenko's.
    for e in [&hex8, &incompatible, &nonlinear] {
        assert!(e[0] > e[1] && e[1] > e[2], "{e:?}");
        assert!(e[2] < 5.0, "{e:?}");
    }
    assert!(nonlinear[0] / nonlinear[2] > 5.0, "{nonlinear:?}");
}

#[test]
fn the_table_has_a_finite_row_per_tier_and_resolution_and_says_why_others_do_not_apply() {
    let rows = cantilever_rows();
    let results = Results {
        rows,
        ..Default::default()
    };
    let table = problem_table(&results, ProblemId::Cantilever);
    println!("{table}");
    let lines: Vec<&str> = table.lines().skip(2).collect();
    let measured: Vec<&&str> = lines.iter().filter(|l| !l.contains("n/a")).collect();
    // linear · hex8, linear · incompatible modes, nonlinear at 8×1×1, 16×2×2, 32×4×4.
    assert_eq!(measured.len(), 9, "{table}");
    for label in ["linear", "linear · incompatible modes", "nonlinear"] {
        for res in ["8×1×1", "16×2×2", "32×4×4"] {
            assert!(
                measured
                    .iter()
                    .any(|l| l.starts_with(&format!("| {label} | {res} |"))),
                "{label} at {res} missing"
            );
        }
    }
    for line in &measured {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // | tier | resolution | elements | ms | front | error | signed error |
        let ms: f64 = cells[4].parse().expect("a time");
        assert!(ms.is_finite() && ms >= 0.0, "{line}");
        for c in &cells[6..8] {
            let v: f64 = c.trim_end_matches(" %").parse().expect("a number");
            assert!(v.is_finite(), "{line}");
        }
    }
    // Skinning and corotational do not apply to a beam: one row each, with the reason.
    let na: Vec<&&str> = lines.iter().filter(|l| l.contains("n/a")).collect();
    assert_eq!(na.len(), 2, "{table}");
    assert!(na
        .iter()
        .any(|l| l.contains("skinning") && l.contains("no mechanics")));
    assert!(!table.contains("NaN") && !table.contains("inf"));
}

#[test]
fn a_tier_the_solver_refuses_is_recorded_with_its_reason_or_measured_once_it_takes_it() {
    // Nonlinear with a rigid obstacle (Hertz), and nonlinear for a hand (the flexion): the
    // solver's own reason today, a finite measure on the day it is supported; never "failed".
    let hertz = problem_rows(
        ProblemId::Hertz,
        &Variant::new(TierName::Nonlinear),
        true,
        None,
        &mut quiet,
    );
    assert_eq!(hertz.len(), 3);
    for r in &hertz {
        match &r.outcome {
            Outcome::NotApplicable(why) => assert!(why.contains("nonlinear"), "{why}"),
            Outcome::Measured { values, .. } => assert!(values.iter().all(|v| v.is_finite())),
            Outcome::Failed(why) => panic!("failed: {why}"),
        }
    }
    let mut scene = ProblemId::Flexion30.scene(0.5);
    Variant::new(TierName::Nonlinear).apply(&mut scene);
    match run_scene(&scene, "flexion") {
        Err(prehensile::bench::accuracy::RunError::Refused(why)) => {
            assert!(why.contains("nonlinear"), "{why}")
        }
        Err(prehensile::bench::accuracy::RunError::Failed(why)) => panic!("failed: {why}"),
        Ok(solved) => assert!(!solved.frames.is_empty()),
    }
}

#[test]
fn the_hand_measure_is_zero_between_identical_solves_and_not_between_tiers() {
    let solve = |tier| {
        let mut scene = ProblemId::Flexion30.scene(0.5);
        Variant {
            step_deg: Some(10.0),
            ..Variant::new(tier)
        }
        .apply(&mut scene);
        run_scene(&scene, "flexion").expect("solved")
    };
    let reference = HandReference {
        finest: solve(TierName::Corotational),
        same_mesh: vec![(0.5, solve(TierName::Corotational))],
    };
    let again = solve(TierName::Corotational);
    let skinned = solve(TierName::Skinning);
    let same = ProblemId::Flexion30
        .measure(&again, 0.5, Some(&reference))
        .unwrap();
    let other = ProblemId::Flexion30
        .measure(&skinned, 0.5, Some(&reference))
        .unwrap();
    println!("same {same:?}\nskinning {other:?}");
    // largest, RMS, largest on the same mesh, volume change, its gap, nodes compared.
    assert!(
        same[0] < 1e-12 && same[1] < 1e-12 && same[2] < 1e-12,
        "{same:?}"
    );
    assert_eq!(same[4], 0.0);
    assert_eq!(same[5], 1.0, "every free node lies in its own mesh");
    // Skinning folds the palmar crease where the FEM bulges: millimetres apart.
    assert!(other[0] > 1e-3 && other[2] > 1e-3, "{other:?}");
    assert!(other[3] < 0.0, "skinning loses volume: {other:?}");
}

#[test]
fn an_embedding_reproduces_linear_fields_and_leaves_out_points_beyond_reach() {
    let fine = box_mesh(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0), [5, 4, 3]);
    let field: Vec<Vector3<f64>> = fine
        .nodes
        .iter()
        .map(|p| Vector3::new(2.0 * p.x - p.y, p.z + 0.5, p.y))
        .collect();
    let points = [
        Vector3::new(0.31, 0.77, 0.12),
        Vector3::new(1.0, 1.0, 1.0),
        Vector3::new(1.05, 0.5, 0.5),
        Vector3::new(1.5, 0.5, 0.5),
    ];
    let e = Embedding::new(&fine, &points, 0.1, |_, _| true);
    assert_eq!(e.inside(), 3);
    let u = e.interpolate(&field);
    let exact = |p: &Vector3<f64>| Vector3::new(2.0 * p.x - p.y, p.z + 0.5, p.y);
    for i in 0..2 {
        assert!((u[i].unwrap() - exact(&points[i])).norm() < 1e-12, "{i}");
    }
    // Just outside: the nearest point of the mesh, x = 1.
    let near = Vector3::new(1.0, 0.5, 0.5);
    assert!((u[2].unwrap() - exact(&near)).norm() < 1e-12);
    assert!(u[3].is_none());
}

#[test]
fn the_plot_and_the_document_are_written_from_the_rows_and_keep_the_guidance() {
    let results = Results {
        rows: cantilever_rows(),
        ..Default::default()
    };
    let image = plot_png(&results, "test").unwrap();
    assert!(image.width() >= 600 && image.height() >= 600);
    // Curves are drawn in the tiers' colours: some pixels of linear's blue.
    let blue = image
        .pixels()
        .filter(|p| p.0[2] > 150 && p.0[0] < 80 && p.0[1] < 140)
        .count();
    assert!(blue > 100, "{blue} blue pixels");
    let machine = Machine::now();
    let first = doc_text(
        &results,
        &machine,
        "images/p.png",
        "prehensile bench accuracy",
        None,
    );
    assert!(first.contains(GUIDANCE_BEGIN) && first.contains(GUIDANCE_END));
    assert!(first.contains("![") && first.contains("images/p.png"));
    let edited = first.replace("(To be written", "Pick incompatible modes. (To be written");
    let second = doc_text(&results, &machine, "images/p.png", "x", Some(&edited));
    assert!(second.contains("Pick incompatible modes."));
    assert!(!second.contains("NaN"));
}

/// `--only`: the sections of the problems run replace theirs in the document; every other
/// section, the guidance and the plot link stay word for word (a whole document written from
/// one problem once cut two sections off).
#[test]
fn a_run_of_some_problems_replaces_only_their_sections() {
    let machine = Machine::now();
    let existing = "# Speed against accuracy\n\nheader\n\n![plot](images/p.png)\n\n\
                    <!-- guidance: written from the numbers, kept by the bench -->\nkeep me\n\
                    <!-- end of guidance -->\n\n\
                    ## (a) cantilever: tip deflection against Timoshenko\n\nold cantilever rows\n\n\
                    ## (b) thick sphere under pressure: radial displacement against Lamé\n\nLamé rows\n\n\
                    Reproduce: `cargo run --release -- bench accuracy`\n";
    let results = Results {
        rows: cantilever_rows(),
        ..Default::default()
    };
    let merged = merged_text(
        existing,
        &results,
        &machine,
        "prehensile bench accuracy --only cantilever",
    );
    assert!(!merged.contains("old cantilever rows"), "{merged}");
    assert!(merged.contains("| linear | 8×1×1 |"), "{merged}");
    assert!(merged.contains("--only cantilever"), "{merged}");
    for kept in [
        "header",
        "![plot](images/p.png)",
        "keep me",
        "Lamé rows",
        "Reproduce: ",
    ] {
        assert!(merged.contains(kept), "{kept} lost: {merged}");
    }
    // In order: the new cantilever section before Lamé's, once.
    assert_eq!(merged.matches("## (a) cantilever").count(), 1);
    assert!(merged.find("## (a)").unwrap() < merged.find("## (b)").unwrap());
    assert!(merged.find("Lamé rows").unwrap() < merged.find("Reproduce: ").unwrap());
    // A problem the document lacks goes before the closing line.
    let without = existing.replace(
        "## (a) cantilever: tip deflection against Timoshenko\n\nold cantilever rows\n\n",
        "",
    );
    let merged = merged_text(&without, &results, &machine, "x");
    assert!(merged.find("## (a)").unwrap() < merged.find("Reproduce: ").unwrap());
    assert!(merged.find("Lamé rows").unwrap() < merged.find("## (a)").unwrap());
}
