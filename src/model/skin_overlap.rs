//! Where a hand's skin has gone into its own flesh: the contact skin's vertices inside the
//! closed skin (`contact::vertices_inside_itself`, by winding number). Without self-contact
//! nothing keeps the skin out of itself — a fist's fingers pass into each other and into the
//! palm, a crease's two sides through each other — and the bones' reactions then miss that
//! contact; the report counts it per part so the animator sees where.

use crate::contact::{vertices_inside_itself, SurfaceEdges};
use crate::hand::HandModel;
use nalgebra::Vector3;

/// How far outside its own side a skin vertex is looked at, m: far below the flesh's
/// millimetres, far above rounding.
const OFF_SIDE: f64 = 5e-5;

/// Skin with other skin this near outside it at rest meets that skin at rest, m: where the
/// digits' skins nearly touch at the webs (the anatomical form's webs: 25 contact-skin vertices
/// inside the flesh at rest at resolution 1, 41 with this reach), the flesh's first motion
/// carries a vertex across — the finger press's ring finger at MCP −5° put one 0.3 mm into the
/// middle finger's web — and that is the webs meeting, not skin folding.
const NEARLY_MET: f64 = 1e-3;

/// Skin this near, along the skin, to skin inside the flesh at rest is where the skins of
/// neighbouring digits meet (the webs), m: two base lattice spacings, the self-contact's
/// neighbourhood. Measured on the shipped scenes: within 3.2 mm of them, 14–45 vertices of a
/// grasp entered the flesh at the webs as the fingers moved; within 6.4 mm, 0–10 besides the
/// thumb's web and the fingers pressed together (docs/hand.md).
const WEB: f64 = 2.0 * crate::hand::BASE_SPACING;

/// What telling a hand's skin inside its own flesh needs from its rest geometry, built once
/// with the model.
#[derive(Clone, Debug)]
pub struct SkinOverlapCheck {
    /// The contact skin's triangles.
    triangles: Vec<[usize; 3]>,
    /// Each vertex's representative among those coinciding with it at rest (split seams).
    joined: Vec<usize>,
    /// Where the skins of neighbouring digits meet at rest: the vertices inside the flesh at
    /// rest, and those within [`WEB`] of one along the skin (the built-in hand: 43 inside at
    /// resolution 1, at the webs). Left out of a frame's overlap.
    met_at_rest: Vec<bool>,
}

impl SkinOverlapCheck {
    /// The check for `hand`'s contact skin.
    pub fn new(hand: &HandModel) -> SkinOverlapCheck {
        let skin = &hand.contact_skin;
        let rest = skin.positions(&hand.flesh.mesh.nodes);
        let triangles: Vec<[usize; 3]> = skin.triangle_indices();
        let edges = SurfaceEdges::new(&rest, &triangles);
        let mut check = SkinOverlapCheck {
            triangles,
            joined: edges.joined().to_vec(),
            met_at_rest: Vec::new(),
        };
        // Inside at rest, or all but: another digit's skin within `NEARLY_MET` outside it.
        let at_rest = vertices_inside_itself(
            &check.triangles,
            &rest,
            &check.joined,
            &[OFF_SIDE, NEARLY_MET],
        );
        let near = edges.within(&at_rest, WEB);
        // (A vertex coinciding with a near one is near: the seam is crossed at no length.)
        check.met_at_rest = (0..rest.len()).map(|v| near.contains_key(&v)).collect();
        check
    }

    /// The contact skin's vertices of `hand` inside its flesh with the flesh's nodes at
    /// `nodes`, sorted.
    pub fn inside_flesh(&self, hand: &HandModel, nodes: &[Vector3<f64>]) -> Vec<usize> {
        let positions = hand.contact_skin.positions(nodes);
        let mut inside =
            vertices_inside_itself(&self.triangles, &positions, &self.joined, &[OFF_SIDE]);
        inside.sort_unstable();
        inside
    }

    /// The contact skin's triangles (vertex indices of `hand.contact_skin`), a closed surface.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// [`Self::inside_flesh`] away from where the digits' skins meet at rest.
    pub fn overlap(&self, hand: &HandModel, nodes: &[Vector3<f64>]) -> Vec<usize> {
        let mut inside = self.inside_flesh(hand, nodes);
        inside.retain(|&v| !self.met_at_rest[v]);
        inside
    }
}
