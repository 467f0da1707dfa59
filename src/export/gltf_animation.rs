//! The solved frames as one animated glTF 2.0 binary (`animation.glb`) for Blender, Maya and
//! other DCC tools: every hand's display skin and each of its bones, and the boundary surface of
//! every other body (the ball, the bowl), deformed, animated over the frames' times.
//!
//! Each surface is one mesh whose base is its first frame and whose morph targets are the other
//! frames (each the displacement from the first); one animation drives the morph weights, frame
//! k at its time with weight 1 on target k (LINEAR between frames: the positions interpolate
//! linearly between solved frames). Morph targets were chosen over a node per frame: one mesh
//! per surface, which Blender imports as an object with animated shape keys, playing smoothly
//! between frames (a node per frame would pop from one copy to the next). The data stay in the
//! scene's Z-up metres; the root node turns them to glTF's Y-up (−90° about x), as Blender's
//! importer expects. The bodies other than hands carry the contact pressure as the vertex
//! colour COLOR_0 (the largest over the frames, blue 0 → red at its peak) when they touch.

use super::glb::GlbBuilder;
use crate::model::Model;
use crate::state::Frame;
use gltf_json as json;
use json::validation::Checked::Valid;
use nalgebra::Vector3;
use std::collections::{BTreeMap, HashMap};

/// One surface animated over the frames.
#[derive(Clone, Debug)]
pub struct AnimatedSurface {
    /// The object's name.
    pub name: String,
    /// Triangles (vertex indices).
    pub triangles: Vec<[u32; 3]>,
    /// The vertex positions of each frame, m (scene axes).
    pub frames: Vec<Vec<Vector3<f64>>>,
    /// A colour per vertex (RGB, 0–1), if any.
    pub colors: Option<Vec<[f32; 3]>>,
}

/// The surfaces of the solved `frames` of `model`: each hand's display skin and bones, and each
/// other body's boundary (its facets split into triangles).
pub fn animated_surfaces(model: &Model, frames: &[&Frame]) -> Vec<AnimatedSurface> {
    let mut out = Vec::new();
    let Some(first) = frames.first() else {
        return out;
    };
    for h in &first.hands {
        let body = &model.bodies[h.body];
        let Some(hand) = body.hand.as_deref() else {
            continue;
        };
        out.push(AnimatedSurface {
            name: format!("{}_skin", body.name),
            triangles: hand
                .skin
                .quads
                .iter()
                .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
                .collect(),
            frames: frames
                .iter()
                .map(|f| hand.skin.positions(&hand_in(f, h).positions))
                .collect(),
            colors: None,
        });
        let posed: Vec<Vec<(usize, crate::hand::TriangleSurface)>> = frames
            .iter()
            .map(|f| hand.posed_bones(&hand_in(f, h).angles))
            .collect();
        for (k, (b, (_, triangles))) in posed[0].iter().enumerate() {
            out.push(AnimatedSurface {
                name: format!("{}_{}", body.name, hand.skeleton.bones[*b].name),
                triangles: triangles.clone(),
                frames: posed.iter().map(|p| p[k].1 .0.clone()).collect(),
                colors: None,
            });
        }
    }
    let pressures: Vec<Option<Vec<f64>>> = frames
        .iter()
        .map(|f| crate::state::contact_pressure(model, f))
        .collect();
    for body in model.bodies.iter().filter(|b| b.hand.is_none()) {
        // The body's boundary nodes, numbered in order of appearance.
        let mut local: HashMap<usize, u32> = HashMap::new();
        let mut nodes = Vec::new();
        let mut index = |n: usize| {
            *local.entry(n).or_insert_with(|| {
                nodes.push(n);
                (nodes.len() - 1) as u32
            })
        };
        let triangles: Vec<[u32; 3]> = body
            .facets
            .iter()
            .flat_map(|f| {
                let q = f.nodes.map(&mut index);
                [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
            })
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let position = |f: &Frame, n: usize| {
            let u = &f.solution.displacement;
            model.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2])
        };
        let peak: Vec<f64> = nodes
            .iter()
            .map(|&n| pressures.iter().flatten().map(|p| p[n]).fold(0.0, f64::max))
            .collect();
        let top = peak.iter().copied().fold(0.0, f64::max);
        out.push(AnimatedSurface {
            name: body.name.clone(),
            triangles,
            frames: frames
                .iter()
                .map(|f| nodes.iter().map(|&n| position(f, n)).collect())
                .collect(),
            colors: (top > 0.0).then(|| {
                peak.iter()
                    .map(|p| {
                        let t = (p / top) as f32;
                        [t, 0.2 * (1.0 - t), 1.0 - t]
                    })
                    .collect()
            }),
        });
    }
    out
}

/// The hand `h` (of the first frame) in frame `f`: `h` itself where `f` lacks it.
fn hand_in<'a>(f: &'a Frame, h: &'a crate::state::HandFrame) -> &'a crate::state::HandFrame {
    f.hands.iter().find(|x| x.body == h.body).unwrap_or(h)
}

/// Why the animation cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    /// A value that is not finite, or a frame count that does not match.
    #[error("surface \"{surface}\": {reason}")]
    Surface {
        /// The surface.
        surface: String,
        /// What is wrong.
        reason: String,
    },
    /// Frame times glTF's 32-bit floats cannot hold as an increasing sequence.
    #[error(
        "frame times {0} s and {1} s are one and the same time in glTF's 32-bit floats (the \
         animation's times must increase): keep the keyframe times below 1e6 s or further apart"
    )]
    Times(f64, f64),
    /// The file would exceed glTF's 4 GiB.
    #[error("the animation would take {0} bytes, beyond glTF's 4 GiB limit")]
    TooLarge(usize),
}

/// The `.glb` bytes of `surfaces` animated at `times` (s, one per frame, increasing).
pub fn animation_glb(surfaces: &[AnimatedSurface], times: &[f64]) -> Result<Vec<u8>, GltfError> {
    let mut b = GlbBuilder::new();
    let targets = times.len().saturating_sub(1);
    for (t0, t1) in times.iter().zip(times.iter().skip(1)) {
        let (a, b) = (*t0 as f32, *t1 as f32);
        if !(a.is_finite() && b.is_finite() && b > a) {
            return Err(GltfError::Times(*t0, *t1));
        }
    }
    let mut nodes = Vec::new();
    // A surface without a triangle has no mesh glTF allows (an accessor of no element).
    for s in surfaces.iter().filter(|s| !s.triangles.is_empty()) {
        let bad = |reason: String| GltfError::Surface {
            surface: s.name.clone(),
            reason,
        };
        if s.frames.len() != times.len() {
            return Err(bad(format!(
                "{} frames for {} times",
                s.frames.len(),
                times.len()
            )));
        }
        let base = &s.frames[0];
        // Every position, and its move from the first frame, within glTF's 32-bit floats.
        let in_f32 = |x: f64| (x as f32).is_finite();
        if let Some(p) = s
            .frames
            .iter()
            .flat_map(|f| f.iter().zip(base))
            .find(|(p, q)| !p.iter().chain((*p - *q).iter()).all(|&x| in_f32(x)))
        {
            return Err(bad(format!(
                "a position ({:e}, {:e}, {:e}) m beyond what glTF's 32-bit floats hold \
                 (±3.4e38): the result is not physical",
                p.0.x, p.0.y, p.0.z
            )));
        }
        let flat = |p: &[Vector3<f64>]| -> Vec<f32> {
            p.iter()
                .flat_map(|v| [v.x as f32, v.y as f32, v.z as f32])
                .collect()
        };
        let positions = b.floats(
            &flat(base),
            json::accessor::Type::Vec3,
            true,
            Some(json::buffer::Target::ArrayBuffer),
        );
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), positions);
        if let Some(colors) = &s.colors {
            let c: Vec<f32> = colors.iter().flatten().copied().collect();
            let accessor = b.floats(
                &c,
                json::accessor::Type::Vec3,
                false,
                Some(json::buffer::Target::ArrayBuffer),
            );
            attributes.insert(Valid(json::mesh::Semantic::Colors(0)), accessor);
        }
        let indices = b.triangles(&s.triangles);
        let morphs: Vec<json::mesh::MorphTarget> = s.frames[1..]
            .iter()
            .map(|frame| {
                let delta: Vec<f32> = frame
                    .iter()
                    .zip(base)
                    .flat_map(|(p, q)| {
                        let d = p - q;
                        [d.x as f32, d.y as f32, d.z as f32]
                    })
                    .collect();
                json::mesh::MorphTarget {
                    positions: Some(b.floats(
                        &delta,
                        json::accessor::Type::Vec3,
                        true,
                        Some(json::buffer::Target::ArrayBuffer),
                    )),
                    normals: None,
                    tangents: None,
                }
            })
            .collect();
        let mesh = b.root.push(json::Mesh {
            extensions: Default::default(),
            extras: Default::default(),
            name: Some(s.name.clone()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: Default::default(),
                extras: Default::default(),
                indices: Some(indices),
                material: None,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: (!morphs.is_empty()).then_some(morphs),
            }],
            weights: (targets > 0).then(|| vec![0.0; targets]),
        });
        nodes.push(b.root.push(json::Node {
            mesh: Some(mesh),
            name: Some(s.name.clone()),
            ..Default::default()
        }));
    }
    if targets > 0 && !nodes.is_empty() {
        // Frame k (k ≥ 1) at its time: weight 1 on target k; frame 0: all zero.
        let input: Vec<f32> = times.iter().map(|&t| t as f32).collect();
        let input = b.floats(&input, json::accessor::Type::Scalar, true, None);
        let mut weights = vec![0.0f32; times.len() * targets];
        for k in 1..times.len() {
            weights[k * targets + (k - 1)] = 1.0;
        }
        let output = b.floats(&weights, json::accessor::Type::Scalar, false, None);
        let sampler = json::animation::Sampler {
            extensions: Default::default(),
            extras: Default::default(),
            input,
            interpolation: Valid(json::animation::Interpolation::Linear),
            output,
        };
        let channels = nodes
            .iter()
            .map(|&node| json::animation::Channel {
                sampler: json::Index::new(0),
                target: json::animation::Target {
                    extensions: Default::default(),
                    extras: Default::default(),
                    node,
                    path: Valid(json::animation::Property::MorphTargetWeights),
                },
                extensions: Default::default(),
                extras: Default::default(),
            })
            .collect();
        b.root.push(json::Animation {
            extensions: Default::default(),
            extras: Default::default(),
            channels,
            name: Some("grasp".into()),
            samplers: vec![sampler],
        });
    }
    // Z-up scene axes to glTF's Y-up: −90° about x.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let root_node = b.root.push(json::Node {
        children: Some(nodes),
        name: Some("prehensile (Z-up)".into()),
        rotation: Some(json::scene::UnitQuaternion([-h, 0.0, 0.0, h])),
        ..Default::default()
    });
    let scene = b.root.push(json::Scene {
        extensions: Default::default(),
        extras: Default::default(),
        name: None,
        nodes: vec![root_node],
    });
    b.root.scene = Some(scene);
    b.finish().map_err(GltfError::TooLarge)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One triangle moved by `shift` (m) in its second frame.
    fn triangle(shift: f64) -> AnimatedSurface {
        let rest = vec![Vector3::zeros(), Vector3::x(), Vector3::y()];
        let moved = rest.iter().map(|p| p + Vector3::z() * shift).collect();
        AnimatedSurface {
            name: "t".into(),
            triangles: vec![[0, 1, 2]],
            frames: vec![rest, moved],
            colors: None,
        }
    }

    /// A move that fits in a double but not in glTF's 32-bit floats is refused (it would be
    /// written as infinity, min and max null); one that fits is written.
    #[test]
    fn positions_beyond_32_bit_floats_are_refused() {
        assert!(animation_glb(&[triangle(1.0)], &[0.0, 1.0]).is_ok());
        let err = animation_glb(&[triangle(4.8e40)], &[0.0, 1.0]).unwrap_err();
        assert!(err.to_string().contains("32-bit floats"), "{err}");
        assert!(err.to_string().contains("surface \"t\""), "{err}");
    }

    /// Times that are distinct doubles but one float (1e8 and 1e8 + 1), or beyond a float, are
    /// refused: glTF's sampler times must increase.
    #[test]
    fn times_that_collapse_in_32_bit_floats_are_refused() {
        assert!(animation_glb(&[triangle(1.0)], &[1e5, 1e5 + 1.0]).is_ok());
        for times in [[1e8, 1e8 + 1.0], [0.0, 1e308]] {
            let err = animation_glb(&[triangle(1.0)], &times).unwrap_err();
            assert!(matches!(err, GltfError::Times(..)), "{err}");
        }
    }

    /// A surface without a triangle is left out rather than written as an empty mesh.
    #[test]
    fn a_surface_without_triangles_is_left_out() {
        let mut empty = triangle(1.0);
        empty.triangles.clear();
        let with = animation_glb(&[triangle(1.0), empty], &[0.0, 1.0]).unwrap();
        let without = animation_glb(&[triangle(1.0)], &[0.0, 1.0]).unwrap();
        assert_eq!(with.len(), without.len());
    }
}
