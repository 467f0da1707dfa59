//! The wgpu renderer: draws the draw lists it is given, in a window or headless.
//! May import util only: it knows nothing of egui, scenes or the FEM.
//!
//! The renderer: wgpu drawing of lit surfaces (bodies, skin, bones), arrows, wireframes, a ground
//! plane with soft shadow and contact occlusion, and a colour-bar legend; into a window's
//! texture or, headless, into an image.
//!
//! It knows nothing of the solver or of any UI: it draws the buffers of a [`DrawList`]
//! (`crate::present` builds them from a solved scene). Typical headless use:
//!
//! ```no_run
//! use prehensile::render::{Camera, DrawList, Renderer, Surface};
//! let mut renderer = Renderer::new_headless()?;
//! let list = DrawList {
//!     surfaces: vec![Surface {
//!         positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
//!         indices: vec![0, 1, 2],
//!         scalars: None,
//!         color: [0.8, 0.3, 0.2, 1.0],
//!     }],
//!     ..Default::default()
//! };
//! let bounds = list.bounds().unwrap();
//! let camera = Camera::preset("three-quarter", &bounds, 16.0 / 9.0).unwrap();
//! let image = renderer.render_to_rgba(&list, &camera, 1280, 720)?;
//! # Ok::<(), prehensile::render::RenderError>(())
//! ```
//!
//! For animation, upload once ([`Renderer::upload`]) and update positions per frame
//! ([`GpuSurface::update_positions`]): only the vertex buffer is rewritten.
//!
//! Shaders are WGSL in the top-level `shaders/` folder. World units are metres, z up.

mod camera;
mod colormap;
mod context;
mod draw_list;
mod error;
mod formats;
mod frame_pipelines;
mod geometry;
mod globals;
mod gpu_scene;
mod legend;
mod pipelines;
mod quality;
mod renderer;

pub use camera::{Bounds, Camera, DEFAULT_FOV_Y, PRESETS};
pub use colormap::{finite_range, guard_range, linear_to_srgb, srgb_to_linear, Colormap};
pub use context::{describe_adapter, GpuContext};
pub use draw_list::{Arrow, DrawList, Ground, Legend, LineSet, Surface};
pub use error::RenderError;
pub use geometry::{arrow_mesh, sort_back_to_front, vertex_normals, vertex_normals_into};
pub use globals::key_direction;
pub use gpu_scene::{Gpu, GpuLines, GpuScene, GpuSurface};
pub use legend::{format_si, legend_image};
pub use pipelines::{DEPTH_FORMAT, MSAA_SAMPLES};
pub use quality::Quality;
pub use renderer::{Renderer, HEADLESS_FORMAT};
