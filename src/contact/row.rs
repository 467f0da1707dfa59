//! A contact constraint row of the exact methods — one node against a facet or an obstacle, its
//! normal and tangent axes frozen when it joined — and its couplings through the Schur
//! complement, C_a·K11⁻¹·C_bᵀ, cached per pair of rows.

use super::point::{Adhesion, Master};
use super::problem::{ContactProblem, Penetration};
use crate::fem::forward::HalfSolved;
use crate::fem::DofPartition;
use nalgebra::{Vector2, Vector3};
use rayon::prelude::*;
use std::collections::HashMap;
/// One active contact, its geometry frozen when it joined.
pub(super) struct Row {
    /// Unique among all rows ever made (the key of the coupling cache).
    pub(super) id: usize,
    pub(super) node: usize,
    pub(super) master: Master,
    pub(super) source: usize,
    pub(super) terms: Vec<(usize, f64)>,
    /// n, t1, t2.
    pub(super) basis: [Vector3<f64>; 3],
    /// Normal bound: n·Σ w U ≥ b.
    pub(super) bound: f64,
    /// Tangential position Σ w U in (t1, t2) when it joined.
    pub(super) reference: Vector2<f64>,
    pub(super) mu: f64,
    pub(super) state: Adhesion,
    /// Direction of the friction force on the node in (t1, t2) while slipping.
    pub(super) slip: Vector2<f64>,
    /// K11⁻¹·C_aᵀ (or half of it) for axis a = n (and t1, t2 with friction).
    pub(super) solved: Solved,
    /// Its multipliers (λ_n, λ_t1, λ_t2) when last settled: the start of the next settle.
    pub(super) last: [f64; 3],
}

/// A constraint row's column of the Schur complement: K11⁻¹·C_aᵀ over the free equations, or
/// L⁻¹·P·C_aᵀ (half the substitution, sparse) when the factor is supernodal; the coupling
/// C_a·K11⁻¹·C_bᵀ is then y_a·y_b, and the displacements need one substitution per settle.
pub(super) enum Solved {
    /// Not yet substituted.
    None,
    /// K11⁻¹·C_aᵀ per axis.
    Full(Vec<Vec<f64>>),
    /// L⁻¹·P·C_aᵀ of all axes.
    Half(HalfSolved),
}

/// The couplings C_a·K11⁻¹·C_bᵀ between pairs of rows, 3 × 3 per pair, keyed by the rows' ids
/// (smaller first).
pub(super) type Couplings = HashMap<(usize, usize), [[f64; 3]; 3]>;

/// C_a·K11⁻¹·C_bᵀ between axis `a` of `x` and axis `b` of `y`, from the cache or computed.
pub(super) fn coupling(
    cache: &mut Couplings,
    x: &Row,
    a: usize,
    y: &Row,
    b: usize,
    partition: &DofPartition,
) -> f64 {
    if x.id <= y.id {
        cache
            .entry((x.id, y.id))
            .or_insert_with(|| x.block(y, partition))[a][b]
    } else {
        cache
            .entry((y.id, x.id))
            .or_insert_with(|| y.block(x, partition))[b][a]
    }
}

/// Every coupling among `rows` not yet in the cache, computed in parallel (each block is a
/// sparse dot product of two rows' half substitutions: independent of the others).
pub(super) fn fill_couplings(cache: &mut Couplings, rows: &[Row], partition: &DofPartition) {
    let missing: Vec<(usize, usize)> = (0..rows.len())
        .flat_map(|i| (i..rows.len()).map(move |j| (i, j)))
        .map(|(i, j)| {
            if rows[i].id <= rows[j].id {
                (i, j)
            } else {
                (j, i)
            }
        })
        .filter(|&(i, j)| !cache.contains_key(&(rows[i].id, rows[j].id)))
        .collect();
    let blocks: Vec<_> = missing
        .par_iter()
        .map(|&(i, j)| ((rows[i].id, rows[j].id), rows[i].block(&rows[j], partition)))
        .collect();
    cache.extend(blocks);
}

impl Row {
    /// Axes substituted (1, or 3 with friction; 0 before).
    pub(super) fn axes(&self) -> usize {
        match &self.solved {
            Solved::None => 0,
            Solved::Full(c) => c.len(),
            Solved::Half(h) => h.columns(),
        }
    }

    /// C_a·K11⁻¹·C_bᵀ for every axis a of this row and b of `other`.
    pub(super) fn block(&self, other: &Row, partition: &DofPartition) -> [[f64; 3]; 3] {
        match (&self.solved, &other.solved) {
            (Solved::Half(x), Solved::Half(y)) => x.gram(y),
            (_, Solved::Full(cols)) => {
                let mut out = [[0.0; 3]; 3];
                for a in 0..self.axes() {
                    for (b, col) in cols.iter().enumerate() {
                        out[a][b] = self.apply_free(a, col, partition);
                    }
                }
                out
            }
            _ => {
                let mut out = other.block(self, partition);
                for a in 0..3 {
                    for b in 0..a {
                        let t = out[a][b];
                        out[a][b] = out[b][a];
                        out[b][a] = t;
                    }
                }
                out
            }
        }
    }

    pub(super) fn new(p: &Penetration, problem: &ContactProblem, u: &[f64], mu: f64) -> Row {
        let terms = problem.contact_terms(p.node, &p.master);
        let n = p.normal;
        let helper = if n.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let t1 = n.cross(&helper).normalize();
        let t2 = n.cross(&t1);
        static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let mut row = Row {
            id: NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            node: p.node,
            master: p.master,
            source: p.source,
            terms,
            basis: [n, t1, t2],
            bound: 0.0,
            reference: Vector2::zeros(),
            mu,
            state: if mu > 0.0 {
                Adhesion::Stick
            } else {
                Adhesion::Frictionless
            },
            slip: Vector2::zeros(),
            solved: Solved::None,
            last: [0.0; 3],
        };
        let x: Vector3<f64> = row
            .terms
            .iter()
            .map(|&(k, w)| problem.positions[k] * w)
            .sum();
        row.bound = n.dot(&p.anchor) - n.dot(&x);
        row.reference = Vector2::new(row.apply(1, u), row.apply(2, u));
        row
    }

    /// basis[axis]·Σ w v_k over the full dof vector `v`.
    pub(super) fn apply(&self, axis: usize, v: &[f64]) -> f64 {
        let d = &self.basis[axis];
        self.terms
            .iter()
            .map(|&(k, w)| w * (d.x * v[3 * k] + d.y * v[3 * k + 1] + d.z * v[3 * k + 2]))
            .sum()
    }

    /// The same over free equations only (`eq` maps dofs to equations).
    pub(super) fn apply_free(&self, axis: usize, v: &[f64], partition: &DofPartition) -> f64 {
        let d = &self.basis[axis];
        let mut s = 0.0;
        for &(k, w) in &self.terms {
            for a in 0..3 {
                if !partition.prescribed[3 * k + a] {
                    s += w * d[a] * v[partition.equation[3 * k + a]];
                }
            }
        }
        s
    }

    /// `scale`·C_aᵀ added into free equations; whether any of it is free.
    pub(super) fn scatter(
        &self,
        axis: usize,
        scale: f64,
        out: &mut [f64],
        partition: &DofPartition,
    ) -> bool {
        let d = &self.basis[axis];
        let mut any = false;
        for &(k, w) in &self.terms {
            for a in 0..3 {
                if !partition.prescribed[3 * k + a] && w * d[a] != 0.0 {
                    out[partition.equation[3 * k + a]] += scale * w * d[a];
                    any = true;
                }
            }
        }
        any
    }

    pub(super) fn key(&self) -> (usize, usize) {
        (self.node, self.source)
    }
}

/// The first slot of every row's axes in G, and the total at the end.
pub(super) fn slot_offsets(rows: &[Row]) -> Vec<usize> {
    let mut out = Vec::with_capacity(rows.len() + 1);
    let mut k = 0;
    for row in rows {
        out.push(k);
        k += row.axes();
    }
    out.push(k);
    out
}

/// The (row, axis) of slot `i`.
pub(super) fn slot_of(offset: &[usize], i: usize) -> (usize, usize) {
    let r = offset.partition_point(|&o| o <= i) - 1;
    (r, i - offset[r])
}
