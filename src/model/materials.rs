//! The scene's materials, checked, and the lookup of a material by name.

use super::check::list;
use crate::fem::Material;
use crate::scene::Scene;

/// The materials in the scene's order, each checked admissible and named once.
pub fn materials(scene: &Scene) -> Result<Vec<Material>, (String, String)> {
    let mut materials = Vec::new();
    for (i, m) in scene.material.iter().enumerate() {
        let field = format!("material \"{}\" (material[{i}])", m.name);
        if scene.material[..i].iter().any(|o| o.name == m.name) {
            return Err((field, "a material of this name is defined twice".into()));
        }
        let mat = Material {
            young: m.young,
            poisson: m.poisson,
            density: m.density,
        };
        mat.check().map_err(|msg| (field, msg))?;
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
                format!("no material named \"{name}\" (defined: {})", list(&known)),
            )
        })
}
