//! Whether the contact forces of a grip hold an object: grasp analysis of a rigid body.
//!
//! The grip presses on the object with normal forces λ_i along the inward normals d_i at the
//! points p_i (what the FEM found). Without any support, the object stays put if friction
//! forces t_i in the contacts' tangent planes, each within its Coulomb cone |t_i| ≤ μ_i·λ_i,
//! balance the load W (its weight, at its centre c) together with the normal forces:
//!
//!   Σ (λ_i d_i + t_i) + W = 0,   Σ (p_i − c) × (λ_i d_i + t_i) = 0.
//!
//! The friction the hold needs is the least s with every |t_i| ≤ s·μ_i·λ_i — a second-order
//! cone programme (minimise s over t and s, the equilibrium as equalities, one Lorentz cone per
//! contact), solved by interior point (`clarabel`). Its inverse, 1/s, is the grip's safety
//! margin on friction: 1 holds just so, 2 holds with friction halved (the grip-force to
//! load-force ratio of human grasping above the slip ratio, Westling & Johansson 1984). The
//! normal forces are taken as they are: a grip whose normal forces do not balance (a thumb
//! pushing the object into a stand) needs friction for that too, as it would once the stand is
//! gone. Friction cannot twist about a contact's normal here (point contacts, no torsional
//! friction): conservative.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nalgebra::Vector3;

/// One contact of the grip on the object.
#[derive(Clone, Copy, Debug)]
pub struct GripContact {
    /// Where it acts, m.
    pub point: Vector3<f64>,
    /// Unit normal into the object (the direction of the normal force on it).
    pub inward: Vector3<f64>,
    /// Normal force on the object, N (≥ 0).
    pub normal_force: f64,
    /// Coulomb friction coefficient of the contact.
    pub friction: f64,
}

/// The margin reported when the normal forces hold the load without friction (a ball lying in
/// a cupped palm): a grip that needs a millionth of its friction holds at any μ worth the name.
pub const MAX_MARGIN: f64 = 1e6;

/// How the grip holds the load.
#[derive(Clone, Debug, PartialEq)]
pub struct HoldMargin {
    /// 1 / (the share of each contact's friction cone the best distribution of friction
    /// needs), capped at [`MAX_MARGIN`]; 0 when no friction within the cones, however large,
    /// balances the load (a contact pushes where nothing opposes it).
    pub margin: f64,
    /// The friction force of each contact in that distribution, N (zero where it cannot hold).
    pub friction: Vec<Vector3<f64>>,
}

/// The friction margin with which `contacts` hold a rigid object whose centre is `centre` (m)
/// against the load `load` (N, applied at the centre); `size` (m, the object's size) scales
/// the moment equations.
pub fn hold_margin(
    contacts: &[GripContact],
    centre: &Vector3<f64>,
    load: &Vector3<f64>,
    size: f64,
) -> HoldMargin {
    let none = || HoldMargin {
        margin: 0.0,
        friction: vec![Vector3::zeros(); contacts.len()],
    };
    let largest = contacts
        .iter()
        .map(|c| c.normal_force)
        .fold(0.0, f64::max)
        .max(load.norm());
    if !(largest > 0.0 && largest.is_finite() && size > 0.0 && size.is_finite()) {
        return none();
    }
    // Forces in units of the largest, lengths in units of the size: the programme is well
    // scaled whatever the grip.
    let f = 1.0 / largest;
    // Contacts pressing with a real force and a friction cone (the others carry nothing).
    let active: Vec<usize> = (0..contacts.len())
        .filter(|&i| {
            let c = &contacts[i];
            c.normal_force * f > 1e-9 && c.friction > 0.0 && c.friction.is_finite()
        })
        .collect();
    // The wrench friction must supply: −W − Σ λ_i d_i and −Σ (p_i − c) × λ_i d_i.
    let mut need = [0.0; 6];
    for c in contacts {
        let force = c.inward * c.normal_force * f;
        let arm = (c.point - centre) / size;
        let moment = arm.cross(&force);
        for a in 0..3 {
            need[a] -= force[a];
            need[3 + a] -= moment[a];
        }
    }
    for a in 0..3 {
        need[a] -= load[a] * f;
    }
    // Each active contact's tangent basis, and its friction's column in the six equations.
    let bases: Vec<[Vector3<f64>; 2]> = active
        .iter()
        .map(|&i| tangent_basis(&contacts[i].inward))
        .collect();
    let column = |k: usize, e: &Vector3<f64>| -> [f64; 6] {
        let arm = (contacts[active[k]].point - centre) / size;
        let m = arm.cross(e);
        [e.x, e.y, e.z, m.x, m.y, m.z]
    };
    let vars = 1 + 2 * active.len();
    let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    let mut b = Vec::new();
    // Equilibrium rows; a row no friction enters (a moment about the axis through every
    // contact) holds only if nothing is needed there.
    let mut equations = 0;
    for r in 0..6 {
        let entries: Vec<(usize, f64)> = (0..active.len())
            .flat_map(|k| {
                let (c1, c2) = (column(k, &bases[k][0]), column(k, &bases[k][1]));
                [(1 + 2 * k, c1[r]), (2 + 2 * k, c2[r])]
            })
            .filter(|e| e.1.abs() > 1e-12)
            .collect();
        if entries.is_empty() {
            if need[r].abs() > 1e-9 {
                return none();
            }
            continue;
        }
        for (c, v) in entries {
            rows.push(equations);
            cols.push(c);
            vals.push(v);
        }
        b.push(need[r]);
        equations += 1;
    }
    if active.is_empty() {
        // Nothing can supply friction; held only if nothing is needed.
        let needed = need.iter().map(|v| v.abs()).fold(0.0, f64::max);
        return if needed <= 1e-9 {
            HoldMargin {
                margin: MAX_MARGIN,
                friction: vec![Vector3::zeros(); contacts.len()],
            }
        } else {
            none()
        };
    }
    // One Lorentz cone per contact: (s·μ_i·λ_i, a_i, b_i), written as b − A·x in the cone.
    for (k, &i) in active.iter().enumerate() {
        let c = &contacts[i];
        let r = equations + 3 * k;
        rows.extend([r, r + 1, r + 2]);
        cols.extend([0, 1 + 2 * k, 2 + 2 * k]);
        vals.extend([-c.friction * c.normal_force * f, -1.0, -1.0]);
        b.extend([0.0, 0.0, 0.0]);
    }
    let m = equations + 3 * active.len();
    let a = CscMatrix::new_from_triplets(m, vars, rows, cols, vals);
    let p = CscMatrix::zeros((vars, vars));
    let mut q = vec![0.0; vars];
    q[0] = 1.0;
    let mut cones: Vec<SupportedConeT<f64>> = vec![SupportedConeT::ZeroConeT(equations)];
    cones.extend(active.iter().map(|_| SupportedConeT::SecondOrderConeT(3)));
    let settings = DefaultSettings {
        verbose: false,
        ..DefaultSettings::default()
    };
    let Ok(mut solver) = DefaultSolver::new(&p, &q, &a, &b, &cones, settings) else {
        return none();
    };
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        _ => return none(),
    }
    let x = &solver.solution.x;
    if !x.iter().all(|v| v.is_finite()) {
        return none();
    }
    let share = x[0].max(0.0);
    let mut friction = vec![Vector3::zeros(); contacts.len()];
    for (k, &i) in active.iter().enumerate() {
        friction[i] = (bases[k][0] * x[1 + 2 * k] + bases[k][1] * x[2 + 2 * k]) / f;
    }
    let margin = if share * MAX_MARGIN <= 1.0 {
        MAX_MARGIN
    } else {
        1.0 / share
    };
    HoldMargin { margin, friction }
}

/// Two unit vectors spanning the plane normal to the unit vector `n`.
fn tangent_basis(n: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = n.cross(&helper).normalize();
    [e1, n.cross(&e1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pinch: two pads pressing a ball of radius r from either side along x with λ each, the
    /// weight W along −z. Friction needed: W/2 at each pad, so the margin is 2·μ·λ/W.
    fn pinch(lambda: f64, mu: f64, weight: f64) -> HoldMargin {
        let r = 0.02;
        let contacts = [
            GripContact {
                point: Vector3::new(-r, 0.0, 0.0),
                inward: Vector3::x(),
                normal_force: lambda,
                friction: mu,
            },
            GripContact {
                point: Vector3::new(r, 0.0, 0.0),
                inward: -Vector3::x(),
                normal_force: lambda,
                friction: mu,
            },
        ];
        hold_margin(
            &contacts,
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, -weight),
            2.0 * r,
        )
    }

    #[test]
    fn a_pinch_holds_with_the_margin_two_mu_lambda_over_the_weight() {
        for (lambda, mu, w) in [(3.0, 0.5, 1.0), (1.0, 0.8, 0.5), (10.0, 0.2, 2.0)] {
            let h = pinch(lambda, mu, w);
            let exact = 2.0 * mu * lambda / w;
            assert!(
                (h.margin - exact).abs() < 1e-6 * exact,
                "λ {lambda} μ {mu} W {w}: margin {} against {exact}",
                h.margin
            );
            // The friction found balances the weight, half at each pad, straight up.
            for t in &h.friction {
                assert!((t - Vector3::new(0.0, 0.0, w / 2.0)).norm() < 1e-6 * w);
            }
        }
        // Twice the weight halves the margin; twice the friction doubles it.
        let base = pinch(2.0, 0.5, 1.0).margin;
        assert!((pinch(2.0, 0.5, 2.0).margin - base / 2.0).abs() < 1e-6 * base);
        assert!((pinch(2.0, 1.0, 1.0).margin - 2.0 * base).abs() < 1e-6 * base);
    }

    /// Unbalanced normal forces need friction too: one pad pressing harder than the other by
    /// Δ needs √(W² + Δ²) of friction in all.
    #[test]
    fn unbalanced_normal_forces_use_up_friction() {
        let r = 0.02;
        let (mu, w, l1, l2) = (0.5, 1.0, 3.0, 2.0);
        let contacts = [
            GripContact {
                point: Vector3::new(-r, 0.0, 0.0),
                inward: Vector3::x(),
                normal_force: l1,
                friction: mu,
            },
            GripContact {
                point: Vector3::new(r, 0.0, 0.0),
                inward: -Vector3::x(),
                normal_force: l2,
                friction: mu,
            },
        ];
        let h = hold_margin(
            &contacts,
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, -w),
            0.04,
        );
        // Tangential forces lie in the y–z plane: the x imbalance cannot be taken by friction
        // of contacts whose normals are ±x.
        assert_eq!(h.margin, 0.0);
        // Turned 45° about y the pads' friction can take it: a cone check by hand.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let tilted = [
            GripContact {
                point: Vector3::new(-r * s, 0.0, -r * s),
                inward: Vector3::new(s, 0.0, s),
                normal_force: l2,
                friction: mu,
            },
            GripContact {
                point: Vector3::new(r * s, 0.0, -r * s),
                inward: Vector3::new(-s, 0.0, s),
                normal_force: l2,
                friction: mu,
            },
        ];
        // Two pads under the ball at 45° carry 2·λ·cos45° = 2.83 N up: more than the 1 N
        // weight, so friction must push down 1.83 N in all; by symmetry 0.914 N each, along
        // the tangent (its vertical share cos45°): |t| = 0.914 / cos45° = 1.293 N each.
        let h = hold_margin(
            &tilted,
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, -w),
            0.04,
        );
        let excess = 2.0 * l2 * s - w;
        let each = excess / 2.0 / s;
        let exact = mu * l2 / each;
        assert!(
            (h.margin - exact).abs() < 1e-6 * exact,
            "{} {exact}",
            h.margin
        );
    }

    /// A ball in a cupped palm (one contact under its centre) is held by the normal force
    /// alone; one contact beside it cannot hold it at any friction.
    #[test]
    fn normal_forces_alone_and_nothing_at_all() {
        let w = 1.0;
        let under = [GripContact {
            point: Vector3::new(0.0, 0.0, -0.02),
            inward: Vector3::z(),
            normal_force: w,
            friction: 0.3,
        }];
        let h = hold_margin(&under, &Vector3::zeros(), &Vector3::new(0.0, 0.0, -w), 0.04);
        assert_eq!(h.margin, MAX_MARGIN);
        let beside = [GripContact {
            point: Vector3::new(-0.02, 0.0, 0.0),
            inward: Vector3::x(),
            normal_force: 1.0,
            friction: 10.0,
        }];
        let h = hold_margin(
            &beside,
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, -w),
            0.04,
        );
        assert_eq!(h.margin, 0.0);
        assert_eq!(
            hold_margin(&[], &Vector3::zeros(), &Vector3::new(0.0, 0.0, -w), 0.04).margin,
            0.0
        );
    }
}
