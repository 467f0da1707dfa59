//! Resolution of a scene selection to the nodes and boundary facets of one body.

use super::names::shown;
use super::BodyModel;
use crate::mesh::{Facet, Mesh};
use crate::scene::{Selection, Shape};
use nalgebra::Vector3;

/// The nodes (sorted, global indices) and boundary facets a selection picks on a body.
pub struct Selected {
    /// Selected nodes.
    pub nodes: Vec<usize>,
    /// Selected boundary facets (empty for a point).
    pub facets: Vec<Facet>,
}

/// Resolves `selection` on `body`; the error says why it cannot be used (never empty on success).
pub fn select(body: &BodyModel, mesh: &Mesh, selection: &Selection) -> Result<Selected, String> {
    let nodes_in = |pred: &dyn Fn(&Vector3<f64>) -> bool| -> Vec<usize> {
        body.nodes
            .clone()
            .filter(|&n| pred(&mesh.nodes[n]))
            .collect()
    };
    let facets_on = |pred: &dyn Fn(&Vector3<f64>) -> bool| -> Vec<Facet> {
        body.facets
            .iter()
            .filter(|f| f.nodes.iter().all(|&n| pred(&mesh.nodes[n])))
            .copied()
            .collect()
    };
    let facet_nodes = |facets: &[Facet]| -> Vec<usize> {
        let mut nodes: Vec<usize> = facets.iter().flat_map(|f| f.nodes).collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    };
    let selected = match selection {
        Selection::Face(face) => {
            let Shape::Box { min, max, .. } = body.shape else {
                return Err(format!(
                    "face = \"{}\" applies to box bodies only; body \"{}\" is not a box \
                     (use surface, box or point)",
                    shown(face),
                    shown(&body.name)
                ));
            };
            let (axis, value) = match face.as_str() {
                "x-" => (0, min[0]),
                "x+" => (0, max[0]),
                "y-" => (1, min[1]),
                "y+" => (1, max[1]),
                "z-" => (2, min[2]),
                "z+" => (2, max[2]),
                other => {
                    return Err(format!(
                        "face = \"{}\" is not a box face (x- x+ y- y+ z- z+)",
                        shown(other)
                    ))
                }
            };
            let tol = 1e-9 * body.size;
            let on = move |p: &Vector3<f64>| (p[axis] - value).abs() <= tol;
            Selected {
                nodes: nodes_in(&on),
                facets: facets_on(&on),
            }
        }
        Selection::Surface(which) => {
            let facets: Vec<Facet> = match (which.as_str(), &body.shape) {
                (
                    "outer",
                    Shape::Shell {
                        center,
                        inner_radius,
                        outer_radius,
                        ..
                    },
                ) => {
                    let (c, mid) = (Vector3::from(*center), 0.5 * (inner_radius + outer_radius));
                    body.facets
                        .iter()
                        .filter(|f| facet_radius(mesh, f, &c) > mid)
                        .copied()
                        .collect()
                }
                (
                    "inner",
                    Shape::Shell {
                        center,
                        inner_radius,
                        outer_radius,
                        ..
                    },
                ) => {
                    let (c, mid) = (Vector3::from(*center), 0.5 * (inner_radius + outer_radius));
                    body.facets
                        .iter()
                        .filter(|f| facet_radius(mesh, f, &c) < mid)
                        .copied()
                        .collect()
                }
                ("outer", _) => body.facets.clone(),
                ("inner", _) => {
                    return Err(format!(
                        "surface = \"inner\" needs a shell body; body \"{}\" has no cavity",
                        shown(&body.name)
                    ))
                }
                (other, _) => {
                    return Err(format!(
                        "surface = \"{}\" is not a surface (outer, inner)",
                        shown(other)
                    ))
                }
            };
            Selected {
                nodes: facet_nodes(&facets),
                facets,
            }
        }
        Selection::Point(p) => {
            if !p.iter().all(|x| x.is_finite()) {
                return Err(format!("point = {p:?} is not a finite point"));
            }
            // |x − p|² = |p|² + s·(|x|²/s − 2·(p/s)·x), s = max(1, |p|∞): the nearest node
            // minimises the bracket, which neither overflows nor loses the nodes' differences
            // to |p|² for a far point (1e300 m picked node 0, every distance infinite).
            // (Only for a far point: near, |x − p|² itself, which keeps exact ties exact.)
            let q = Vector3::from(*p);
            let s = q.amax().max(1.0);
            let key = |n: usize| {
                let x = mesh.nodes[n];
                if s < 1e150 {
                    (x - q).norm_squared()
                } else {
                    x.norm_squared() / s - 2.0 * (q / s).dot(&x)
                }
            };
            let nearest = body
                .nodes
                .clone()
                .min_by(|&a, &b| key(a).total_cmp(&key(b)))
                .ok_or("the body has no node")?;
            Selected {
                nodes: vec![nearest],
                facets: Vec::new(),
            }
        }
        Selection::Bone(name) => {
            let Some(hand) = &body.hand else {
                return Err(format!(
                    "bone = \"{}\" applies to hand bodies only; body \"{}\" is not a hand",
                    shown(name),
                    shown(&body.name)
                ));
            };
            let Some(b) = hand.skeleton.bone_index(name) else {
                return Err(format!(
                    "there is no bone \"{}\"; the bones are: {}",
                    shown(name),
                    hand.skeleton.bone_names()
                ));
            };
            Selected {
                nodes: hand
                    .bone_nodes(b)
                    .into_iter()
                    .map(|n| n + body.nodes.start)
                    .collect(),
                facets: Vec::new(),
            }
        }
        Selection::Box { min, max } => {
            let tol = 1e-9 * body.size;
            let (lo, hi) = (Vector3::from(*min), Vector3::from(*max));
            let inside =
                move |p: &Vector3<f64>| (0..3).all(|i| p[i] >= lo[i] - tol && p[i] <= hi[i] + tol);
            Selected {
                nodes: nodes_in(&inside),
                facets: facets_on(&inside),
            }
        }
    };
    if selected.nodes.is_empty() {
        return Err(format!("selects no node of body \"{}\"", shown(&body.name)));
    }
    Ok(selected)
}

/// How far the farthest node of facet `f` lies from `c`. A shell's nodes lie on spheres: its
/// inner facets' nodes at the inner radius, its outer facets' at the outer one (a facet's
/// centroid lies below its nodes' sphere, by 12 % of the radius on the coarsest shell: by the
/// centroid, its outer facets would pass for inner ones).
fn facet_radius(mesh: &Mesh, f: &Facet, c: &Vector3<f64>) -> f64 {
    f.nodes
        .iter()
        .map(|&n| mesh.nodes[n].metric_distance(c))
        .fold(0.0, f64::max)
}

/// |a − b|, m, scaled by the largest component so that it does not overflow (a point 1e300 m
/// away is that far, not infinitely: 1e300² is beyond f64).
pub(crate) fn distance(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let d = a - b;
    let s = d.amax();
    if s > 0.0 && s.is_finite() {
        s * (d / s).norm()
    } else {
        s
    }
}
