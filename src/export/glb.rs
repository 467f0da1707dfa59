//! A glTF 2.0 binary (`.glb`) being built: the JSON document and its one binary buffer, with the
//! accessors the exports need (f32 vectors with their bounds, integer vectors, triangle indices)
//! and the final GLB container. Shared by the animation (`animation.glb`) and the rigged hand.

use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use std::borrow::Cow;

/// The binary buffer and the JSON being built.
pub struct GlbBuilder {
    /// The glTF document; push nodes, meshes, skins, scenes into it.
    pub root: json::Root,
    bin: Vec<u8>,
}

impl Default for GlbBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl GlbBuilder {
    /// An empty document whose generator is this program.
    pub fn new() -> Self {
        let mut root = json::Root::default();
        root.asset.generator = Some(format!("prehensile {}", env!("CARGO_PKG_VERSION")));
        Self {
            root,
            bin: Vec::new(),
        }
    }

    /// A buffer view of `bytes` (padded to 4 bytes), for vertex data or indices.
    pub fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            target: target.map(Valid),
        })
    }

    /// An accessor of f32 values of `type_` (with min and max when asked).
    pub fn floats(
        &mut self,
        values: &[f32],
        type_: json::accessor::Type,
        bounds: bool,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::Accessor> {
        let width = type_.multiplicity();
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let (min, max) = if bounds {
            let mut min = vec![f32::INFINITY; width];
            let mut max = vec![f32::NEG_INFINITY; width];
            for chunk in values.chunks(width) {
                for i in 0..width {
                    min[i] = min[i].min(chunk[i]);
                    max[i] = max[i].max(chunk[i]);
                }
            }
            (Some(json::Value::from(min)), Some(json::Value::from(max)))
        } else {
            (None, None)
        };
        self.accessor(
            view,
            values.len() / width,
            json::accessor::ComponentType::F32,
            type_,
            (min, max),
        )
    }

    /// An accessor of `count` integer elements of `type_`, each component a `component`
    /// (U8, U16 or U32), given as their little-endian `bytes`.
    pub fn integers(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(bytes, target);
        self.accessor(view, count, component, type_, (None, None))
    }

    /// The index accessor of `triangles` (u32).
    pub fn triangles(&mut self, triangles: &[[u32; 3]]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        self.integers(
            &bytes,
            3 * triangles.len(),
            json::accessor::ComponentType::U32,
            json::accessor::Type::Scalar,
            Some(json::buffer::Target::ElementArrayBuffer),
        )
    }

    fn accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        (min, max): (Option<json::Value>, Option<json::Value>),
    ) -> json::Index<json::Accessor> {
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: Default::default(),
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// The `.glb` bytes: the document with its buffer, or `Err(length)` when the file would
    /// exceed glTF's 4 GiB.
    pub fn finish(mut self) -> Result<Vec<u8>, usize> {
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            extensions: Default::default(),
            extras: Default::default(),
            name: None,
            uri: None,
        });
        let text = json::serialize::to_string(&self.root).expect("the glTF JSON serialises");
        let mut json_bytes = text.into_bytes();
        while !json_bytes.len().is_multiple_of(4) {
            json_bytes.push(b' ');
        }
        let length = 12 + 8 + json_bytes.len() + 8 + self.bin.len();
        let length32 = u32::try_from(length).map_err(|_| length)?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: length32,
            },
            json: Cow::Owned(json_bytes),
            bin: Some(Cow::Owned(self.bin)),
        };
        glb.to_vec().map_err(|_| length)
    }
}
