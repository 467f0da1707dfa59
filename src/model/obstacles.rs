//! Rigid obstacles, and the nodes that may touch them.

use super::check::finite;
use super::names::shown;
use super::BodyModel;
use crate::contact::Obstacle;
use crate::scene::{ObstacleShape, Scene};
use nalgebra::Vector3;

/// The scene's `[[obstacle]]`s, by name.
pub fn obstacles(scene: &Scene) -> Result<Vec<(String, Obstacle)>, (String, String)> {
    let mut obstacles = Vec::new();
    for (i, o) in scene.obstacle.iter().enumerate() {
        let field = format!("obstacle \"{}\" (obstacle[{i}])", shown(&o.name));
        super::names::named("obstacle", &o.name).map_err(|m| (field.clone(), m))?;
        if scene.obstacle[..i].iter().any(|p| p.name == o.name) {
            return Err((field, "an obstacle of this name is defined twice".into()));
        }
        // `[[friction]] between` names materials and obstacles alike: one name for both would
        // leave its pair ambiguous.
        if let Some(m) = scene.material.iter().position(|m| m.name == o.name) {
            return Err((
                format!("{field}.name"),
                format!(
                    "is also the name of material \"{}\" (material[{m}]).name, and \
                     [[friction]] between = [...] names materials and obstacles alike: give the \
                     obstacle a name of its own",
                    shown(&o.name)
                ),
            ));
        }
        let obstacle = match &o.shape {
            ObstacleShape::Plane { point, normal } => {
                // Scaled by its largest component before it is normalised, so that neither a
                // huge normal (whose length overflows) nor a tiny one (whose length underflows)
                // loses its direction: only the direction is meant.
                let n = Vector3::from(*normal);
                let largest = n.amax();
                if !(finite(point) && finite(normal)) || largest == 0.0 {
                    return Err((
                        format!("{field}.shape.plane"),
                        "needs a finite point and a non-zero finite normal".into(),
                    ));
                }
                Obstacle::Plane {
                    point: Vector3::from(*point),
                    normal: (n / largest).normalize(),
                }
            }
            ObstacleShape::Sphere { center, radius } => {
                if !(finite(center) && radius.is_finite() && *radius > 0.0) {
                    return Err((
                        format!("{field}.shape.sphere"),
                        format!("needs a finite center and a radius > 0 (radius = {radius})"),
                    ));
                }
                Obstacle::Sphere {
                    center: Vector3::from(*center),
                    radius: *radius,
                }
            }
        };
        obstacles.push((o.name.clone(), obstacle));
    }
    Ok(obstacles)
}

/// Nodes that may touch the obstacles: the boundary nodes of every body but hands (sorted).
pub fn contact_candidates(bodies: &[BodyModel]) -> Vec<usize> {
    let mut contact_candidates: Vec<usize> = bodies
        .iter()
        .filter(|b| b.hand.is_none())
        .flat_map(|b| b.facets.iter().flat_map(|f| f.nodes))
        .collect();
    contact_candidates.sort_unstable();
    contact_candidates.dedup();
    contact_candidates
}
