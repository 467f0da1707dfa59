//! The scene's named cameras, validated.

use super::check::finite;
use super::names::shown;
use crate::scene::{CameraDef, Scene};
use nalgebra::Vector3;

/// The scene's `[[camera]]`s, each checked: a unique name, a finite view that looks somewhere,
/// a field of view between 1° and 170°.
pub fn cameras(scene: &Scene) -> Result<Vec<CameraDef>, (String, String)> {
    for (i, c) in scene.camera.iter().enumerate() {
        let field = format!("camera \"{}\" (camera[{i}])", shown(&c.name));
        super::names::named("camera", &c.name).map_err(|m| (field.clone(), m))?;
        if scene.camera[..i].iter().any(|o| o.name == c.name) {
            return Err((field, "a camera of this name is defined twice".into()));
        }
        let (eye, target, up) = (
            Vector3::from(c.eye),
            Vector3::from(c.target),
            Vector3::from(c.up),
        );
        if !(finite(&c.eye) && finite(&c.target) && finite(&c.up)) {
            return Err((field, "eye, target and up must be finite".into()));
        }
        if (eye - target).norm() < 1e-9 || up.cross(&(eye - target)).norm() < 1e-12 {
            return Err((
                field,
                "eye must differ from target, and up must not be along the view".into(),
            ));
        }
        if !(1.0..=170.0).contains(&c.fov_deg) {
            return Err((
                format!("{field}.fov_deg"),
                format!("must be between 1 and 170 degrees, got {}", c.fov_deg),
            ));
        }
    }
    Ok(scene.camera.clone())
}
