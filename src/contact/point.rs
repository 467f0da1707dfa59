//! What a contact solve produces: contact points with their normal and friction forces, and the
//! settings and errors shared by the contact methods.

use crate::fem::solve::{Solution, SolveError};
use nalgebra::Vector3;
use thiserror::Error;

/// How contact is resolved (`[solver] contact = "..."`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactMethod {
    /// Active set of Lagrange multipliers through the Schur complement of the factored stiffness:
    /// exact non-penetration at convergence, one factorization, Coulomb friction.
    #[default]
    Lagrange,
    /// The paper's six-step iteration: repel and prescribe, solve, transfer the reactions, release,
    /// solve again; repeated until the displacements stop changing.
    Paper,
}

impl ContactMethod {
    /// The scene name.
    pub fn name(self) -> &'static str {
        match self {
            ContactMethod::Lagrange => "lagrange",
            ContactMethod::Paper => "paper",
        }
    }
}

/// Which side of a contact between a hand and an object is checked node against facet
/// (`[solver] contact_pairs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairSides {
    /// Skin nodes against object facets (the finer side: the default).
    #[default]
    SkinNodes,
    /// Object nodes against skin facets (the paper's direction).
    ObjectNodes,
    /// Both ways.
    Both,
}

/// How the paper's iteration relaxes the contact forces it transfers (step 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Relaxation {
    /// A fixed factor ω (1 = the published procedure, unrelaxed).
    Fixed(f64),
    /// Aitken's dynamic factor, recomputed every iteration from the last two force changes.
    Aitken,
    /// The interface quasi-Newton method (IQN-ILS, `quasi_newton.rs`): the next forces from a
    /// least-squares secant model of every previous iteration's; converges where the object is
    /// much stiffer than the flesh, where Aitken's single factor does not.
    QuasiNewton,
}

/// Settings of the contact iteration.
#[derive(Clone, Copy, Debug)]
pub struct ContactSettings {
    /// Penetration allowed at convergence, m.
    pub tolerance: f64,
    /// Most iterations.
    pub max_iterations: usize,
    /// Method.
    pub method: ContactMethod,
    /// Largest change of any displacement between two iterations of the paper's method at
    /// convergence, m.
    pub change_tolerance: f64,
    /// Relaxation of the paper's method.
    pub relaxation: Relaxation,
    /// Farthest a node may be behind a facet and still be found penetrating it, m.
    pub search_depth: f64,
    /// Which nodes the Lagrange method checks against which facets.
    pub pairs: PairSides,
}

impl ContactSettings {
    /// Largest penetration accepted on the current geometry after the linearised contact has
    /// converged (the geometry moves while contact is linearised about the start): the
    /// tolerance, or 5 % of the search depth when larger.
    pub fn penetration_limit(&self) -> f64 {
        self.tolerance.max(0.05 * self.search_depth)
    }
}

/// The contact iterations of [`ContactSettings`] when the scene does not say
/// (`solver.contact_max_iterations`).
pub const DEFAULT_MAX_ITERATIONS: usize = 50;

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            tolerance: 1e-9,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            method: ContactMethod::Lagrange,
            change_tolerance: 1e-6,
            relaxation: Relaxation::QuasiNewton,
            search_depth: 0.01,
            pairs: PairSides::SkinNodes,
        }
    }
}

/// What a contact node pushes against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Master {
    /// A rigid obstacle (its index).
    Obstacle(usize),
    /// A triangle of another body's surface: the force on the node, −R_C, is shared by the
    /// triangle's nodes as h_i·R_C (Figure 5).
    Facet {
        /// The body.
        body: usize,
        /// Its nodes.
        nodes: [usize; 3],
        /// Barycentric weights h_i of the contact point C.
        weights: [f64; 3],
    },
}

/// Friction state of a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Adhesion {
    /// μ = 0.
    Frictionless,
    /// The tangential force holds the node: |F_t| < μ·F_n.
    Stick,
    /// The node slides: |F_t| = μ·F_n, against the sliding.
    Slip,
}

/// One node (or embedded skin point) in contact.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPoint {
    /// The slave: a node, or an embedded point (an index past the nodes, see
    /// [`super::EmbeddedPoints`]).
    pub node: usize,
    /// The nodes its force acts on, with their weights: the slave's (+w: 1 for a node, the
    /// shape functions of its cell for an embedded point) and the master facet's (−h·w).
    pub terms: Vec<(usize, f64)>,
    /// How many of `terms` are the slave's (they come first).
    pub slave_terms: usize,
    /// What it touches.
    pub master: Master,
    /// Outward unit normal of the master surface at the contact.
    pub normal: Vector3<f64>,
    /// Normal contact force on the node, N (≥ 0; along `normal`).
    pub force: f64,
    /// Friction force on the node, N (tangential).
    pub tangential: Vector3<f64>,
    /// Friction state.
    pub adhesion: Adhesion,
    /// Gap at convergence, m (≥ −tolerance).
    pub gap: f64,
}

impl ContactPoint {
    /// The rigid obstacle touched, if any.
    pub fn obstacle(&self) -> Option<usize> {
        match self.master {
            Master::Obstacle(o) => Some(o),
            Master::Facet { .. } => None,
        }
    }

    /// The total contact force on the node, N.
    pub fn force_vector(&self) -> Vector3<f64> {
        self.normal * self.force + self.tangential
    }

    /// Every node's share of this contact's force: the slave's force on its node (or on the
    /// nodes of the cell it is embedded in, by their weights), and the equal and opposite force
    /// shared among the master facet's nodes (R_i = h_i·R_C).
    pub fn nodal_forces(&self) -> Vec<(usize, Vector3<f64>)> {
        let f = self.force_vector();
        self.terms.iter().map(|&(n, w)| (n, f * w)).collect()
    }

    /// The node that carries most of the slave (the slave itself when it is a node).
    pub fn slave_node(&self) -> usize {
        super::embedded::heaviest(&self.terms[..self.slave_terms], self.node)
    }
}

/// The contacts' forces over every dof (`dofs` long): each contact's force on its slave and,
/// equal and opposite, on its master's nodes ([`ContactPoint::nodal_forces`]) — the load
/// vector Cᵀλ of the exact method, the forces the paper's step 4 transfers.
pub fn transferred_forces(contacts: &[ContactPoint], dofs: usize) -> Vec<f64> {
    let mut f = vec![0.0; dofs];
    for c in contacts {
        for (n, share) in c.nodal_forces() {
            for a in 0..3 {
                f[3 * n + a] += share[a];
            }
        }
    }
    f
}

/// The slaves of `contacts`, sorted, each once (the next solve's warm start).
pub fn held_nodes(contacts: &[ContactPoint]) -> Vec<usize> {
    let mut held: Vec<usize> = contacts.iter().map(|c| c.node).collect();
    held.sort_unstable();
    held.dedup();
    held
}

/// The solved contact problem: the displacements and what the contact solve found
/// (its fields are read through the summary: `result.contacts`, `result.iterations`, …).
#[derive(Clone, Debug)]
pub struct ContactResult {
    /// Displacements and support reactions (contact forces excluded).
    pub solution: Solution,
    /// Everything else: the contact points, the cost, the penetration left.
    pub summary: ContactSummary,
}

impl std::ops::Deref for ContactResult {
    type Target = ContactSummary;
    fn deref(&self) -> &ContactSummary {
        &self.summary
    }
}

impl std::ops::DerefMut for ContactResult {
    fn deref_mut(&mut self) -> &mut ContactSummary {
        &mut self.summary
    }
}

/// What a contact solve found besides the displacements (a frame keeps this, and the
/// displacements once, in its own solution).
#[derive(Clone, Debug)]
pub struct ContactSummary {
    /// Active contacts.
    pub contacts: Vec<ContactPoint>,
    /// Method used.
    pub method: ContactMethod,
    /// Iterations.
    pub iterations: usize,
    /// Factorizations of a stiffness matrix.
    pub factorizations: usize,
    /// Substitutions with an existing factor.
    pub substitutions: usize,
    /// Largest penetration at convergence, m (0 when none).
    pub max_penetration: f64,
    /// Time spent in the contact iterations (after the first solve), ms.
    pub contact_ms: f64,
    /// Largest displacement change in the last iteration, m (paper's method; 0 otherwise).
    pub last_change: f64,
    /// The iteration was stopped because a bone's reaction overran its threshold.
    pub stopped_by_threshold: bool,
    /// The active set still changed at the iteration cap (rows that hardly touch joining and
    /// leaving in turn): the last settled set was kept, every contact pushing and the
    /// penetration within the limit, though beyond the tolerance.
    pub at_iteration_cap: bool,
    /// Hand cells solved with the contact (0 without a hand).
    pub region_cells: usize,
    /// Where the time went.
    pub times: ContactTimes,
    /// The contact points embedded in each hand's skin: (hand body, contact index of its
    /// skin's first vertex); the hand's skin vertices are numbered on from there.
    pub skin_points: Vec<(usize, usize)>,
    /// The other bodies' factor (src/solve/objects_factor.rs): `Some(false)` made for this step
    /// (beside its detection, or beside its knot's flexion), `Some(true)` kept from an earlier
    /// step (the same values: an object that stays linear), `None` not made apart (Neo-Hookean
    /// objects, or no contact solved).
    pub objects_kept: Option<bool>,
}

impl ContactSummary {
    /// A contact frame in which nothing touches (no contact solved): `skin_points` as in
    /// [`ContactSummary::skin_points`], the detection's time in ms.
    pub fn without_contacts(
        method: ContactMethod,
        skin_points: Vec<(usize, usize)>,
        detection_ms: f64,
    ) -> ContactSummary {
        ContactSummary {
            contacts: Vec::new(),
            method,
            iterations: 0,
            factorizations: 0,
            substitutions: 0,
            max_penetration: 0.0,
            contact_ms: detection_ms,
            last_change: 0.0,
            stopped_by_threshold: false,
            at_iteration_cap: false,
            region_cells: 0,
            times: ContactTimes {
                detection: detection_ms,
                ..ContactTimes::default()
            },
            skin_points,
            objects_kept: None,
        }
    }

    /// The sum of the normal contact forces, N (a node held against two facets counts twice).
    pub fn normal_force(&self) -> f64 {
        self.contacts.iter().map(|c| c.force).sum()
    }
}

/// Where a contact frame's time went, ms.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ContactTimes {
    /// Surfaces, hierarchies, the pairs and the region solved with the contact.
    pub detection: f64,
    /// Assembly of K on the current geometry.
    pub assembly: f64,
    /// Ordering and symbolic analysis of K11.
    pub symbolic: f64,
    /// Numeric factorizations.
    pub factorization: f64,
    /// Substitutions with the factor (U⁰ and the constraint columns K11⁻¹·Cᵀ).
    pub substitution: f64,
    /// Candidate search on the current geometry.
    pub search: f64,
    /// The active-set (Schur complement) solves.
    pub settle: f64,
    /// Stresses of the frame.
    pub stress: f64,
    /// The other bodies' assembly and factorization, made beside the detection (on the other
    /// core: on the step's way only where the detection ends first).
    pub beside: f64,
}

impl ContactTimes {
    /// Adds the phases of one partitioned solve.
    pub fn add_solve(&mut self, stats: &crate::fem::solve::SolveStats) {
        self.symbolic += stats.symbolic_ms;
        self.factorization += stats.factorization_ms;
        self.substitution += stats.solve_ms;
    }

    /// Adds every phase of `other` (a contact solve nested in another).
    pub fn add(&mut self, other: &ContactTimes) {
        self.detection += other.detection;
        self.assembly += other.assembly;
        self.symbolic += other.symbolic;
        self.factorization += other.factorization;
        self.substitution += other.substitution;
        self.search += other.search;
        self.settle += other.settle;
        self.stress += other.stress;
        self.beside += other.beside;
    }
}

/// Why contact could not be resolved.
#[derive(Debug, Error)]
pub enum ContactError {
    /// The linear solve failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// The active set did not settle.
    #[error(
        "contact did not converge in {iterations} iterations ({method}): {active} nodes active, \
         largest penetration {penetration:.3e} m (tolerance {tolerance:.1e} m){}; {advice}",
        .change.map_or(String::new(), |c| format!(", last change {c:.3e} m"))
    )]
    NotConverged {
        /// Method.
        method: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Active nodes at the end.
        active: usize,
        /// Largest penetration, m.
        penetration: f64,
        /// Tolerance, m.
        tolerance: f64,
        /// Largest displacement change of the last iteration, m (where the method measures it).
        change: Option<f64>,
        /// The cause as the method knows it, and what to do where something is known to help.
        advice: &'static str,
    },
    /// The constraints are dependent (e.g. a node prescribed and in contact).
    #[error(
        "the contact constraints are not independent (Schur complement singular): {active} \
         contacts"
    )]
    Singular {
        /// Active contacts.
        active: usize,
    },
    /// A body is held by nothing: after contact it still moves rigidly.
    #[error(
        "body \"{body}\" is not held: {} % of the forces on it are carried by nothing \
         (it {motion}); {place}give it supports (a [[constraint]]) (in a scene without hands, \
         contact with obstacles is frictionless: they hold a body only along their normals)",
        crate::util::readable(*.held)
    )]
    NotHeld {
        /// The body.
        body: String,
        /// Share of the load not carried, %.
        held: f64,
        /// What it does ("falls", "slides").
        motion: String,
        /// Advice before the supports ("place it on what holds it, or "), or nothing.
        place: String,
    },
    /// Contact and friction cannot hold a body still: it runs away (slides or falls) until only
    /// the weak ground springs of a floating body stop it.
    #[error(
        "contact cannot hold the bodies: node {node} would move {distance:.3e} m ({contacts} \
         contacts, {slipping} slipping); the body slides or falls — give it supports (a \
         [[constraint]]) (in a scene without hands, contact with obstacles is frictionless: more \
         friction does not hold it)"
    )]
    Runaway {
        /// The node moving most.
        node: usize,
        /// How far, m.
        distance: f64,
        /// Active contacts.
        contacts: usize,
        /// Of which slipping.
        slipping: usize,
    },
    /// A node of a held body would move further than the body's own size within one contact
    /// step: not a motion the search is too short for, but a linearised step that diverges
    /// (a soft pressurised ball on a tier that turns its small-strain elements, whose
    /// corrections at the pose swing: the corotational tier on the finger press at 1.12 MPa).
    #[error(
        "node {node} of body \"{body}\" would move {distance:.3e} m within one contact step, \
         more than the body's size ({size:.3e} m): the linearised contact step diverges{advice}"
    )]
    Diverges {
        /// The node, numbered within its body.
        node: usize,
        /// Its body.
        body: String,
        /// How far it would move, m.
        distance: f64,
        /// The longest side of the body's box at rest, m.
        size: f64,
        /// What to change, with its leading separator, or empty.
        advice: String,
    },
    /// A node of a body that its supports (or bones) hold moved more than the contact's reach
    /// allows within one contact step: the contact search is too short for the motion (a
    /// runaway of a held body is not a missing support).
    #[error(
        "node {node} of body \"{body}\" would move {distance:.3e} m within one contact step, \
         more than {factor} × the contact search depth ({search:.1e} m): the search is too \
         short for this motion — raise solver.contact_search (the default is {default:.0e} m)"
    )]
    BeyondSearch {
        /// The node, numbered within its body.
        node: usize,
        /// Its body.
        body: String,
        /// How far it would move, m.
        distance: f64,
        /// The runaway factor.
        factor: f64,
        /// The contact search depth, m.
        search: f64,
        /// The default search depth, m.
        default: f64,
    },
    /// A Neo-Hookean body's tangent stiffness about the state a contact step starts from is
    /// not positive definite: squeezed past a stable state (compressed until it buckles, or
    /// its cells near inversion), no linearised step from there is unique.
    #[error(
        "the tangent stiffness of body \"{body}\" (Neo-Hookean) is not positive definite at its \
         node {node} (at rest at ({:.1}, {:.1}, {:.1}) mm): the press has squeezed it past a stable state (it buckles or its cells \
         near inversion)",
        rest[0] * 1e3,
        rest[1] * 1e3,
        rest[2] * 1e3
    )]
    Unstable {
        /// The body.
        body: String,
        /// The node at the failing pivot, numbered within its body.
        node: usize,
        /// Its position at rest, m.
        rest: [f64; 3],
    },
    /// The step's displacements turn an element of a pressed body inside out.
    #[error(
        "the step turns element {element} of body \"{body}\" inside out (det J / size³ = \
         {relative_det:.3e}): the press goes further than its mesh follows in one step"
    )]
    Inverts {
        /// The body.
        body: String,
        /// The element, numbered within its body.
        element: usize,
        /// Its relative Jacobian determinant (or det F for a Neo-Hookean body).
        relative_det: f64,
    },
    /// A node of one body is inside another and the contact does not hold it: beyond what
    /// contact detection reaches, or where the other body's facets fold around it further than
    /// one linearised step follows.
    #[error(
        "{place} lies {depth_mm:.1} mm inside body \"{other}\" and the contact does not hold \
         it: {advice}"
    )]
    TooDeep {
        /// Where: the penetrating body, its node or skin point (with the bone under it) and
        /// its position.
        place: String,
        /// The penetrated body.
        other: String,
        /// Estimated depth, mm.
        depth_mm: f64,
        /// The search depth, mm.
        search_mm: f64,
        /// Why, and what to change: deeper than the search depth, raise it; otherwise the
        /// diagnosis, the facets fold around it (`solve::grasp::too_deep`).
        advice: String,
    },
}
