//! The other bodies of a contact step turned with the motion carried so far (issue 15, item 2):
//! a power grasp squashes and rolls a soft ball through angles where a linear element sees its
//! rotation as strain. Each contact step linearises the bodies about the displacements U_c the
//! last step left: every element's stiffness turned by the rotation R_e of its centre
//! (F = R·U there), K̃ = Σ_e R_e K_e R_eᵀ, with the internal force
//! f(U_c) = Σ_e R_e K_e (R_eᵀ (X_e + U_e) − X_e), which vanishes for a rigid turn; the step
//! solves K̃·ΔU = R(x_c) − f(U_c) + Cᵀλ, with the pressures on the surface where it is now
//! (a follower load: equation (4)'s surface term on the deformed facets). Without carried
//! displacements (a keyframe solved in one step) every R_e = I and this is the linear step.
//!
//! K̃ alone is not the tangent of that residual: a stressed element's forces turn with it, and
//! a pressure follows its facets. A step without motion to follow (a correction at a pose, a
//! keyframe in one step from a frame in contact) adds the symmetric part of both to its matrix
//! (`geometric`; `fem::geometric`: the turn's stiffness of every corotated cell,
//! −∂(pressure load)/∂x), and the internal force is written so that f(U_c) is unchanged: the
//! corrections at a pose converge to the same state, without the overshoot of a pressurised
//! ball's wall whose tension the step did not see (each correction of a touching finger's 2°
//! move alternated in sign and took 3–5 to settle; now one settles it, docs/performance.md).
//! Steps along a motion keep K̃ alone (docs/contact.md).

use crate::fem::assembly::{
    assemble_only, assemble_warped_stressed, AssemblyError, Cells, Stiffness, Taken,
};
use crate::fem::geometric::pressure_load_stiffness;
use crate::fem::hex8::centre_rotation;
use crate::fem::kept_elements::KeptElements;
use crate::fem::loads::add_pressure;
use crate::mesh::Mesh;
use crate::model::Model;
use nalgebra::{Matrix3, Vector3};

/// The stiffness of a contact step and the internal force it starts from.
pub(super) struct Linearised {
    /// K: the hands' cells on their posed geometry; the other bodies' at rest, turned by their
    /// carried rotation when corotated.
    pub k: Stiffness,
    /// f(U_c) − K·U_c over every dof: what the carried state's internal force adds to K·U_c
    /// (zero where nothing is turned), so that f(U_c) = K·U_c + this even after supports'
    /// springs are added to K.
    pub offset: Option<Vec<f64>>,
}

impl Linearised {
    /// The sum of two linearisations of disjoint cells on one pattern (a contact step's hands'
    /// cells and its other bodies'): entry by entry, each the one part's plus the other's
    /// zero, so the same numbers as one assembly of both.
    pub(super) fn joined(mut self, other: Linearised) -> Linearised {
        debug_assert!(std::sync::Arc::ptr_eq(&self.k.pattern, &other.k.pattern));
        for (a, b) in self.k.values.iter_mut().zip(&other.k.values) {
            *a += b;
        }
        self.offset = match (self.offset, other.offset) {
            (Some(mut a), Some(b)) => {
                for (a, b) in a.iter_mut().zip(&b) {
                    *a += b;
                }
                Some(a)
            }
            (a, b) => a.or(b),
        };
        self
    }
}

/// K for a contact step of `model` on `mesh` (the hands posed, the other bodies at rest), with
/// the other bodies corotated about `carried` when the model's tier turns its elements and
/// something is carried (the nonlinear tier's are Neo-Hookean: `hyperelastic_objects.rs`).
///
/// `geometric`: the turn's and the pressures' stiffness joins K̃ (see the module's notes);
/// without it K̃ alone, positive definite where the bodies are supported, for a step from a
/// state where the complete tangent is not (a wall squeezed in compression).
///
/// Only the cells `needed` takes are assembled: the others (a hand's cells away from the step's
/// free flesh, carrying nothing) would add nothing to the step (zero displacement on every
/// node: no force, no reaction); they are only checked for inversion, but those `unchecked`
/// takes (another assembly of the step takes or checks them). A cell's K_e in `kept` is taken
/// from there: kept on the positions `mesh` gives the cell (the objects' at rest).
pub(super) fn linearise(
    model: &Model,
    mesh: &Mesh,
    carried: Option<&[f64]>,
    geometric: bool,
    (needed, unchecked, kept): (Cells<'_>, Option<Cells<'_>>, Option<&KeptElements>),
) -> Result<Linearised, AssemblyError> {
    let taken = Taken {
        take: Some(needed),
        unchecked,
        kept,
    };
    let rotations = match carried {
        Some(u) if model.corotates_objects() => Some(rotations(model, u, needed)?),
        _ => None,
    };
    let Some(rotations) = rotations else {
        let k = assemble_only(&model.pattern, mesh, &model.cell_materials, taken)?;
        return Ok(Linearised { k, offset: None });
    };
    let u = carried.expect("rotations come from a carried state");
    let node_u = |n: usize| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
    let object = |c: usize| model.bodies[model.cell_body[c]].hand.is_none();
    let displaced = |c: usize| (geometric && object(c)).then(|| mesh.cells[c].map(node_u));
    let (mut k, b) = assemble_warped_stressed(
        &model.pattern,
        mesh,
        &model.cell_materials,
        &rotations,
        &displaced,
        taken,
    )?;
    let x: Vec<f64> = mesh.nodes.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    let kx = k.mul(&x);
    let mut offset: Vec<f64> = kx.iter().zip(&b).map(|(a, b)| a - b).collect();
    if !geometric {
        return Ok(Linearised {
            k,
            offset: Some(offset),
        });
    }
    add_pressure_stiffness(model, mesh, u, &mut k, &mut offset);
    Ok(Linearised {
        k,
        offset: Some(offset),
    })
}

/// The pressures follow the surface (`loads_at`): −∂(loads)/∂x at the positions `mesh` + `u`
/// (the symmetric part, `fem::geometric`) joins the tangent `k`, and `offset` keeps
/// f(U_c) = K·U_c + offset.
pub(super) fn add_pressure_stiffness(
    model: &Model,
    mesh: &Mesh,
    u: &[f64],
    k: &mut Stiffness,
    offset: &mut [f64],
) {
    let node_u = |n: usize| Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
    let now = Mesh {
        nodes: (0..mesh.node_count())
            .map(|n| mesh.nodes[n] + node_u(n))
            .collect(),
        cells: Vec::new(),
    };
    for l in &model.loads {
        if let Some((p, facets)) = &l.pressure {
            for (a, bn, block) in pressure_load_stiffness(&now, facets, *p) {
                k.add_block(a, bn, &(-block));
                let f = block * node_u(bn);
                for i in 0..3 {
                    offset[3 * a + i] += f[i];
                }
            }
        }
    }
}

/// Each cell's rotation: the polar rotation at its centre of the carried displacements for the
/// cells of the other bodies; the identity for the hands' (their flesh was turned by flexion)
/// and for cells not `needed` (left out of the assembly).
fn rotations(
    model: &Model,
    carried: &[f64],
    needed: Cells<'_>,
) -> Result<Vec<Matrix3<f64>>, AssemblyError> {
    let mesh = &model.mesh;
    (0..mesh.cell_count())
        .map(|c| {
            // (A cell the assembly leaves out is not turned.)
            if model.bodies[model.cell_body[c]].hand.is_some() || !needed(c) {
                return Ok(Matrix3::identity());
            }
            let u = mesh.cells[c]
                .map(|n| Vector3::new(carried[3 * n], carried[3 * n + 1], carried[3 * n + 2]));
            centre_rotation(&mesh.cell_coords(c), &u)
                .map_err(|inverted| AssemblyError { cell: c, inverted })
        })
        .collect()
}

/// The load vector of a contact step: the model's, with every pressure on the other bodies
/// acting on their facets where `positions` put them (where the model corotates them and
/// something is carried), the rest unchanged. The gas cavity's unit load on the same facets.
pub(super) fn loads_at(
    model: &Model,
    positions: &[Vector3<f64>],
    carried: Option<&[f64]>,
) -> (Vec<f64>, Option<Vec<f64>>) {
    let mut loads = model.load_vector.clone();
    if carried.is_none() || !model.corotates_objects() {
        return (loads, None);
    }
    let now = Mesh {
        nodes: positions.to_vec(),
        cells: model.mesh.cells.clone(),
    };
    for l in &model.loads {
        if let Some((p, facets)) = &l.pressure {
            add_pressure(&mut loads, &model.mesh, facets, -p);
            add_pressure(&mut loads, &now, facets, *p);
        }
    }
    let unit = model.gas.as_ref().map(|g| g.unit_load_on(&now));
    (loads, unit)
}

/// The right-hand side of a contact step from the displacements `carried` (over every dof;
/// `given`: a state was carried, whose pressures then act on the surface where it is now, at
/// `positions`).
pub(super) struct StepLoads {
    /// The loads less the forces the carried state already holds, f(U_c) = K·U_c + offset; the
    /// floating bodies' springs resting at the anchor: k·(U − U_a), so K·U less k·U_a.
    pub loads: Vec<f64>,
    /// The gas cavity's unit load on the surface where it is now, if any (see [`loads_at`]).
    pub unit_gas: Option<Vec<f64>>,
    /// The supports' values less what they already moved; zero at the hands' dofs (their bones
    /// do not move further, the flesh outside the step's region stays put).
    pub prescribed: Vec<f64>,
}

impl StepLoads {
    /// The loads with the gas `cavity` at gauge pressure `p` (its unit load on the surface where
    /// it is now, where the step has one).
    pub fn at_gauge(&self, cavity: &crate::model::GasCavity, p: f64) -> Vec<f64> {
        match &self.unit_gas {
            Some(unit) => cavity.with_gauge_on(&self.loads, p, unit),
            None => cavity.with_gauge(&self.loads, p),
        }
    }
}

/// [`StepLoads`] of a step with stiffness `k` (the springs of the floating bodies in it, resting
/// at `anchor`, or at rest) and the linearisation's `offset`, over `partition`.
pub(super) fn step_loads(
    model: &Model,
    (k, offset): (&Stiffness, Option<&[f64]>),
    (springs, anchor): (&[(usize, f64)], Option<&[f64]>),
    partition: &crate::fem::DofPartition,
    (carried, given): (&[f64], bool),
    positions: &[Vector3<f64>],
) -> StepLoads {
    let mut held = k.mul(carried);
    if let Some(offset) = offset {
        for (h, o) in held.iter_mut().zip(offset) {
            *h += o;
        }
    }
    let (loads_now, unit_gas) = loads_at(model, positions, given.then_some(carried));
    let mut loads: Vec<f64> = loads_now.iter().zip(&held).map(|(r, f)| r - f).collect();
    if let Some(anchor) = anchor {
        for &(b, spring) in springs {
            let nodes = model.bodies[b].nodes.clone();
            for d in 3 * nodes.start..3 * nodes.end {
                if !partition.prescribed[d] {
                    loads[d] += spring * anchor[d];
                }
            }
        }
    }
    let hand_dof = |d: usize| model.bodies[model.body_of_node(d / 3)].hand.is_some();
    let prescribed = (0..model.prescribed.len())
        .map(|d| {
            if hand_dof(d) {
                0.0
            } else {
                model.prescribed[d] - carried[d]
            }
        })
        .collect();
    StepLoads {
        loads,
        unit_gas,
        prescribed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::assembly::{assemble_warped, StiffnessPattern};
    use crate::fem::Material;
    use crate::mesh::box_mesh;
    use nalgebra::Rotation3;
    use std::sync::Arc;

    fn rubber() -> Material {
        Material::rubber()
    }

    /// f(y) = K̃·y − b for the block turned by `rotation` per cell.
    fn internal_force(mesh: &Mesh, rotation: &[Matrix3<f64>], y: &[Vector3<f64>]) -> Vec<f64> {
        let pattern = Arc::new(StiffnessPattern::new(mesh));
        let materials = vec![rubber(); mesh.cell_count()];
        let (k, b) = assemble_warped(&pattern, mesh, &materials, rotation).unwrap();
        let yv: Vec<f64> = y.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
        k.mul(&yv).iter().zip(&b).map(|(a, b)| a - b).collect()
    }

    /// A block turned rigidly by 60° about a skew axis: the polar rotation of every cell is that
    /// turn (to round-off), and the corotated internal force vanishes, where the linear one
    /// (K·U) is of the order of the stiffness times the displacement.
    #[test]
    fn a_rigid_turn_has_no_internal_force() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(0.04, 0.02, 0.01), [4, 2, 2]);
        let turn = Rotation3::from_axis_angle(
            &nalgebra::Unit::new_normalize(Vector3::new(1.0, 2.0, 0.5)),
            60f64.to_radians(),
        );
        let y: Vec<Vector3<f64>> = mesh.nodes.iter().map(|p| turn * p).collect();
        let rotations: Vec<Matrix3<f64>> = (0..mesh.cell_count())
            .map(|c| {
                let u = mesh.cells[c].map(|n| y[n] - mesh.nodes[n]);
                centre_rotation(&mesh.cell_coords(c), &u).unwrap()
            })
            .collect();
        for r in &rotations {
            assert!((r - turn.matrix()).norm() < 1e-12, "{r}");
        }
        let f = internal_force(&mesh, &rotations, &y);
        let corotated = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let linear = internal_force(&mesh, &vec![Matrix3::identity(); mesh.cell_count()], &y);
        let linear = linear.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(linear > 100.0, "linear {linear} N");
        assert!(corotated < 1e-9 * linear, "corotated {corotated} N");
    }

    /// A uniform stretch then turned: the corotated forces are the stretch's forces turned
    /// (objectivity), to round-off.
    #[test]
    fn a_turned_stretch_has_the_stretchs_forces_turned() {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(0.04, 0.02, 0.01), [4, 2, 2]);
        let stretch = Matrix3::from_diagonal(&Vector3::new(1.01, 0.995, 0.998));
        let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), 35f64.to_radians());
        let stretched: Vec<Vector3<f64>> = mesh.nodes.iter().map(|p| stretch * p).collect();
        let turned: Vec<Vector3<f64>> = stretched.iter().map(|p| turn * p).collect();
        let identity = vec![Matrix3::identity(); mesh.cell_count()];
        let rotations: Vec<Matrix3<f64>> = (0..mesh.cell_count())
            .map(|c| {
                let u = mesh.cells[c].map(|n| turned[n] - mesh.nodes[n]);
                centre_rotation(&mesh.cell_coords(c), &u).unwrap()
            })
            .collect();
        let f0 = internal_force(&mesh, &identity, &stretched);
        let f1 = internal_force(&mesh, &rotations, &turned);
        let scale = f0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 1.0, "{scale} N");
        for n in 0..mesh.node_count() {
            let a = turn * Vector3::new(f0[3 * n], f0[3 * n + 1], f0[3 * n + 2]);
            let b = Vector3::new(f1[3 * n], f1[3 * n + 1], f1[3 * n + 2]);
            assert!((a - b).norm() < 1e-9 * scale, "node {n}: {a} vs {b}");
        }
    }
}
