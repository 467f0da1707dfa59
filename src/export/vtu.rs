//! VTK XML unstructured grid (`.vtu`) files that ParaView opens: the reference mesh with the
//! point data displacement, von Mises stress and stress tensor, and the cell data material id,
//! body id and von Mises stress (written by `vtu_grid`). Apply ParaView's "Warp By Vector" on
//! `displacement` to see the deformed shape.

use super::vtu_grid::{DataArray, Grid, VtuEncoding};
use crate::fem::stress::von_mises;
use crate::model::Model;
use crate::state::Frame;
use std::fmt::Write;

/// VTK cell type of an 8-node hexahedron.
const VTK_HEXAHEDRON: u8 = 12;

/// The frame as a VTU file (`encoding`: binary, the default, or ASCII).
pub fn frame_vtu(model: &Model, frame: &Frame, encoding: VtuEncoding) -> Vec<u8> {
    frame_grid(model, frame).to_bytes(encoding)
}

/// The frame's grid: the reference mesh, the point data displacement, von Mises stress,
/// stress tensor, bone id (and the tactile map, contact pressure, with contact), the cell data
/// material id, body id and von Mises stress.
pub fn frame_grid(model: &Model, frame: &Frame) -> Grid {
    let mesh = &model.mesh;
    let mut grid = Grid::new(
        mesh.nodes.iter().map(|p| [p.x, p.y, p.z]),
        mesh.cells.iter().map(|c| c.as_slice()),
        VTK_HEXAHEDRON,
    );
    grid.point_active = "Vectors=\"displacement\" Scalars=\"von_mises\"".into();
    grid.point_data.push(DataArray::f64(
        "displacement",
        3,
        frame.solution.displacement.clone(),
    ));
    grid.point_data.push(DataArray::f64(
        "von_mises",
        1,
        frame.stress.nodal.iter().map(von_mises).collect(),
    ));
    // VTK's symmetric tensor order: XX YY ZZ XY YZ XZ.
    grid.point_data.push(DataArray::f64(
        "stress",
        6,
        frame
            .stress
            .nodal
            .iter()
            .flat_map(|m| {
                [
                    m[(0, 0)],
                    m[(1, 1)],
                    m[(2, 2)],
                    m[(0, 1)],
                    m[(1, 2)],
                    m[(0, 2)],
                ]
            })
            .collect(),
    ));
    // The bone a node is attached to (prescribed by), −1 for free nodes and other bodies.
    let mut bone_id = vec![-1i32; mesh.node_count()];
    for body in &model.bodies {
        if let Some(hand) = &body.hand {
            for (n, b) in hand.flesh.node_bone.iter().enumerate() {
                if let Some(b) = b {
                    bone_id[body.nodes.start + n] = *b as i32;
                }
            }
        }
    }
    grid.point_data.push(DataArray::i32("bone_id", bone_id));
    if let Some(pressure) = crate::state::contact_pressure(model, frame) {
        // The tactile map.
        grid.point_data
            .push(DataArray::f64("contact_pressure", 1, pressure));
    }
    grid.cell_active = "Scalars=\"material_id\"".into();
    grid.cell_data.push(DataArray::i32(
        "material_id",
        model.cell_material.iter().map(|&m| m as i32).collect(),
    ));
    grid.cell_data.push(DataArray::i32(
        "body_id",
        model.cell_body.iter().map(|&b| b as i32).collect(),
    ));
    grid.cell_data.push(DataArray::f64(
        "von_mises",
        1,
        frame.stress.cell_von_mises.clone(),
    ));
    grid
}

/// A ParaView collection (`.pvd`) listing frame files with their times.
pub fn collection_pvd(frames: &[(f64, String)]) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n<Collection>\n",
    );
    for (time, file) in frames {
        let _ = writeln!(
            s,
            "<DataSet timestep=\"{time}\" part=\"0\" file=\"{file}\"/>"
        );
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    s
}
