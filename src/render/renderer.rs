//! The renderer: created once (device, queue, pipelines), it draws uploaded scenes into a
//! texture view (the interactive window) or into an image (headless).

use super::camera::Camera;
use super::colormap::Colormap;
use super::context::{describe_adapter, GpuContext};
use super::draw_list::{DrawList, Legend};
use super::error::RenderError;
use super::frame_pipelines::FramePipelines;
use super::globals::{frame_globals, LightSampling};
use super::gpu_scene::{Gpu, GpuScene};
use super::legend::legend_image;
use super::pipelines::{
    Pipelines, DEPTH_FORMAT, MSAA_SAMPLES, SHADOW_MAP_SIZE, UNDER_FORMAT, UNDER_MAP_SIZE,
};
use super::quality::Quality;
use image::RgbaImage;
use std::sync::{Arc, Mutex};

/// Colour format of headless images (8-bit sRGB).
pub const HEADLESS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Colour and depth targets of one size and number of samples (the multisampled colour
/// resolved into the caller's target; plus, headless, the resolved image and its readback
/// buffer).
struct Targets {
    size: (u32, u32),
    samples: u32,
    /// The multisampled colour, `None` with one sample (drawn into the target itself).
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    resolved: Option<(wgpu::Texture, wgpu::TextureView, wgpu::Buffer, u32)>,
}

/// The legend texture for one legend at one frame height.
struct LegendOverlay {
    key: (Legend, u32, (u32, u32)),
    group: wgpu::BindGroup,
}

/// Draws [`DrawList`]s. Knows nothing of where they come from.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    max_side: u32,
    /// The adapter's largest buffer, bytes (what an image is read back through).
    max_buffer: u64,
    format: wgpu::TextureFormat,
    pipelines: Pipelines,
    /// The frame's pipelines with one sample per pixel, made at the first draft.
    draft: Option<FramePipelines>,
    quality: Quality,
    /// What the shadow map and the under-map hold: the casters' geometry stamps and the two
    /// lights' view-projections they were drawn with (`None`: nothing drawn yet).
    light_maps: Option<(Vec<u64>, [f32; 32])>,
    globals_buffer: wgpu::Buffer,
    globals_group: wgpu::BindGroup,
    key_light: (wgpu::Buffer, wgpu::BindGroup),
    under_light: (wgpu::Buffer, wgpu::BindGroup),
    shadow_view: wgpu::TextureView,
    under_view: wgpu::TextureView,
    under_depth: wgpu::TextureView,
    colormap_texture: wgpu::Texture,
    colormap: Option<Colormap>,
    targets: Option<Targets>,
    legend: Option<LegendOverlay>,
    errors: Arc<Mutex<Vec<String>>>,
}

fn depth_texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    samples: u32,
    sampled: bool,
) -> wgpu::TextureView {
    let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
    if sampled {
        usage |= wgpu::TextureUsages::TEXTURE_BINDING;
    }
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage,
            view_formats: &[],
        })
        .create_view(&Default::default())
}

impl Renderer {
    /// A renderer on the best adapter available without a window (see [`GpuContext`]), drawing
    /// 8-bit sRGB images.
    pub fn new_headless() -> Result<Self, RenderError> {
        let ctx = GpuContext::new_headless()?;
        Ok(Self::from_device(
            ctx.device,
            ctx.queue,
            ctx.info,
            HEADLESS_FORMAT,
        ))
    }

    /// A renderer on an existing device (the window's), drawing into targets of `format`.
    pub fn from_device(
        device: wgpu::Device,
        queue: wgpu::Queue,
        info: wgpu::AdapterInfo,
        format: wgpu::TextureFormat,
    ) -> Self {
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let pipelines = Pipelines::new(&device, format);
        let globals_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: 4 * 4 * (3 * 4 + 10),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let identity = bytemuck::cast_slice(&glam::Mat4::IDENTITY.to_cols_array()).to_vec();
        let key_light = pipelines.uniform(&device, &pipelines.light_layout, &identity);
        let under_light = pipelines.uniform(&device, &pipelines.light_layout, &identity);
        let shadow_view = depth_texture(
            &device,
            "key shadow map",
            (SHADOW_MAP_SIZE, SHADOW_MAP_SIZE),
            1,
            true,
        );
        let under_view = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("under map"),
                size: wgpu::Extent3d {
                    width: UNDER_MAP_SIZE,
                    height: UNDER_MAP_SIZE,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: UNDER_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let under_depth = depth_texture(
            &device,
            "under map depth",
            (UNDER_MAP_SIZE, UNDER_MAP_SIZE),
            1,
            false,
        );
        let colormap_texture = sampled_rgba_texture(&device, "colormap", 256, 1);
        let colormap_view = colormap_texture.create_view(&Default::default());
        let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &pipelines.globals_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: globals_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&shadow_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&pipelines.shadow_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&under_view),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&colormap_view),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(&pipelines.linear_sampler),
                },
            ],
        });
        let max_side = device.limits().max_texture_dimension_2d;
        let max_buffer = device.limits().max_buffer_size;
        Self {
            device,
            queue,
            info,
            max_side,
            max_buffer,
            format,
            pipelines,
            draft: None,
            quality: Quality::Full,
            light_maps: None,
            globals_buffer,
            globals_group,
            key_light,
            under_light,
            shadow_view,
            under_view,
            under_depth,
            colormap_texture,
            colormap: None,
            targets: None,
            legend: None,
            errors,
        }
    }

    /// The adapter in use.
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// One line about the adapter (name, backend, type, driver).
    pub fn adapter_summary(&self) -> String {
        describe_adapter(&self.info)
    }

    /// Draws the frames that follow at `quality` (anti-aliased until set otherwise).
    pub fn set_quality(&mut self, quality: Quality) {
        self.prepare(quality);
        self.quality = quality;
    }

    /// Makes the pipelines of `quality` now, if they are not made yet: a window makes its
    /// draft's when it opens (150–200 ms on llvmpipe) rather than at the first drag.
    pub fn prepare(&mut self, quality: Quality) {
        if quality.samples() != MSAA_SAMPLES && self.draft.is_none() {
            self.draft = Some(
                self.pipelines
                    .frame_pipelines(&self.device, quality.samples()),
            );
        }
    }

    /// The quality frames are drawn at.
    pub fn quality(&self) -> Quality {
        self.quality
    }

    /// The device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Device, queue and pipelines, for uploading and updating scenes.
    pub fn gpu(&self) -> Gpu<'_> {
        Gpu {
            device: &self.device,
            queue: &self.queue,
            pipelines: &self.pipelines,
        }
    }

    /// Uploads a draw list; keep the result and update it between frames.
    pub fn upload(&self, list: &DrawList) -> Result<GpuScene, RenderError> {
        GpuScene::new(&self.gpu(), list)
    }

    /// Whether an image of `width`×`height` can be drawn and read back on this adapter.
    pub fn check_size(&self, width: u32, height: u32) -> Result<(), RenderError> {
        if width == 0 || height == 0 || width > self.max_side || height > self.max_side {
            return Err(RenderError::Size {
                width,
                height,
                max: self.max_side,
            });
        }
        // The read-back buffer: rows padded to 256 bytes, four bytes a pixel.
        let row = (u64::from(width) * 4).div_ceil(256) * 256;
        let bytes = row * u64::from(height);
        if bytes > self.max_buffer {
            let side = ((self.max_buffer / 4) as f64).sqrt().floor() as u32 / 256 * 256;
            return Err(RenderError::TooLarge {
                width,
                height,
                megabytes: bytes as f64 / 1e6,
                max_megabytes: self.max_buffer as f64 / 1e6,
                side,
            });
        }
        Ok(())
    }

    /// The device's errors since the last call, if any (and then the lights' maps are drawn
    /// again: what they hold is not known).
    fn take_errors(&mut self) -> Result<(), RenderError> {
        let mut errors = self
            .errors
            .lock()
            .map_err(|_| RenderError::Gpu("error log poisoned".into()))?;
        if errors.is_empty() {
            Ok(())
        } else {
            let all = errors.join("; ");
            errors.clear();
            drop(errors);
            self.light_maps = None;
            Err(RenderError::Gpu(all))
        }
    }

    fn ensure_targets(&mut self, width: u32, height: u32, headless: bool) {
        let samples = self.quality.samples();
        let fits = self.targets.as_ref().is_some_and(|t| {
            t.size == (width, height) && t.samples == samples && (!headless || t.resolved.is_some())
        });
        if fits {
            return;
        }
        let extent = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let color = |samples, usage| {
            self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("frame colour"),
                size: extent,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format: self.format,
                usage,
                view_formats: &[],
            })
        };
        let msaa = (samples > 1).then(|| {
            color(samples, wgpu::TextureUsages::RENDER_ATTACHMENT).create_view(&Default::default())
        });
        let depth = depth_texture(&self.device, "frame depth", (width, height), samples, false);
        let resolved = headless.then(|| {
            let texture = color(
                1,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            );
            let view = texture.create_view(&Default::default());
            let row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
                * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
            let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: row as u64 * height as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            (texture, view, buffer, row)
        });
        self.targets = Some(Targets {
            size: (width, height),
            samples,
            msaa,
            depth,
            resolved,
        });
    }

    fn ensure_colormap(&mut self, colormap: Colormap) {
        if self.colormap == Some(colormap) {
            return;
        }
        self.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.colormap_texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &colormap.texels(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(256 * 4),
                rows_per_image: None,
            },
            wgpu::Extent3d {
                width: 256,
                height: 1,
                depth_or_array_layers: 1,
            },
        );
        self.colormap = Some(colormap);
    }

    /// The legend's texture and screen rectangle (top right corner) for a frame of this size.
    fn ensure_legend(&mut self, legend: &Legend, width: u32, height: u32) {
        let key = (legend.clone(), height, (width, height));
        if self.legend.as_ref().is_some_and(|l| l.key == key) {
            return;
        }
        let image = legend_image(legend, height);
        let (w, h) = (image.width().min(width), image.height().min(height));
        let texture = sampled_rgba_texture(&self.device, "legend", image.width(), image.height());
        self.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            image.as_raw(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(image.width() * 4),
                rows_per_image: None,
            },
            texture.size(),
        );
        let margin = (16.0 * height as f32 / 720.0).round();
        let (fw, fh) = (width as f32, height as f32);
        let right = fw - margin;
        let left = right - w as f32;
        let ndc = [
            2.0 * left / fw - 1.0,
            1.0 - 2.0 * margin / fh,
            2.0 * right / fw - 1.0,
            1.0 - 2.0 * (margin + h as f32) / fh,
        ];
        let rect = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("legend rect"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue
            .write_buffer(&rect, 0, bytemuck::cast_slice(&ndc));
        let view = texture.create_view(&Default::default());
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("legend"),
            layout: &self.pipelines.overlay_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: rect.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&self.pipelines.nearest_sampler),
                },
            ],
        });
        self.legend = Some(LegendOverlay { key, group });
    }

    /// Draws `scene` seen by `camera` into `target` (a single-sampled view of this renderer's
    /// format, `width`×`height`) and submits the work. The interactive window calls this with
    /// its surface texture.
    pub fn render(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        self.check_size(width, height)?;
        self.ensure_targets(width, height, false);
        let encoder = self.encode(scene, camera, target, width, height)?;
        self.queue.submit([encoder.finish()]);
        self.take_errors()
    }

    fn encode(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) -> Result<wgpu::CommandEncoder, RenderError> {
        let legend = scene.legend.clone();
        self.ensure_colormap(legend.as_ref().map_or(Colormap::Viridis, |l| l.colormap));
        if let Some(l) = &legend {
            self.ensure_legend(l, width, height);
        }
        let aspect = width as f32 / height as f32;
        let fg = frame_globals(
            camera,
            aspect,
            &scene.bounds(),
            scene.ground.as_ref(),
            legend.as_ref(),
            LightSampling::of(self.quality),
        );
        self.queue
            .write_buffer(&self.globals_buffer, 0, bytemuck::cast_slice(&fg.globals));
        self.queue.write_buffer(
            &self.key_light.0,
            0,
            bytemuck::cast_slice(&fg.light_view_proj.to_cols_array()),
        );
        self.queue.write_buffer(
            &self.under_light.0,
            0,
            bytemuck::cast_slice(&fg.under_view_proj.to_cols_array()),
        );
        let translucent = scene.sorted_translucent(&self.queue, camera.eye);

        let mut encoder = self.device.create_command_encoder(&Default::default());
        // The key light's shadow map (depth only), then the under-map (depth kept as colour).
        let under_color = [Some(wgpu::RenderPassColorAttachment {
            view: &self.under_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                store: wgpu::StoreOp::Store,
            },
        })];
        let light_passes: [(
            &wgpu::TextureView,
            &[Option<wgpu::RenderPassColorAttachment>],
            _,
            _,
        ); 2] = [
            (
                &self.shadow_view,
                &[],
                &self.pipelines.shadow,
                &self.key_light.1,
            ),
            (
                &self.under_depth,
                &under_color,
                &self.pipelines.under,
                &self.under_light.1,
            ),
        ];
        // The maps hold what the lights see of the casters: drawn again only when a caster's
        // geometry or a light's view changed (not while the camera alone moves: an orbit).
        let mut lights = [0.0; 32];
        lights[..16].copy_from_slice(&fg.light_view_proj.to_cols_array());
        lights[16..].copy_from_slice(&fg.under_view_proj.to_cols_array());
        let maps = (scene.caster_geometry(), lights);
        let light_passes = if self.light_maps.as_ref() == Some(&maps) {
            &light_passes[..0]
        } else {
            self.light_maps = Some(maps);
            &light_passes[..]
        };
        for &(depth, color, pipeline, light) in light_passes {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("light view"),
                color_attachments: color,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, light, &[]);
            for s in scene.casters() {
                s.draw_geometry(&mut pass);
            }
        }
        let targets = self.targets.as_ref().expect("targets were just made");
        let frame = match (&targets.msaa, &self.draft) {
            (Some(_), _) => &self.pipelines.frame,
            (None, Some(draft)) => draft,
            (None, None) => unreachable!("one-sample targets are made with the draft pipelines"),
        };
        // Multisampled: drawn into the samples, resolved into the target; one sample: drawn
        // into the target.
        let (view, resolve_target, store) = match &targets.msaa {
            Some(msaa) => (msaa, Some(target), wgpu::StoreOp::Discard),
            None => (target, None, wgpu::StoreOp::Store),
        };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_bind_group(0, &self.globals_group, &[]);
            pass.set_pipeline(&frame.background);
            pass.draw(0..3, 0..1);
            if scene.ground.is_some_and(|g| g.extent > 0.0) {
                pass.set_pipeline(&frame.ground);
                pass.draw(0..6, 0..1);
            }
            pass.set_pipeline(&frame.opaque);
            for s in scene.opaque() {
                s.draw(&mut pass);
            }
            pass.set_pipeline(&frame.lines);
            for l in &scene.lines {
                l.draw(&mut pass);
            }
            pass.set_pipeline(&frame.translucent);
            for i in translucent {
                scene.surfaces[i].draw(&mut pass);
            }
            if let (Some(_), Some(overlay)) = (&legend, &self.legend) {
                pass.set_pipeline(&frame.overlay);
                pass.set_bind_group(0, &overlay.group, &[]);
                pass.draw(0..6, 0..1);
            }
        }
        Ok(encoder)
    }

    /// Draws an uploaded scene into an image (headless).
    pub fn render_scene_to_rgba(
        &mut self,
        scene: &mut GpuScene,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<RgbaImage, RenderError> {
        self.check_size(width, height)?;
        self.ensure_targets(width, height, true);
        let (texture, view, buffer, row) = {
            let r = self
                .targets
                .as_ref()
                .and_then(|t| t.resolved.as_ref())
                .expect("made above");
            (r.0.clone(), r.1.clone(), r.2.clone(), r.3)
        };
        let mut encoder = self.encode(scene, camera, &view, width, height)?;
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(height),
                },
            },
            texture.size(),
        );
        self.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| RenderError::Readback(e.to_string()))?
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        self.take_errors()?;
        let mut pixels = Vec::with_capacity(width as usize * height as usize * 4);
        {
            let data = buffer
                .get_mapped_range(..)
                .map_err(|e| RenderError::Readback(e.to_string()))?;
            for y in 0..height as usize {
                let start = y * row as usize;
                pixels.extend_from_slice(&data[start..start + width as usize * 4]);
            }
        }
        buffer.unmap();
        RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| RenderError::Readback("short image".into()))
    }

    /// Uploads `list` and draws it into an image (headless, one-off).
    pub fn render_to_rgba(
        &mut self,
        list: &DrawList,
        camera: &Camera,
        width: u32,
        height: u32,
    ) -> Result<RgbaImage, RenderError> {
        let mut scene = self.upload(list)?;
        self.render_scene_to_rgba(&mut scene, camera, width, height)
    }

    /// Waits until the GPU has finished all submitted work (benchmarks).
    pub fn wait_idle(&self) -> Result<(), RenderError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| RenderError::Gpu(e.to_string()))
    }
}

/// An sRGB RGBA texture that shaders sample and the queue writes into.
fn sampled_rgba_texture(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}
