//! A solve never writes over what it reads: its scene file, or a rigged hand's glTF file, in
//! the output folder under a name the solve gives its outputs (a rig named `animation.glb`
//! there was replaced by the result, found by a hostile-input probe, 2026-12-03).

use super::solve::PipelineError;
use crate::export::output::is_output_name;
use crate::scene::{Scene, Shape};
use std::path::{Path, PathBuf};

/// The scene file at `scene_path` and the glTF files its hands read, where one of them is a
/// file `out` would be written over: refused, naming it, before anything is solved.
pub fn refuse_writing_over_inputs(
    scene: &Scene,
    scene_path: &Path,
    out: &Path,
) -> Result<(), PipelineError> {
    let beside = scene_path.parent().unwrap_or(Path::new("."));
    let mut inputs: Vec<PathBuf> = vec![scene_path.to_path_buf()];
    for body in &scene.body {
        if let Shape::Hand {
            gltf: Some(file), ..
        } = &body.shape
        {
            inputs.push(beside.join(file));
        }
    }
    // A folder not there yet holds nothing to lose.
    let Ok(out_dir) = out.canonicalize() else {
        return Ok(());
    };
    for input in inputs {
        let (Ok(real), Some(name)) = (input.canonicalize(), input.file_name()) else {
            continue;
        };
        let name = name.to_string_lossy();
        if real.parent() == Some(out_dir.as_path()) && is_output_name(&name) {
            return Err(PipelineError::Output {
                dir: out.display().to_string(),
                reason: std::io::Error::other(format!(
                    "the scene reads \"{}\" there, and \"{name}\" is the name of one of the \
                     solve's outputs, which would replace it: write the outputs to another \
                     folder (--out), or rename the input",
                    input.display()
                )),
            });
        }
    }
    Ok(())
}
