use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::*;
use prehensile::sim::*;
fn main() {
    let hand = HandModel::new(Side::Right, 1.0).unwrap();
    let mat = Material {
        young: 5.0e4,
        poisson: 0.45,
        density: 1000.0,
    };
    let settings = FlexionSettings::default();
    let mut fl = Flexion::new(&hand, "hand", mat, settings, FillOrdering::NestedDissection);
    let mut st = HandState::rest(&hand);
    for a in (10..=90).step_by(10) {
        let mut pose = Pose::new();
        pose.insert("index.pip".into(), a as f64);
        let target = hand.skeleton.apply_pose(&st.angles, &pose).unwrap();
        let prev = st.clone();
        match fl.move_to(&mut st, &target) {
            Ok(_) => println!("{a}: ok"),
            Err(SimError::InvertedElement { element, .. }) => {
                let c = hand.flesh.mesh.cells[element];
                let rest: nalgebra::Vector3<f64> = c
                    .iter()
                    .map(|&n| hand.flesh.mesh.nodes[n])
                    .sum::<nalgebra::Vector3<f64>>()
                    / 8.0;
                println!(
                    "{a}: inverted cell {element} rest centre {:?} digit {:?}",
                    rest.as_slice(),
                    hand.flesh.cell_digit[element]
                );
                for &n in &c {
                    println!(
                        "   node {n} rest {:?} prev {:?} bone {:?}",
                        hand.flesh.mesh.nodes[n].as_slice(),
                        prev.positions[n].as_slice(),
                        hand.flesh.node_bone[n].map(|b| hand.skeleton.bones[b].name.clone())
                    );
                }
                break;
            }
            Err(e) => {
                println!("{e}");
                break;
            }
        }
    }
}
