//! Bodies held by nothing but contact (a ball resting in a grasp, a block on a slope): their
//! stiffness is singular until contact holds them, so each free dof of such a "floating" body
//! gets a weak spring to the ground, 10⁻⁶ of the body's mean diagonal stiffness (weaker springs
//! make the contact system ill-conditioned: the rigid motions' compliance swamps the elastic one). After the solve,
//! the force those springs carry must be negligible against the forces on the body; if not, the
//! body is not held (it falls, or slides) and the solve says so.

use super::error::SimError;
use crate::contact::{ContactError, ContactResult};
use crate::fem::assembly::Stiffness;
use crate::fem::DofPartition;
use crate::model::Model;
use nalgebra::Vector3;

/// Relative stiffness of the ground springs.
pub const SPRING: f64 = 1e-6;

/// Largest share of the forces on a body its springs may carry.
pub const HELD: f64 = 1e-4;

/// Adds the ground springs of the floating bodies to `k`; returns (body, spring stiffness).
pub fn stabilize(model: &Model, k: &mut Stiffness, partition: &DofPartition) -> Vec<(usize, f64)> {
    let mut out = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        if !body.floating {
            continue;
        }
        let dofs: Vec<usize> = (3 * body.nodes.start..3 * body.nodes.end)
            .filter(|&d| !partition.prescribed[d])
            .collect();
        if dofs.is_empty() {
            continue;
        }
        let mean = dofs.iter().map(|&d| k.diagonal(d)).sum::<f64>() / dofs.len() as f64;
        let spring = SPRING * mean;
        for &d in &dofs {
            k.add_to_diagonal(d, spring);
        }
        out.push((b, spring));
    }
    out
}

/// Checks that the springs of `springs` (resting at `anchor`, or at rest) carry a negligible
/// force after `result`.
pub fn check_held(
    model: &Model,
    springs: &[(usize, f64)],
    result: &ContactResult,
    anchor: Option<&[f64]>,
) -> Result<(), ContactError> {
    let u = &result.solution.displacement;
    for &(b, spring) in springs {
        let body = &model.bodies[b];
        let mut carried: Vector3<f64> = Vector3::zeros();
        let mut applied: Vector3<f64> = Vector3::zeros();
        let mut moved: Vector3<f64> = Vector3::zeros();
        // The loads' gross size: where they balance (a cavity's air), what round-off is measured
        // against.
        let mut gross = 0.0;
        for n in body.nodes.clone() {
            for a in 0..3 {
                let d = 3 * n + a;
                if !model.partition.prescribed[d] {
                    carried[a] += spring * (u[d] - anchor.map_or(0.0, |x| x[d]));
                }
                applied[a] += model.load_vector[d];
                gross += model.load_vector[d].abs();
                moved[a] += u[d] - anchor.map_or(0.0, |x| x[d]);
            }
        }
        let moved = moved / body.nodes.len().max(1) as f64;
        let mut contact = 0.0;
        let mut touching = false;
        for c in &result.contacts {
            for (n, f) in c.nodal_forces() {
                if body.nodes.contains(&n) {
                    contact += f.norm();
                    touching = true;
                }
            }
        }
        let scale = applied
            .norm()
            .max(contact)
            .max(1e-9 * gross)
            .max(f64::MIN_POSITIVE);
        if carried.norm() > HELD * scale {
            // Touching after a rigid move of more than the contact's tolerance: it started
            // that far from what holds it (a block above its table falls onto it).
            let apart = moved.norm() > model.contact.penetration_limit();
            return Err(ContactError::NotHeld {
                body: body.name.clone(),
                held: 100.0 * carried.norm() / scale,
                motion: match (touching, apart) {
                    (false, _) => "falls: nothing touches it".into(),
                    (true, true) => format!(
                        "moves {:.3e} m along ({:.2}, {:.2}, {:.2}) before contact holds it: it \
                         starts that far from what holds it",
                        moved.norm(),
                        moved.x / moved.norm(),
                        moved.y / moved.norm(),
                        moved.z / moved.norm()
                    ),
                    (true, false) => "slides: friction and contact cannot balance the load".into(),
                },
                place: if touching && apart {
                    "place it on what holds it, or ".into()
                } else {
                    String::new()
                },
            });
        }
    }
    Ok(())
}

/// Refuses a frame without contact in which the loads on a floating body do not balance
/// (its weight): nothing but its stabilising springs would hold it (it falls), and it would be
/// written hanging from them, displaced by its load over their stiffness, out of balance. (A
/// cavity's air alone balances on its wall.)
pub(super) fn falls_untouched(model: &Model) -> Result<(), SimError> {
    let loaded = |b: usize| {
        let nodes = &model.bodies[b].nodes;
        let mut net = nalgebra::Vector3::<f64>::zeros();
        let mut gross = 0.0;
        for n in nodes.clone() {
            for a in 0..3 {
                net[a] += model.load_vector[3 * n + a];
                gross += model.load_vector[3 * n + a].abs();
            }
        }
        net.norm() > 1e-9 * gross
    };
    match (0..model.bodies.len()).find(|&b| model.bodies[b].floating && loaded(b)) {
        Some(b) => Err(SimError::Contact(ContactError::NotHeld {
            body: model.bodies[b].name.clone(),
            held: 100.0,
            motion: "falls: nothing touches it".into(),
            // (A hand posed around it does not yet hold a free body by friction: the advice is
            // what works.)
            place: if model.obstacles.is_empty() {
                String::new()
            } else {
                "place it on an [[obstacle]] that holds it, or ".into()
            },
        })),
        None => Ok(()),
    }
}
