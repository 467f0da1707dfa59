//! A draw list uploaded to the GPU. Surfaces stay on the GPU between frames: a deformed surface
//! updates only its positions and normals (one `write_buffer`), never the pipelines.

use super::draw_list::{Arrow, DrawList, Ground, Legend, LineSet, Surface};
use super::error::RenderError;
use super::geometry::{
    arrow_mesh, sort_back_to_front, split_creases, vertex_normals_into, CREASE_DEGREES,
};
use super::pipelines::Pipelines;
use super::Bounds;
use glam::Vec3;
use wgpu::util::DeviceExt;

/// The device, queue and pipelines a scene is uploaded with.
pub struct Gpu<'a> {
    /// Device.
    pub device: &'a wgpu::Device,
    /// Queue.
    pub queue: &'a wgpu::Queue,
    /// Pipelines (for the bind group layouts).
    pub pipelines: &'a Pipelines,
}

/// Per-object uniform: colour and flags (x: colour from scalars).
fn object_bytes(color: [f32; 4], scalars: bool) -> Vec<u8> {
    let flags = [if scalars { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0];
    bytemuck::cast_slice(&[color, flags]).to_vec()
}

fn check_indices(
    indices: &[u32],
    group: usize,
    vertices: usize,
    what: &str,
) -> Result<(), RenderError> {
    if !indices.len().is_multiple_of(group) {
        return Err(RenderError::InvalidInput(format!(
            "{what} has {} indices, not a multiple of {group}",
            indices.len()
        )));
    }
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= vertices) {
        return Err(RenderError::InvalidInput(format!(
            "{what} index {bad} is out of range ({vertices} vertices)"
        )));
    }
    Ok(())
}

/// A lit surface on the GPU, with the CPU copy of its geometry that normals and sorting need.
pub struct GpuSurface {
    vertices: wgpu::Buffer,
    scalars: wgpu::Buffer,
    indices: wgpu::Buffer,
    object: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// Input vertex of each drawn vertex (vertices are split along creases); `None`: the same.
    source: Option<Vec<u32>>,
    input_count: usize,
    /// Drawn vertices and triangles.
    positions: Vec<[f32; 3]>,
    triangles: Vec<u32>,
    normals: Vec<[f32; 3]>,
    interleaved: Vec<[f32; 6]>,
    color: [f32; 4],
    has_scalars: bool,
    /// Stamp of the geometry in its vertex buffer: unique among every surface's every upload
    /// (`light_maps`: the lights' maps are drawn again only when a caster's stamp changes).
    geometry: u64,
}

/// The next geometry stamp.
fn next_geometry() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl GpuSurface {
    /// Uploads `surface`; `normals` replaces the computed ones (arrows bring their own).
    fn new(
        gpu: &Gpu,
        surface: &Surface,
        normals: Option<Vec<[f32; 3]>>,
    ) -> Result<Self, RenderError> {
        let n = surface.positions.len();
        check_indices(&surface.indices, 3, n, "a surface")?;
        if let Some(s) = &surface.scalars {
            if s.len() != n {
                return Err(RenderError::InvalidInput(format!(
                    "a surface has {} scalars for {n} vertices",
                    s.len()
                )));
            }
        }
        let (source, positions, triangles) = if normals.is_some() {
            (None, surface.positions.clone(), surface.indices.clone())
        } else {
            let split = split_creases(&surface.positions, &surface.indices, CREASE_DEGREES);
            let drawn = split
                .source
                .iter()
                .map(|&v| surface.positions[v as usize])
                .collect();
            (Some(split.source), drawn, split.indices)
        };
        let n = positions.len();
        let usage = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST;
        // Buffers are never empty: wgpu rejects zero-sized bindings.
        let vertices = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("surface vertices"),
            size: (n.max(1) as u64) * super::pipelines::SURFACE_STRIDE,
            usage,
            mapped_at_creation: false,
        });
        let scalars = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("surface scalars"),
            size: (n.max(1) * 4) as u64,
            usage,
            mapped_at_creation: false,
        });
        let mut index_data = triangles.clone();
        if index_data.is_empty() {
            index_data.extend([0, 0, 0]);
        }
        let indices = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("surface indices"),
                contents: bytemuck::cast_slice(&index_data),
                usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
            });
        let has_scalars = surface.scalars.is_some();
        let (object, bind_group) = gpu.pipelines.uniform(
            gpu.device,
            &gpu.pipelines.object_layout,
            &object_bytes(surface.color, has_scalars),
        );
        let mut s = Self {
            vertices,
            scalars,
            indices,
            object,
            bind_group,
            source,
            input_count: surface.positions.len(),
            positions,
            triangles,
            normals: Vec::new(),
            interleaved: Vec::new(),
            color: surface.color,
            has_scalars,
            geometry: next_geometry(),
        };
        match normals {
            Some(given) => {
                s.normals = given;
                s.upload_vertices(gpu.queue);
            }
            None => s.refresh_normals(gpu.queue),
        }
        let zeros = vec![0.0; s.input_count];
        s.write_scalars(gpu.queue, surface.scalars.as_deref().unwrap_or(&zeros));
        Ok(s)
    }

    fn refresh_normals(&mut self, queue: &wgpu::Queue) {
        vertex_normals_into(&self.positions, &self.triangles, &mut self.normals);
        self.upload_vertices(queue);
    }

    fn upload_vertices(&mut self, queue: &wgpu::Queue) {
        self.geometry = next_geometry();
        self.interleaved.clear();
        self.interleaved.extend(
            self.positions
                .iter()
                .zip(&self.normals)
                .map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]]),
        );
        if !self.interleaved.is_empty() {
            queue.write_buffer(&self.vertices, 0, bytemuck::cast_slice(&self.interleaved));
        }
    }

    /// Writes per-input-vertex values, copied to the drawn vertices (non-finite ones as 0).
    fn write_scalars(&self, queue: &wgpu::Queue, values: &[f32]) {
        let clean = |v: f32| if v.is_finite() { v } else { 0.0 };
        let drawn: Vec<f32> = match &self.source {
            Some(src) => src.iter().map(|&i| clean(values[i as usize])).collect(),
            None => values.iter().map(|&v| clean(v)).collect(),
        };
        if !drawn.is_empty() {
            queue.write_buffer(&self.scalars, 0, bytemuck::cast_slice(&drawn));
        }
    }

    /// Number of vertices as given.
    pub fn vertex_count(&self) -> usize {
        self.input_count
    }

    /// Number of vertices drawn (more than given where creases split them).
    pub fn drawn_vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len() / 3
    }

    /// Whether it is drawn translucent (colour alpha below 1).
    pub fn is_translucent(&self) -> bool {
        self.color[3] < 1.0
    }

    /// New positions for the same vertices (a deformed frame): normals are recomputed and both
    /// are written to the existing vertex buffer.
    pub fn update_positions(
        &mut self,
        queue: &wgpu::Queue,
        positions: &[[f32; 3]],
    ) -> Result<(), RenderError> {
        if positions.len() != self.input_count {
            return Err(RenderError::InvalidInput(format!(
                "{} positions for a surface of {} vertices",
                positions.len(),
                self.input_count
            )));
        }
        match &self.source {
            Some(src) => {
                for (p, &i) in self.positions.iter_mut().zip(src) {
                    *p = positions[i as usize];
                }
            }
            None => self.positions.copy_from_slice(positions),
        }
        self.refresh_normals(queue);
        Ok(())
    }

    /// New per-vertex scalars (the surface must have been uploaded with scalars).
    pub fn update_scalars(
        &mut self,
        queue: &wgpu::Queue,
        scalars: &[f32],
    ) -> Result<(), RenderError> {
        if !self.has_scalars || scalars.len() != self.input_count {
            return Err(RenderError::InvalidInput(format!(
                "{} scalars for a surface of {} vertices (uploaded with scalars: {})",
                scalars.len(),
                self.input_count,
                self.has_scalars
            )));
        }
        self.write_scalars(queue, scalars);
        Ok(())
    }

    /// New colour (alpha below 1: translucent).
    pub fn set_color(&mut self, queue: &wgpu::Queue, color: [f32; 4]) {
        self.color = color;
        queue.write_buffer(&self.object, 0, &object_bytes(color, self.has_scalars));
    }

    /// Distance from `eye` to the centre of its bounds (orders translucent surfaces).
    fn distance_from(&self, eye: Vec3) -> f32 {
        let b = Bounds::of(self.positions.iter().map(|p| Vec3::from(*p)));
        if b.is_valid() {
            (b.center() - eye).length()
        } else {
            0.0
        }
    }

    /// Sorts its triangles back to front as seen from `eye` and uploads the indices.
    fn sort_for(&mut self, queue: &wgpu::Queue, eye: Vec3) {
        if self.triangles.is_empty() {
            return;
        }
        sort_back_to_front(&self.positions, &mut self.triangles, eye);
        queue.write_buffer(&self.indices, 0, bytemuck::cast_slice(&self.triangles));
    }

    /// Records its draw (pipeline and globals already set).
    pub(super) fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.triangles.is_empty() {
            return;
        }
        pass.set_bind_group(1, &self.bind_group, &[]);
        self.draw_geometry(pass);
    }

    /// Records its geometry only (shadow passes).
    pub(super) fn draw_geometry(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.triangles.is_empty() {
            return;
        }
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_vertex_buffer(1, self.scalars.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.triangles.len() as u32, 0, 0..1);
    }
}

/// A wireframe on the GPU.
pub struct GpuLines {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
    bind_group: wgpu::BindGroup,
    _object: wgpu::Buffer,
    positions: Vec<[f32; 3]>,
}

impl GpuLines {
    fn new(gpu: &Gpu, lines: &LineSet) -> Result<Self, RenderError> {
        check_indices(&lines.indices, 2, lines.positions.len(), "a line set")?;
        let mut pos = lines.positions.clone();
        if pos.is_empty() {
            pos.push([0.0; 3]);
        }
        let mut idx = lines.indices.clone();
        if idx.is_empty() {
            idx.extend([0, 0]);
        }
        let vertices = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("line vertices"),
                contents: bytemuck::cast_slice(&pos),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            });
        let indices = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("line indices"),
                contents: bytemuck::cast_slice(&idx),
                usage: wgpu::BufferUsages::INDEX,
            });
        let (object, bind_group) = gpu.pipelines.uniform(
            gpu.device,
            &gpu.pipelines.object_layout,
            &object_bytes(lines.color, false),
        );
        Ok(Self {
            vertices,
            indices,
            count: lines.indices.len() as u32,
            bind_group,
            _object: object,
            positions: lines.positions.clone(),
        })
    }

    /// New positions for the same vertices.
    pub fn update_positions(
        &mut self,
        queue: &wgpu::Queue,
        positions: &[[f32; 3]],
    ) -> Result<(), RenderError> {
        if positions.len() != self.positions.len() {
            return Err(RenderError::InvalidInput(format!(
                "{} positions for a line set of {} vertices",
                positions.len(),
                self.positions.len()
            )));
        }
        self.positions.copy_from_slice(positions);
        if !positions.is_empty() {
            queue.write_buffer(&self.vertices, 0, bytemuck::cast_slice(positions));
        }
        Ok(())
    }

    pub(super) fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.count == 0 {
            return;
        }
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.count, 0, 0..1);
    }
}

/// A draw list on the GPU: upload once with `Renderer::upload`, then update what changes.
pub struct GpuScene {
    /// Lit surfaces, in draw-list order.
    pub surfaces: Vec<GpuSurface>,
    /// Wireframes, in draw-list order.
    pub lines: Vec<GpuLines>,
    pub(super) arrows: Vec<GpuSurface>,
    /// Ground plane.
    pub ground: Option<Ground>,
    /// Colour bar (also sets the scalar range of every surface).
    pub legend: Option<Legend>,
}

fn arrow_surfaces(gpu: &Gpu, arrows: &[Arrow]) -> Result<Vec<GpuSurface>, RenderError> {
    arrows
        .iter()
        .map(|a| {
            let (positions, normals, indices) = arrow_mesh(a.origin.into(), a.vector.into(), None);
            let s = Surface {
                positions,
                indices,
                scalars: None,
                color: a.color,
            };
            GpuSurface::new(gpu, &s, Some(normals))
        })
        .collect()
}

impl GpuScene {
    /// Uploads a draw list.
    pub fn new(gpu: &Gpu, list: &DrawList) -> Result<Self, RenderError> {
        Ok(Self {
            surfaces: list
                .surfaces
                .iter()
                .map(|s| GpuSurface::new(gpu, s, None))
                .collect::<Result<_, _>>()?,
            lines: list
                .lines
                .iter()
                .map(|l| GpuLines::new(gpu, l))
                .collect::<Result<_, _>>()?,
            arrows: arrow_surfaces(gpu, &list.arrows)?,
            ground: list.ground,
            legend: list.legend.clone(),
        })
    }

    /// Replaces the arrows (they are small: rebuilt every time).
    pub fn set_arrows(&mut self, gpu: &Gpu, arrows: &[Arrow]) -> Result<(), RenderError> {
        self.arrows = arrow_surfaces(gpu, arrows)?;
        Ok(())
    }

    /// Bounds of everything drawn except the ground.
    pub fn bounds(&self) -> Bounds {
        let mut b = Bounds::empty();
        for s in self.surfaces.iter().chain(&self.arrows) {
            s.positions.iter().for_each(|p| b.include(Vec3::from(*p)));
        }
        for l in &self.lines {
            l.positions.iter().for_each(|p| b.include(Vec3::from(*p)));
        }
        b
    }

    /// Opaque surfaces and arrows, for the shadow passes and the opaque pass.
    pub(super) fn opaque(&self) -> impl Iterator<Item = &GpuSurface> {
        self.surfaces
            .iter()
            .filter(|s| !s.is_translucent())
            .chain(self.arrows.iter())
    }

    /// The geometry stamps of the surfaces that cast shadows, in order: the same stamps, the
    /// same shadows.
    pub(super) fn caster_geometry(&self) -> Vec<u64> {
        self.casters().map(|s| s.geometry).collect()
    }

    /// Every surface that casts a shadow (translucent ones too).
    pub(super) fn casters(&self) -> impl Iterator<Item = &GpuSurface> {
        self.surfaces.iter().chain(self.arrows.iter())
    }

    /// Translucent surfaces, farthest first, each with its triangles sorted back to front.
    pub(super) fn sorted_translucent(&mut self, queue: &wgpu::Queue, eye: Vec3) -> Vec<usize> {
        let mut order: Vec<(f32, usize)> = self
            .surfaces
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_translucent())
            .map(|(i, s)| (s.distance_from(eye), i))
            .collect();
        order.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(_, i) in &order {
            self.surfaces[i].sort_for(queue, eye);
        }
        order.into_iter().map(|(_, i)| i).collect()
    }
}
