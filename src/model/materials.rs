//! The scene's materials, checked, and the lookup of a material by name.

use super::check::list;
use super::names::shown;
use crate::fem::Material;
use crate::scene::Scene;

/// Young's moduli a scene may give, Pa: beyond them a value is a mistake of units (and its
/// displacements overflow).
const YOUNG_RANGE: (f64, f64) = (1e-3, 1e13);

/// The densest a scene's material may be, kg/m³.
const MAX_DENSITY: f64 = 1e5;

/// The materials in the scene's order, each checked admissible and named once.
pub fn materials(scene: &Scene) -> Result<Vec<Material>, (String, String)> {
    let mut materials = Vec::new();
    for (i, m) in scene.material.iter().enumerate() {
        let field = format!("material \"{}\" (material[{i}])", shown(&m.name));
        super::names::named("material", &m.name).map_err(|m| (field.clone(), m))?;
        if scene.material[..i].iter().any(|o| o.name == m.name) {
            return Err((field, "a material of this name is defined twice".into()));
        }
        let mat = Material {
            young: m.young,
            poisson: m.poisson,
            density: m.density,
        };
        mat.check().map_err(|msg| (field.clone(), msg))?;
        if !(YOUNG_RANGE.0..=YOUNG_RANGE.1).contains(&mat.young) {
            return Err((
                format!("{field}.young"),
                format!(
                    "young = {:e} Pa lies outside the moduli of real materials, {:e} to {:e} Pa \
                     (the softest gels ~10 Pa, diamond 1.2e12 Pa): check the units (Pa)",
                    mat.young, YOUNG_RANGE.0, YOUNG_RANGE.1
                ),
            ));
        }
        if mat.density > MAX_DENSITY {
            return Err((
                format!("{field}.density"),
                format!(
                    "density = {:e} kg/m³ exceeds that of any material ({MAX_DENSITY:e} kg/m³; \
                     osmium 22 590): check the units (kg/m³)",
                    mat.density
                ),
            ));
        }
        materials.push(mat);
    }
    Ok(materials)
}

/// The index of the material `name` (the materials are checked to be named once); `field`
/// names the reference in the error.
pub fn find_material(scene: &Scene, name: &str, field: String) -> Result<usize, (String, String)> {
    scene
        .material
        .iter()
        .position(|m| m.name == name)
        .ok_or_else(|| {
            let known: Vec<&str> = scene.material.iter().map(|m| m.name.as_str()).collect();
            (
                field,
                format!(
                    "no material named \"{}\" (defined: {})",
                    shown(name),
                    list(&known)
                ),
            )
        })
}
