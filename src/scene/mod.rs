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

/// The largest scene file read, bytes: a scene is a few kilobytes of TOML (a rig's table or
/// many keyframes, some hundreds).
pub const MAX_SCENE_BYTES: u64 = 16_000_000;

impl Scene {
    /// Reads and parses a scene file (refused beyond [`MAX_SCENE_BYTES`]).
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let io = |reason| SceneError::Io {
            file: path.display().to_string(),
            reason,
        };
        let bytes = crate::util::read::read_at_most(path, MAX_SCENE_BYTES).map_err(io)?;
        let text = String::from_utf8(bytes).map_err(|e| {
            io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!(
                    "it is not UTF-8 text (byte {} is not), as a TOML scene is",
                    e.utf8_error().valid_up_to()
                ),
            ))
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
