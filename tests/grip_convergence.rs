//! What the fingers feel converges under refinement (issue 15): the five-digit grasp of the
//! pressurised ball (`assets/scenes/hand-grasp-ball.toml`, the paper's Figure 4) solved with the
//! hand at resolutions 1, 1.5 and 2 and the ball refined alike (the accuracy bench's scene:
//! 12r cells per face edge, 2r layers). Between 1.5 and 2 the grip Σ|F| over the parts is
//! within 5 %, and each digit that carries at least 10 % of it within 10 %; the printed table
//! gives each part at each resolution and the ratio of successive changes. What each part's
//! skeleton bears as a whole (the sum of its bones' reactions) is within 10 % likewise. This is the suite's
//! longest test (several minutes on 2 cores): resolution 2 is 1.4·10⁵ dofs in the hand.

use prehensile::bench::accuracy::ProblemId;
use prehensile::headless::solve_scene;
use prehensile::state::outcome::PARTS;

/// |F| of each part (palm, thumb … little) in the grasp keyframe, at hand resolution `r`, and
/// the magnitude of the sum of each part's bones' reactions.
fn parts_at(r: f64) -> (Vec<f64>, Vec<f64>) {
    let scene = ProblemId::Grasp.scene(r);
    let name = format!("grasp r={r}");
    let solved = solve_scene(&scene, &name).unwrap_or_else(|e| panic!("{name}: {e}"));
    let frame = solved.frames.last().unwrap();
    let contact = frame.contact.as_ref().expect("the grasp touches the ball");
    assert!(
        contact.max_penetration <= solved.model.contact.penetration_limit(),
        "{name}: {} m",
        contact.max_penetration
    );
    let hand = &frame.hands[0];
    assert!(
        hand.stats.stopped_short.is_none(),
        "{name}: {:?}",
        hand.stats.stopped_short
    );
    let report = &solved.report.frames.last().unwrap().hands["hand"];
    // Action = reaction: the parts' forces sum to what the ball and its stand feel from the hand.
    let on_hand: nalgebra::Vector3<f64> = report
        .contact
        .values()
        .map(|p| nalgebra::Vector3::from(p.force))
        .sum();
    let on_ball: nalgebra::Vector3<f64> = contact
        .contacts
        .iter()
        .filter(|c| c.obstacle().is_none())
        .map(|c| c.force_vector())
        .sum();
    assert!(
        (on_hand.norm() - on_ball.norm()).abs() < 1e-6 * on_ball.norm().max(1e-3),
        "{name}: hand {on_hand:?} vs ball {on_ball:?}"
    );
    let contact = PARTS
        .iter()
        .map(|p| report.contact.get(*p).map_or(0.0, |f| f.magnitude))
        .collect();
    let bones = PARTS
        .iter()
        .map(|p| report.part_reactions[*p].magnitude)
        .collect();
    (contact, bones)
}

#[test]
fn the_grip_converges_under_refinement() {
    let resolutions = [1.0, 1.5, 2.0];
    let (parts, bones): (Vec<Vec<f64>>, Vec<Vec<f64>>) =
        resolutions.iter().map(|&r| parts_at(r)).unzip();
    let grips: Vec<f64> = parts.iter().map(|p| p.iter().sum()).collect();
    println!("| resolution | grip Σ|F| (N) | {} |", PARTS.join(" | "));
    for ((r, p), g) in resolutions.iter().zip(&parts).zip(&grips) {
        let cells: Vec<String> = p.iter().map(|f| format!("{f:.3}")).collect();
        println!("| {r} | {g:.3} | {} |", cells.join(" | "));
    }
    let (g1, g15, g2) = (grips[0], grips[1], grips[2]);
    println!(
        "grip change 1 → 1.5: {:+.2} %, 1.5 → 2: {:+.2} % (ratio of the changes {:.2})",
        100.0 * (g15 - g1) / g15,
        100.0 * (g2 - g15) / g2,
        (g15 - g1).abs() / (g2 - g15).abs().max(1e-12)
    );
    assert!(g2 > 1.0, "the grip is {g2} N");
    assert!(
        (g15 - g2).abs() <= 0.05 * g2,
        "grip 1.5 vs 2: {g15} vs {g2} N"
    );
    let mut compared = 0;
    for (i, name) in PARTS.iter().enumerate().skip(1) {
        let (f15, f2) = (parts[1][i], parts[2][i]);
        if f2 >= 0.1 * g2 {
            compared += 1;
            assert!(
                (f15 - f2).abs() <= 0.10 * f2,
                "{name}: {f15} N at 1.5 against {f2} N at 2"
            );
        }
    }
    // Thumb and at least two fingers carry a tenth of the grip each.
    assert!(
        compared >= 3,
        "only {compared} digits carry 10 % of the grip"
    );
    // What each part's skeleton bears as a whole (the sum of its bones' reactions): within
    // 10 % between 1.5 and 2 for every part (measured 2026-11-27: palm 1.6 %, thumb 0.3 %,
    // index 1 %, middle 0.6 %, ring 0.5 %, little 5 %; the bones one by one up to 3× apart).
    println!(
        "| resolution | part reactions |Σ R| (N): {} |",
        PARTS.join(" | ")
    );
    for (r, b) in resolutions.iter().zip(&bones) {
        let cells: Vec<String> = b.iter().map(|f| format!("{f:.3}")).collect();
        println!("| {r} | {} |", cells.join(" | "));
    }
    for (i, name) in PARTS.iter().enumerate() {
        let (r15, r2) = (bones[1][i], bones[2][i]);
        assert!(r2 > 0.5, "{name}'s bones bear {r2} N");
        assert!(
            (r15 - r2).abs() <= 0.10 * r2,
            "{name}'s bones: {r15} N at 1.5 against {r2} N at 2"
        );
    }
}
