//! The 3D view of the window: the project's [`Renderer`], on egui's wgpu device, draws the shown
//! draw list into an offscreen texture registered with egui, redrawn only when the frame, the
//! camera or the size changed. Drag to orbit, right-drag (or shift-drag) to pan, scroll to
//! zoom, double-click to frame the bodies again.
//!
//! A level of detail while the view changes fast: a preview (a pose being dragged, drawn with
//! the coarse skin) and an orbit, pan or zoom in progress are drawn at
//! [`INTERACTIVE_SCALE`] of the view's pixels in each direction with one sample per pixel
//! (`Quality::Draft`), shown stretched; the solved frame, once the camera rests, is drawn again
//! at full size, anti-aliased. On a software renderer the draw is mostly pixels and their samples
//! (shadow taps, 4× MSAA, the translucent skin): a quarter of the pixels at one sample each keeps
//! the view moving while a slider or the camera is dragged.

use super::jobs::Solution;
use super::state::SceneView;
use crate::render::{
    Bounds, Camera, DrawList, GpuScene, Quality, Renderer, HEADLESS_FORMAT, PRESETS,
};
use crate::util::timing::ms;
use eframe::egui;
use eframe::egui_wgpu::RenderState;
use egui::{Color32, Rect, Sense};
use std::sync::Arc;
use std::time::Instant;

/// The share of the view's width and height drawn while it changes fast (a preview, the camera
/// moving).
pub const INTERACTIVE_SCALE: f32 = 0.5;

/// Offscreen target registered with egui.
struct Target {
    view: wgpu::TextureView,
    id: egui::TextureId,
    size: (u32, u32),
}

/// The window's 3D view.
pub struct View3d {
    renderer: Renderer,
    render_state: RenderState,
    scene: Option<GpuScene>,
    list: Option<Arc<DrawList>>,
    camera: Option<Camera>,
    bounds: Option<Bounds>,
    target: Option<Target>,
    dirty: bool,
    /// The frame shown is a preview, or a frame whose contact is settling: replaced shortly,
    /// drawn at the interactive scale as a draft.
    preview: bool,
    /// The camera moved in the last UI frame (drawn at the interactive scale).
    moving: bool,
    /// Milliseconds of the last redraw of the 3D texture (encoding and submission).
    pub last_render_ms: f64,
    /// Last error of the renderer, shown over the view.
    pub error: Option<String>,
}

impl View3d {
    /// A view drawing with a renderer on `render_state`'s device.
    pub fn new(render_state: &RenderState) -> Self {
        let mut renderer = Renderer::from_device(
            render_state.device.clone(),
            render_state.queue.clone(),
            render_state.adapter.get_info(),
            HEADLESS_FORMAT,
        );
        renderer.prepare(Quality::Draft);
        View3d {
            renderer,
            render_state: render_state.clone(),
            scene: None,
            list: None,
            camera: None,
            bounds: None,
            target: None,
            dirty: true,
            preview: false,
            moving: false,
            last_render_ms: 0.0,
            error: None,
        }
    }

    /// The adapter, for the log.
    pub fn adapter_summary(&self) -> String {
        self.renderer.adapter_summary()
    }

    fn frame_camera(&mut self, preset: &str) {
        if let (Some(b), Some(t)) = (&self.bounds, &self.target) {
            let aspect = t.size.0 as f32 / t.size.1.max(1) as f32;
            self.camera = Camera::preset(preset, b, aspect);
            self.dirty = true;
        }
    }

    fn ensure_target(&mut self, size: (u32, u32)) {
        if self.target.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let device = &self.render_state.device;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("3d view"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: HEADLESS_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let mut egui_renderer = self.render_state.renderer.write();
        let id = match &self.target {
            Some(old) => {
                egui_renderer.update_egui_texture_from_wgpu_texture(
                    device,
                    &view,
                    wgpu::FilterMode::Linear,
                    old.id,
                );
                old.id
            }
            None => egui_renderer.register_native_texture(device, &view, wgpu::FilterMode::Linear),
        };
        self.target = Some(Target { view, id, size });
        self.dirty = true;
    }

    fn redraw(&mut self) {
        let (Some(scene), Some(camera), Some(t)) = (&mut self.scene, &self.camera, &self.target)
        else {
            return;
        };
        let start = Instant::now();
        self.renderer.set_quality(if self.preview || self.moving {
            Quality::Draft
        } else {
            Quality::Full
        });
        match self
            .renderer
            .render(scene, camera, &t.view, t.size.0, t.size.1)
        {
            Ok(()) => self.error = None,
            Err(e) => self.error = Some(e.to_string()),
        }
        self.last_render_ms = ms(start);
        self.dirty = false;
    }

    /// Moves the camera by the pointer; returns whether it moved.
    fn handle_input(&mut self, ui: &egui::Ui, response: &egui::Response, rect: Rect) -> bool {
        let mut moving = false;
        let Some(camera) = &mut self.camera else {
            return moving;
        };
        let d = response.drag_delta();
        let height = rect.height().max(1.0);
        let pan = response.dragged_by(egui::PointerButton::Secondary)
            || (response.dragged() && ui.input(|i| i.modifiers.shift));
        if d != egui::Vec2::ZERO {
            if pan {
                camera.pan(d.x / height, -d.y / height);
            } else if response.dragged_by(egui::PointerButton::Primary) {
                camera.orbit(-d.x * 0.008, d.y * 0.008);
            }
            self.dirty = true;
            moving = true;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                camera.zoom((-scroll * 0.002).exp());
                self.dirty = true;
                moving = true;
            }
        }
        if response.double_clicked() {
            self.frame_camera("three-quarter");
        }
        moving
    }
}

/// The pixels drawn for a view of `full` pixels: all of them, or [`INTERACTIVE_SCALE`] of each
/// side while the view changes fast (at least 16).
pub fn drawn_size(full: (u32, u32), interactive: bool) -> (u32, u32) {
    if !interactive {
        return full;
    }
    let scale = |n: u32| {
        ((n as f32 * INTERACTIVE_SCALE).round() as u32)
            .max(16)
            .min(n)
    };
    (scale(full.0), scale(full.1))
}

impl SceneView for View3d {
    fn show_solution(&mut self, solution: &Solution, range: [f32; 2]) {
        let list = solution.draw_list.clone();
        match self.renderer.upload(&list) {
            Ok(mut scene) => {
                if let Some(legend) = &mut scene.legend {
                    legend.range = range;
                }
                self.scene = Some(scene);
                self.error = None;
            }
            Err(e) => self.error = Some(e.to_string()),
        }
        if self.bounds.is_none() {
            self.bounds = list.bounds();
            self.camera = None;
        }
        self.list = Some(list);
        self.preview = solution.preview || solution.settling;
        self.dirty = true;
    }

    fn set_range(&mut self, range: [f32; 2]) {
        if let Some(legend) = self.scene.as_mut().and_then(|s| s.legend.as_mut()) {
            legend.range = range;
            self.dirty = true;
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui) {
        let rect = ui.available_rect_before_wrap();
        let ppp = ui.ctx().pixels_per_point();
        let full = (
            ((rect.width() * ppp).round() as u32).clamp(16, 4096),
            ((rect.height() * ppp).round() as u32).clamp(16, 4096),
        );
        let response = ui.allocate_rect(rect, Sense::click_and_drag());
        // The camera stays framed as at full size: the reduced target has the same aspect.
        self.ensure_target(drawn_size(full, self.preview || self.moving));
        if self.camera.is_none() {
            self.frame_camera("three-quarter");
        }
        let moving = self.handle_input(ui, &response, rect);
        // Moving, or a preview: reduced; the camera at rest on a solved frame: full size
        // (a change of size marks the view for a redraw).
        self.moving = moving || response.dragged();
        self.ensure_target(drawn_size(full, self.preview || self.moving));
        if self.dirty {
            self.redraw();
        }
        if let Some(t) = &self.target {
            let uv = Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            ui.painter().image(t.id, rect, uv, Color32::WHITE);
        }
        // Camera presets over the top-left corner of the view.
        let mut chosen = None;
        let mut overlay = ui.new_child(
            egui::UiBuilder::new()
                .max_rect(rect.shrink(8.0))
                .layout(egui::Layout::left_to_right(egui::Align::Min)),
        );
        for (name, _) in PRESETS.iter().take(4) {
            if overlay.small_button(*name).clicked() {
                chosen = Some(*name);
            }
        }
        if let Some(name) = chosen {
            self.frame_camera(name);
        }
        if let Some(e) = &self.error {
            overlay.colored_label(Color32::LIGHT_RED, e);
        }
        if self.list.is_none() {
            overlay.label("solving the first frame…");
        }
    }

    fn capture(
        &mut self,
        solution: Option<&Solution>,
        width: u32,
        height: u32,
    ) -> Result<image::RgbaImage, String> {
        // The view's camera; the export's aspect may differ from the view's.
        let cam = self.camera.ok_or("nothing shown yet")?;
        self.renderer.set_quality(Quality::Full);
        let out = match solution {
            Some(s) => self
                .renderer
                .render_to_rgba(&s.draw_list, &cam, width, height),
            None => {
                let scene = self.scene.as_mut().ok_or("nothing shown yet")?;
                self.renderer
                    .render_scene_to_rgba(scene, &cam, width, height)
            }
        };
        self.dirty = true;
        out.map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::drawn_size;

    #[test]
    fn the_interactive_size_is_half_of_each_side_never_below_16_pixels() {
        assert_eq!(drawn_size((780, 700), false), (780, 700));
        assert_eq!(drawn_size((780, 700), true), (390, 350));
        assert_eq!(drawn_size((20, 17), true), (16, 16));
        assert_eq!(drawn_size((16, 16), true), (16, 16));
    }
}
