//! Constraints: the prescribed dofs of each named selection, and the hands held in the statics.

use super::bodies::find_body;
use super::names::shown;
use super::select::select;
use super::{BodyModel, ConstraintModel};
use crate::mesh::Mesh;
use crate::scene::{Scene, Selection};

/// The constraints and the dofs they prescribe.
pub struct Prescribed {
    /// Constraints, in the scene's order.
    pub constraints: Vec<ConstraintModel>,
    /// Which dofs are prescribed.
    pub mask: Vec<bool>,
    /// Prescribed values (zero at free dofs).
    pub values: Vec<f64>,
}

/// The scene's `[[constraint]]`s on the joined mesh of the bodies.
pub fn constraints(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
) -> Result<Prescribed, (String, String)> {
    let dofs = 3 * mesh.node_count();
    let mut prescribed_mask = vec![false; dofs];
    let mut prescribed = vec![0.0; dofs];
    let mut owner = vec![usize::MAX; dofs];
    let mut constraints: Vec<ConstraintModel> = Vec::new();
    for (i, c) in scene.constraint.iter().enumerate() {
        let field = format!("constraint \"{}\" (constraint[{i}])", shown(&c.name));
        super::names::named("constraint", &c.name).map_err(|m| (field.clone(), m))?;
        if constraints.iter().any(|o| o.name == c.name) {
            return Err((field, "a constraint of this name is defined twice".into()));
        }
        let b = find_body(bodies, &c.body, format!("{field}.body"))?;
        let sel = select(&bodies[b], mesh, &c.selection)
            .map_err(|msg| (format!("{field}.where"), msg))?;
        let components = c.displacement.components();
        if bodies[b].hand.is_some()
            && (!matches!(c.selection, Selection::Bone(_))
                || components.iter().any(|v| *v != Some(0.0)))
        {
            return Err((
                field,
                "a hand moves with its skeleton (pose and keyframes): a constraint on a hand \
                 selects a bone (`where = { bone = \"index.distal\" }`) with `displacement = \
                 [0, 0, 0]`, and reports that bone's reaction under its name"
                    .into(),
            ));
        }
        if components.iter().all(Option::is_none) {
            return Err((
                format!("{field}.displacement"),
                "prescribes no component (give x, y or z)".into(),
            ));
        }
        if components.iter().flatten().any(|v| !v.is_finite()) {
            return Err((
                format!("{field}.displacement"),
                "is not a finite number".into(),
            ));
        }
        let mut own = Vec::new();
        for &n in &sel.nodes {
            for (axis, value) in components.iter().enumerate() {
                let Some(value) = *value else { continue };
                let d = 3 * n + axis;
                if prescribed_mask[d] {
                    if (prescribed[d] - value).abs() > 1e-15 * (1.0 + value.abs()) {
                        return Err((
                            format!("{field}.displacement"),
                            format!(
                                "node {} is already prescribed along {} by constraint \"{}\" \
                                 with another value ({} m against {} m)",
                                n - bodies[b].nodes.start,
                                ["x", "y", "z"][axis],
                                shown(&constraints[owner[d]].name),
                                prescribed[d],
                                value
                            ),
                        ));
                    }
                    continue;
                }
                prescribed_mask[d] = true;
                prescribed[d] = value;
                owner[d] = constraints.len();
                own.push(d);
            }
        }
        constraints.push(ConstraintModel {
            name: c.name.clone(),
            body: b,
            dofs: own,
        });
    }
    Ok(Prescribed {
        constraints,
        mask: prescribed_mask,
        values: prescribed,
    })
}

/// A hand moves by its skeleton, solved increment by increment (`solve::Flexion`); in the
/// static solve of the other bodies all its nodes are held where they are.
pub fn hold_hands(bodies: &[BodyModel], prescribed_mask: &mut [bool]) {
    for body in bodies {
        if body.hand.is_some() {
            prescribed_mask[3 * body.nodes.start..3 * body.nodes.end].fill(true);
        }
    }
}
