//! The File panel's actions: save and load the scene (with its keyframes) as TOML, written
//! atomically; export the shown frame as PNG, and the solved timeline frames as a PNG sequence
//! and as OBJ files (skin and bones) or one animated glTF (`animation.glb`).

use super::state::ViewerState;
use crate::export::gltf_animation::{animated_surfaces, animation_glb};
use crate::export::hand_geometry::frame_obj;
use crate::export::output::OutputSet;
use crate::export::png::{png_bytes, write_png_atomic};
use crate::scene::{Scene, SceneError};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a file action failed.
#[derive(Debug, Error)]
pub enum FileError {
    /// Reading or writing failed.
    #[error("{path}: {reason}")]
    Io {
        /// The file or folder.
        path: String,
        /// Why (kept out of the error chain so that it is said once).
        reason: std::io::Error,
    },
    /// The scene could not be written as TOML.
    #[error("the scene cannot be written as TOML: {0}")]
    Toml(#[from] toml::ser::Error),
    /// The loaded scene is unusable.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene's keyframes or poses are unusable.
    #[error("{0}")]
    Timeline(String),
    /// Nothing to export yet.
    #[error("{0}")]
    Nothing(&'static str),
    /// The 3D view could not render.
    #[error("rendering failed: {0}")]
    Render(String),
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> FileError + '_ {
    move |reason| FileError::Io {
        path: path.display().to_string(),
        reason,
    }
}

/// Writes `bytes` to `path` through a temporary file beside it and a rename
/// ([`crate::export::png::write_bytes_atomic`]); the error names `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    crate::export::png::write_bytes_atomic(path, bytes).map_err(io(path))
}

/// Saves the scene with its keys to `state.scene_path`.
pub fn save_scene(state: &ViewerState) -> Result<PathBuf, FileError> {
    let path = state.scene_file();
    let text = toml::to_string(&state.scene_with_keys())?;
    write_atomic(&path, text.as_bytes())?;
    Ok(path)
}

/// Loads the scene at `state.scene_path` in place of the current one.
pub fn load_scene(state: &mut ViewerState) -> Result<(), FileError> {
    let path = state.scene_file();
    let scene = Scene::load(&path)?;
    state
        .replace_scene(scene, &path.display().to_string())
        .map_err(FileError::Timeline)
}

/// Renders the shown frame with the view's camera into `dir/frame.png`.
pub fn export_png(state: &mut ViewerState, width: u32, height: u32) -> Result<PathBuf, FileError> {
    let dir = PathBuf::from(&state.export_dir);
    let view = state
        .view
        .as_mut()
        .ok_or(FileError::Nothing("no 3D view"))?;
    let image = view
        .capture(None, width, height)
        .map_err(FileError::Render)?;
    let path = dir.join("frame.png");
    write_png_atomic(&path, &image).map_err(io(&path))?;
    Ok(path)
}

/// Renders every solved timeline frame into `dir/frames/frame_NNNN.png`, all or nothing.
pub fn export_png_sequence(
    state: &mut ViewerState,
    width: u32,
    height: u32,
) -> Result<Vec<PathBuf>, FileError> {
    let dir = PathBuf::from(&state.export_dir).join("frames");
    let frames: Vec<_> = state.timeline.frames.iter().flatten().cloned().collect();
    if frames.is_empty() {
        return Err(FileError::Nothing("no timeline frame is solved yet"));
    }
    let view = state
        .view
        .as_mut()
        .ok_or(FileError::Nothing("no 3D view"))?;
    let mut out = OutputSet::new(&dir).map_err(io(&dir))?;
    for (i, f) in frames.iter().enumerate() {
        let image = view
            .capture(Some(f), width, height)
            .map_err(FileError::Render)?;
        let bytes = png_bytes(&image).map_err(io(&dir))?;
        out.write(&format!("frame_{i:04}.png"), &bytes)
            .map_err(io(&dir))?;
    }
    out.commit().map_err(io(&dir))
}

/// Writes every solved timeline frame's hands as `dir/obj/hand_NNNN.obj`, all or nothing.
pub fn export_obj(state: &ViewerState) -> Result<Vec<PathBuf>, FileError> {
    let dir = PathBuf::from(&state.export_dir).join("obj");
    let mut out = OutputSet::new(&dir).map_err(io(&dir))?;
    let mut any = false;
    for (i, f) in state.timeline.frames.iter().flatten().enumerate() {
        if let Some(obj) = frame_obj(&f.model, &f.frame) {
            out.write(&format!("hand_{i:04}.obj"), obj.as_bytes())
                .map_err(io(&dir))?;
            any = true;
        }
    }
    if !any {
        return Err(FileError::Nothing(
            "no solved timeline frame with a hand to export",
        ));
    }
    out.commit().map_err(io(&dir))
}

/// Writes the solved timeline frames (those of the current scene, at their keys' times) as one
/// animated glTF, `dir/animation.glb`, atomically.
pub fn export_gltf(state: &ViewerState) -> Result<PathBuf, FileError> {
    let solved: Vec<(f64, &super::jobs::Solution)> = state
        .timeline
        .keys
        .iter()
        .zip(&state.timeline.frames)
        .filter_map(|(k, f)| f.as_ref().map(|f| (k.time, f)))
        .collect();
    let Some((_, first)) = solved.first() else {
        return Err(FileError::Nothing("no solved timeline frame to export"));
    };
    let model = &first.model;
    // Frames of the same mesh only (a frame left from before an edit of the scene is not).
    let same = |m: &crate::model::Model| {
        m.mesh.node_count() == model.mesh.node_count()
            && m.mesh.cell_count() == model.mesh.cell_count()
            && m.bodies.len() == model.bodies.len()
    };
    let (times, frames): (Vec<f64>, Vec<&crate::state::Frame>) = solved
        .iter()
        .filter(|(_, f)| same(&f.model))
        .map(|(t, f)| (*t, &*f.frame))
        .unzip();
    let dir = PathBuf::from(&state.export_dir);
    let bytes = animation_glb(&animated_surfaces(model, &frames), &times)
        .map_err(|e| FileError::Timeline(e.to_string()))?;
    let path = dir.join("animation.glb");
    std::fs::create_dir_all(&dir).map_err(io(&dir))?;
    write_atomic(&path, &bytes)?;
    Ok(path)
}
