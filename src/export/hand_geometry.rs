//! A posed hand's geometry for other tools: the display skin and the bones as a Wavefront OBJ
//! (Blender, one object per surface), and the bones as a VTU of triangles (ParaView, beside the
//! flesh VTU).

use super::vtu_grid::{DataArray, Grid, VtuEncoding};
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
pub fn bones_vtu(model: &Model, frame: &Frame, encoding: VtuEncoding) -> Option<Vec<u8>> {
    if frame.hands.is_empty() {
        return None;
    }
    let mut points = Vec::new();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    let mut ids = Vec::new();
    let mut reactions = Vec::new();
    for h in &frame.hands {
        let hand = model.bodies[h.body].hand.as_deref()?;
        for (b, (pos, tri)) in hand.posed_bones(&h.angles) {
            let base = points.len();
            points.extend(pos);
            for t in tri {
                triangles.push(t.map(|i| i as usize + base));
                ids.push(b as i32);
                reactions.extend(h.bone_reactions[b].iter().copied());
            }
        }
    }
    let mut grid = Grid::new(
        points.iter().map(|p: &Vector3<f64>| [p.x, p.y, p.z]),
        triangles.iter().map(|t| t.as_slice()),
        VTK_TRIANGLE,
    );
    grid.cell_active = "Scalars=\"bone_id\" Vectors=\"reaction\"".into();
    grid.cell_data.push(DataArray::i32("bone_id", ids));
    grid.cell_data
        .push(DataArray::f64("reaction", 3, reactions));
    Some(grid.to_bytes(encoding))
}

/// A VTU of every hand's contact skin (the smooth skin at the lattice's resolution, the surface
/// the contact acts on) in the frame's deformed state, quads, with the point data
/// `contact_pressure` (Pa: the tactile map on the skin, each vertex's force over its own area,
/// 0 off contact) and `contact_patch_pressure` (Pa: the same press read over patches of skin
/// 3.2 mm in radius, `state::TACTILE_PATCH_RADIUS`: the map that converges under refinement),
/// and the cell data `hand` (the body index); `None` without hands.
pub fn skin_vtu(model: &Model, frame: &Frame, encoding: VtuEncoding) -> Option<Vec<u8>> {
    if frame.hands.is_empty() {
        return None;
    }
    let mut points = Vec::new();
    let mut pressure = Vec::new();
    let mut patch = Vec::new();
    let mut quads: Vec<[usize; 4]> = Vec::new();
    let mut owner = Vec::new();
    for h in &frame.hands {
        let hand = model.bodies[h.body].hand.as_deref()?;
        let skin = &hand.contact_skin;
        let base = points.len();
        points.extend(skin.positions(&h.positions));
        pressure.extend(
            crate::state::contact_skin_pressure(model, frame, h.body)
                .unwrap_or_else(|| vec![0.0; skin.vertex_count()]),
        );
        patch.extend(
            crate::state::skin_patch_pressure(model, frame, h.body)
                .unwrap_or_else(|| vec![0.0; skin.vertex_count()]),
        );
        for q in &skin.quads {
            quads.push(q.map(|v| v as usize + base));
            owner.push(h.body as i32);
        }
    }
    let mut grid = Grid::new(
        points.iter().map(|p: &Vector3<f64>| [p.x, p.y, p.z]),
        quads.iter().map(|q| q.as_slice()),
        VTK_QUAD,
    );
    grid.point_active = "Scalars=\"contact_pressure\"".into();
    grid.point_data
        .push(DataArray::f64("contact_pressure", 1, pressure));
    grid.point_data
        .push(DataArray::f64("contact_patch_pressure", 1, patch));
    grid.cell_active = "Scalars=\"hand\"".into();
    grid.cell_data.push(DataArray::i32("hand", owner));
    Some(grid.to_bytes(encoding))
}
