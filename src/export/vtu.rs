//! VTK XML unstructured grid (`.vtu`) files that ParaView opens: the reference mesh with the
//! point data displacement, von Mises stress and stress tensor, and the cell data material id,
//! body id and von Mises stress. Apply ParaView's "Warp By Vector" on `displacement` to see the
//! deformed shape.

use crate::fem::stress::von_mises;
use crate::model::Model;
use crate::state::Frame;
use std::fmt::Write;

/// VTK cell type of an 8-node hexahedron.
const VTK_HEXAHEDRON: u8 = 12;

/// Renders the frame as VTU text (ASCII data arrays).
pub fn frame_vtu(model: &Model, frame: &Frame) -> String {
    let mesh = &model.mesh;
    let mut s = String::with_capacity(200 * mesh.node_count());
    let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        s,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    );
    let _ = writeln!(s, "<UnstructuredGrid>");
    let _ = writeln!(
        s,
        r#"<Piece NumberOfPoints="{}" NumberOfCells="{}">"#,
        mesh.node_count(),
        mesh.cell_count()
    );
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &mesh.nodes {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    s.push_str("</DataArray>\n</Points>\n");

    s.push_str("<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in &mesh.cells {
        let line: Vec<String> = c.iter().map(|n| n.to_string()).collect();
        let _ = writeln!(s, "{}", line.join(" "));
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 1..=mesh.cell_count() {
        let _ = write!(s, "{} ", 8 * i);
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..mesh.cell_count() {
        let _ = write!(s, "{VTK_HEXAHEDRON} ");
    }
    s.push_str("\n</DataArray>\n</Cells>\n");

    s.push_str("<PointData Vectors=\"displacement\" Scalars=\"von_mises\">\n");
    s.push_str(
        "<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for chunk in frame.solution.displacement.chunks(3) {
        let _ = writeln!(s, "{} {} {}", chunk[0], chunk[1], chunk[2]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Float64\" Name=\"von_mises\" format=\"ascii\">\n");
    for sigma in &frame.stress.nodal {
        let _ = writeln!(s, "{}", von_mises(sigma));
    }
    s.push_str(
        "</DataArray>\n<DataArray type=\"Float64\" Name=\"stress\" NumberOfComponents=\"6\" \
         format=\"ascii\">\n",
    );
    for m in &frame.stress.nodal {
        // VTK's symmetric tensor order: XX YY ZZ XY YZ XZ.
        let _ = writeln!(
            s,
            "{} {} {} {} {} {}",
            m[(0, 0)],
            m[(1, 1)],
            m[(2, 2)],
            m[(0, 1)],
            m[(1, 2)],
            m[(0, 2)]
        );
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int32\" Name=\"bone_id\" format=\"ascii\">\n");
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
    for b in &bone_id {
        let _ = write!(s, "{b} ");
    }
    if let Some(pressure) = crate::state::contact_pressure(model, frame) {
        // The tactile map.
        s.push_str(
            "\n</DataArray>\n<DataArray type=\"Float64\" Name=\"contact_pressure\" format=\"ascii\">\n",
        );
        for p in &pressure {
            let _ = write!(s, "{p} ");
        }
    }
    s.push_str("\n</DataArray>\n</PointData>\n");

    s.push_str("<CellData Scalars=\"material_id\">\n");
    s.push_str("<DataArray type=\"Int32\" Name=\"material_id\" format=\"ascii\">\n");
    for m in &model.cell_material {
        let _ = write!(s, "{m} ");
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"Int32\" Name=\"body_id\" format=\"ascii\">\n");
    for b in &model.cell_body {
        let _ = write!(s, "{b} ");
    }
    s.push_str(
        "\n</DataArray>\n<DataArray type=\"Float64\" Name=\"von_mises\" format=\"ascii\">\n",
    );
    for v in &frame.stress.cell_von_mises {
        let _ = writeln!(s, "{v}");
    }
    s.push_str("</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    s
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
