//! Headless rendering of solved scenes: what `prehensile render` does for each frame, shared
//! with the image regression tests.

use crate::headless::Solved;
use crate::present::{draw_list, Overlay, VisualError, VisualOptions};
use crate::render::{Bounds, Camera, DrawList, RenderError, Renderer};
use image::RgbaImage;
use thiserror::Error;

/// Why a frame could not be rendered.
#[derive(Debug, Error)]
pub enum HeadlessError {
    /// The draw list could not be built.
    #[error(transparent)]
    Visual(#[from] VisualError),
    /// The renderer failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// No camera of that name.
    #[error("no camera named \"{name}\" (known: {known})")]
    UnknownCamera {
        /// The name asked for.
        name: String,
        /// The known names.
        known: String,
    },
    /// No such frame.
    #[error("frame {frame} does not exist (the scene has {count} frame(s), numbered from 0)")]
    NoFrame {
        /// Asked for.
        frame: usize,
        /// Frames solved.
        count: usize,
    },
    /// Nothing to draw.
    #[error("the scene has nothing to draw")]
    Empty,
}

/// The draw lists of every frame.
pub fn draw_lists(solved: &Solved, options: &VisualOptions) -> Result<Vec<DrawList>, VisualError> {
    // The pressure overlay of a scene in which nothing ever touches says so (a frame out of
    // contact in a scene with contact shows zero pressure). The skin pressed on itself is
    // contact too.
    let touches =
        |f: &crate::state::Frame| f.contact.is_some() || f.hands.iter().any(|h| h.presses_itself());
    if options.overlay == Overlay::Pressure && !solved.frames.iter().any(touches) {
        return Err(VisualError::NoContact);
    }
    solved
        .frames
        .iter()
        .map(|f| draw_list(&solved.model, f, options))
        .collect()
}

/// The named camera framing all of `lists` (one camera for all frames, so that an animation
/// does not jump), for images of aspect `width / height`.
pub fn camera_for(lists: &[DrawList], name: &str, aspect: f32) -> Result<Camera, HeadlessError> {
    let mut bounds = Bounds::empty();
    for b in lists.iter().filter_map(DrawList::bounds) {
        bounds.include(b.min);
        bounds.include(b.max);
    }
    if !bounds.is_valid() {
        return Err(HeadlessError::Empty);
    }
    Camera::preset(name, &bounds, aspect).ok_or_else(|| HeadlessError::UnknownCamera {
        name: name.to_string(),
        known: Camera::preset_names(),
    })
}

/// The camera called `name`: one of the scene's `[[camera]]`s, else a built-in preset framing
/// all of `lists`.
pub fn scene_camera(
    solved: &Solved,
    lists: &[DrawList],
    name: &str,
    aspect: f32,
) -> Result<Camera, HeadlessError> {
    if let Some(c) = solved.model.cameras.iter().find(|c| c.name == name) {
        let v = |a: [f64; 3]| glam::Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
        return Ok(Camera {
            eye: v(c.eye),
            target: v(c.target),
            up: v(c.up),
            fov_y: (c.fov_deg as f32).to_radians(),
        });
    }
    camera_for(lists, name, aspect).map_err(|e| match e {
        HeadlessError::UnknownCamera { name, known } => {
            let mut all: Vec<String> = solved
                .model
                .cameras
                .iter()
                .map(|c| c.name.clone())
                .collect();
            all.push(known);
            HeadlessError::UnknownCamera {
                name,
                known: all.join(", "),
            }
        }
        other => other,
    })
}

/// Renders frame `frame` of a solved scene with the named camera (a scene camera or a preset).
pub fn render_frame(
    renderer: &mut Renderer,
    solved: &Solved,
    frame: usize,
    options: &VisualOptions,
    camera: &str,
    width: u32,
    height: u32,
) -> Result<RgbaImage, HeadlessError> {
    if frame >= solved.frames.len() {
        return Err(HeadlessError::NoFrame {
            frame,
            count: solved.frames.len(),
        });
    }
    let lists = draw_lists(solved, options)?;
    let cam = scene_camera(solved, &lists, camera, width as f32 / height.max(1) as f32)?;
    Ok(renderer.render_to_rgba(&lists[frame], &cam, width, height)?)
}
