//! The Object panel's model: the scene's ball (the first shell or sphere body) as a few numbers
//! — radius, Young's modulus, Poisson ratio, internal pressure, shell or solid, centre, the
//! skin's friction on it — and how an edit rewrites the scene: the body's shape, its own
//! material (and the friction pairs that named the old one), its pressure load, the skin–ball
//! friction pair, and the box selections and probe points on it, carried along with the ball's
//! centre and radius.

use crate::scene::{FrictionDef, LoadDef, MaterialDef, Scene, Selection, Shape};

/// Shell wall thickness as a fraction of the outer radius (the default ball's 4 mm of 35 mm).
const WALL: f64 = 4.0 / 35.0;

/// The ball as the Object panel shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct BallParams {
    /// Index of the body in the scene.
    pub body: usize,
    /// Outer radius, m.
    pub radius: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// Pressure on the cavity, Pa (shells only).
    pub pressure: f64,
    /// Hollow (shell) or solid.
    pub shell: bool,
    /// Centre, m.
    pub center: [f64; 3],
    /// Coulomb's μ between the hands' flesh and the ball (0: frictionless, the scene's default
    /// where no `[[friction]]` pairs them).
    pub friction: f64,
}

/// The materials of the scene's hands.
fn hand_materials(scene: &Scene) -> Vec<String> {
    scene
        .body
        .iter()
        .filter(|b| matches!(b.shape, Shape::Hand { .. }))
        .map(|b| b.material.clone())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect()
}

/// Whether friction pair `f` is between a material of `hands` and material `ball`.
fn pairs_skin_with(f: &FrictionDef, hands: &[String], ball: &str) -> bool {
    let names = |a: &str, b: &str| {
        f.between.len() == 2
            && ((f.between[0] == a && f.between[1] == b)
                || (f.between[0] == b && f.between[1] == a))
    };
    hands.iter().any(|h| names(h, ball))
}

impl BallParams {
    /// The first ball (shell or sphere body) of `scene`, if any.
    pub fn from_scene(scene: &Scene) -> Option<BallParams> {
        let (body, def) = scene
            .body
            .iter()
            .enumerate()
            .find(|(_, b)| matches!(b.shape, Shape::Shell { .. } | Shape::Sphere { .. }))?;
        let (center, radius, shell) = match def.shape {
            Shape::Shell {
                center,
                outer_radius,
                ..
            } => (center, outer_radius, true),
            Shape::Sphere { center, radius, .. } => (center, radius, false),
            _ => unreachable!("matched above"),
        };
        let material = scene.material.iter().find(|m| m.name == def.material)?;
        let pressure = scene
            .load
            .iter()
            .find(|l| l.body == def.name && is_inner(&l.selection))
            .and_then(|l| l.pressure)
            .unwrap_or(0.0);
        let hands = hand_materials(scene);
        let friction = scene
            .friction
            .iter()
            .find(|f| pairs_skin_with(f, &hands, &def.material))
            .map_or(0.0, |f| f.mu);
        Some(BallParams {
            body,
            radius,
            young: material.young,
            poisson: material.poisson,
            pressure,
            shell,
            center,
            friction,
        })
    }

    /// Writes these parameters into `scene` (which must be the scene they came from, possibly
    /// already edited).
    pub fn apply(&self, scene: &mut Scene) {
        let Some(old) = BallParams::from_scene(scene) else {
            return;
        };
        let name = scene.body[self.body].name.clone();
        let material = format!("{name} material");
        let density = scene
            .material
            .iter()
            .find(|m| m.name == scene.body[self.body].material)
            .map_or(1100.0, |m| m.density);
        // The ball gets a material of its own, so that editing it changes no other body; the
        // friction pairs that named its old material name the new one too.
        let before = scene.body[self.body].material.clone();
        let hands = hand_materials(scene);
        if before != material {
            let renamed: Vec<FrictionDef> = scene
                .friction
                .iter()
                .filter(|f| f.between.contains(&before))
                .map(|f| FrictionDef {
                    between: f
                        .between
                        .iter()
                        .map(|n| {
                            if *n == before {
                                material.clone()
                            } else {
                                n.clone()
                            }
                        })
                        .collect(),
                    mu: f.mu,
                })
                .collect();
            scene.friction.retain(|f| !f.between.contains(&material));
            scene.friction.extend(renamed);
        }
        // The skin on the ball: μ as set (no pair at 0).
        scene
            .friction
            .retain(|f| !pairs_skin_with(f, &hands, &material));
        if self.friction > 0.0 {
            for h in &hands {
                scene.friction.push(FrictionDef {
                    between: vec![h.clone(), material.clone()],
                    mu: self.friction,
                });
            }
        }
        scene.material.retain(|m| m.name != material);
        scene.material.push(MaterialDef {
            name: material.clone(),
            young: self.young,
            poisson: self.poisson,
            density,
        });
        let body = &mut scene.body[self.body];
        body.material = material;
        // A refinement stays on the ball, solid or hollow.
        let refine = match &body.shape {
            Shape::Sphere { refine, .. } | Shape::Shell { refine, .. } => refine.clone(),
            _ => None,
        };
        body.shape = if self.shell {
            let (cells, layers) = match body.shape {
                Shape::Shell { cells, layers, .. } => (cells, layers),
                _ => (12, 2),
            };
            Shape::Shell {
                center: self.center,
                inner_radius: self.radius * (1.0 - WALL),
                outer_radius: self.radius,
                cells,
                layers,
                refine,
            }
        } else {
            let cells = match body.shape {
                Shape::Sphere { cells, .. } => cells,
                _ => 8,
            };
            Shape::Sphere {
                center: self.center,
                radius: self.radius,
                cells,
                refine,
            }
        };
        // Carry every point and box on the ball along with its centre and radius.
        let s = self.radius / old.radius;
        let map = |p: [f64; 3]| -> [f64; 3] {
            std::array::from_fn(|i| self.center[i] + (p[i] - old.center[i]) * s)
        };
        // The refinement's point moves with the ball, its size scales with it.
        if let Shape::Sphere {
            refine: Some(refine),
            ..
        }
        | Shape::Shell {
            refine: Some(refine),
            ..
        } = &mut scene.body[self.body].shape
        {
            refine.toward = map(refine.toward);
            refine.size = refine.size.map(|h| h * s);
        }
        let carry = |sel: &mut Selection| match sel {
            Selection::Point(p) => *p = map(*p),
            Selection::Box { min, max } => {
                *min = map(*min);
                *max = map(*max);
            }
            _ => {}
        };
        for c in scene.constraint.iter_mut().filter(|c| c.body == name) {
            carry(&mut c.selection);
        }
        for r in scene.region.iter_mut().filter(|r| r.body == name) {
            carry(&mut r.selection);
        }
        for p in scene.probe.iter_mut().filter(|p| p.body == name) {
            p.point = map(p.point);
        }
        for l in scene.load.iter_mut().filter(|l| l.body == name) {
            carry(&mut l.selection);
        }
        // The internal pressure: on the cavity of a shell; a solid ball has none. A gas cavity
        // stays one (with its ambient pressure).
        let gas = scene
            .load
            .iter()
            .find(|l| l.body == name && is_inner(&l.selection))
            .map_or((false, None), |l| (l.gas, l.ambient));
        scene
            .load
            .retain(|l| !(l.body == name && is_inner(&l.selection)));
        if self.shell && self.pressure != 0.0 {
            scene.load.push(LoadDef {
                name: Some("air".into()),
                body: name,
                selection: Selection::Surface("inner".into()),
                pressure: Some(self.pressure),
                gas: gas.0,
                ambient: gas.1,
                force: None,
                traction: None,
            });
        }
    }
}

fn is_inner(s: &Selection) -> bool {
    matches!(s, Selection::Surface(name) if name == "inner")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        Scene::parse(include_str!("../../assets/scenes/hand-and-ball.toml"), "t").unwrap()
    }

    #[test]
    fn reads_the_default_ball() {
        let b = BallParams::from_scene(&scene()).unwrap();
        assert_eq!(b.body, 1);
        assert!((b.radius - 0.035).abs() < 1e-12 && b.shell);
        assert_eq!(b.young, 2.0e6);
        assert_eq!(b.pressure, 3.0e4);
    }

    #[test]
    fn edits_move_the_support_and_keep_the_hand_material() {
        let mut s = scene();
        let mut b = BallParams::from_scene(&s).unwrap();
        b.radius = 0.05;
        b.young = 1.0e9;
        b.center[0] += 0.01;
        b.shell = false;
        b.apply(&mut s);
        let again = BallParams::from_scene(&s).unwrap();
        assert_eq!(again.young, 1.0e9);
        assert!(!again.shell && (again.radius - 0.05).abs() < 1e-12);
        // No pressure on a solid ball; the hand keeps its flesh.
        assert_eq!(again.pressure, 0.0);
        assert!(s
            .material
            .iter()
            .any(|m| m.name == "flesh" && m.young == 5.0e4));
        // The support box still straddles the bottom of the ball.
        let Selection::Box { min, max } = &s.constraint[0].selection else {
            panic!("a box")
        };
        let bottom = again.center[2] - again.radius;
        assert!(
            min[2] < bottom && max[2] > bottom,
            "{min:?} {max:?} {bottom}"
        );
        assert!(min[0] < again.center[0] && max[0] > again.center[0]);
        // And the edited scene builds.
        crate::model::Model::build(&s, "t").unwrap();
    }

    #[test]
    fn a_refinement_moves_and_scales_with_the_ball() {
        let mut s = scene();
        let Shape::Shell { refine, .. } = &mut s.body[1].shape else {
            panic!("a shell")
        };
        // Toward the palm, above the ball's centre (0.065, 0, −0.065), radius 35 mm.
        *refine = Some(crate::scene::Refine {
            toward: [0.065, 0.0, 0.0],
            size: Some(0.001),
        });
        let mut b = BallParams::from_scene(&s).unwrap();
        b.radius = 0.07;
        b.center[0] += 0.01;
        b.shell = false;
        b.apply(&mut s);
        let Shape::Sphere {
            refine: Some(refine),
            ..
        } = &s.body[1].shape
        else {
            panic!("a refined sphere")
        };
        // 65 mm above the old centre is 130 mm above the new one, the size doubled.
        let expected = [0.075, 0.0, -0.065 + 0.13];
        assert!(
            (0..3).all(|i| (refine.toward[i] - expected[i]).abs() < 1e-12),
            "{:?}",
            refine.toward
        );
        assert!((refine.size.unwrap() - 0.002).abs() < 1e-12);
        crate::model::Model::build(&s, "t").unwrap();
    }

    /// The skin's friction on the ball: none in the default scene; set, it pairs the hand's
    /// flesh with the ball's own material in the model; an edit of the ball keeps it and the
    /// ball's other pairs (with an obstacle) under its new material's name; back to 0 it is
    /// gone.
    #[test]
    fn the_skins_friction_on_the_ball_is_set_and_kept_through_edits() {
        let text = format!(
            "{}\n[[obstacle]]\nname = \"table\"\n\
             shape = {{ plane = {{ point = [0.0, 0.0, -0.2], normal = [0.0, 0.0, 1.0] }} }}\n",
            include_str!("../../assets/scenes/hand-and-ball.toml")
        );
        let mut s = Scene::parse(&text, "t").unwrap();
        s.friction.push(FrictionDef {
            between: vec!["rubber".into(), "table".into()],
            mu: 0.3,
        });
        let mut b = BallParams::from_scene(&s).unwrap();
        assert_eq!(b.friction, 0.0);
        b.friction = 0.8;
        b.apply(&mut s);
        let b = BallParams::from_scene(&s).unwrap();
        assert_eq!(b.friction, 0.8);
        let ball = s.body[b.body].material.clone();
        assert_ne!(ball, "rubber", "the ball's own material");
        let model = crate::model::Model::build(&s, "t").unwrap();
        assert_eq!(model.friction_between("flesh", &ball), 0.8);
        assert_eq!(model.friction_between(&ball, "table"), 0.3);
        // Edited again (radius): the pairs stay, one each.
        let mut c = b.clone();
        c.radius = 0.03;
        c.apply(&mut s);
        assert_eq!(BallParams::from_scene(&s).unwrap().friction, 0.8);
        let skin_pairs = s
            .friction
            .iter()
            .filter(|f| f.between.contains(&ball) && f.between.contains(&"flesh".into()))
            .count();
        assert_eq!(skin_pairs, 1, "{:?}", s.friction);
        c.friction = 0.0;
        c.apply(&mut s);
        assert_eq!(BallParams::from_scene(&s).unwrap().friction, 0.0);
        let model = crate::model::Model::build(&s, "t").unwrap();
        assert_eq!(model.friction_between("flesh", &ball), 0.0);
        assert_eq!(model.friction_between(&ball, "table"), 0.3);
    }
}
