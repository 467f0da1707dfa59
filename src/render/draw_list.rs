//! What the renderer is asked to draw: plain buffers in world space (metres, z up), with no idea
//! of where they come from.

use super::colormap::Colormap;

/// A triangle surface, lit and smooth-shaded. The renderer recomputes its normals from the
/// positions it is given (area-weighted vertex normals), so deformed positions shade correctly.
#[derive(Clone, Debug, Default)]
pub struct Surface {
    /// Vertex positions, m.
    pub positions: Vec<[f32; 3]>,
    /// Triangles, three vertex indices each, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
    /// One value per vertex, coloured with the draw list's legend (colormap and range); `None`
    /// draws the surface in `color`.
    pub scalars: Option<Vec<f32>>,
    /// Linear RGBA colour; alpha below 1 draws the surface translucent (after the opaque ones,
    /// its triangles sorted back to front).
    pub color: [f32; 4],
}

/// A 3D arrow (a shaded cylinder and cone) from `origin` to `origin + vector`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrow {
    /// Tail, m.
    pub origin: [f32; 3],
    /// Tail to tip, already scaled to metres.
    pub vector: [f32; 3],
    /// Linear RGBA colour (see [`Colormap::force_ratio`] for colouring against a threshold).
    pub color: [f32; 4],
}

/// Line segments (a wireframe), drawn unlit on top of coincident surfaces.
#[derive(Clone, Debug, Default)]
pub struct LineSet {
    /// Vertex positions, m.
    pub positions: Vec<[f32; 3]>,
    /// Segments, two vertex indices each.
    pub indices: Vec<u32>,
    /// Linear RGBA colour.
    pub color: [f32; 4],
}

/// A horizontal ground plane (z = `height`), receiving shadows; it never hides anything drawn
/// below it (arrows of supports under a body stay visible).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Height of the plane, m.
    pub height: f32,
    /// Centre of the visible square, m (x, y).
    pub center: [f32; 2],
    /// Half side of the visible square, m.
    pub extent: f32,
}

/// The colour bar: how surface scalars map to colours, and its labels.
#[derive(Clone, Debug, PartialEq)]
pub struct Legend {
    /// Title, e.g. "von Mises stress".
    pub title: String,
    /// Unit symbol without prefix, e.g. "Pa", "m" (labels get an SI prefix).
    pub unit: String,
    /// Values mapped to the two ends of the colormap (guarded when equal or not finite).
    pub range: [f32; 2],
    /// The colormap.
    pub colormap: Colormap,
}

/// Everything to draw in one frame.
#[derive(Clone, Debug, Default)]
pub struct DrawList {
    /// Lit surfaces.
    pub surfaces: Vec<Surface>,
    /// Arrows.
    pub arrows: Vec<Arrow>,
    /// Wireframes.
    pub lines: Vec<LineSet>,
    /// Ground plane.
    pub ground: Option<Ground>,
    /// Colour bar for the surfaces' scalars; without it scalars fall back to a 0–1 range.
    pub legend: Option<Legend>,
}

impl DrawList {
    /// Axis-aligned bounds of everything drawn (surfaces, arrows, lines; not the ground), or
    /// `None` when empty.
    pub fn bounds(&self) -> Option<super::Bounds> {
        let mut b = super::Bounds::empty();
        for s in &self.surfaces {
            s.positions.iter().for_each(|p| b.include((*p).into()));
        }
        for l in &self.lines {
            l.positions.iter().for_each(|p| b.include((*p).into()));
        }
        for a in &self.arrows {
            let o = glam::Vec3::from(a.origin);
            b.include(o);
            b.include(o + glam::Vec3::from(a.vector));
        }
        b.is_valid().then_some(b)
    }
}
