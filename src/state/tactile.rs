//! The tactile map of a solved frame: the contact pressure at every node of the model, and on
//! each hand's smooth skin — the press of other bodies and of the skin on itself (a fold, a
//! fingertip on the palm, fingers side by side: `HandFrame::self_contact`, felt on both sides).

use super::Frame;
use crate::contact::{nodal_pressure_with, patch_pressure, Master};
use crate::model::Model;

/// Contact pressure at every node (Pa, 0 off contact), over the boundary facets of all bodies;
/// `None` when the frame has no contact. A hand's contact is on its smooth skin: its lattice
/// nodes get the share of their cells' skin points (see [`skin_pressure`] for the map on the
/// skin itself).
pub fn contact_pressure(model: &Model, frame: &Frame) -> Option<Vec<f64>> {
    // The skin's press on itself, each contact-skin vertex's force on its cell's nodes.
    let mut own = Vec::new();
    for h in &frame.hands {
        let (Some(hand), nodes) = (
            model.bodies[h.body].hand.as_deref(),
            &model.bodies[h.body].nodes,
        ) else {
            continue;
        };
        for (v, &force) in h.self_contact.iter().enumerate() {
            if force != 0.0 {
                let terms = hand
                    .contact_skin
                    .terms(v)
                    .map(|(n, w)| (nodes.start + n, w))
                    .collect();
                own.push((terms, force));
            }
        }
    }
    if frame.contact.is_none() && own.is_empty() {
        return None;
    }
    let facets: Vec<crate::mesh::Facet> = model
        .bodies
        .iter()
        .flat_map(|b| b.facets.iter().copied())
        .collect();
    let contacts = frame.contact.as_ref().map_or(&[][..], |c| &c.contacts[..]);
    Some(nodal_pressure_with(
        &model.mesh.nodes,
        &facets,
        contacts,
        &own,
    ))
}

/// Contact pressure on hand `body`'s display skin (Pa at each display vertex, 0 off contact):
/// each contact skin vertex's normal contact force over the area it stands for on the display
/// skin (its bilinear share of the display vertices' areas, deformed), carried bilinearly to
/// the display skin over the control quads both skins share — so that the map drawn and
/// exported integrates over the display skin to the contact's normal force. `None` without
/// contact on this hand's skin.
pub fn skin_pressure(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    let p = pressed_skin(model, frame, body)?;
    Some(on_display_skin(p.hand, p.positions, &p.force))
}

/// The press of hand frame `h`'s skin on itself alone, on its display skin (Pa at each display
/// vertex, as [`skin_pressure`]); `None` where it presses nowhere.
pub fn self_contact_skin_pressure(model: &Model, h: &super::HandFrame) -> Option<Vec<f64>> {
    let (hand, force) = pressed_by_itself(model, h)?;
    Some(on_display_skin(hand, &h.positions, &force))
}

/// A hand's skin as pressed in a frame.
struct PressedSkin<'a> {
    /// The hand.
    hand: &'a crate::hand::HandModel,
    /// Its flesh's nodes in the frame.
    positions: &'a [nalgebra::Vector3<f64>],
    /// The normal force at each of its contact skin's vertices, N.
    force: Vec<f64>,
}

/// Hand `body`'s skin as pressed in `frame` (`contact_skin_forces`: other bodies' press and its
/// own); `None` without contact on its skin.
fn pressed_skin<'a>(model: &'a Model, frame: &'a Frame, body: usize) -> Option<PressedSkin<'a>> {
    let hand = model.bodies[body].hand.as_deref()?;
    let force = contact_skin_forces(model, frame, body)?;
    let positions = &frame.hands.iter().find(|h| h.body == body)?.positions;
    Some(PressedSkin {
        hand,
        positions,
        force,
    })
}

/// Hand frame `h`'s model and the force of its skin's press on itself at each contact skin
/// vertex; `None` where it presses nowhere.
fn pressed_by_itself<'a>(
    model: &'a Model,
    h: &super::HandFrame,
) -> Option<(&'a crate::hand::HandModel, Vec<f64>)> {
    let hand = model.bodies[h.body].hand.as_deref()?;
    if !h.presses_itself() {
        return None;
    }
    let mut force = h.self_contact.clone();
    force.resize(hand.contact_skin.vertex_count(), 0.0);
    Some((hand, force))
}

/// The radius of the tactile map's patches (m): the pressure a patch of skin this wide reads
/// (`contact::patch_pressure`), the peak the reports give beside the vertices' own. The hand
/// lattice's base spacing (3.2 mm, the spacing at resolution 1, `hand::lattice`): a patch every
/// resolution resolves, about the fingertip's tactile acuity (two points 2–3 mm apart felt as
/// two) and a pressure-mapping film's sensel.
pub const TACTILE_PATCH_RADIUS: f64 = 3.2e-3;

/// The press of other bodies and of the skin on itself at hand `body`'s contact skin vertices,
/// read over patches of [`TACTILE_PATCH_RADIUS`] (Pa; 0 off contact; `None` without contact on
/// this hand's skin): the pressure that converges under refinement where the vertices' own
/// (`contact_skin_pressure`) peaks at single points.
pub fn skin_patch_pressure(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    let p = pressed_skin(model, frame, body)?;
    Some(on_patches(p.hand, p.positions, &p.force))
}

/// The press of hand frame `h`'s skin on itself alone, over patches (as [`skin_patch_pressure`]);
/// `None` where it presses nowhere.
pub fn self_contact_patch_pressure(model: &Model, h: &super::HandFrame) -> Option<Vec<f64>> {
    let (hand, force) = pressed_by_itself(model, h)?;
    Some(on_patches(hand, &h.positions, &force))
}

/// The peaks of a frame's press on its hands' skins (other bodies' and the skin's own), Pa.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TactilePeaks {
    /// Over patches of [`TACTILE_PATCH_RADIUS`]: how much (converges under refinement).
    pub patch: f64,
    /// At one contact-skin vertex, its force over its own area: where the skins first meet.
    pub vertex: f64,
}

/// The peaks of the press on `frame`'s hands' contact skins; `None` where no hand's skin is
/// pressed.
pub fn tactile_peaks(model: &Model, frame: &Frame) -> Option<TactilePeaks> {
    let mut out: Option<TactilePeaks> = None;
    for h in &frame.hands {
        // The skin's forces, areas and normals once for both maps.
        let Some(p) = pressed_skin(model, frame, h.body) else {
            continue;
        };
        let (at, area, normal) = contact_skin_areas(p.hand, p.positions);
        let peak = |v: Vec<f64>| v.into_iter().fold(0.0, f64::max);
        let vertex = peak(per_area(&p.force, &area));
        let patch = peak(patch_pressure(
            &at,
            &normal,
            &area,
            &p.force,
            TACTILE_PATCH_RADIUS,
        ));
        if vertex > 0.0 {
            let o = out.get_or_insert(TactilePeaks {
                patch: 0.0,
                vertex: 0.0,
            });
            o.patch = o.patch.max(patch);
            o.vertex = o.vertex.max(vertex);
        }
    }
    out
}

/// The normal forces `force` at the contact skin's vertices (N) read over patches, on the
/// contact skin deformed with the flesh at `positions`: each vertex's area a quarter of its
/// quads', its normal theirs (area-weighted).
fn on_patches(
    hand: &crate::hand::HandModel,
    positions: &[nalgebra::Vector3<f64>],
    force: &[f64],
) -> Vec<f64> {
    let (at, area, normal) = contact_skin_areas(hand, positions);
    patch_pressure(&at, &normal, &area, force, TACTILE_PATCH_RADIUS)
}

/// The normal forces `force` at the contact skin's vertices (N) as a pressure on the display
/// skin of `hand` with its flesh at `positions` (Pa at each display vertex).
fn on_display_skin(
    hand: &crate::hand::HandModel,
    positions: &[nalgebra::Vector3<f64>],
    force: &[f64],
) -> Vec<f64> {
    // The contact skin is the control net itself (its quads are the control quads).
    const _: () = assert!(crate::hand::CONTACT_SKIN_LEVELS == 0);
    let area = hand.skin.vertex_areas(&hand.skin.positions(positions));
    let quads = &hand.contact_skin.quads;
    let share = hand.skin.to_control(&area, quads, force.len());
    let pressure = per_area(force, &share);
    hand.skin
        .from_control(|q, i| pressure[quads[q][i] as usize])
}

/// Contact pressure at each vertex of hand `body`'s contact skin (Pa, 0 off contact): the
/// normal contact force there (as the slave, or its share h_i as a facet corner) over the
/// vertex's quarter of the adjacent quads on the deformed skin. `None` without contact on this
/// hand's skin.
pub fn contact_skin_pressure(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    let p = pressed_skin(model, frame, body)?;
    let (_, area, _) = contact_skin_areas(p.hand, p.positions);
    Some(per_area(&p.force, &area))
}

/// Hand `hand`'s contact skin deformed with its flesh at `positions`: each vertex's position,
/// its area (a quarter of each of its quads') and its unit normal (its quads', area-weighted;
/// zero where they cancel).
fn contact_skin_areas(
    hand: &crate::hand::HandModel,
    positions: &[nalgebra::Vector3<f64>],
) -> (
    Vec<nalgebra::Vector3<f64>>,
    Vec<f64>,
    Vec<nalgebra::Vector3<f64>>,
) {
    let skin = &hand.contact_skin;
    let at = skin.positions(positions);
    let mut area = vec![0.0; at.len()];
    let mut normal = vec![nalgebra::Vector3::zeros(); at.len()];
    for q in &skin.quads {
        let p = q.map(|v| at[v as usize]);
        let n = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1]));
        for &v in q {
            area[v as usize] += 0.25 * n.norm();
            normal[v as usize] += n;
        }
    }
    for n in &mut normal {
        *n = n
            .try_normalize(0.0)
            .unwrap_or_else(nalgebra::Vector3::zeros);
    }
    (at, area, normal)
}

/// The normal contact force at each vertex of hand `body`'s contact skin, N: as the slave, or
/// its share h_i as a facet's corner, against other bodies and against the skin itself. `None`
/// without contact on this hand's skin.
fn contact_skin_forces(model: &Model, frame: &Frame, body: usize) -> Option<Vec<f64>> {
    let hand = model.bodies[body].hand.as_deref()?;
    let count = hand.contact_skin.vertex_count();
    let own = frame
        .hands
        .iter()
        .find(|h| h.body == body)
        .map_or(&[][..], |h| &h.self_contact[..]);
    let others = frame
        .contact
        .as_ref()
        .and_then(|c| Some((c, c.skin_points.iter().find(|s| s.0 == body)?.1)));
    if others.is_none() && own.is_empty() {
        return None;
    }
    let mut force = own.to_vec();
    force.resize(count, 0.0);
    let Some((contact, first)) = others else {
        return Some(force);
    };
    let local = |v: usize| (v >= first && v < first + count).then(|| v - first);
    for c in &contact.contacts {
        if let Some(v) = local(c.node) {
            force[v] += c.force;
        }
        if let Master::Facet { nodes, weights, .. } = c.master {
            for (&m, h) in nodes.iter().zip(weights) {
                if let Some(v) = local(m) {
                    force[v] += h * c.force;
                }
            }
        }
    }
    Some(force)
}

/// Force over area at each vertex, 0 where the area is none.
fn per_area(force: &[f64], area: &[f64]) -> Vec<f64> {
    force
        .iter()
        .zip(area)
        .map(|(f, a)| if *a > 0.0 { f / a } else { 0.0 })
        .collect()
}
