//! Why a frame could not be solved: the one error type of the solve stage.

use crate::contact::ContactError;
use crate::fem::solve::SolveError;
use crate::model::Model;
use thiserror::Error;

/// Why a frame could not be solved.
#[derive(Debug, Error)]
pub enum SimError {
    /// An element is inverted or flat.
    #[error("body \"{body}\": element {element} is inverted or has zero volume (smallest det J / size³ = {relative_det:.3e})")]
    InvertedElement {
        /// The body.
        body: String,
        /// The element, numbered within its body.
        element: usize,
        /// Its smallest relative Jacobian.
        relative_det: f64,
    },
    /// A flexion increment would turn a flesh element inside out even after halving the step.
    #[error(
        "body \"{body}\": flesh element {element} (at rest near [{:.1}, {:.1}, {:.1}] mm) would turn \
         inside out as {joint} reaches {angle:.1}°, even with the increment halved four times: \
         the flesh is crushed (in a crease of the joint, or between bones that come too close \
         for it); {}",
        rest_position_mm[0], rest_position_mm[1], rest_position_mm[2],
        stop_short_advice(*self_contact, *share)
    )]
    FleshCrushed {
        /// The hand body.
        body: String,
        /// The element, numbered within the hand.
        element: usize,
        /// Its centre in the rest pose, mm.
        rest_position_mm: [f64; 3],
        /// The joint moving most.
        joint: String,
        /// Its angle at the failing increment, degrees.
        angle: f64,
        /// Whether the skin's self-contact was on.
        self_contact: bool,
        /// The share of the keyframe's motion (from the pose before it) at which the failing
        /// increment ended, once the driver knows the keyframe.
        share: Option<f64>,
    },
    /// A flexion increment's self-contact did not settle, even after halving the step.
    #[error(
        "body \"{body}\": the skin's self-contact did not settle as {joint} reaches {angle:.1}°, \
         even with the increment halved four times ({reason}); {}",
        stop_short_advice(true, *share)
    )]
    SelfContactUnsettled {
        /// The hand body.
        body: String,
        /// The joint moving most.
        joint: String,
        /// Its angle at the failing increment, degrees.
        angle: f64,
        /// Why the increment's Newton with the self-contact's barrier failed.
        reason: String,
        /// As [`SimError::FleshCrushed::share`].
        share: Option<f64>,
    },
    /// A nonlinear flexion increment found no equilibrium, even at the smallest step allowed.
    #[error(
        "body \"{body}\": the nonlinear flexion found no equilibrium as {joint} reaches \
         {angle:.2}°, with the increment halved {halvings} times (to {step_deg:.3}°): {reason}"
    )]
    FlexionNoEquilibrium {
        /// The hand body.
        body: String,
        /// The moved joint nearest to the trouble (or the one moving most).
        joint: String,
        /// That joint's angle at the failing increment, degrees.
        angle: f64,
        /// The size of the failing increment, degrees of the joint moving most.
        step_deg: f64,
        /// Halvings done.
        halvings: usize,
        /// Why Newton failed.
        reason: String,
    },
    /// The linear tier's one solve from rest turns a flesh element inside out (no increment to
    /// halve: the rotation is too large for small-strain elasticity on the rest geometry).
    #[error(
        "body \"{body}\": the linear tier (small strain on the rest geometry) turns flesh element \
         {element} (at rest near [{:.1}, {:.1}, {:.1}] mm) inside out as {joint} reaches \
         {angle:.1}°: a rotation this large is outside linear elasticity; use tier \
         \"corotational\" or \"incremental\"",
        rest_position_mm[0], rest_position_mm[1], rest_position_mm[2]
    )]
    LinearTierInverted {
        /// The hand body.
        body: String,
        /// The element, numbered within the hand.
        element: usize,
        /// Its centre in the rest pose, mm.
        rest_position_mm: [f64; 3],
        /// The moved joint nearest to it.
        joint: String,
        /// That joint's angle, degrees.
        angle: f64,
    },
    /// Contact could not be resolved.
    #[error(transparent)]
    Contact(ContactError),
    /// A newer request made this solve stale: it stopped between two increments.
    #[error("cancelled: a newer request replaced this solve")]
    Cancelled,
    /// No pressure of a gas cavity satisfies its gas law (p·V = P0·V0).
    #[error("gas cavity \"{load}\": {reason}")]
    Gas {
        /// The load that is the cavity.
        load: String,
        /// Why, and what to do.
        reason: String,
    },
    /// A combination of settings the solver does not support yet.
    #[error("{0}")]
    Unsupported(String),
    /// The paper's contact iteration (`[solver] contact = "paper"`) failed in the smallest
    /// contact step along a keyframe's motion: a failure of the method, not a limit of the
    /// grasp, so no frame is given for it.
    #[error(
        "the paper's contact iteration could not follow the motion beyond {:.0} % of the \
         keyframe, even in its smallest contact step ({}). Solve the scene with `[solver] \
         contact = \"lagrange\"`, which resolves the contact exactly along the motion",
        reached * 100.0,
        what_failed(cause)
    )]
    PaperCannotFollow {
        /// The fraction of the keyframe's motion its last converged step reached.
        reached: f64,
        /// The contact error of the smallest step.
        cause: ContactError,
    },
    /// The nonlinear tier failed (`[solver] tier = "nonlinear"`).
    #[error("body \"{body}\"{}: {source}{advice}", element_note(.element))]
    Nonlinear {
        /// The body (all bodies' names when no element is to blame).
        body: String,
        /// The inverted element, numbered within its body, if one is to blame.
        element: Option<usize>,
        /// Why.
        source: Box<crate::fem::NonlinearError>,
        /// What to ask instead (empty, or a sentence beginning with ". ").
        advice: String,
    },
    /// A keyframe failed on a scene whose static frame already strains a body far beyond
    /// small-strain elasticity (`state::STRAIN_WARNING`): that is the cause to mend first.
    #[error(
        "body \"{body}\" strains {:.0} % under its own loads (the static frame{}): far outside \
         small-strain elasticity, whose displacements grow as 1/E without bound, so {} cannot be \
         solved on it ({}). Make the body stiffer — {advice} — or its loads {}× smaller",
        strain * 100.0,
        if *hands { ", before any hand moves" } else { "" },
        if *hands { "the grasp" } else { "the scene" },
        brief(cause),
        times(*factor)
    )]
    BeyondSmallStrain {
        /// The body.
        body: String,
        /// Whether the scene has hands (the words of the message).
        hands: bool,
        /// Its largest principal strain in the static frame.
        strain: f64,
        /// The factor by which its Young's moduli must grow (or its loads shrink) for the
        /// strain of its loads alone to be half `STRAIN_WARNING` (linear elasticity scales
        /// exactly; the half leaves room for what contact with obstacles adds).
        factor: f64,
        /// Each of its materials with the Young's modulus that does it.
        advice: String,
        /// The error the keyframe met.
        cause: Box<SimError>,
    },
    /// As [`SimError::BeyondSmallStrain`], where an obstacle cuts the strained body at rest:
    /// the static frame pushed the body out of it, and that is what strains it.
    #[error(
        "obstacle \"{obstacle}\" cuts body \"{body}\" at rest: the body's nodes lie up to \
         {:.1} mm behind its surface (the body is {:.1} mm across), and pushing them out \
         strains the body {:.0} % in the static frame, before any hand moves — far outside \
         small-strain elasticity, so the grasp cannot be solved on it ({cause}). Move the \
         obstacle clear of the body at rest (an overlap of a few per cent of the body's size is \
         a squeeze the contact resolves)",
        depth * 1e3,
        size * 1e3,
        strain * 100.0
    )]
    ObstacleCutsBody {
        /// The obstacle.
        obstacle: String,
        /// The body.
        body: String,
        /// How far its deepest node lies behind the obstacle's surface at rest, m.
        depth: f64,
        /// The body's size, m.
        size: f64,
        /// Its largest principal strain in the static frame.
        strain: f64,
        /// The error the keyframe met.
        cause: Box<SimError>,
    },
    /// A solved value overflowed: nothing is written or shown.
    #[error(
        "body \"{}\": the {} at {} is {} — the scene's magnitudes overflow double precision, \
         so nothing was written. {advice}",
        .value.body, .value.quantity, .value.at, .value.value
    )]
    NonFinite {
        /// The value, its quantity and where.
        value: Box<crate::state::NonFinite>,
        /// The scene's extreme magnitudes, the likely cause, and what to do.
        advice: String,
    },
    /// The stiffness lost positive definiteness to rounding on a body so slender, and so
    /// finely cut along its length, that its bending stiffness is below double precision.
    #[error(
        "body \"{body}\": the factorization of its stiffness met a pivot that is not positive \
         (pivot {pivot} of {equations}, node {node}), yet the constraints hold it (no rigid \
         motion is left): the body is {slenderness:.0} times longer than it is thick and cut into about {cells:.0} \
         cells along its length, so its bending stiffness is below the rounding error of its \
         stretching stiffness (their ratio falls as (slenderness × cells along)², here \
         {:.1e}, and double precision holds to about 1e16). Make (length / thickness) × (cells \
         along the length) at most 1e8: a thicker or shorter body, or fewer cells along it",
        (slenderness * cells).powi(2)
    )]
    TooSlender {
        /// The body.
        body: String,
        /// Its longest over its shortest extent.
        slenderness: f64,
        /// About how many cells it has along its longest extent.
        cells: f64,
        /// Elimination step that failed.
        pivot: usize,
        /// Equations in all.
        equations: usize,
        /// A node (of the model) whose dof sits at that pivot.
        node: usize,
    },
    /// The linear solve failed.
    #[error("body \"{body}\": {source}")]
    Solve {
        /// The body the failing dof belongs to.
        body: String,
        /// Why.
        source: SolveError,
    },
}

/// (Longest / shortest extent) × (cells along the longest) above which a pivot lost is told as
/// the body's slenderness: 1e16, double precision, is this squared (a body at 1e3 × 1e5 solves;
/// 1e4 × 1e5 loses a pivot).
const SLENDER: f64 = 1e8;

/// A body's longest over its shortest bounding-box extent, and about how many cells it has along
/// the longest (that extent over the cells' mean extent along it).
fn slenderness(model: &Model, body: &crate::model::BodyModel) -> (f64, f64) {
    let nodes = &model.mesh.nodes[body.nodes.clone()];
    let Some(first) = nodes.first() else {
        return (1.0, 1.0);
    };
    let (lo, hi) = nodes
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let extent = hi - lo;
    let axis = extent.imax();
    let (longest, shortest) = (extent.max(), extent.min());
    if shortest.is_nan() || shortest <= 0.0 || body.cells.is_empty() {
        return (1.0, 1.0);
    }
    let along: f64 = body
        .cells
        .clone()
        .map(|c| {
            let x = model.mesh.cell_coords(c).map(|p| p[axis]);
            let (a, b) = x
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            b - a
        })
        .sum::<f64>()
        / body.cells.len() as f64;
    let cells = if along > 0.0 { longest / along } else { 1.0 };
    (longest / shortest, cells)
}

/// A factor with three significant digits (12.3, 1.23, 5565).
fn times(factor: f64) -> String {
    match factor {
        f if f >= 100.0 => format!("{f:.0}"),
        f if f >= 10.0 => format!("{f:.1}"),
        f => format!("{f:.2}"),
    }
}

fn element_note(element: &Option<usize>) -> String {
    element.map_or(String::new(), |e| format!(" (its element {e})"))
}

/// The constraint prescribing the largest displacement of any dof, and its size (m).
fn largest_prescribed(model: &Model) -> Option<(&crate::model::ConstraintModel, f64)> {
    model
        .constraints
        .iter()
        .flat_map(|c| c.dofs.iter().map(move |&d| (c, model.prescribed[d].abs())))
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// What to ask of a nonlinear static solve that found equilibrium up to the share `reached` of
/// its loads and prescribed displacements (scaled together) and no further: that share, and the
/// largest prescribed displacement against the scene's size where it exceeds a tenth of it.
pub(crate) fn scaled_back(model: &Model, reached: f64) -> String {
    let size = model.mesh.bounding_size();
    let largest = largest_prescribed(model).filter(|&(_, d)| d > 0.1 * size);
    let displacement = largest.map_or(String::new(), |(c, d)| {
        format!(
            " (constraint \"{}\" prescribes {d:.3e} m, {:.0} % of the scene's size {size:.3e} m: \
             {:.3e} m is reached)",
            c.name,
            100.0 * d / size,
            d * reached
        )
    });
    if reached <= 0.0 {
        return format!(
            ". No share of the loads and prescribed displacements{displacement} found an \
             equilibrium: make them smaller, or the body stiffer"
        );
    }
    format!(
        ". Equilibrium was found up to {:.1} % of the loads and prescribed displacements, scaled \
         together{displacement}: ask for less than that, or make the body stiffer",
        100.0 * reached
    )
}

impl SimError {
    /// `frame` unless one of its values is not finite: then the error naming it, with the
    /// scene's largest load and softest material as the likely cause.
    pub(crate) fn finite(
        model: &Model,
        frame: crate::state::Frame,
    ) -> Result<crate::state::Frame, SimError> {
        let Some(value) = crate::state::first_non_finite(model, &frame) else {
            return Ok(frame);
        };
        let mut advice = Vec::new();
        let largest = model
            .loads
            .iter()
            .max_by(|a, b| a.total.amax().total_cmp(&b.total.amax()));
        // The bodies' weight, when it outweighs every load (or is not finite): `[world]
        // gravity` is then the load to look at.
        let weight = model.gravity_total;
        let gravity = model.gravity.filter(|_| {
            !weight.amax().is_finite() || largest.is_none_or(|l| weight.amax() > l.total.amax())
        });
        if let Some(g) = gravity {
            advice.push(format!(
                "[world] gravity = [{:.3e}, {:.3e}, {:.3e}] m/s² weighs [{:.3e}, {:.3e}, {:.3e}] \
                 N in all",
                g.x, g.y, g.z, weight.x, weight.y, weight.z
            ));
        }
        if let Some(load) = largest {
            let t = load.total;
            advice.push(format!(
                "its largest load is \"{}\", [{:.3e}, {:.3e}, {:.3e}] N in all",
                load.name, t.x, t.y, t.z
            ));
        }
        // The largest prescribed displacement, when it exceeds the scene's own size (an
        // overflowing one cannot be told by the loads and moduli).
        let size = model.mesh.bounding_size();
        if let Some((c, d)) = largest_prescribed(model).filter(|&(_, d)| d > size || d.is_nan()) {
            advice.push(format!(
                "constraint \"{}\" prescribes a displacement of {d:.3e} m, beyond the scene's \
                 size ({size:.3e} m)",
                c.name
            ));
        }
        if let Some((i, m)) = model
            .cell_materials
            .iter()
            .zip(&model.cell_material)
            .min_by(|a, b| a.0.young.total_cmp(&b.0.young))
            .map(|(m, &i)| (i, m))
        {
            advice.push(format!(
                "its softest material is \"{}\", E = {:.3e} Pa",
                model.material_names.get(i).map_or("?", String::as_str),
                m.young
            ));
        }
        let advice = format!(
            "Check the units (N, Pa, m, kg/m³) and bring the loads, displacements and moduli to \
             physical values{}",
            if advice.is_empty() {
                String::new()
            } else {
                format!(": {}", advice.join("; "))
            }
        );
        Err(SimError::NonFinite {
            value: Box::new(value),
            advice,
        })
    }

    /// Cell `cell` of the model (numbered in the whole mesh) is inverted or flat.
    pub(crate) fn inverted(model: &Model, cell: usize, relative_det: f64) -> SimError {
        let b = model.cell_body[cell];
        SimError::InvertedElement {
            body: model.bodies[b].name.clone(),
            element: cell - model.bodies[b].cells.start,
            relative_det,
        }
    }

    /// A linear solve of the whole model failed: named after the body of the failing node, or
    /// after every body when no node is to blame.
    pub(crate) fn solve(model: &Model, source: SolveError) -> SimError {
        let body = match &source {
            &SolveError::NotPositiveDefinite {
                node,
                pivot,
                equations,
            } => {
                let b = &model.bodies[model.body_of_node(node)];
                let (slenderness, cells) = slenderness(model, b);
                if slenderness * cells > SLENDER {
                    return SimError::TooSlender {
                        body: b.name.clone(),
                        slenderness,
                        cells,
                        pivot,
                        equations,
                        node: node - b.nodes.start,
                    };
                }
                b.name.clone()
            }
            _ => model
                .bodies
                .iter()
                .map(|b| b.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        };
        SimError::Solve { body, source }
    }
}

/// Each material of body `b` once (regions may give a cell another material), with the Young's
/// modulus `factor` times its own: "material \"rubber\": Young's modulus ≥ 2.240e6 Pa (now
/// 1.120e6)", joined by commas.
pub(crate) fn stiffer_materials(model: &Model, b: usize, factor: f64) -> String {
    let mut materials: Vec<(usize, f64)> = model.bodies[b]
        .cells
        .clone()
        .map(|c| (model.cell_material[c], model.cell_materials[c].young))
        .collect();
    materials.sort_by_key(|m| m.0);
    materials.dedup_by_key(|m| m.0);
    materials
        .iter()
        .map(|&(m, young)| {
            format!(
                "material \"{}\": Young's modulus ≥ {:.3e} Pa (now {young:.3e})",
                model.material_name(m),
                young * factor
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// What went wrong in `cause`, without the advice it gives for a cause of its own: where the
/// static frame's strain is the cause to mend, a runaway body is not one to "give supports"
/// (it has them: the strain tore it off them).
fn brief(cause: &SimError) -> String {
    match cause {
        SimError::Contact(ContactError::Runaway {
            node,
            distance,
            contacts,
            slipping,
        }) => format!(
            "contact cannot hold the bodies: node {node} would move {distance:.3e} m ({contacts} \
             contacts, {slipping} slipping)"
        ),
        SimError::Contact(ContactError::NotHeld {
            body, held, motion, ..
        }) => format!(
            "body \"{body}\" is not held: {} % of the forces on it are carried by nothing (it \
             {motion})",
            crate::util::readable(*held)
        ),
        SimError::Contact(c) => what_failed(c),
        other => other.to_string(),
    }
}

/// What a contact step of the paper's iteration met, without the advice its own message gives
/// (raise the iterations): for the paper's iteration the advice that
/// works is the exact method, which [`SimError::PaperCannotFollow`] gives.
pub(crate) fn what_failed(cause: &ContactError) -> String {
    match cause {
        ContactError::NotConverged {
            iterations,
            penetration,
            change,
            ..
        } => match change {
            Some(change) => format!(
                "it did not converge in {iterations} iterations: the displacements still \
                 changed by {change:.3e} m, largest penetration {penetration:.3e} m"
            ),
            None => format!(
                "it did not converge in {iterations} iterations: largest penetration \
                 {penetration:.3e} m"
            ),
        },
        ContactError::TooDeep {
            place,
            other,
            depth_mm,
            ..
        } => format!("it left {place} {depth_mm:.1} mm inside body \"{other}\""),
        other => other.to_string(),
    }
}

/// The advice of a flexion that failed within a keyframe: stop the motion short of where it
/// failed (every increment before it was solved, so a keyframe ending there is reached), and,
/// with the self-contact on, turn it off (the flexion without it passes; the skin may then
/// pass through itself). `share`: where the motion failed, as a share of the keyframe's.
fn stop_short_advice(self_contact: bool, share: Option<f64>) -> String {
    let short = match share {
        Some(share) => format!(
            "pose the frame short of that (its keyframe; for the first frame, the body's \
             `pose`): the motion failed at {:.1} % of its way from the pose before it (a pose \
             with every joint's motion scaled to less than that is reached)",
            100.0 * share
        ),
        None => "stop the joints short of those angles".into(),
    };
    if self_contact {
        format!(
            "{short}, or set solver.self_contact = false (the skin may then pass through itself)"
        )
    } else {
        short
    }
}

/// `error` from the flexion of a keyframe, given the share of the keyframe's motion where it
/// failed: `share_of(body, joint, angle)` measures the failing joint's angle along its own
/// motion in the keyframe (every joint of a hand moves in proportion).
pub(crate) fn with_keyframe_share(
    mut error: SimError,
    share_of: impl Fn(&str, &str, f64) -> Option<f64>,
) -> SimError {
    if let SimError::FleshCrushed {
        body,
        joint,
        angle,
        share,
        ..
    }
    | SimError::SelfContactUnsettled {
        body,
        joint,
        angle,
        share,
        ..
    } = &mut error
    {
        if share.is_none() {
            *share = share_of(body, joint, *angle);
        }
    }
    error
}
