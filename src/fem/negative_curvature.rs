//! The direction of most negative curvature of an indefinite tangent, for Newton to leave an
//! unstable equilibrium (a saddle of the energy: a branch past a bifurcation, such as flesh
//! that should crease but is still held in its uncreased shape by symmetry).
//!
//! Preconditioned inverse iteration (Knyazev & Neymeyr 2003, PINVIT): v ← v − P⁻¹(K v − ρ v)
//! with the Rayleigh quotient ρ = vᵀKv / vᵀv, converges to the eigenvector of the smallest
//! eigenvalue of K. P is K + τ·diag(K) with the smallest τ that makes it positive definite,
//! factored by the solver: each step costs one product with K and one forward and back
//! substitution.

use super::assembly::Stiffness;
use super::partition::DofPartition;
use super::solve::PartitionedSolver;

/// The approximate eigenvector (every dof, zero at prescribed ones, unit length) of the
/// smallest eigenvalue of K11 and its Rayleigh quotient, after `steps` preconditioned inverse
/// iterations with the factor `solver` holds; `None` if the substitutions fail.
pub fn lowest_mode(
    solver: &mut PartitionedSolver,
    k: &Stiffness,
    partition: &DofPartition,
    steps: usize,
) -> Option<(Vec<f64>, f64)> {
    let dofs = partition.prescribed.len();
    let free = &partition.free;
    // A fixed, irregular start (no mode of the mesh is favoured).
    let mut v: Vec<f64> = vec![0.0; dofs];
    for (i, &d) in free.iter().enumerate() {
        v[d] = ((i as f64 * 12.9898).sin() * 43_758.545).fract();
    }
    for _ in 0..steps {
        normalise(&mut v)?;
        let kv = k.mul(&v);
        let rho: f64 = free.iter().map(|&d| v[d] * kv[d]).sum::<f64>();
        let mut r: Vec<f64> = free.iter().map(|&d| kv[d] - rho * v[d]).collect();
        solver.solve_factored(&mut r, 1).ok()?;
        for (i, &d) in free.iter().enumerate() {
            v[d] -= r[i];
        }
    }
    normalise(&mut v)?;
    let kv = k.mul(&v);
    let rho = free.iter().map(|&d| v[d] * kv[d]).sum::<f64>();
    Some((v, rho))
}

fn normalise(v: &mut [f64]) -> Option<()> {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(n.is_finite() && n > 0.0) {
        return None;
    }
    v.iter_mut().for_each(|x| *x /= n);
    Some(())
}
