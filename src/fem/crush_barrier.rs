//! Flesh kept from being crushed inside out in a linear increment (`fem::quadratic_body`):
//! the small-strain flesh of an increment resists a cell's loss of volume no more at 90 % than
//! at 10 %, and a pulp squeezed between two bones turns inside out where real flesh, nearly
//! incompressible, stiffens without bound. Beside the linear energy, each Gauss point whose
//! volume ratio q = det J / det J₀ (now against rest) falls below [`CRUSH_ONSET`] adds
//!
//!   κ · V₀ · b(q),   b(q) = −(q − q̂)² ln(q / q̂)  for 0 < q < q̂,  0 above,
//!
//! incremental potential contact's log barrier applied to the volume (as the Neo-Hookean
//! flesh's λ/2·(ln J)² does): κ the cell's bulk modulus E / (3(1 − 2ν)), V₀ the point's rest
//! volume. It is zero, with its force and stiffness, until a point has lost half its volume;
//! it is infinite at q = 0, and Newton's steps stop short of it (`largest_step`: det J along a
//! step is a cubic in the step's length).

use super::added_energy::{AddedEnergy, NodeBlock};
use super::hex8::{gauss_derivatives, jacobian};
use super::material::Material;
use crate::mesh::Mesh;
use nalgebra::{DMatrix, Matrix3, SVector, Vector3};
use rayon::prelude::*;
use std::sync::Mutex;

/// The volume ratio below which a Gauss point resists further crushing (q̂).
pub const CRUSH_ONSET: f64 = 0.5;

/// Share of the way to a point's volume reaching a tenth of where a step starts that the step
/// may go.
const TO_COLLAPSE: f64 = 0.8;

/// The barrier over a mesh's cells (displacements from its node positions, its rest).
pub struct CrushBarrier<'a> {
    mesh: &'a Mesh,
    /// κ of each cell, Pa.
    modulus: Vec<f64>,
    /// det J₀ at each cell's Gauss points (the points' rest volumes, weights 1).
    rest: Vec<[f64; 8]>,
    /// The cell that cut the last step asked short, its smallest volume ratio where the step
    /// started, and the share of the step allowed.
    limiting: Mutex<Option<(usize, f64, f64)>>,
}

/// b(q), b'(q), b''(q) for 0 < q < q̂.
fn barrier(q: f64) -> (f64, f64, f64) {
    let (d, l) = (q - CRUSH_ONSET, (q / CRUSH_ONSET).ln());
    (
        -d * d * l,
        -2.0 * d * l - d * d / q,
        -2.0 * l - 4.0 * d / q + d * d / (q * q),
    )
}

/// ∂ det J / ∂c_j for J's columns c_j: c₁×c₂, c₂×c₀, c₀×c₁.
fn det_by_columns(j: &Matrix3<f64>) -> [Vector3<f64>; 3] {
    let (c0, c1, c2) = (j.column(0), j.column(1), j.column(2));
    [c1.cross(&c2), c2.cross(&c0), c0.cross(&c1)]
}

impl<'a> CrushBarrier<'a> {
    /// The barrier over `mesh` (at rest) whose cells are of `materials` (one per cell). A cell
    /// inside out at rest gives no point a rest volume: it is not admissible anywhere.
    pub fn new(mesh: &'a Mesh, materials: &[Material]) -> Self {
        assert_eq!(materials.len(), mesh.cell_count());
        let modulus = materials
            .iter()
            .map(|m| m.young / (3.0 * (1.0 - 2.0 * m.poisson)))
            .collect();
        let rest = (0..mesh.cell_count())
            .map(|c| {
                let x = mesh.cell_coords(c);
                let mut r = [0.0; 8];
                for (g, dn) in gauss_derivatives().iter().enumerate() {
                    r[g] = jacobian(&x, dn).determinant();
                }
                r
            })
            .collect();
        CrushBarrier {
            mesh,
            modulus,
            rest,
            limiting: Mutex::new(None),
        }
    }

    /// The cell that cut the last step `largest_step` was asked short (the mesh's numbering),
    /// its smallest volume ratio where that step started, and the share of the step it
    /// allowed; `None` if it cut none.
    pub fn limiting(&self) -> Option<(usize, f64, f64)> {
        *self.limiting.lock().unwrap()
    }

    /// The smallest volume ratio of cell `c`'s Gauss points at `u`.
    fn smallest_ratio(&self, c: usize, u: &[f64]) -> f64 {
        let x = self.positions(c, u);
        gauss_derivatives()
            .iter()
            .zip(&self.rest[c])
            .map(|(dn, rest)| jacobian(&x, dn).determinant() / rest)
            .fold(f64::INFINITY, f64::min)
    }

    fn positions(&self, c: usize, u: &[f64]) -> [Vector3<f64>; 8] {
        self.mesh.cells[c]
            .map(|n| self.mesh.nodes[n] + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]))
    }

    /// A cell's energy, its gradient over its 8 nodes and (if `hessian`) its Hessian, where
    /// some point is below the onset; `None` inside out; `Some(None)` above the onset.
    #[allow(clippy::type_complexity)]
    fn cell(
        &self,
        c: usize,
        u: &[f64],
        hessian: bool,
    ) -> Option<Option<(f64, SVector<f64, 24>, Option<DMatrix<f64>>)>> {
        let x = self.positions(c, u);
        let mut out: Option<(f64, SVector<f64, 24>, Option<DMatrix<f64>>)> = None;
        for (g, dn) in gauss_derivatives().iter().enumerate() {
            let j = jacobian(&x, dn);
            let det = j.determinant();
            let rest = self.rest[c][g];
            if !(rest > 0.0 && det > 0.0) {
                return None;
            }
            let q = det / rest;
            if q >= CRUSH_ONSET {
                continue;
            }
            let k = self.modulus[c];
            let (b, b1, b2) = barrier(q);
            let d = det_by_columns(&j);
            // ∂det/∂x_a = Σ_j ∂N_a/∂ξ_j · ∂det/∂c_j.
            let mut grad = SVector::<f64, 24>::zeros();
            for a in 0..8 {
                let v = d[0] * dn[a].x + d[1] * dn[a].y + d[2] * dn[a].z;
                grad.fixed_rows_mut::<3>(3 * a).copy_from(&v);
            }
            let entry = out.get_or_insert_with(|| {
                (
                    0.0,
                    SVector::zeros(),
                    hessian.then(|| DMatrix::zeros(24, 24)),
                )
            });
            entry.0 += k * rest * b;
            // E = κ·det₀·b(det/det₀): ∇E = κ b'·∇det, ∇²E = κ (b''/det₀ ∇det∇detᵀ + b' ∇²det).
            entry.1 += grad * (k * b1);
            if let Some(h) = &mut entry.2 {
                let outer = grad * grad.transpose() * (k * b2 / rest);
                *h += DMatrix::from_column_slice(24, 24, outer.as_slice());
                // ∂²det/∂c_j∂c_k: −[c₂]× (0,1), −[c₀]× (1,2), −[c₁]× (2,0), transposed below
                // the diagonal, zero on it.
                let mut dd = [[Matrix3::zeros(); 3]; 3];
                let cols = [
                    j.column(0).into_owned(),
                    j.column(1).into_owned(),
                    j.column(2).into_owned(),
                ];
                for (p, q2, other) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
                    let m = -cols[other].cross_matrix();
                    dd[p][q2] = m;
                    dd[q2][p] = m.transpose();
                }
                for a in 0..8 {
                    for bn in 0..8 {
                        let mut block = Matrix3::zeros();
                        for (p, row) in dd.iter().enumerate() {
                            for (q2, m) in row.iter().enumerate() {
                                block += m * (dn[a][p] * dn[bn][q2]);
                            }
                        }
                        let mut view = h.fixed_view_mut::<3, 3>(3 * a, 3 * bn);
                        view += block * (k * b1);
                    }
                }
            }
        }
        Some(out)
    }

    /// The first share α ∈ (0, 1] of the step `du` at which some point's det J falls to a tenth
    /// of where it starts (1 if none does), for cell `c`.
    fn first_collapse(&self, c: usize, u: &[f64], du: &[f64]) -> f64 {
        let x = self.positions(c, u);
        let d = self.mesh.cells[c].map(|n| Vector3::new(du[3 * n], du[3 * n + 1], du[3 * n + 2]));
        let mut first = 1.0f64;
        for dn in gauss_derivatives() {
            let (a, b) = (jacobian(&x, dn), jacobian(&d, dn));
            let da = det_by_columns(&a);
            let db = det_by_columns(&b);
            // det(A + αB) = c₀ + c₁α + c₂α² + c₃α³.
            let c0 = a.determinant();
            let c1 = (0..3).map(|j| da[j].dot(&b.column(j))).sum::<f64>();
            let c2 = (0..3).map(|j| db[j].dot(&a.column(j))).sum::<f64>();
            let c3 = b.determinant();
            if c0 <= 0.0 || c0.is_nan() {
                return 0.0;
            }
            let floor = 0.1 * c0;
            let p = |t: f64| c0 - floor + t * (c1 + t * (c2 + t * c3));
            if p(1.0) > 0.0 && c1 >= 0.0 && c2 >= 0.0 && c3 >= 0.0 {
                continue;
            }
            // Split [0, 1] where p' = c₁ + 2c₂α + 3c₃α² vanishes; p is monotone between.
            let mut cuts = vec![0.0, 1.0];
            let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, c1);
            if qa.abs() > 1e-300 {
                let disc = qb * qb - 4.0 * qa * qc;
                if disc >= 0.0 {
                    // The two roots without cancellation: q/qa and qc/q.
                    let q = -0.5 * (qb + qb.signum() * disc.sqrt());
                    if q != 0.0 {
                        cuts.push(q / qa);
                        cuts.push(qc / q);
                    } else {
                        cuts.push(0.0);
                    }
                }
            } else if qb.abs() > 1e-300 {
                cuts.push(-qc / qb);
            }
            cuts.retain(|t| (0.0..=1.0).contains(t));
            cuts.sort_by(f64::total_cmp);
            for w in cuts.windows(2) {
                let (mut lo, mut hi) = (w[0], w[1]);
                if p(hi) > 0.0 {
                    continue;
                }
                // p(lo) > 0 ≥ p(hi): bisect.
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if p(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                first = first.min(lo);
                break;
            }
        }
        first
    }
}

impl AddedEnergy for CrushBarrier<'_> {
    fn energy(&self, u: &[f64], gradient: &mut [f64]) -> Option<f64> {
        let cells: Option<Vec<_>> = (0..self.mesh.cell_count())
            .into_par_iter()
            .filter_map(|c| match self.cell(c, u, false) {
                None => Some(None),
                Some(None) => None,
                Some(Some((e, g, _))) => Some(Some((c, e, g))),
            })
            .collect();
        let mut total = 0.0;
        for (c, e, g) in cells? {
            total += e;
            for (a, &n) in self.mesh.cells[c].iter().enumerate() {
                for i in 0..3 {
                    gradient[3 * n + i] += g[3 * a + i];
                }
            }
        }
        Some(total)
    }

    fn hessian(&self, u: &[f64], projected: bool) -> Vec<NodeBlock> {
        (0..self.mesh.cell_count())
            .into_par_iter()
            .filter_map(|c| {
                let (_, _, h) = self.cell(c, u, true)??;
                let mut matrix = h?;
                if projected {
                    let eig = matrix.clone().symmetric_eigen();
                    let clamped = eig.eigenvalues.map(|l| l.max(0.0));
                    matrix = &eig.eigenvectors
                        * DMatrix::from_diagonal(&clamped)
                        * eig.eigenvectors.transpose();
                }
                Some(NodeBlock {
                    nodes: self.mesh.cells[c].to_vec(),
                    matrix,
                })
            })
            .collect()
    }

    fn largest_step(&self, u: &[f64], du: &[f64]) -> f64 {
        let (first, cell) = (0..self.mesh.cell_count())
            .into_par_iter()
            .map(|c| (self.first_collapse(c, u, du), c))
            .reduce(|| (1.0, usize::MAX), |a, b| if b.0 < a.0 { b } else { a });
        if first >= 1.0 {
            *self.limiting.lock().unwrap() = None;
            1.0
        } else {
            let allowed = TO_COLLAPSE * first;
            *self.limiting.lock().unwrap() = Some((cell, self.smallest_ratio(cell, u), allowed));
            allowed
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::assembly::{assemble, StiffnessPattern};
    use crate::fem::elastic_energy::ElasticEnergy;
    use crate::fem::newton::{solve_increment_with, NewtonSettings};
    use crate::fem::quadratic_body::QuadraticBody;
    use crate::fem::solve::FillOrdering;
    use crate::fem::{DofPartition, PartitionedSolver};
    use crate::mesh::box_mesh;
    use std::sync::Arc;

    fn flesh() -> Material {
        Material {
            young: 5.0e4,
            poisson: 0.45,
            density: 1050.0,
        }
    }

    /// A cube of side h squeezed between plates with its sides held (confined compression) to
    /// a volume ratio q: the energy is κ·h³·b(q), the force on its top κ·h²·b'(q) (both zero at
    /// or above the onset).
    #[test]
    fn a_confined_cube_holds_the_barriers_energy_and_force() {
        let h = 0.01;
        let mesh = box_mesh(Vector3::zeros(), Vector3::repeat(h), [1, 1, 1]);
        let m = flesh();
        let kappa = m.young / (3.0 * (1.0 - 2.0 * m.poisson));
        let crush = CrushBarrier::new(&mesh, &[m]);
        for q in [0.7, 0.5, 0.4, 0.1, 0.01] {
            let mut u = vec![0.0; 3 * mesh.node_count()];
            for (n, x) in mesh.nodes.iter().enumerate() {
                u[3 * n + 2] = -(1.0 - q) * x.z;
            }
            let mut g = vec![0.0; u.len()];
            let e = crush.energy(&u, &mut g).unwrap();
            let top: f64 = (0..mesh.node_count())
                .filter(|&n| mesh.nodes[n].z == h)
                .map(|n| g[3 * n + 2])
                .sum();
            let (b, b1) = if q < CRUSH_ONSET {
                let (b, b1, _) = barrier(q);
                (b, b1)
            } else {
                (0.0, 0.0)
            };
            let (e_exact, f_exact) = (kappa * h.powi(3) * b, kappa * h * h * b1);
            assert!(
                (e - e_exact).abs() <= 1e-9 * e_exact.abs().max(1e-12),
                "{e} {e_exact}"
            );
            assert!(
                (top - f_exact).abs() <= 1e-9 * f_exact.abs().max(1e-9),
                "{top} {f_exact}"
            );
        }
        // Squeezed flat it is not admissible.
        let mut u = vec![0.0; 3 * mesh.node_count()];
        for (n, x) in mesh.nodes.iter().enumerate() {
            u[3 * n + 2] = -x.z;
        }
        assert!(crush.energy(&u, &mut vec![0.0; u.len()]).is_none());
    }

    /// The gradient and the Hessian against central differences, on a cell sheared and
    /// crushed so that its Gauss points lie at different volume ratios below the onset.
    #[test]
    fn gradient_and_hessian_are_the_energys_derivatives() {
        let h = 0.01;
        let mesh = box_mesh(Vector3::zeros(), Vector3::repeat(h), [1, 1, 1]);
        let crush = CrushBarrier::new(&mesh, &[flesh()]);
        let mut u = vec![0.0; 3 * mesh.node_count()];
        for (n, x) in mesh.nodes.iter().enumerate() {
            u[3 * n] = 0.3 * x.z + 0.05 * x.y;
            u[3 * n + 1] = -0.1 * x.x;
            u[3 * n + 2] = -0.6 * x.z - 0.15 * x.x * x.z / h;
        }
        let energy = |u: &[f64]| crush.energy(u, &mut vec![0.0; u.len()]).unwrap();
        let gradient = |u: &[f64]| {
            let mut g = vec![0.0; u.len()];
            crush.energy(u, &mut g).unwrap();
            g
        };
        let g = gradient(&u);
        let blocks = crush.hessian(&u, false);
        assert_eq!(blocks.len(), 1);
        let hess = &blocks[0].matrix;
        let step = 1e-7 * h;
        let scale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0);
        let hscale = hess.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for d in 0..u.len() {
            let (mut up, mut down) = (u.clone(), u.clone());
            up[d] += step;
            down[d] -= step;
            let fd = (energy(&up) - energy(&down)) / (2.0 * step);
            assert!(
                (fd - g[d]).abs() < 1e-5 * scale,
                "dof {d}: {fd} against {}",
                g[d]
            );
            let (gu, gd) = (gradient(&up), gradient(&down));
            // Block order is the cell's node order; box_mesh's single cell numbers its nodes
            // as the cell lists them.
            let cell = mesh.cells[0];
            let (a, i) = (cell.iter().position(|&n| n == d / 3).unwrap(), d % 3);
            for (b, &n) in cell.iter().enumerate() {
                for k in 0..3 {
                    let fd = (gu[3 * n + k] - gd[3 * n + k]) / (2.0 * step);
                    let exact = hess[(3 * b + k, 3 * a + i)];
                    assert!((fd - exact).abs() < 1e-5 * hscale, "{fd} against {exact}");
                }
            }
        }
        // Projected: positive semi-definite.
        let projected = &crush.hessian(&u, true)[0].matrix;
        let least = projected.clone().symmetric_eigen().eigenvalues.min();
        assert!(least >= -1e-9 * hscale, "{least}");
    }

    /// Two cells of side h in a column, the top one ten times softer, confined at their sides
    /// (only the middle nodes' z free), the bottom held and the top pushed down by `squeeze`.
    struct Column {
        mesh: Mesh,
        materials: Vec<Material>,
        stiff: Material,
        soft: Material,
        k: crate::fem::Stiffness,
        partition: DofPartition,
        target: Vec<f64>,
    }

    fn column(h: f64, squeeze: f64) -> Column {
        let mesh = box_mesh(Vector3::zeros(), Vector3::new(h, h, 2.0 * h), [1, 1, 2]);
        let stiff = flesh();
        let soft = Material {
            young: stiff.young / 10.0,
            ..stiff
        };
        let materials: Vec<Material> = (0..2)
            .map(|c| {
                let z = mesh.cell_coords(c).iter().map(|x| x.z).sum::<f64>() / 8.0;
                if z > h {
                    soft
                } else {
                    stiff
                }
            })
            .collect();
        let k = assemble(&Arc::new(StiffnessPattern::new(&mesh)), &mesh, &materials).unwrap();
        let dofs = 3 * mesh.node_count();
        let partition = DofPartition::new(
            (0..dofs)
                .map(|d| d % 3 != 2 || mesh.nodes[d / 3].z != h)
                .collect(),
        );
        let mut target = vec![0.0; dofs];
        for (n, x) in mesh.nodes.iter().enumerate() {
            if x.z == 2.0 * h {
                target[3 * n + 2] = -squeeze;
            }
        }
        Column {
            mesh,
            materials,
            stiff,
            soft,
            k,
            partition,
            target,
        }
    }

    /// The settings of the flexion's increments with self-contact.
    fn flexion_settings() -> NewtonSettings {
        NewtonSettings {
            escape_saddles: false,
            expand_steps: true,
            placing_iterations: 12,
            ..NewtonSettings::descent(100, FillOrdering::Auto)
        }
    }

    /// Two cells in a column, confined at their sides, squeezed by 95 % of its height: the top
    /// one ten times softer. Linear flesh alone would put 91 % of the squeeze into the soft
    /// cell and turn it inside out (its strain 1.73); with the barrier Newton finds the
    /// equilibrium where both cells carry the same stress M·ε − κ·b'(1 − ε), the soft cell's
    /// volume still positive, and the force on the top plate is that stress times its area.
    #[test]
    fn a_soft_cell_squeezed_in_series_with_a_stiff_one_stays_right_side_out() {
        let h = 0.01;
        let squeeze = 0.95 * 2.0 * h;
        let c = column(h, squeeze);
        let (mesh, materials, k) = (&c.mesh, &c.materials, &c.k);
        let (partition, target, stiff, soft) = (&c.partition, &c.target, c.stiff, c.soft);
        let dofs = 3 * mesh.node_count();
        let zeros = vec![0.0; dofs];
        let body = QuadraticBody::new(k, mesh, zeros.clone(), zeros.clone());
        let crush = CrushBarrier::new(mesh, materials);
        // (The flexion's settings: a squeeze the flesh can take is placed within its placing
        // iterations.)
        let settings = flexion_settings();
        let solve = |added: Option<&dyn AddedEnergy>| {
            let mut solver = PartitionedSolver::new(FillOrdering::Auto);
            solve_increment_with(
                &body,
                (partition, &zeros, target, &zeros),
                added,
                &settings,
                &mut solver,
            )
        };
        assert!(
            solve(None).result.is_err(),
            "linear flesh alone turns inside out"
        );
        let u = solve(Some(&crush)).result.expect("Newton converges");
        // The 1-D balance: σ_stiff(ε₁) = σ_soft(0.95·2 − ε₁), by bisection.
        let stress = |m: &Material, e: f64| {
            let modulus = m.lambda() + 2.0 * m.mu();
            let kappa = m.young / (3.0 * (1.0 - 2.0 * m.poisson));
            let q = 1.0 - e;
            modulus * e
                - if q < CRUSH_ONSET {
                    kappa * barrier(q).1
                } else {
                    0.0
                }
        };
        let total = squeeze / h;
        let (mut lo, mut hi) = (total - 1.0 + 1e-12, 1.0 - 1e-12);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if stress(&stiff, mid) < stress(&soft, total - mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let e1 = 0.5 * (lo + hi);
        let middle = (0..mesh.node_count())
            .find(|&n| mesh.nodes[n].z == h)
            .unwrap();
        let moved = -u[3 * middle + 2] / h;
        assert!((moved - e1).abs() < 1e-6 * e1, "{moved} against {e1}");
        let q_soft = 1.0 - (total - moved);
        assert!(q_soft > 0.0 && q_soft < CRUSH_ONSET, "{q_soft}");
        // Linear flesh alone: the soft cell's strain would be 1.73.
        let m = |m: &Material| m.lambda() + 2.0 * m.mu();
        assert!(total * m(&stiff) / (m(&stiff) + m(&soft)) > 1.0);
        // The force on the top plate: the gradient of the flesh's and the barrier's energy.
        let (_, mut f) = body.internal_forces(&u).unwrap();
        crush.energy(&u, &mut f).unwrap();
        let top: f64 = (0..mesh.node_count())
            .filter(|&n| mesh.nodes[n].z == 2.0 * h)
            .map(|n| f[3 * n + 2])
            .sum();
        let exact = -stress(&stiff, e1) * h * h;
        assert!((top / exact - 1.0).abs() < 1e-6, "{top} against {exact}");
        eprintln!(
            "soft cell's volume ratio {q_soft:.4}, stress {:.4e} Pa",
            -exact / (h * h)
        );
    }

    /// Plates squeezed past the column's height (no flesh fits between them): each step toward
    /// them is cut short of a cell's collapse, Newton stops once its placing iterations are
    /// spent, and the barrier names a crushed cell as the one in the way.
    #[test]
    fn a_squeeze_no_flesh_fits_fails_fast_and_names_the_cell() {
        let h = 0.01;
        let c = column(h, 2.05 * h);
        let (mesh, materials, k) = (&c.mesh, &c.materials, &c.k);
        let (partition, target) = (&c.partition, &c.target);
        let zeros = vec![0.0; 3 * mesh.node_count()];
        let body = QuadraticBody::new(k, mesh, zeros.clone(), zeros.clone());
        let crush = CrushBarrier::new(mesh, materials);
        let settings = flexion_settings();
        let outcome = solve_increment_with(
            &body,
            (partition, &zeros, target, &zeros),
            Some(&crush),
            &settings,
            &mut PartitionedSolver::new(FillOrdering::Auto),
        );
        assert!(
            matches!(
                outcome.result,
                Err(crate::fem::newton::StepFailure::NotPlaced { iterations: 12 })
            ),
            "{:?}",
            outcome.result
        );
        // The cell named (either: both are crushed by then) is past the onset, and cut the
        // step short.
        let (_, q, allowed) = crush.limiting().expect("the barrier cut the steps");
        assert!(q > 0.0 && q < CRUSH_ONSET, "{q}");
        assert!(allowed > 0.0 && allowed < 1.0, "{allowed}");
    }
}
