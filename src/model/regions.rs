//! Regions of other materials: the elements of a body inside a selection take another material.

use super::bodies::find_body;
use super::materials::find_material;
use super::select::select;
use super::BodyModel;
use crate::mesh::Mesh;
use crate::scene::Scene;

/// Applies the scene's `[[region]]`s, in order, to the material index of each cell.
pub fn apply_regions(
    scene: &Scene,
    bodies: &[BodyModel],
    mesh: &Mesh,
    cell_material: &mut [usize],
) -> Result<(), (String, String)> {
    for (i, r) in scene.region.iter().enumerate() {
        let field = format!("region[{i}]");
        let b = find_body(bodies, &r.body, format!("{field}.body"))?;
        let m = find_material(scene, &r.material, format!("{field}.material"))?;
        let sel = select(&bodies[b], mesh, &r.selection)
            .map_err(|msg| (format!("{field}.where"), msg))?;
        let mut chosen = vec![false; mesh.node_count()];
        for &n in &sel.nodes {
            chosen[n] = true;
        }
        let mut count = 0;
        for c in bodies[b].cells.clone() {
            if mesh.cells[c].iter().all(|&n| chosen[n]) {
                cell_material[c] = m;
                count += 1;
            }
        }
        if count == 0 {
            return Err((
                format!("{field}.where"),
                "contains no whole element of the body (a region takes the elements whose \
                 eight nodes are all selected)"
                    .into(),
            ));
        }
    }
    Ok(())
}
