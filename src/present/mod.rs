//! State → draw lists: what to draw of a frame, colours, overlays, arrows, the tactile map.
//! May import model, state, render, the kernels and util; never solve or a front-end.
//!
//! From a solved frame to a [`DrawList`]: the bridge between the solver's data (f64, nodes,
//! facets, reactions) and the renderer's buffers (f32 triangles, scalars, arrows). The renderer
//! stays generic; everything that knows about bodies and overlays lives here.
//!
//! - Each body is drawn as its boundary facets, deformed by `displacement × displacement_scale`;
//!   a quadrilateral facet becomes two triangles, a collapsed one (a repeated node) one.
//! - Overlays colour the bodies per vertex (nodal von Mises stress, displacement magnitude) or
//!   add arrows (the reaction of each constraint, at the centroid of its nodes).
//! - A hand is drawn as its smooth display skin (embedded in the flesh mesh, moved by its
//!   displacement field; overlays interpolated onto it) and its posed bones; the skin may be
//!   translucent so that the bones show through (the paper's Figure 2). The forces overlay adds,
//!   per bone, the load the flesh puts on it (−R_u of equation (8)), from the bone's centre.
//! - The ground plane lies under the lowest point of the deformed bodies, always: the scenes of
//!   today have no table body (the table is a constraint), so the plane shows where "down" is
//!   and receives the shadows. Arrows of supports below a body are drawn over it.

use crate::fem::stress::von_mises;
use crate::model::Model;
use crate::render::{
    finite_range, guard_range, Arrow, Bounds, Colormap, DrawList, Ground, Legend, LineSet, Surface,
};
use crate::state::Frame;
use glam::Vec3;
use nalgebra::Vector3;
use std::collections::{BTreeSet, HashMap};
use thiserror::Error;

/// What colours the bodies or is added to them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Overlay {
    /// Plain bodies.
    #[default]
    None,
    /// Nodal von Mises stress.
    Stress,
    /// Displacement magnitude.
    Displacement,
    /// Reaction force of every constraint, as arrows.
    Forces,
    /// Contact pressure (the tactile map; zero on a frame out of contact).
    Pressure,
}

/// How to turn a frame into a draw list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisualOptions {
    /// The overlay.
    pub overlay: Overlay,
    /// Displacements are multiplied by this for display (1 = true scale).
    pub displacement_scale: f64,
    /// Draw the edges of the simulation mesh's boundary facets.
    pub wireframe: bool,
    /// Opacity of hand skin (1 opaque; below 1 the bones show through).
    pub skin_opacity: f32,
    /// Draw the bones of hands.
    pub bones: bool,
}

impl Default for VisualOptions {
    fn default() -> Self {
        Self {
            overlay: Overlay::None,
            displacement_scale: 1.0,
            wireframe: false,
            skin_opacity: 1.0,
            bones: true,
        }
    }
}

/// Why a frame cannot be drawn as asked.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum VisualError {
    /// The pressure overlay needs contact.
    #[error("no contact in this scene: the pressure overlay needs contact pairs or the skin pressed on itself with `[solver] self_contact` (use stress, displacement or forces)")]
    NoContact,
    /// The frame does not belong to the model.
    #[error("the frame has {got} displacement values, the model needs {expected}")]
    Mismatch {
        /// Values in the frame.
        got: usize,
        /// 3 × nodes of the model.
        expected: usize,
    },
}

/// Colour of a body without overlay (linear RGB): soft rubber red, then other hues.
pub fn body_color(body: usize) -> [f32; 4] {
    const COLORS: [[f32; 4]; 4] = [
        [0.62, 0.16, 0.10, 1.0],
        [0.16, 0.32, 0.60, 1.0],
        [0.55, 0.50, 0.20, 1.0],
        [0.30, 0.50, 0.30, 1.0],
    ];
    COLORS[body % COLORS.len()]
}

/// Deformed position of node `n`.
fn deformed(model: &Model, frame: &Frame, n: usize, scale: f64) -> Vector3<f64> {
    model.mesh.nodes[n] + frame.solution.node_displacement(n) * scale
}

fn to_f32(v: &Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The boundary of body `b` as a triangle surface: (surface, global node of each vertex).
pub fn body_surface(model: &Model, frame: &Frame, b: usize, scale: f64) -> (Surface, Vec<usize>) {
    let mut local: HashMap<usize, u32> = HashMap::new();
    let mut nodes = Vec::new();
    let mut indices = Vec::new();
    let mut vertex = |n: usize, nodes: &mut Vec<usize>| {
        *local.entry(n).or_insert_with(|| {
            nodes.push(n);
            (nodes.len() - 1) as u32
        })
    };
    for f in &model.bodies[b].facets {
        // Distinct nodes in order: a collapsed quad repeats one.
        let mut ring: Vec<usize> = Vec::with_capacity(4);
        for &n in &f.nodes {
            if ring.last() != Some(&n) && ring.first() != Some(&n) || ring.is_empty() {
                ring.push(n);
            }
        }
        let v: Vec<u32> = ring.iter().map(|&n| vertex(n, &mut nodes)).collect();
        match v.len() {
            3 => indices.extend([v[0], v[1], v[2]]),
            4 => indices.extend([v[0], v[1], v[2], v[0], v[2], v[3]]),
            _ => {}
        }
    }
    let positions = nodes
        .iter()
        .map(|&n| to_f32(&deformed(model, frame, n, scale)))
        .collect();
    (
        Surface {
            positions,
            indices,
            scalars: None,
            color: body_color(b),
        },
        nodes,
    )
}

/// A rigid sphere obstacle as a grey surface.
fn rigid_sphere(center: &Vector3<f64>, radius: f64) -> Surface {
    let (rings, around) = (24u32, 48u32);
    let mut positions = Vec::new();
    for i in 0..=rings {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..around {
            let phi = std::f64::consts::TAU * j as f64 / around as f64;
            let d = Vector3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            positions.push(to_f32(&(center + d * radius)));
        }
    }
    let mut indices = Vec::new();
    for i in 0..rings {
        for j in 0..around {
            let (a, b) = (i * around + j, i * around + (j + 1) % around);
            let (c, d) = (a + around, b + around);
            indices.extend([a, c, d, a, d, b]);
        }
    }
    Surface {
        positions,
        indices,
        scalars: None,
        color: [0.35, 0.36, 0.38, 1.0],
    }
}

/// Skin colour (linear RGB), and bone colour.
const SKIN: [f32; 3] = [0.74, 0.42, 0.30];
const BONE: [f32; 4] = [0.78, 0.72, 0.56, 1.0];

/// Which skin a hand is drawn with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SkinDetail {
    /// The display skin (the skin quads subdivided twice: ≈ 100 000 vertices at resolution 1).
    #[default]
    Full,
    /// The contact skin: the same smooth skin at the lattice's resolution, 16 times fewer
    /// vertices, for what must be drawn at once (the viewer's preview of a pose) on a software
    /// renderer.
    Coarse,
}

/// Adds hand body `b` (skin, bones) to `list`; returns each bone's load (−R, N) with the bone's
/// posed centre.
fn hand_drawing(
    model: &Model,
    frame: &Frame,
    b: usize,
    (options, detail): (&VisualOptions, SkinDetail),
    list: &mut DrawList,
) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let body = &model.bodies[b];
    let hand = body.hand.as_deref().expect("a hand body");
    let skin = match detail {
        SkinDetail::Full => &hand.skin,
        SkinDetail::Coarse => &hand.contact_skin,
    };
    let scale = options.displacement_scale;
    let nodes: Vec<Vector3<f64>> = body
        .nodes
        .clone()
        .map(|n| deformed(model, frame, n, scale))
        .collect();
    let positions = skin.positions(&nodes);
    let nodal = |f: &dyn Fn(usize) -> f64| -> Vec<f64> { body.nodes.clone().map(f).collect() };
    let scalars = match options.overlay {
        // (A frame whose stresses are pending — a drag's draft at its pose — has none to draw.)
        Overlay::Stress if frame.stress.nodal.is_empty() => None,
        Overlay::Stress => Some(skin.interpolate(&nodal(&|n| von_mises(&frame.stress.nodal[n])))),
        Overlay::Displacement => {
            Some(skin.interpolate(&nodal(&|n| frame.solution.node_displacement(n).norm())))
        }
        // The tactile map on the skin itself (the contact is on the smooth skin).
        Overlay::Pressure => Some(
            match detail {
                SkinDetail::Full => crate::state::skin_pressure(model, frame, b),
                SkinDetail::Coarse => crate::state::contact_skin_pressure(model, frame, b),
            }
            .unwrap_or_else(|| vec![0.0; skin.vertex_count()]),
        ),
        _ => None,
    }
    // Every field is non-negative; the skin's weights extrapolate slightly past the cells.
    .map(|v| v.iter().map(|x| x.max(0.0) as f32).collect());
    list.surfaces.push(Surface {
        positions: positions.iter().map(to_f32).collect(),
        indices: skin.triangles().into_iter().flatten().collect(),
        scalars,
        color: [
            SKIN[0],
            SKIN[1],
            SKIN[2],
            options.skin_opacity.clamp(0.05, 1.0),
        ],
    });
    let Some(h) = frame.hands.iter().find(|h| h.body == b) else {
        return Vec::new();
    };
    let mut loads = Vec::new();
    for (bone, (pos, tri)) in hand.posed_bones(&h.angles) {
        if options.bones && options.skin_opacity < 1.0 {
            list.surfaces.push(Surface {
                positions: pos.iter().map(to_f32).collect(),
                indices: tri.into_iter().flatten().collect(),
                scalars: None,
                color: BONE,
            });
        }
        let centre = pos.iter().sum::<Vector3<f64>>() / pos.len().max(1) as f64;
        loads.push((-h.bone_reactions[bone], centre));
    }
    loads
}

/// Edges of body `b`'s boundary facets (no diagonals), deformed, as a line set.
pub fn body_wireframe(model: &Model, frame: &Frame, b: usize, scale: f64) -> LineSet {
    let mut edges = BTreeSet::new();
    for f in &model.bodies[b].facets {
        for k in 0..4 {
            let (a, c) = (f.nodes[k], f.nodes[(k + 1) % 4]);
            if a != c {
                edges.insert((a.min(c), a.max(c)));
            }
        }
    }
    let mut local: HashMap<usize, u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (a, c) in edges {
        for n in [a, c] {
            let i = *local.entry(n).or_insert_with(|| {
                positions.push(to_f32(&deformed(model, frame, n, scale)));
                (positions.len() - 1) as u32
            });
            indices.push(i);
        }
    }
    LineSet {
        positions,
        indices,
        color: [0.02, 0.02, 0.03, 0.55],
    }
}

/// Each constraint's total reaction (N) and the centroid of its nodes (deformed), in model order.
pub fn constraint_reactions(
    model: &Model,
    frame: &Frame,
    scale: f64,
) -> Vec<(String, Vector3<f64>, Vector3<f64>)> {
    model
        .constraints
        .iter()
        .filter(|c| !c.dofs.is_empty())
        .map(|c| {
            let mut total = Vector3::zeros();
            let mut nodes = BTreeSet::new();
            for &d in &c.dofs {
                total[d % 3] += frame.solution.reaction[d];
                nodes.insert(d / 3);
            }
            let centroid = nodes
                .iter()
                .map(|&n| deformed(model, frame, n, scale))
                .sum::<Vector3<f64>>()
                / nodes.len() as f64;
            (c.name.clone(), total, centroid)
        })
        .collect()
}

/// The draw list of one solved frame.
pub fn draw_list(
    model: &Model,
    frame: &Frame,
    options: &VisualOptions,
) -> Result<DrawList, VisualError> {
    draw_list_with(model, frame, options, SkinDetail::Full)
}

/// [`draw_list`] with the hands' skin at `detail`.
pub fn draw_list_with(
    model: &Model,
    frame: &Frame,
    options: &VisualOptions,
    detail: SkinDetail,
) -> Result<DrawList, VisualError> {
    let expected = 3 * model.mesh.node_count();
    if frame.solution.displacement.len() != expected {
        return Err(VisualError::Mismatch {
            got: frame.solution.displacement.len(),
            expected,
        });
    }
    // A frame out of contact has no contact pressure: zero everywhere (the map of a hand that
    // has let go of the ball).
    let pressure = crate::state::contact_pressure(model, frame)
        .unwrap_or_else(|| vec![0.0; model.mesh.node_count()]);
    let scale = options.displacement_scale;
    let mut list = DrawList::default();
    let mut bone_loads = Vec::new();
    for b in 0..model.bodies.len() {
        if model.bodies[b].hand.is_some() {
            bone_loads.extend(hand_drawing(model, frame, b, (options, detail), &mut list));
            if options.wireframe {
                list.lines.push(body_wireframe(model, frame, b, scale));
            }
            continue;
        }
        let (mut surface, nodes) = body_surface(model, frame, b, scale);
        surface.scalars = match options.overlay {
            Overlay::Stress if frame.stress.nodal.is_empty() => None,
            Overlay::Stress => Some(
                nodes
                    .iter()
                    .map(|&n| von_mises(&frame.stress.nodal[n]) as f32)
                    .collect(),
            ),
            Overlay::Displacement => Some(
                nodes
                    .iter()
                    .map(|&n| frame.solution.node_displacement(n).norm() as f32)
                    .collect(),
            ),
            Overlay::Pressure => Some(nodes.iter().map(|&n| pressure[n] as f32).collect()),
            _ => None,
        };
        list.surfaces.push(surface);
        if options.wireframe {
            list.lines.push(body_wireframe(model, frame, b, scale));
        }
    }
    let scalars = list
        .surfaces
        .iter()
        .filter_map(|s| s.scalars.as_ref())
        .flatten()
        .copied();
    let range = guard_range(finite_range(scalars).unwrap_or([0.0, 1.0]));
    list.legend = match options.overlay {
        Overlay::Pressure => Some(Legend {
            title: "contact pressure".into(),
            unit: "Pa".into(),
            range,
            colormap: Colormap::Heat,
        }),
        Overlay::Stress => Some(Legend {
            title: "von Mises stress".into(),
            unit: "Pa".into(),
            range,
            colormap: Colormap::Viridis,
        }),
        Overlay::Displacement => Some(Legend {
            title: "displacement".into(),
            unit: "m".into(),
            range,
            colormap: Colormap::Viridis,
        }),
        _ => None,
    };
    let bodies = Bounds::of(
        list.surfaces
            .iter()
            .flat_map(|s| s.positions.iter().map(|p| Vec3::from(*p))),
    );
    let size = if bodies.is_valid() {
        bodies.radius()
    } else {
        1.0
    };
    if options.overlay == Overlay::Forces {
        let mut reactions = constraint_reactions(model, frame, scale);
        // Bone loads point away from the bone's centre: the arrow's tail sits on the bone.
        let bone_arrows: Vec<(Vector3<f64>, Vector3<f64>)> = bone_loads;
        let largest_bone = bone_arrows.iter().map(|r| r.0.norm()).fold(0.0, f64::max);
        if largest_bone > 0.0 {
            reactions.retain(|(name, _, _)| {
                !model
                    .constraints
                    .iter()
                    .any(|c| &c.name == name && model.bodies[c.body].hand.is_some())
            });
        }
        let largest = reactions
            .iter()
            .map(|r| r.1.norm())
            .fold(largest_bone, f64::max);
        if largest > 0.0 && largest.is_finite() {
            for (force, at) in &bone_arrows {
                let ratio = force.norm() / largest;
                if ratio < 1e-3 {
                    continue;
                }
                let v = force / largest * (0.7 * size as f64);
                list.arrows.push(Arrow {
                    origin: to_f32(at),
                    vector: to_f32(&v),
                    color: Colormap::Traffic.linear(ratio as f32),
                });
            }
            for (_, force, at) in &reactions {
                let ratio = force.norm() / largest;
                // The largest arrow is 70% of the scene radius; the tip touches the body.
                let v = force / largest * (0.7 * size as f64);
                list.arrows.push(Arrow {
                    origin: to_f32(&(at - v)),
                    vector: to_f32(&v),
                    color: Colormap::Traffic.linear(ratio as f32),
                });
            }
        }
        list.legend = Some(Legend {
            title: "reaction force".into(),
            unit: "N".into(),
            range: guard_range([0.0, largest as f32]),
            colormap: Colormap::Traffic,
        });
    }
    // Rigid spheres are drawn; a horizontal obstacle plane is the ground.
    for (_, o) in &model.obstacles {
        if let crate::contact::Obstacle::Sphere { center, radius } = o {
            list.surfaces.push(rigid_sphere(center, *radius));
        }
    }
    let table = model
        .obstacles
        .iter()
        .filter_map(|(_, o)| match o {
            crate::contact::Obstacle::Plane { point, normal } if normal.z > 0.999 => {
                Some(point.z as f32)
            }
            _ => None,
        })
        .fold(f32::INFINITY, f32::min);
    if bodies.is_valid() {
        let c = bodies.center();
        list.ground = Some(Ground {
            height: bodies.min.z.min(table),
            center: [c.x, c.y],
            extent: 4.0 * size,
        });
    }
    Ok(list)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::headless::solve_scene;
    use crate::scene::Scene;

    fn block(cells: usize) -> crate::headless::Solved {
        let text = format!(
            r#"
            [[material]]
            name = "rubber"
            young = 1.0e6
            poisson = 0.3
            [[body]]
            name = "block"
            material = "rubber"
            shape = {{ box = {{ min = [0, 0, 0], max = [1, 1, 1], cells = [{cells}, {cells}, {cells}] }} }}
            [[constraint]]
            name = "base"
            body = "block"
            where = {{ face = "z-" }}
            displacement = [0, 0, 0]
            [[constraint]]
            name = "press"
            body = "block"
            where = {{ face = "z+" }}
            displacement = {{ z = -0.01 }}
            "#
        );
        solve_scene(&Scene::parse(&text, "t").unwrap(), "t").unwrap()
    }

    #[test]
    fn block_surface_counts_and_ground() {
        let s = block(2);
        let opts = VisualOptions {
            overlay: Overlay::Displacement,
            displacement_scale: 1.0,
            wireframe: true,
            ..Default::default()
        };
        let list = draw_list(&s.model, &s.frames[0], &opts).unwrap();
        let surf = &list.surfaces[0];
        // A 2×2×2 box: 6 faces of 4 quads, 26 boundary nodes, 48 triangles.
        assert_eq!(surf.positions.len(), 26);
        assert_eq!(surf.indices.len(), 48 * 3);
        // 12 edges of 2 segments, plus 6 faces × 2 interior lines of 2 segments: 48 segments.
        assert_eq!(list.lines[0].indices.len(), 48 * 2);
        // The top is pressed 1 cm: the largest displacement is at least that.
        let legend = list.legend.unwrap();
        assert!(legend.range[1] >= 0.01 - 1e-6 && legend.range[0] >= 0.0);
        assert!(list.ground.unwrap().height.abs() < 1e-6);
        // Facets face outwards: the triangles' normals point away from the centre.
        let c = Vec3::splat(0.5);
        for t in surf.indices.chunks_exact(3) {
            let p = [t[0], t[1], t[2]].map(|i| Vec3::from(surf.positions[i as usize]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(n.dot((p[0] + p[1] + p[2]) / 3.0 - c) > 0.0);
        }
    }

    /// The stress overlay colours a body by its von Mises stress; a frame whose stresses are
    /// still pending (a drag's draft, which the window draws without them unless the overlay
    /// asks) is drawn uncoloured, not read out of bounds.
    #[test]
    fn the_stress_overlay_colours_solved_stresses_and_skips_pending_ones() {
        let s = block(2);
        let opts = VisualOptions {
            overlay: Overlay::Stress,
            ..Default::default()
        };
        let list = draw_list(&s.model, &s.frames[0], &opts).unwrap();
        let scalars = list.surfaces[0].scalars.clone().unwrap();
        assert!(scalars.iter().all(|v| v.is_finite()) && scalars.iter().any(|&v| v > 0.0));
        let mut pending = s.frames[0].clone();
        pending.stress = Default::default();
        pending.stress_pending = Some(crate::state::PendingStress::Composed);
        let list = draw_list(&s.model, &pending, &opts).unwrap();
        assert!(list.surfaces[0].scalars.is_none());
    }

    #[test]
    fn reaction_arrows_balance_and_touch_the_body() {
        let s = block(3);
        let opts = VisualOptions {
            overlay: Overlay::Forces,
            ..Default::default()
        };
        let r = constraint_reactions(&s.model, &s.frames[0], 1.0);
        assert_eq!(r.len(), 2);
        // No gravity: the two reactions balance (equation (8)).
        assert!((r[0].1 + r[1].1).norm() < 1e-6 * r[0].1.norm());
        assert!(r[0].1.z > 0.0 && r[1].1.z < 0.0);
        let list = draw_list(&s.model, &s.frames[0], &opts).unwrap();
        assert_eq!(list.arrows.len(), 2);
        let tip = Vec3::from(list.arrows[1].origin) + Vec3::from(list.arrows[1].vector);
        assert!((tip - Vec3::new(0.5, 0.5, 0.99)).length() < 1e-4, "{tip}");
        // Out of contact, the tactile map is zero everywhere (not an error: the frame of a
        // hand that let go in a scene with contact).
        let pressure = draw_list(
            &s.model,
            &s.frames[0],
            &VisualOptions {
                overlay: Overlay::Pressure,
                ..opts
            },
        )
        .unwrap();
        let scalars: Vec<f32> = pressure
            .surfaces
            .iter()
            .flat_map(|s| s.scalars.clone().unwrap())
            .collect();
        assert!(!scalars.is_empty() && scalars.iter().all(|&p| p == 0.0));
    }
}
