//! The scene file: serde types with their own enums, parsing, errors naming file and field.
//! May import util only: nothing of the solver.
//!
//! Scene files (TOML): materials, bodies, constraints, loads and probes, with validation errors
//! that name the file and the field. The format is documented in `docs/scene-format.md`.

mod error;
mod names;
mod types;

pub use error::SceneError;
pub use names::*;
pub use types::*;

use std::path::Path;

/// The built-in default scene, what the viewer opens without a scene file: a right hand, fingers
/// slightly curled, beside a pressurised rubber ball (`assets/scenes/hand-and-ball.toml`).
pub const DEFAULT_SCENE: &str = include_str!("../../assets/scenes/hand-and-ball.toml");

/// The pressurised rubber ball pressed at its top (`assets/scenes/default.toml`), the default
/// scene before the viewer: the renderer's benchmark and image tests use it.
pub const BALL_SCENE: &str = include_str!("../../assets/scenes/default.toml");

impl Scene {
    /// Reads and parses a scene file.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|reason| SceneError::Io {
            file: path.display().to_string(),
            reason,
        })?;
        Scene::parse(&text, &path.display().to_string())
    }

    /// Parses scene text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
        let deserializer =
            toml::Deserializer::parse(text).map_err(|e| SceneError::syntax(file, text, "", &e))?;
        serde_path_to_error::deserialize::<_, Scene>(deserializer).map_err(|e| {
            let field = e.path().to_string();
            let field = if field == "." { String::new() } else { field };
            SceneError::syntax(file, text, &field, e.inner())
        })
    }
}
