//! `prehensile bench elements`: accuracy against cost of the element options on the cantilever
//! of `docs/validation.md` (8 × 1 × 1 m, E = 1 MPa, ν = 0.3, clamped at x = 0, tip load 1 N),
//! meshed with 8k × k × k hexahedra: the standard hex8, hex8 with incompatible modes, and the
//! nonlinear tier (Neo-Hookean, mean dilatation, Newton), against Timoshenko's tip deflection.

use crate::fem::assembly::{assemble_kind, ElementKind, StiffnessPattern};
use crate::fem::loads::add_shared_force;
use crate::fem::newton::{solve_nonlinear, NewtonSettings};
use crate::fem::solve::{FillOrdering, PartitionedSolver};
use crate::fem::{DofPartition, Material};
use crate::mesh::{box_mesh, Mesh};
use crate::util::timing::ms;
use anyhow::Context;
use nalgebra::Vector3;
use std::sync::Arc;
use std::time::Instant;

/// Length, height (= width), Young's modulus of the beam; the tip force is `TIP_FORCE` along −z.
pub const BEAM: (f64, f64, f64) = (8.0, 1.0, 1.0e6);
/// Total transverse force at the free end, N.
pub const TIP_FORCE: f64 = 1.0;

/// A cantilever problem ready for any of the solvers.
pub struct Cantilever {
    /// 8k × k × k hexahedra.
    pub mesh: Mesh,
    /// One material everywhere.
    pub materials: Vec<Material>,
    /// The clamped face's dofs are prescribed.
    pub partition: DofPartition,
    /// All zero.
    pub prescribed: Vec<f64>,
    /// The tip force shared by the end nodes.
    pub loads: Vec<f64>,
    /// Nodes of the free end.
    pub end: Vec<usize>,
}

/// The cantilever with k elements through the thickness, Poisson ratio `poisson`, tip force
/// `force` (N, along −z).
pub fn cantilever(k: usize, poisson: f64, force: f64) -> Cantilever {
    let (l, h, young) = BEAM;
    let mesh = box_mesh(Vector3::zeros(), Vector3::new(l, h, h), [8 * k, k, k]);
    let material = Material {
        young,
        poisson,
        density: 0.0,
    };
    let end: Vec<usize> = (0..mesh.node_count())
        .filter(|&n| (mesh.nodes[n].x - l).abs() < 1e-9)
        .collect();
    let mut loads = vec![0.0; 3 * mesh.node_count()];
    add_shared_force(&mut loads, &end, &Vector3::new(0.0, 0.0, -force));
    let mask = (0..3 * mesh.node_count())
        .map(|d| mesh.nodes[d / 3].x.abs() < 1e-9)
        .collect();
    Cantilever {
        materials: vec![material; mesh.cell_count()],
        partition: DofPartition::new(mask),
        prescribed: vec![0.0; 3 * mesh.node_count()],
        loads,
        end,
        mesh,
    }
}

impl Cantilever {
    /// Mean vertical displacement of the end nodes, m.
    pub fn tip(&self, displacement: &[f64]) -> f64 {
        self.end
            .iter()
            .map(|&n| displacement[3 * n + 2])
            .sum::<f64>()
            / self.end.len() as f64
    }

    /// Linear solve with element `kind`; the displacement vector.
    pub fn solve_linear(&self, kind: ElementKind) -> Vec<f64> {
        self.try_solve_linear(kind).expect("the cantilever solves")
    }

    /// [`Self::solve_linear`], or why it failed.
    pub fn try_solve_linear(&self, kind: ElementKind) -> anyhow::Result<Vec<f64>> {
        let pattern = Arc::new(StiffnessPattern::new(&self.mesh));
        let k = assemble_kind(&pattern, &self.mesh, &self.materials, kind)
            .map_err(|e| anyhow::anyhow!("element {} is inverted or flat", e.cell))?;
        Ok(PartitionedSolver::new(FillOrdering::Auto)
            .solve(
                &k,
                &self.partition,
                &self.prescribed,
                &self.loads,
                &self.mesh.nodes,
            )?
            .displacement)
    }
}

/// Timoshenko's tip deflection δ = PL³/(3EI) + PL/(κGA), κ = 5/6, signed like the load (−z).
pub fn timoshenko_tip(poisson: f64, force: f64) -> f64 {
    let (l, h, e) = BEAM;
    let i = h.powi(4) / 12.0;
    let g = e / (2.0 * (1.0 + poisson));
    -(force * l.powi(3) / (3.0 * e * i) + force * l / (5.0 / 6.0 * g * h * h))
}

/// One row: k, elements, and for each of hex8, incompatible modes, nonlinear: the tip error
/// against Timoshenko (signed, relative) and the time in ms.
#[derive(Clone, Debug)]
pub struct ElementRow {
    /// Elements through the thickness.
    pub k: usize,
    /// Elements.
    pub elements: usize,
    /// (error, ms) of the standard hex8.
    pub hex8: (f64, f64),
    /// (error, ms) of hex8 with incompatible modes.
    pub incompatible: (f64, f64),
    /// (error, ms, Newton iterations) of the nonlinear tier.
    pub nonlinear: (f64, f64, usize),
}

/// Measures each resolution (elements through the thickness, at least 1); a mesh that cannot be
/// solved is the error, naming it.
pub fn element_rows(resolutions: &[usize]) -> anyhow::Result<Vec<ElementRow>> {
    let exact = timoshenko_tip(0.3, TIP_FORCE);
    resolutions
        .iter()
        .map(|&k| {
            if k == 0 {
                anyhow::bail!("--resolutions 0: the cantilever needs at least 1 element through its thickness");
            }
            let c = cantilever(k, 0.3, TIP_FORCE);
            let context = || format!("--resolutions {k}: the {}×{k}×{k} cantilever", 8 * k);
            let timed = |kind| -> anyhow::Result<(f64, f64)> {
                let t = Instant::now();
                let u = c.try_solve_linear(kind).with_context(context)?;
                Ok((c.tip(&u) / exact - 1.0, ms(t)))
            };
            let hex8 = timed(ElementKind::Hex8)?;
            let incompatible = timed(ElementKind::IncompatibleModes)?;
            let t = Instant::now();
            let sol = solve_nonlinear(
                &c.mesh,
                &c.materials,
                &c.partition,
                &c.prescribed,
                &c.loads,
                &NewtonSettings::default(),
            )
            .with_context(context)?;
            let nonlinear = (
                c.tip(&sol.displacement) / exact - 1.0,
                ms(t),
                sol.iterations(),
            );
            Ok(ElementRow {
                k,
                elements: c.mesh.cell_count(),
                hex8,
                incompatible,
                nonlinear,
            })
        })
        .collect()
}

/// Formats rows as a Markdown table.
pub fn element_table(rows: &[ElementRow]) -> String {
    let mut s = String::from(
        "| mesh | elements | hex8 error | hex8 ms | incompatible error | incompatible ms | nonlinear error | nonlinear ms (Newton iterations) |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s += &format!(
            "| {}×{}×{} | {} | {:+.2} % | {:.1} | {:+.2} % | {:.1} | {:+.2} % | {:.1} ({}) |\n",
            8 * r.k,
            r.k,
            r.k,
            r.elements,
            r.hex8.0 * 100.0,
            r.hex8.1,
            r.incompatible.0 * 100.0,
            r.incompatible.1,
            r.nonlinear.0 * 100.0,
            r.nonlinear.1,
            r.nonlinear.2
        );
    }
    s
}
