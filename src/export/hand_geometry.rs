//! A posed hand's geometry for other tools: the display skin and the bones as a Wavefront OBJ
//! (Blender, one object per surface), and the bones as a VTU of triangles (ParaView, beside the
//! flesh VTU).

use crate::model::Model;
use crate::state::Frame;
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
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece \
         NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        triangles.len()
    );
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &points {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for t in &triangles {
        let _ = writeln!(s, "{} {} {}", t[0], t[1], t[2]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 1..=triangles.len() {
        let _ = write!(s, "{} ", 3 * i);
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in &triangles {
        let _ = write!(s, "{VTK_TRIANGLE} ");
    }
    s.push_str("\n</DataArray>\n</Cells>\n<CellData Scalars=\"bone_id\" Vectors=\"reaction\">\n");
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
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" \
         byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece \
         NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        quads.len()
    );
    s.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &points {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    s.push_str("</DataArray>\n</Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for q in &quads {
        let _ = writeln!(s, "{} {} {} {}", q[0], q[1], q[2], q[3]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 1..=quads.len() {
        let _ = write!(s, "{} ", 4 * i);
    }
    s.push_str("\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in &quads {
        let _ = write!(s, "{VTK_QUAD} ");
    }
    s.push_str("\n</DataArray>\n</Cells>\n<PointData Scalars=\"contact_pressure\">\n");
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
