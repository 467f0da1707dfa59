//! File: save and load the scene with its keyframes; export PNG, PNG sequence, OBJ, glTF.

use super::super::files::{
    export_gltf, export_obj, export_png, export_png_sequence, load_scene, save_scene,
};
use super::super::state::ViewerState;

const EXPORT_SIZE: (u32, u32) = (1280, 720);

pub(super) fn ui(state: &mut ViewerState, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        ui.label("scene");
        ui.text_edit_singleline(&mut state.scene_path)
            .on_hover_text("scene file to save to or load from");
    });
    ui.horizontal(|ui| {
        if ui.button("Save").clicked() {
            state.status.message = Some(match save_scene(state) {
                Ok(p) => format!("saved {}", p.display()),
                Err(e) => format!("not saved: {e}"),
            });
        }
        if ui.button("Load").clicked() {
            state.status.message = Some(match load_scene(state) {
                Ok(()) => format!("loaded {}", state.scene_name),
                Err(e) => format!("not loaded: {e}"),
            });
        }
    });
    ui.horizontal(|ui| {
        ui.label("export to");
        ui.text_edit_singleline(&mut state.export_dir)
            .on_hover_text("folder receiving the exports");
    });
    let (w, h) = EXPORT_SIZE;
    ui.horizontal_wrapped(|ui| {
        if ui.button("PNG").clicked() {
            state.status.message = Some(match export_png(state, w, h) {
                Ok(p) => format!("wrote {}", p.display()),
                Err(e) => format!("no PNG: {e}"),
            });
        }
        if ui.button("PNG sequence").clicked() {
            state.status.message = Some(match export_png_sequence(state, w, h) {
                Ok(p) => format!("wrote {} PNG files", p.len()),
                Err(e) => format!("no PNG sequence: {e}"),
            });
        }
        if ui.button("OBJ").clicked() {
            state.status.message = Some(match export_obj(state) {
                Ok(p) => format!("wrote {} OBJ files", p.len()),
                Err(e) => format!("no OBJ: {e}"),
            });
        }
        if ui
            .button("glTF")
            .on_hover_text("every solved timeline frame as one animated animation.glb (Blender)")
            .clicked()
        {
            state.status.message = Some(match export_gltf(state) {
                Ok(p) => format!("wrote {}", p.display()),
                Err(e) => format!("no glTF: {e}"),
            });
        }
    });
    if let Some(m) = &state.status.message {
        ui.label(m);
    }
}
