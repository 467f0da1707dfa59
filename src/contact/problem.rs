//! A contact problem: the linear system of equation (5) with its prescribed dofs, and what may
//! touch what (nodes against rigid obstacles, nodes of one body against the facets of another),
//! with the detection shared by the contact methods.

use super::bounds::Bounds;
use super::embedded::EmbeddedPoints;
use super::obstacle::Obstacle;
use super::point::{ContactSettings, Master, PairSides};
use super::self_contact::OwnNeighbourhood;
use super::surface::{ContactSurface, Projection, SurfaceBvh};
use crate::fem::assembly::Stiffness;
use crate::fem::DofPartition;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::sync::Arc;

/// The nodes `slaves` may not enter the surface `surface`.
#[derive(Clone, Debug)]
pub struct SurfacePair {
    /// Candidate nodes (global).
    pub slaves: Vec<usize>,
    /// Index into [`ContactProblem::surfaces`].
    pub surface: usize,
    /// The paper's direction (object nodes repelled from the skin): the pairs its method uses.
    pub primary: bool,
    /// The surface the slave nodes lie on: a node only meets facets that face it (their
    /// normals opposed), so a node through a thin wall is not pushed out of its far side.
    pub slave_surface: Option<usize>,
    /// For slaves on the surface they meet (self-contact): the facets each may not meet, its
    /// own neighbourhood on the rest geometry ([`OwnNeighbourhood`]).
    pub own: Option<Arc<OwnNeighbourhood>>,
}

/// A node whose path over a step of the motion went into another body through one of its
/// facets: it is held against that facet, not against the one nearest to where it ended (past a
/// thin wall, the nearest facet is the far side's, and the node would look outside).
#[derive(Clone, Copy, Debug)]
pub struct Crossing {
    /// The node (global).
    pub node: usize,
    /// Index into [`ContactProblem::surfaces`]: the surface crossed.
    pub surface: usize,
    /// The facet's corners (global).
    pub nodes: [usize; 3],
    /// Barycentric weights of the crossing point on the facet.
    pub weights: [f64; 3],
}

/// The friction coefficient μ of a node against a master.
pub type FrictionLaw<'a> = &'a (dyn Fn(usize, &Master) -> f64 + Sync);

/// Decides, from the reactions at the prescribed dofs after a solve, whether to stop (a bone's
/// reaction overran its threshold).
pub type StopCheck<'a> = &'a (dyn Fn(&[f64]) -> bool + Sync);

/// A linear problem K·U = R with prescribed dofs, and its possible contacts.
pub struct ContactProblem<'a> {
    /// Stiffness (rest geometry of each body, or its current geometry for an increment).
    pub k: &'a Stiffness,
    /// Prescribed dofs.
    pub partition: &'a DofPartition,
    /// Prescribed values (read at prescribed dofs).
    pub prescribed: &'a [f64],
    /// Loads R.
    pub loads: &'a [f64],
    /// Reference positions X of every contact index: the mesh's nodes (the displacement U is
    /// measured from them), then the embedded points at those positions.
    pub positions: &'a [Vector3<f64>],
    /// Contact points embedded in the mesh (the smooth skin's vertices), numbered after the
    /// nodes: they may be slaves and facet corners like nodes.
    pub embedded: &'a EmbeddedPoints,
    /// Rigid obstacles.
    pub obstacles: &'a [Obstacle],
    /// Nodes that may touch the obstacles.
    pub obstacle_candidates: &'a [usize],
    /// Deformable surfaces.
    pub surfaces: &'a [ContactSurface],
    /// Which nodes may touch which surface.
    pub pairs: &'a [SurfacePair],
    /// Coulomb friction coefficient of each contact.
    pub friction: FrictionLaw<'a>,
    /// Threshold check for the paper's iteration.
    pub stop: Option<StopCheck<'a>>,
    /// Nodes held against the facet their motion crossed (empty: each node meets its nearest).
    pub crossings: &'a [Crossing],
    /// The contact nodes (sorted) that the last solve of a sequence held — a contact step
    /// along a motion, a correction at the pose: the exact method's first iteration takes
    /// every candidate of theirs that penetrates, instead of the deepest first (empty: a cold
    /// start). The solution is that of a cold start; it is reached in fewer iterations.
    pub held_before: &'a [usize],
    /// The contact forces (over every dof) the paper's iteration converged to in the last solve
    /// of such a sequence: its first iterate, with the nodes of `held_before` kept on their
    /// facets (empty: a cold start, from no force).
    pub forces_before: &'a [f64],
}

/// A penetration found at the current displacements.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Penetration {
    /// The node.
    pub node: usize,
    /// What it penetrates.
    pub master: Master,
    /// Which obstacle (`o`) or pair (`obstacles + p`) found it.
    pub source: usize,
    /// Outward normal of the master.
    pub normal: Vector3<f64>,
    /// Signed gap, m (negative inside).
    pub gap: f64,
    /// Fixed point of the master for an obstacle (its nearest point), zero for a facet.
    pub anchor: Vector3<f64>,
}

impl ContactProblem<'_> {
    /// Current position of contact index `n` (a node or an embedded point) with displacements
    /// `u`.
    pub fn position(&self, u: &[f64], n: usize) -> Vector3<f64> {
        if n < self.embedded.first() {
            self.positions[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2])
        } else {
            self.positions[n] + self.embedded.displacement(u, n)
        }
    }

    /// The mesh nodes' reference positions (without the embedded points).
    pub fn node_positions(&self) -> &[Vector3<f64>] {
        &self.positions[..self.embedded.first()]
    }

    /// Whether contact index `n` can move (some dof of it, or of a node it is embedded in, is
    /// free).
    pub(crate) fn movable(&self, n: usize) -> bool {
        let mut any = false;
        self.embedded.for_each(n, |m, _| {
            any |= (0..3).any(|a| !self.partition.prescribed[3 * m + a]);
        });
        any
    }

    /// The nodes a contact of `slave` against `master` acts on, with their weights: the slave's
    /// (+w), the facet corners' (−h·w); the constraint is n·Σ w U ≥ b and the contact force R_C
    /// on the slave gives w·R_C at each node.
    pub(crate) fn contact_terms(&self, slave: usize, master: &Master) -> Vec<(usize, f64)> {
        let mut terms = Vec::new();
        self.embedded.for_each(slave, |n, w| terms.push((n, w)));
        if let Master::Facet { nodes, weights, .. } = master {
            for (&c, &h) in nodes.iter().zip(weights) {
                self.embedded.for_each(c, |n, w| terms.push((n, -h * w)));
            }
        }
        terms
    }

    /// Every node behind an obstacle or a facet by more than `tolerance` (and less than the
    /// search depth), at displacements `u`, over the pairs of `sides`.
    pub(crate) fn penetrations(
        &self,
        u: &[f64],
        settings: &ContactSettings,
        threshold: f64,
        sides: PairSides,
    ) -> Vec<Penetration> {
        let current: Vec<Vector3<f64>> = (0..self.positions.len())
            .into_par_iter()
            .map(|n| self.position(u, n))
            .collect();
        let mut out = Vec::new();
        let free = |n: usize| self.movable(n);
        for &node in self.obstacle_candidates {
            for (o, obstacle) in self.obstacles.iter().enumerate() {
                let (gap, normal, anchor) = obstacle.nearest(&current[node]);
                if gap < threshold && free(node) {
                    out.push(Penetration {
                        node,
                        master: Master::Obstacle(o),
                        source: o,
                        normal,
                        gap,
                        anchor,
                    });
                }
            }
        }
        let wanted = |pair: &SurfacePair| match sides {
            PairSides::Both => true,
            PairSides::ObjectNodes => pair.primary,
            PairSides::SkinNodes => !pair.primary,
        };
        // Hierarchies of the surfaces some wanted pair projects onto (on its own surface a
        // pair searches the facets' swept boxes instead, below).
        let hierarchies: Vec<Option<SurfaceBvh>> = (0..self.surfaces.len())
            .map(|s| {
                self.pairs
                    .iter()
                    .any(|p| p.surface == s && wanted(p) && p.own.is_none())
                    .then(|| self.surfaces[s].hierarchy(&current, settings.search_depth))
            })
            .collect();
        for (p, pair) in self.pairs.iter().enumerate() {
            if !wanted(pair) {
                continue;
            }
            let surface = &self.surfaces[pair.surface];
            // On its own surface a point meets only facets its path over the step passed
            // through or that it lay on where the step started: those whose swept boxes its
            // path's box meets, grown by how far beside it they may lie (far fewer than lie
            // within the search depth of where it is).
            let swept = pair.own.as_ref().map(|o| {
                (
                    surface.swept_hierarchy(self.positions, &current),
                    o.reach_beside_path(),
                )
            });
            // The slave surface's normals on the reference geometry (the positions the
            // surfaces were made from).
            let normals = pair
                .slave_surface
                .map(|s| self.surfaces[s].reference_normals());
            // Each slave on its own (in parallel; in the slaves' order).
            let of_node = |node: usize| -> Vec<Penetration> {
                let mut out = Vec::new();
                let facing = |t: &[usize; 3]| -> bool {
                    let Some(normals) = &normals else { return true };
                    let Some(m) = normals.get(&node) else {
                        return true;
                    };
                    let n = (current[t[1]] - current[t[0]]).cross(&(current[t[2]] - current[t[0]]));
                    n.dot(m) < 0.0
                };
                // Inside or outside: the side of the nearest facet of all. The facet it is
                // pushed out of: the nearest of those that face it.
                let bvh = || {
                    hierarchies[pair.surface]
                        .as_ref()
                        .expect("a wanted pair on another body's surface")
                };
                let own = normals.as_ref().and_then(|m| m.get(&node));
                // Its own facets, and on its own surface its neighbourhood, are not met.
                let apart = |t: &[usize; 3]| {
                    t.contains(&node)
                        || pair.own.as_ref().is_some_and(|o| {
                            let (start, now) =
                                (t.map(|m| self.positions[m]), t.map(|m| current[m]));
                            o.excludes(node, t)
                                || own.is_none_or(|m| {
                                    let path = (&self.positions[node], &current[node], m);
                                    !o.met_over_step((node, t), path, &start, &now)
                                })
                        })
                };
                // The nearest facet `skip` leaves: on its own surface, among those its path
                // may have met (a facet not met over the step is one `skip` leaves out).
                let nearest_left = |skip: &dyn Fn(&[usize; 3]) -> bool| -> Option<Projection> {
                    match &swept {
                        Some((swept, reach)) => {
                            let x = &current[node];
                            let path = Bounds::of([x, &self.positions[node]]).grown(*reach);
                            // Within the search depth of where it is, as the facets the
                            // hierarchy of the current positions holds.
                            let within = |t: &[usize; 3]| {
                                Bounds::of(t.map(|m| &current[m]))
                                    .grown(settings.search_depth)
                                    .holds(x)
                            };
                            swept.project_near(x, &path, &current, own, |t| !within(t) || skip(t))
                        }
                        None => bvh().project(&current[node], &current, own, skip),
                    }
                };
                // The facet the node is pushed out of, among those `skip` leaves, if it is behind
                // one by more than `threshold` (and less than the search depth).
                let met = |skip: &dyn Fn(&[usize; 3]) -> bool| -> Option<Projection> {
                    let nearest = nearest_left(skip)?;
                    // In front of the nearest facet's plane, but nearest to its edge or
                    // corner: inside after all where the surface folds into a pit there. (Not
                    // on a body's own surface: its creases are not closed pits.)
                    let nearest = if nearest.gap >= threshold && pair.own.is_none() {
                        bvh()
                            .behind_feature(&current[node], &current, &nearest, skip)
                            .filter(|behind| behind.gap < threshold)?
                    } else if nearest.gap >= threshold {
                        return None;
                    } else {
                        nearest
                    };
                    // The nearest facet, unless it does not face the node: then a facing facet
                    // almost as near (a node on an edge or a corner of the other body, as close
                    // to its side as to the face it presses), else nothing if the node is
                    // outside (the far side of a thin finger, a crease), else the nearest
                    // (inside: out the nearest way; a node past the middle of a thin part of a
                    // solid body leaves by the far side, so keep increments shallower than half
                    // of it; a hollow object's cavity wall is not part of the surface skin
                    // meets, `exterior_quads`, so skin in a shell's wall leaves it outwards).
                    let proj = if facing(&nearest.nodes) {
                        nearest
                    } else {
                        let band = nearest.distance + 0.1 * settings.search_depth;
                        let alternative =
                            nearest_left(&|t| skip(t) || !facing(t)).filter(|p| p.distance <= band);
                        match alternative {
                            Some(p) => p,
                            None if nearest.gap >= 0.0 => return None,
                            None => nearest,
                        }
                    };
                    let movable = free(node) || proj.nodes.iter().any(|&n| free(n));
                    (proj.gap < threshold && proj.gap > -settings.search_depth && movable)
                        .then_some(proj)
                };
                // The node met by facet `nodes` of this pair's surface at `weights`.
                // `smooth`: along the surface's smoothed normal, the gap measured along it,
                // where that gap is on the same side as the facet's own (with the closest point
                // clamped to an edge or a corner, the point can lie behind the facet's plane
                // yet in front along the smoothed normal: that row would not hold it, and the
                // facet's normal is kept). Not on a body's own skin (self-contact keeps its
                // facets' normals, its folds being creases), nor at a crossing point (the
                // point held where its path went through the facet).
                let on_facet = |nodes: [usize; 3],
                                weights: [f64; 3],
                                normal: Vector3<f64>,
                                gap: f64,
                                smooth: bool| {
                    let smoothed = (smooth && pair.own.is_none())
                        .then(|| surface.smoothed_normal(&nodes, &weights, &current))
                        .flatten()
                        .map(|n| {
                            let point: Vector3<f64> =
                                (0..3).map(|i| current[nodes[i]] * weights[i]).sum();
                            (n, n.dot(&(current[node] - point)))
                        })
                        .filter(|(_, g)| (*g < 0.0) == (gap < 0.0));
                    let (normal, gap) = smoothed.unwrap_or((normal, gap));
                    Penetration {
                        node,
                        master: Master::Facet {
                            body: surface.body,
                            nodes,
                            weights,
                        },
                        source: self.obstacles.len() + p,
                        normal,
                        gap,
                        anchor: Vector3::zeros(),
                    }
                };
                // A node that crossed this surface: against the facet it went through.
                if let Some(c) = self
                    .crossings
                    .iter()
                    .find(|c| c.node == node && c.surface == pair.surface)
                {
                    let corners = c.nodes.map(|m| current[m]);
                    let normal = (corners[1] - corners[0]).cross(&(corners[2] - corners[0]));
                    let Some(normal) = normal.try_normalize(0.0) else {
                        return out;
                    };
                    let point: Vector3<f64> = (0..3).map(|i| corners[i] * c.weights[i]).sum();
                    let gap = normal.dot(&(current[node] - point));
                    let movable = free(node) || c.nodes.iter().any(|&n| free(n));
                    if gap < threshold && gap > -settings.search_depth && movable {
                        out.push(on_facet(c.nodes, c.weights, normal, gap, false));
                    }
                    // The facets around the one it went through: where the other body
                    // folds there (a soft body dented into a valley across its facet), the
                    // node held on its facet's plane can slide over the fold's edge and lie
                    // behind the next facet, or in a pit at a corner. Where that neighbourhood
                    // (its own facet included) says it is behind another facet, that one is
                    // met too.
                    let around = |t: &[usize; 3]| t.iter().any(|m| c.nodes.contains(m));
                    let next = met(&|t: &[usize; 3]| apart(t) || !around(t))
                        .filter(|q| !q.nodes.iter().all(|m| c.nodes.contains(m)));
                    if let Some(q) = next {
                        out.push(on_facet(q.nodes, q.weights, q.normal, q.gap, true));
                    }
                    return out;
                }
                if let Some(proj) = met(&apart) {
                    out.push(on_facet(
                        proj.nodes,
                        proj.weights,
                        proj.normal,
                        proj.gap,
                        true,
                    ));
                }
                out
            };
            let found: Vec<Vec<Penetration>> =
                pair.slaves.par_iter().map(|&n| of_node(n)).collect();
            out.extend(found.into_iter().flatten());
        }
        out
    }

    /// Largest penetration at `u` over every candidate, m (0 when none).
    pub fn max_penetration(&self, u: &[f64], settings: &ContactSettings) -> f64 {
        let found = self.penetrations(u, settings, 0.0, settings.pairs);
        found.iter().map(|p| -p.gap).fold(0.0, f64::max)
    }
}
