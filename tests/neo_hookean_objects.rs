//! The nonlinear tier carries the other bodies in contact as Neo-Hookean solids (issue 15,
//! item 2): each contact step is a Newton iteration of the ball about where the last left it
//! (tangent and internal force of the Neo-Hookean hexahedra), and the corrections at the pose
//! iterate it to equilibrium. Tested on the index pressing the pressurised rubber ball (the
//! shipped finger press, held by its stand, without the table): at the last frame the ball's
//! Neo-Hookean internal force balances its loads (the air on the wall where it is now, its
//! weight) and the contact forces at every free dof, and the hand feels what the ball feels.
//! The corotational tier's frame is not in that balance: its ball is a small-strain law.

use nalgebra::Vector3;
use prehensile::fem::hyperelastic_body::HyperelasticBody;
use prehensile::fem::loads::add_pressure;
use prehensile::headless::{solve_scene, Solved};
use prehensile::mesh::Mesh;
use prehensile::scene::Scene;

/// The shipped finger press at hand resolution 0.75 on `tier`, pressed to MCP 23°; with
/// `table`, the ball also rests on its table (a rigid obstacle).
fn press(tier: &str, table: bool) -> Solved {
    let text = std::fs::read_to_string("assets/scenes/finger-press-ball.toml").unwrap();
    let obstacle = text.find("[[obstacle]]").unwrap();
    let keyframes = text.find("[[keyframe]]").unwrap();
    let text = if table {
        text.clone()
    } else {
        format!("{}{}", &text[..obstacle], &text[keyframes..])
    };
    let text = text
        .replace("resolution = 1.0", "resolution = 0.75")
        .replace("[solver]", &format!("[solver]\ntier = \"{tier}\""))
        .replace(
            "pose = { \"index.mcp.flex\" = 21.5 }",
            "pose = { \"index.mcp.flex\" = 23.0 }",
        );
    let scene = Scene::parse(&text, "press.toml").unwrap();
    solve_scene(&scene, "press.toml").unwrap_or_else(|e| panic!("{tier}: {e}"))
}

/// The largest out-of-balance force on a free dof of the ball, measured with its Neo-Hookean
/// internal force, and the contact force on it (N).
fn ball_balance(solved: &Solved) -> (f64, f64) {
    let model = &solved.model;
    let frame = solved.frames.last().unwrap();
    let ball = model.bodies.iter().position(|b| b.name == "ball").unwrap();
    let nodes = model.bodies[ball].nodes.clone();
    let u = &frame.solution.displacement;
    let mut body_u = vec![0.0; u.len()];
    for n in nodes.clone() {
        body_u[3 * n..3 * n + 3].copy_from_slice(&u[3 * n..3 * n + 3]);
    }
    let body = HyperelasticBody::new(&model.mesh, &model.cell_materials, model.flexion.volumetric)
        .unwrap();
    let (_, internal) = body.internal_forces(&body_u).unwrap();
    // The loads: the air on the wall where it is now, the weight where it was.
    let now = Mesh {
        nodes: (0..model.mesh.node_count())
            .map(|n| model.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
            .collect(),
        cells: model.mesh.cells.clone(),
    };
    let mut loads = model.load_vector.clone();
    for l in &model.loads {
        if let Some((p, facets)) = &l.pressure {
            add_pressure(&mut loads, &model.mesh, facets, -p);
            add_pressure(&mut loads, &now, facets, *p);
        }
    }
    let mut contact = vec![0.0; u.len()];
    let mut on_ball = Vector3::zeros();
    for c in &frame.contact.as_ref().unwrap().contacts {
        for (n, f) in c.nodal_forces() {
            if nodes.contains(&n) {
                // The table's contacts act on the ball's nodes alone; the pad's on both.
                if c.obstacle().is_none() {
                    on_ball += f;
                }
                for a in 0..3 {
                    contact[3 * n + a] += f[a];
                }
            }
        }
    }
    let mut worst: f64 = 0.0;
    for n in model.bodies[ball].nodes.clone() {
        for a in 0..3 {
            let d = 3 * n + a;
            if model.partition.prescribed[d] {
                continue;
            }
            worst = worst.max((internal[d] - loads[d] - contact[d]).abs());
        }
    }
    (worst, on_ball.norm())
}

#[test]
fn the_pressed_ball_is_in_neo_hookean_equilibrium() {
    let nonlinear = press("nonlinear", false);
    let (residual, on_ball) = ball_balance(&nonlinear);
    let frame = nonlinear.frames.last().unwrap();
    let hand = frame.hands[0]
        .contact_force
        .iter()
        .sum::<Vector3<f64>>()
        .norm();
    println!("nonlinear: contact on the ball {on_ball:.4} N, hand {hand:.4} N, residual {residual:.2e} N");
    assert!(on_ball > 0.5, "{on_ball} N");
    // Action = reaction between the hand and the ball.
    assert!(
        (hand - on_ball).abs() < 1e-6 * on_ball,
        "{hand} vs {on_ball} N"
    );
    // The corrections stop when the force changes by less than 0.1 %: the balance holds to a
    // few tenths of a per cent of the press at any one dof.
    assert!(
        residual < 3e-3 * on_ball,
        "residual {residual} N of {on_ball} N"
    );

    let corotational = press("corotational", false);
    let (residual_c, on_ball_c) = ball_balance(&corotational);
    println!("corotational: contact on the ball {on_ball_c:.4} N, Neo-Hookean residual {residual_c:.2e} N");
    // The corotated small-strain ball is not in Neo-Hookean balance (the inflated wall's
    // tension stiffens it): the check above can fail.
    assert!(residual_c > 10.0 * residual, "{residual_c} vs {residual} N");
}

/// On its table (a rigid obstacle) the ball's static frame is solved by Newton with the
/// table's contact in every iteration (refused by the nonlinear tier before): at rest the
/// table and the stand carry its weight, and the pressed frame is in Neo-Hookean balance with
/// the pad and the table at once.
#[test]
fn the_ball_on_its_table_is_in_neo_hookean_equilibrium() {
    let solved = press("nonlinear", true);
    let still = &solved.report.frames[0];
    let weight = Vector3::from(still.gravity).norm();
    let imbalance = Vector3::from(still.equilibrium.imbalance).norm();
    let table: Vector3<f64> = solved.frames[0]
        .contact
        .as_ref()
        .expect("the table's contact")
        .contacts
        .iter()
        .map(|c| c.force_vector())
        .sum();
    println!("the table carries {:.4} N", table.norm());
    // The table is engaged: the inflated ball pushes its bottom onto it past the stand.
    assert!(table.norm() > 0.1 * weight, "{table}");
    println!("on the table: weight {weight:.4} N, imbalance {imbalance:.2e} N");
    assert!(weight > 0.01, "{weight} N");
    assert!(imbalance < 1e-6 * weight, "{imbalance} of {weight} N");
    let (residual, on_ball) = ball_balance(&solved);
    println!("pressed on the table: {on_ball:.4} N, residual {residual:.2e} N");
    assert!(on_ball > 0.5, "{on_ball} N");
    assert!(
        residual < 3e-3 * on_ball,
        "residual {residual} N of {on_ball} N"
    );
}

/// The viewer's Power grasp preset on the default scene, on `tier`.
fn power_grasp(tier: Option<prehensile::scene::TierName>) -> Solved {
    use prehensile::app::pose::Preset;
    let mut scene = prehensile::bench::grasp::preset_scene(Preset::PowerGrasp);
    scene.solver.tier = tier;
    solve_scene(&scene, "power.toml").unwrap_or_else(|e| panic!("{tier:?}: {e}"))
}

/// The Power grasp squeezes the pressurised ball to a principal strain of 0.3: the
/// corotational tier's ball (a small-strain law) is warned of, naming the hands' press as the
/// cause and a less deep pose as the remedy (until 2026-11-27 also the nonlinear tier); on the
/// nonlinear tier the ball is Neo-Hookean,
/// no such warning, and the corrections at the pose — slow under the air's follower load
/// (−15 %, −13 %, −11 %, −9 %, −7 %, −6 % when plain: 21.4 → 11.2 N, still 6 % off) —
/// are relaxed by Aitken's Δ² on the carried state and go past the plain six while they
/// shrink. They do not settle to 0.1 %: a contact point changing facet moves the force by about
/// 1 % from one correction to the next (docs/contact.md, limits). What is asserted is that this is told: the warning is given exactly
/// when the last change is above the report's threshold, and it stays within 10 %. (Extrapolated on
/// the force alone, 2026-11-26, the twelfth changed it by 1.34 %; relaxed on the state,
/// 2026-11-27, the seventh by 1.25 %, where going on went 11.0 → 12.6 → 9.8 N; with the contact
/// normal smoothed and a correction started past the last one's end redone plainly where it
/// fails, 9.19 → 9.06 → 8.89 → 8.73 → 8.48 → 9.14 N, 7.8 % at the ninth; with the air's load
/// stiffness in the corrections' tangent, 2026-11-29: 8.62 → 8.35 → 8.24 → 8.24 → 8.28 → 8.36 N,
/// 0.88 % at the eighth, no longer warned.)
#[test]
fn the_power_grasps_squeezed_ball_is_warned_of_and_the_nonlinear_tier_tells_how_settled_its_contact_is(
) {
    let corotational = power_grasp(None);
    let warnings = &corotational.report.warnings;
    let strain = warnings
        .iter()
        .find(|w| w.contains("body \"ball\": principal strain"))
        .unwrap_or_else(|| panic!("{warnings:?}"));
    // A pressurised ball: the pose is advised, not the nonlinear tier, whose corrections do
    // not settle on it (below).
    assert!(
        strain.contains("the hands press it that far")
            && strain.contains("pose the grasp less deep")
            && !strain.contains("tier = \"nonlinear\""),
        "{strain}"
    );
    let nonlinear = power_grasp(Some(prehensile::scene::TierName::Nonlinear));
    let warnings = &nonlinear.report.warnings;
    println!("{warnings:#?}");
    assert!(
        !warnings.iter().any(|w| w.contains("principal strain")),
        "{warnings:?}"
    );
    let stats = &nonlinear.frames.last().unwrap().hands[0].stats;
    let change = stats.unsettled_at_pose.unwrap_or(0.0);
    println!(
        "nonlinear: {} corrections, last change {:.3} %",
        stats.pose_corrections,
        change * 100.0
    );
    assert!(change < 0.10, "{change}");
    // Warned exactly when above the report's threshold.
    assert_eq!(
        warnings.iter().any(|w| w.contains("still changed by")),
        change > prehensile::state::KeyframeStats::UNSETTLED_WARNING,
        "{warnings:?}"
    );
    assert!(stats.pose_corrections > 6, "{}", stats.pose_corrections);
}

/// The air's load stiffness in the corrections' tangent (since 2026-11-29): the five-digit grasp
/// of the pressurised ball (`hand-grasp-ball.toml`) on the nonlinear tier settles at its pose —
/// the last correction changes the hands' force by less than the report's 0.1 % — in at most
/// four corrections (measured: 3, Σ|F| 2.9186 N; without the load stiffness 8, 2.9201 N).
#[test]
fn the_five_digit_grasp_settles_in_few_corrections_with_the_airs_load_stiffness() {
    let text = std::fs::read_to_string("assets/scenes/hand-grasp-ball.toml")
        .unwrap()
        .replace("[solver]", "[solver]\ntier = \"nonlinear\"");
    let scene = Scene::parse(&text, "hand-grasp-ball.toml").unwrap();
    let solved = solve_scene(&scene, "hand-grasp-ball.toml").unwrap();
    let stats = &solved.frames.last().unwrap().hands[0].stats;
    let grip: f64 = solved.report.frames.last().unwrap().hands["hand"]
        .contact
        .values()
        .map(|p| p.magnitude)
        .sum();
    println!(
        "{} corrections, unsettled {:?}, grip {grip:.4} N",
        stats.pose_corrections, stats.unsettled_at_pose
    );
    assert!(
        stats.unsettled_at_pose.is_none(),
        "{:?}",
        stats.unsettled_at_pose
    );
    assert!(stats.stopped_short.is_none(), "{:?}", stats.stopped_short);
    assert!(
        (1..=4).contains(&stats.pose_corrections),
        "{}",
        stats.pose_corrections
    );
}
