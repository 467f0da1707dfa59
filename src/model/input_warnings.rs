//! Warnings about what the scene asks that is admissible but likely not meant: a material so
//! nearly incompressible that the chosen element locks, a point (probe, load, constraint)
//! so far from its body that the node it snaps to is not where the user pointed, and `[solver]`
//! keys that have no effect on the scene (a hand's keys without a hand, an element the tier
//! does not use, contact pairs the paper's iteration does not choose).

use super::names::shown;
use super::BodyModel;
use crate::fem::{ElementKind, Material};
use crate::mesh::Mesh;
use crate::scene::{spelling, ContactMethodName, PairSidesName, Scene, Selection, TierName};
use nalgebra::Vector3;

/// Poisson's ratio above which the fully integrated hex8 locks visibly (its volumetric
/// stiffness grows as 1/(1 − 2ν): 50× the shear stiffness at ν = 0.49).
pub const LOCKING_POISSON: f64 = 0.49;

/// The warnings of a built model's input.
pub fn input_warnings(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
    cell_materials: &[Material],
    element: ElementKind,
    nonlinear: bool,
) -> Vec<String> {
    let mut out = locking_warnings(scene, bodies, cell_materials, element, nonlinear);
    out.extend(far_point_warnings(scene, bodies, mesh));
    out.extend(obstacle_friction_warning(scene, bodies));
    out.extend(mended_hand_warnings(bodies));
    out.extend(ineffective_solver_keys(scene, bodies, nonlinear));
    out
}

/// `[solver]` keys given that have no effect on this scene: a hand's keys in a scene without a
/// hand, `element` where no linear static solve uses it, `contact_pairs` with the paper's
/// iteration (which checks both ways whatever it says).
fn ineffective_solver_keys(scene: &Scene, bodies: &[BodyModel], nonlinear: bool) -> Vec<String> {
    let s = &scene.solver;
    let mut out = Vec::new();
    if !bodies.iter().any(|b| b.hand.is_some()) {
        if s.self_contact == Some(true) {
            out.push(
                "solver.self_contact = true: has no effect, the scene has no hand (it keeps a \
                 hand's skin from passing through itself)"
                    .to_string(),
            );
        }
        // `tier = "linear"` is what the bodies get without a hand, and `"nonlinear"` solves
        // their static frame by Newton: only the hands' own tiers are lost.
        let hands_tier = s
            .tier
            .filter(|t| !matches!(t, TierName::Linear | TierName::Nonlinear))
            .map(|t| spelling(&t));
        if let Some(tier) = hands_tier {
            out.push(format!(
                "solver.tier = \"{tier}\": has no effect, the scene has no hand (it sets how a \
                 hand's flesh is solved; the bodies get the linear static solve, or Newton's \
                 with tier = \"nonlinear\")"
            ));
        }
        let keys: [(&str, bool, &str); 9] = [
            (
                "flesh",
                s.flesh.is_some(),
                "how a hand's flesh follows its bones",
            ),
            (
                "flesh_digits",
                !s.flesh_digits.is_empty(),
                "how each part of a hand's flesh follows its bones",
            ),
            (
                "flexion",
                s.flexion.is_some(),
                "the scheme of a hand's flexion increments",
            ),
            (
                "max_step_deg",
                s.max_step_deg.is_some(),
                "the largest joint rotation of a hand's flexion increment",
            ),
            (
                "flesh_region",
                s.flesh_region.is_some(),
                "which of a hand's cells a keyframe solves",
            ),
            (
                "flesh_region_radius",
                s.flesh_region_radius.is_some(),
                "which of a hand's cells a keyframe solves",
            ),
            (
                "far_from_contact",
                s.far_from_contact.is_some(),
                "whether a hand's parts far from contact are skinned",
            ),
            (
                "near_contact",
                s.near_contact.is_some(),
                "how near another body a hand's part counts as near contact",
            ),
            (
                "skinning",
                s.skinning.is_some(),
                "the blend of a hand's skinning",
            ),
        ];
        for (key, given, what) in keys {
            if given {
                out.push(format!(
                    "solver.{key}: has no effect, the scene has no hand (it sets {what})"
                ));
            }
        }
    }
    if let Some(element) = s.element {
        let element = spelling(&element);
        let why = if !bodies.iter().any(|b| b.hand.is_none()) {
            Some(
                "the scene has no body other than hands, and `element` is the element of the \
                 other bodies' linear static solve (a hand's flexion always uses hex8)",
            )
        } else if nonlinear {
            Some(
                "solver.tier = \"nonlinear\" solves the bodies by Newton on its own \
                 Neo-Hookean hexahedron (solver.volumetric); `element` is the element of the \
                 linear static solve",
            )
        } else {
            None
        };
        if let Some(why) = why {
            out.push(format!(
                "solver.element = \"{element}\": has no effect, {why}"
            ));
        }
    }
    // The paper's iteration checks both ways (its step 3: src/contact/paper.rs); `contact_pairs`
    // only chooses the pairs its reported `max_penetration` is measured over.
    if s.contact == Some(ContactMethodName::Paper) {
        let pairs = s
            .contact_pairs
            .filter(|p| *p != PairSidesName::Both)
            .map(|p| spelling(&p));
        if let Some(pairs) = pairs {
            out.push(format!(
                "solver.contact_pairs = \"{pairs}\": has no effect on the contact solve, the \
                 paper's iteration (solver.contact = \"paper\") checks contact both ways \
                 whatever contact_pairs says; it only chooses the pairs the report's \
                 max_penetration is measured over. Remove it, or solve with contact = \
                 \"lagrange\", whose pairs it chooses"
            ));
        }
    }
    out
}

/// What building a hand changed of its rig (a joint outside its finger moved into it), said
/// per hand body.
fn mended_hand_warnings(bodies: &[BodyModel]) -> Vec<String> {
    bodies
        .iter()
        .filter_map(|b| b.hand.as_ref().map(|h| (b, h)))
        .flat_map(|(b, h)| {
            h.mended
                .iter()
                .map(move |note| format!("body \"{}\": {note}", shown(&b.name)))
        })
        .collect()
}

/// Friction asked for against obstacles in a scene without hands, whose static frame solves
/// contact with obstacles frictionless.
fn obstacle_friction_warning(scene: &Scene, bodies: &[BodyModel]) -> Option<String> {
    if scene.obstacle.is_empty() || bodies.iter().any(|b| b.hand.is_some()) {
        return None;
    }
    let default = scene.solver.friction.unwrap_or(0.0);
    let pair = scene.friction.iter().position(|f| {
        f.mu > 0.0
            && f.between
                .iter()
                .any(|n| scene.obstacle.iter().any(|o| &o.name == n))
    });
    let field = match (pair, default > 0.0) {
        (Some(i), _) => format!("friction[{i}]"),
        (None, true) => "solver.friction".to_string(),
        (None, false) => return None,
    };
    Some(format!(
        "{field}: friction against the obstacles is not used in a scene without hands (its \
         static frame solves their contact frictionless): a body on an obstacle is held along \
         the obstacle's normal only; give it a [[constraint]] where it must not slide"
    ))
}

/// A body whose cells have ν above [`LOCKING_POISSON`] on an element that locks: the fully
/// integrated hex8 of the small-strain and corotational tiers (a hand's flesh is hex8 there
/// whatever `element` says: its cure is the nonlinear tier), or the nonlinear tier's with
/// `volumetric = "full"`.
fn locking_warnings(
    scene: &Scene,
    bodies: &[BodyModel],
    cell_materials: &[Material],
    element: ElementKind,
    nonlinear: bool,
) -> Vec<String> {
    let mut out = Vec::new();
    for body in bodies {
        // A hand's flesh is solved by FEM only near contact (another body, an obstacle) or
        // with `far_from_contact = "solve"`; skinned alone, it has no element to lock.
        let flesh_solved = scene.solver.far_from_contact
            == Some(crate::scene::FarFromContact::Solve)
            || bodies.len() > 1
            || !scene.obstacle.is_empty();
        if body.hand.is_some() && !flesh_solved {
            continue;
        }
        let cells = &cell_materials[body.cells.clone()];
        let Some(nu) = cells.iter().map(|m| m.poisson).max_by(f64::total_cmp) else {
            continue;
        };
        if nu <= LOCKING_POISSON {
            continue;
        }
        let ratio = 1.0 / (1.0 - 2.0 * nu).max(f64::MIN_POSITIVE);
        // The scene's materials this body's cells are made of, nearly incompressible.
        let names: Vec<&str> = scene
            .material
            .iter()
            .filter(|m| {
                m.poisson > LOCKING_POISSON
                    && cells
                        .iter()
                        .any(|c| c.poisson == m.poisson && c.young == m.young)
            })
            .map(|m| m.name.as_str())
            .collect();
        // The nonlinear tier's Neo-Hookean bodies take the volumetric integration of
        // `[solver] volumetric`: mean dilatation (the default) does not lock.
        let full = scene.solver.volumetric == Some(crate::scene::VolumetricName::Full);
        let cure = if nonlinear && full {
            "set [solver] volumetric = \"mean_dilatation\" (the default), which does not lock"
        } else if nonlinear {
            continue;
        } else if body.hand.is_some() {
            "solve the scene with [solver] tier = \"nonlinear\", whose flesh is integrated with \
             mean dilatation, which does not lock"
        } else if element == ElementKind::Hex8 {
            "set [solver] element = \"incompatible_modes\", which does not lock"
        } else {
            continue;
        };
        let what = if body.hand.is_some() { "flesh" } else { "body" };
        out.push(format!(
            "body \"{}\": ν = {nu} (material {}) is nearly incompressible: the fully integrated \
             hex8 locks, its volumetric stiffness {ratio:.3e}× the shear stiffness, and the \
             {what} comes out far too stiff; {cure}",
            shown(&body.name),
            names
                .iter()
                .map(|n| format!("\"{}\"", shown(n)))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    out
}

/// The points of probes, loads and constraints farther from their body's nearest node than the
/// size of that node's cells.
fn far_point_warnings(scene: &Scene, bodies: &[BodyModel], mesh: &Mesh) -> Vec<String> {
    let mut points: Vec<(String, &str, [f64; 3])> = Vec::new();
    for (i, p) in scene.probe.iter().enumerate() {
        let field = format!("probe \"{}\" (probe[{i}]).point", shown(&p.name));
        points.push((field, &p.body, p.point));
    }
    for (i, l) in scene.load.iter().enumerate() {
        if let Selection::Point(p) = l.selection {
            let name = l.name.clone().unwrap_or_else(|| format!("load[{i}]"));
            let field = format!("load \"{}\" (load[{i}]).where", shown(&name));
            points.push((field, &l.body, p));
        }
    }
    for (i, c) in scene.constraint.iter().enumerate() {
        if let Selection::Point(p) = c.selection {
            let field = format!("constraint \"{}\" (constraint[{i}]).where", shown(&c.name));
            points.push((field, &c.body, p));
        }
    }
    let mut out = Vec::new();
    for (field, body_name, p) in points {
        let Some(body) = bodies.iter().find(|b| b.name == body_name) else {
            continue;
        };
        let p = Vector3::from(p);
        let Some((node, distance)) = body
            .nodes
            .clone()
            .map(|n| (n, super::select::distance(&mesh.nodes[n], &p)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
        else {
            continue;
        };
        let cell = cell_size_at(mesh, body, node);
        if distance > cell {
            let q = mesh.nodes[node];
            out.push(format!(
                "{field}: the point is {distance:.4e} m from body \"{}\", farther than the \
                 size of its cells there ({cell:.3e} m): it acts at the nearest node, its node \
                 {} at [{:.4}, {:.4}, {:.4}] m",
                shown(&body.name),
                node - body.nodes.start,
                q.x,
                q.y,
                q.z
            ));
        }
    }
    out
}

/// The longest edge (bounding-box diagonal) of the body's cells that hold `node`; the body's
/// size where none does.
fn cell_size_at(mesh: &Mesh, body: &BodyModel, node: usize) -> f64 {
    body.cells
        .clone()
        .filter(|&c| mesh.cells[c].contains(&node))
        .map(|c| {
            let coords = mesh.cell_coords(c);
            let (mut lo, mut hi) = (coords[0], coords[0]);
            for x in &coords {
                lo = lo.inf(x);
                hi = hi.sup(x);
            }
            (hi - lo).norm()
        })
        .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.max(d))))
        .unwrap_or(body.size)
}
