//! The native window (eframe, winit, egui-wgpu): the viewer state with the real solver thread
//! and the renderer-backed 3D view. Without a display it fails with
//! [`ViewerError::NoDisplay`], whose message names the headless commands.

use super::physics::Physics;
use super::state::ViewerState;
use super::view3d::View3d;
use super::worker::ThreadSolver;
use crate::scene::Scene;
use eframe::egui;
use std::path::PathBuf;
use std::sync::Arc;
use thiserror::Error;

/// The headless commands, for the no-display message.
const HEADLESS: &str =
    "use the headless commands instead: `prehensile solve SCENE.toml --out DIR`, \
                        `prehensile render SCENE.toml --out frame.png`";

/// Why the window could not run.
#[derive(Debug, Error)]
pub enum ViewerError {
    /// No display to open a window on.
    #[error("no display to open the viewer window on ({reason}); {HEADLESS}")]
    NoDisplay {
        /// What is missing or what failed.
        reason: String,
    },
    /// The scene's poses or keyframes are unusable.
    #[error("{0}")]
    Scene(String),
    /// The screenshot could not be written.
    #[error("screenshot {path}: {reason}")]
    Screenshot {
        /// The file.
        path: String,
        /// Why (kept out of the error chain so that it is said once).
        reason: std::io::Error,
    },
}

/// Options of `prehensile view`.
#[derive(Clone, Debug, Default)]
pub struct ViewOptions {
    /// Write a screenshot of the window here once the first frame is solved, then close.
    pub screenshot: Option<PathBuf>,
    /// Close after this many frames (with `screenshot`: take it then at the latest).
    pub exit_after_frames: Option<u64>,
    /// Inner window size, points.
    pub size: [f32; 2],
    /// Starting pose.
    pub preset: Option<super::pose::Preset>,
    /// Starting overlay.
    pub overlay: Option<crate::present::Overlay>,
    /// The timeline key to show once it is solved.
    pub key: Option<usize>,
}

struct ViewerApp {
    state: ViewerState,
    options: ViewOptions,
    frames: u64,
    /// Frames since the shown frame became current (for the screenshot).
    settled: u64,
    asked: bool,
    captured: Arc<std::sync::Mutex<Option<Arc<egui::ColorImage>>>>,
    result: Arc<std::sync::Mutex<Option<ViewerError>>>,
}

impl ViewerApp {
    fn screenshot(&mut self, ui: &egui::Ui) {
        let Some(path) = self.options.screenshot.clone() else {
            return;
        };
        let image = self
            .captured
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take();
        if let Some(image) = image {
            let [w, h] = image.size;
            let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
            let written = image::RgbaImage::from_raw(w as u32, h as u32, rgba)
                .ok_or_else(|| std::io::Error::other("short image"))
                .and_then(|img| crate::export::png::write_png_atomic(&path, &img));
            if let Err(source) = written {
                *self.result.lock().unwrap_or_else(|e| e.into_inner()) =
                    Some(ViewerError::Screenshot {
                        path: path.display().to_string(),
                        reason: source,
                    });
            }
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        }
        let on_key = self
            .options
            .key
            .is_none_or(|k| self.state.timeline.current == k);
        let ready = self.state.shown.is_some() && !self.state.computing() && on_key;
        self.settled = if ready { self.settled + 1 } else { 0 };
        let last = self
            .options
            .exit_after_frames
            .is_some_and(|n| self.frames >= n);
        if !self.asked && (self.settled >= 3 || last) {
            self.asked = true;
            let slot = self.captured.clone();
            let ctx = ui.ctx().clone();
            ui.ctx().request_screenshot(move |image| {
                *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(image);
                ctx.request_repaint();
            });
        }
        ui.ctx().request_repaint();
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frames += 1;
        if let Some(k) = self.options.key {
            let solved = self
                .state
                .timeline
                .frames
                .get(k)
                .is_some_and(|f| f.is_some());
            if solved && self.state.timeline.current != k {
                self.state.scrub_to(k);
            }
        }
        self.state.ui(ui);
        self.screenshot(ui);
        if self.options.screenshot.is_none()
            && self
                .options
                .exit_after_frames
                .is_some_and(|n| self.frames >= n)
        {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}

fn display_available() -> Result<(), ViewerError> {
    let set = |v: &str| std::env::var_os(v).is_some_and(|s| !s.is_empty());
    if set("DISPLAY") || set("WAYLAND_DISPLAY") {
        Ok(())
    } else {
        Err(ViewerError::NoDisplay {
            reason: "DISPLAY and WAYLAND_DISPLAY are not set".into(),
        })
    }
}

/// Opens the viewer on `scene` (called `name`) and runs until the window closes.
pub fn run_viewer(scene: Scene, name: &str, options: ViewOptions) -> Result<(), ViewerError> {
    super::timeline::Timeline::from_scene(&scene, &super::pose::hands_of(&scene))
        .map_err(ViewerError::Scene)?;
    display_available()?;
    let size = if options.size[0] > 0.0 {
        options.size
    } else {
        [1600.0, 900.0]
    };
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(format!("Prehensile — {name}"))
            .with_inner_size(size),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    let result: Arc<std::sync::Mutex<Option<ViewerError>>> = Arc::default();
    let app_result = result.clone();
    let name = name.to_string();
    let run = eframe::run_native(
        "prehensile",
        native,
        Box::new(move |cc| {
            let render_state = cc
                .wgpu_render_state
                .as_ref()
                .ok_or("the window has no wgpu device")?;
            let ctx = cc.egui_ctx.clone();
            let notify: Arc<dyn Fn() + Send + Sync> = Arc::new(move || ctx.request_repaint());
            let port = ThreadSolver::spawn(Physics::new(), notify);
            let mut state = ViewerState::new(scene, &name, Box::new(port))?;
            if let Some(p) = options.preset {
                for (h, (_, angles)) in state.hands.iter().zip(state.pose.iter_mut()) {
                    *angles = p.angles(&h.skeleton);
                }
            }
            if let Some(o) = options.overlay {
                state.display.overlay = o;
            }
            let view = View3d::new(render_state);
            eprintln!("adapter: {}", view.adapter_summary());
            state.view = Some(Box::new(view));
            Ok(Box::new(ViewerApp {
                state,
                options,
                frames: 0,
                settled: 0,
                asked: false,
                captured: Arc::default(),
                result: app_result,
            }))
        }),
    );
    if let Err(e) = run {
        return Err(ViewerError::NoDisplay {
            reason: format!("the window could not be opened: {e}"),
        });
    }
    let taken = result.lock().unwrap_or_else(|e| e.into_inner()).take();
    match taken {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
