//! A posed hand's geometry for other tools: the display skin and the bones as a Wavefront OBJ
//! (Blender, one object per surface), and the bones as a VTU of triangles (ParaView, beside the
//! flesh VTU).

use crate::model::Model;
use crate::state::Frame;
use nalgebra::Vector3;
use std::fmt::Write;

/// VTK cell type of a triangle.
const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a quadrilateral.
const VTK_QUAD: u8 = 9;

/// An OBJ holding, for every hand of the frame, its skin (quads) and its bones (triangles); `None`
/// without hands.
pub fn frame_obj(model: &Model, frame: &Frame) -> Option<String> {
    if frame.hands.is_empty() {
        return None;
    }
    let mut s = String::from("# Prehensile: posed hand skin and bones, metres\n");
    let mut base = 1usize;
    for h in &frame.hands {
        let body = &model.bodies[h.body];
        let hand = body.hand.as_deref()?;
        let _ = writeln!(s, "o {}_skin", body.name);
        let skin = hand.skin.positions(&h.positions);
        for p in &skin {
            let _ = writeln!(s, "v {:.7} {:.7} {:.7}", p.x, p.y, p.z);
        }
        for q in &hand.skin.quads {
            let _ = writeln!(
                s,
                "f {} {} {} {}",
                q[0] as usize + base,
                q[1] as usize + base,
                q[2] as usize + base,
                q[3] as usize + base
            );
        }
        base += skin.len();
        for (b, (pos, tri)) in hand.posed_bones(&h.angles) {
            let _ = writeln!(s, "o {}_{}", body.name, hand.skeleton.bones[b].name);
            for p in &pos {
                let _ = writeln!(s, "v {:.7} {:.7} {:.7}", p.x, p.y, p.z);
            }
            for t in &tri {
                let _ = writeln!(
                    s,
                    "f {} {} {}",
                    t[0] as usize + base,
                    t[1] as usize + base,
                    t[2] as usize + base
                );
            }
            base += pos.len();
        }
    }
    Some(s)
}

/// A VTU of the bones of every hand of the frame (triangles, in their posed position) with the
/// cell data `bone_id` and `reaction` (the bone's reaction force, N); `None` without hands.
pub fn bones_vtu(model: &Model, frame: &Frame) -> Option<String> {
    if frame.hands.is_empty() {
        return None;
    }
    let mut points = Vec::new();
    let mut triangles = Vec::new();
    let mut ids = Vec::new();
    let mut reactions = Vec::new();
    for h in &frame.hands {
        let hand = model.bodies[h.body].hand.as_deref()?;
        for (b, (pos, tri)) in hand.posed_bones(&h.angles) {
            let base = points.len() as u32;
            points.extend(pos);
            for t in tri {
                triangles.push(t.map(|i| i + base));
                ids.push(b);
                reactions.push(h.bone_reactions[b]);
            }
        }
    }
    let cells: Vec<&[u32]> = triangles.iter().map(|t| t.as_slice()).collect();
    let mut s = grid_head(&points, &cells, VTK_TRIANGLE);
    s.push_str("<CellData Scalars=\"bone_id\" Vectors=\"reaction\">\n");
    s.push_str("<DataArray type=\"Int32\" Name=\"bone_id\" format=\"ascii\">\n");
    for b in &ids {
        let _ = write!(s, "{b} ");
    }
    s.push_str(
        "\n</DataArray>\n<DataArray type=\"Float64\" Name=\"reaction\" NumberOfComponents=\"3\" \
         format=\"ascii\">\n",
    );
    for r in &reactions {
        let _ = writeln!(s, "{} {} {}", r.x, r.y, r.z);
    }
    s.push_str("</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    Some(s)
}

/// A VTU of every hand's contact skin (the smooth skin at the lattice's resolution, the surface
/// the contact acts on) in the frame's deformed state, quads, with the point data
/// `contact_pressure` (Pa: the tactile map on the skin, 0 off contact) and the cell data
/// `hand` (the body index); `None` without hands.
pub fn skin_vtu(model: &Model, frame: &Frame) -> Option<String> {
    if frame.hands.is_empty() {
        return None;
    }
    let mut points = Vec::new();
    let mut pressure = Vec::new();
    let mut quads = Vec::new();
    let mut owner = Vec::new();
    for h in &frame.hands {
        let hand = model.bodies[h.body].hand.as_deref()?;
        let skin = &hand.contact_skin;
        let base = points.len() as u32;
        points.extend(skin.positions(&h.positions));
        pressure.extend(
            crate::state::contact_skin_pressure(model, frame, h.body)
                .unwrap_or_else(|| vec![0.0; skin.vertex_count()]),
        );
        for q in &skin.quads {
            quads.push(q.map(|v| v + base));
            owner.push(h.body);
        }
    }
    let cells: Vec<&[u32]> = quads.iter().map(|q| q.as_slice()).collect();
    let mut s = grid_head(&points, &cells, VTK_QUAD);
    s.push_str("<PointData Scalars=\"contact_pressure\">\n");
    s.push_str("<DataArray type=\"Float64\" Name=\"contact_pressure\" format=\"ascii\">\n");
    for p in &pressure {
        let _ = write!(s, "{p} ");
    }
    s.push_str("\n</DataArray>\n</PointData>\n<CellData Scalars=\"hand\">\n");
    s.push_str("<DataArray type=\"Int32\" Name=\"hand\" format=\"ascii\">\n");
    for b in &owner {
        let _ = write!(s, "{b} ");
    }
    s.push_str("\n</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    Some(s)
}

/// The head of a VTU unstructured grid of one piece: the points and the cells (each of
/// `vtk_type`, its point indices), up to and with `</Cells>`; the caller adds the data arrays and
/// closes with `</Piece></UnstructuredGrid></VTKFile>`.
fn grid_head(points: &[Vector3<f64>], cells: &[&[u32]], vtk_type: u8) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece \
         NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        cells.len()
    );
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in points {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for c in cells {
        let ids: Vec<String> = c.iter().map(|i| i.to_string()).collect();
        let _ = writeln!(s, "{}", ids.join(" "));
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut offset = 0;
    for c in cells {
        offset += c.len();
        let _ = write!(s, "{offset} ");
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in cells {
        let _ = write!(s, "{vtk_type} ");
    }
    s.push_str("\n</DataArray>\n</Cells>\n");
    s
}
