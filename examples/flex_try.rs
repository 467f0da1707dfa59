use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::*;
use prehensile::sim::*;
use std::io::Write;
fn obj(path: &str, hand: &HandModel, st: &HandState) {
    let mut s = std::fs::File::create(path).unwrap();
    for p in hand.skin.positions(&st.positions) {
        writeln!(s, "v {} {} {}", p.x, p.y, p.z).unwrap();
    }
    for q in &hand.skin.quads {
        writeln!(s, "f {} {} {} {}", q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1).unwrap();
    }
}
fn main() {
    faer::set_global_parallelism(faer::Par::rayon(0));
    let res: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(1.0);
    let whole = std::env::args().nth(2).is_some();
    let t = std::time::Instant::now();
    let hand = HandModel::new(Side::Right, res).unwrap();
    println!(
        "build {:?}, skin verts {}",
        t.elapsed(),
        hand.skin.vertex_count()
    );
    let mat = Material {
        young: 5.0e4,
        poisson: 0.45,
        density: 1000.0,
    };
    let mut results = vec![];
    for step in [10.0, 5.0] {
        let mut settings = FlexionSettings::default();
        settings.max_step_deg = step;
        if whole {
            settings.region = FleshRegion::Whole;
        }
        let mut fl = Flexion::new(&hand, "hand", mat, settings, FillOrdering::NestedDissection);
        let mut st = HandState::rest(&hand);
        let v0 = st.flesh_volume(&hand);
        let mut pose = Pose::new();
        pose.insert("index.pip".into(), 90.0);
        let target = hand.skeleton.apply_pose(&st.angles, &pose).unwrap();
        let stats = fl.move_to(&mut st, &target).unwrap();
        println!("step {step}: {:?}", stats);
        println!(
            "  volume change {:.4}%",
            (st.flesh_volume(&hand) / v0 - 1.0) * 100.0
        );
        let r = st.bone_reactions(&hand);
        for (b, bone) in hand.skeleton.bones.iter().enumerate() {
            if r[b].norm() > 1e-6 {
                println!("  {} {:?}", bone.name, r[b].as_slice());
            }
        }
        results.push(st);
    }
    let (a, b) = (&results[0], &results[1]);
    let d: Vec<f64> = a
        .positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| (p - q).norm())
        .collect();
    let disp: Vec<f64> = b
        .positions
        .iter()
        .zip(&hand.flesh.mesh.nodes)
        .map(|(p, q)| (p - q).norm())
        .collect();
    println!(
        "max diff 10 vs 5: {:.3e} m, max disp {:.3e}",
        d.iter().cloned().fold(0.0, f64::max),
        disp.iter().cloned().fold(0.0, f64::max)
    );
    // skinning
    let mut settings = FlexionSettings::default();
    settings.methods = [FleshMethod::Skinning; 6];
    let mut fl = Flexion::new(&hand, "hand", mat, settings, FillOrdering::NestedDissection);
    let mut st = HandState::rest(&hand);
    let mut pose = Pose::new();
    pose.insert("index.pip".into(), 90.0);
    let target = hand.skeleton.apply_pose(&st.angles, &pose).unwrap();
    let stats = fl.move_to(&mut st, &target).unwrap();
    println!(
        "skinning: {:.2} ms, volume change {:.4}%",
        stats.total_ms,
        (st.flesh_volume(&hand) / HandState::rest(&hand).flesh_volume(&hand) - 1.0) * 100.0
    );
    let sa = hand.skin.positions(&b.positions);
    let sb = hand.skin.positions(&st.positions);
    let d: Vec<f64> = sa.iter().zip(&sb).map(|(p, q)| (p - q).norm()).collect();
    println!(
        "skin fem vs skinning: max {:.3e} rms {:.3e}",
        d.iter().cloned().fold(0.0, f64::max),
        (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
    );
    obj("/tmp/flex.obj", &hand, b);
    obj("/tmp/rest.obj", &hand, &HandState::rest(&hand));
}
