//! Sparse symmetric assembly of the global stiffness K (the paper's equations (3)–(5)).
//!
//! The sparsity pattern is built once per mesh: the upper triangle of K in compressed sparse
//! columns over all 3·NBP degrees of freedom (dof 3n+i is node n along axis i), plus, for every
//! cell, where each of its node-pair blocks lands. Cells are coloured so that no two cells of a
//! colour share a node; a colour is then assembled in parallel without locks.

use super::hex8::{element_stiffness, mapped_points, ElementStiffness, InvertedCell};
use super::incompatible;
use super::kept_elements::KeptElements;
use super::material::Material;
use crate::mesh::Mesh;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Where the blocks of each cell go in the upper triangle of K; computed once per mesh.
#[derive(Debug)]
pub struct StiffnessPattern {
    /// Number of degrees of freedom (3 per node).
    pub dofs: usize,
    /// Column pointers of the upper triangle (length dofs + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices of the upper triangle, sorted within each column.
    pub row_idx: Vec<usize>,
    /// For cell c and local node pair (a, b): the rank of node(a) among the neighbours ≤ node(b)
    /// of node(b), or `u32::MAX` when node(a) > node(b) (a lower-triangle block).
    ranks: Vec<[u32; 64]>,
    /// Cells grouped into colours; cells of one colour share no node.
    colours: Vec<Vec<usize>>,
    /// For every node, its neighbours (nodes sharing a cell), itself excluded, sorted.
    pub node_neighbours: Vec<Vec<usize>>,
}

impl StiffnessPattern {
    /// About how many bytes the pattern of `nodes` nodes of a hexahedral mesh and the matrices
    /// built on it take (its row indices, K's values, K11's gathered indices and values): up to
    /// 27 neighbours a node, 3 × 3 entries each, half of them stored.
    pub fn bytes_for(nodes: usize) -> u64 {
        const ENTRIES_PER_NODE: u64 = (27 * 9 + 3) / 2;
        (nodes as u64)
            .saturating_mul(ENTRIES_PER_NODE)
            .saturating_mul(32)
    }

    /// Builds the pattern of `mesh`.
    pub fn new(mesh: &Mesh) -> Self {
        let n = mesh.node_count();
        let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
        for cell in &mesh.cells {
            for &a in cell {
                for &b in cell {
                    if a != b {
                        neighbours[a].push(b);
                    }
                }
            }
        }
        neighbours.par_iter_mut().for_each(|l| {
            l.sort_unstable();
            l.dedup();
        });
        let mut pattern = Self::from_neighbours(neighbours);
        let neighbours = &pattern.node_neighbours;
        let lower_count: Vec<usize> = neighbours
            .iter()
            .enumerate()
            .map(|(j, l)| l.partition_point(|&i| i < j))
            .collect();
        pattern.ranks = mesh
            .cells
            .par_iter()
            .map(|cell| {
                let mut r = [u32::MAX; 64];
                for a in 0..8 {
                    for b in 0..8 {
                        let (na, nb) = (cell[a], cell[b]);
                        if na < nb {
                            let list = &neighbours[nb][..lower_count[nb]];
                            r[a * 8 + b] = list.binary_search(&na).expect("neighbour") as u32;
                        } else if na == nb {
                            r[a * 8 + b] = lower_count[nb] as u32;
                        }
                    }
                }
                r
            })
            .collect();
        pattern.colours = colour_cells(mesh);
        pattern
    }

    /// The pattern of nodes coupled as `neighbours` says (each node's neighbours, itself
    /// excluded, sorted; symmetric): for solving, not for assembling cells (it knows none).
    pub fn from_neighbours(neighbours: Vec<Vec<usize>>) -> Self {
        let n = neighbours.len();
        // Lower neighbours of node j (i < j), then j itself: the node-level upper column j.
        let lower_count: Vec<usize> = neighbours
            .iter()
            .enumerate()
            .map(|(j, l)| l.partition_point(|&i| i < j))
            .collect();
        let dofs = 3 * n;
        let mut col_ptr = Vec::with_capacity(dofs + 1);
        col_ptr.push(0);
        for j in 0..n {
            for c in 0..3 {
                let len = 3 * lower_count[j] + c + 1;
                col_ptr.push(col_ptr.last().unwrap() + len);
            }
        }
        let mut row_idx = vec![0usize; *col_ptr.last().unwrap()];
        for j in 0..n {
            for c in 0..3 {
                let mut p = col_ptr[3 * j + c];
                for &i in &neighbours[j][..lower_count[j]] {
                    for d in 0..3 {
                        row_idx[p] = 3 * i + d;
                        p += 1;
                    }
                }
                for d in 0..=c {
                    row_idx[p] = 3 * j + d;
                    p += 1;
                }
            }
        }
        Self {
            dofs,
            col_ptr,
            row_idx,
            ranks: Vec::new(),
            colours: Vec::new(),
            node_neighbours: neighbours,
        }
    }

    /// Number of stored entries (upper triangle).
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Number of cell colours (cells of one colour are assembled in parallel).
    pub fn colour_count(&self) -> usize {
        self.colours.len()
    }
}

/// Greedy colouring: each cell takes the first colour no cell touching its nodes has taken.
fn colour_cells(mesh: &Mesh) -> Vec<Vec<usize>> {
    let mut used = vec![0u64; mesh.node_count()];
    let mut colours: Vec<Vec<usize>> = Vec::new();
    for (c, cell) in mesh.cells.iter().enumerate() {
        let taken = cell.iter().fold(0u64, |m, &n| m | used[n]);
        let colour = (taken.trailing_ones() as usize).min(63);
        if colour < 63 {
            for &n in cell {
                used[n] |= 1 << colour;
            }
        }
        if colours.len() <= colour {
            colours.resize(colour + 1, Vec::new());
        }
        colours[colour].push(c);
    }
    colours
}

/// An assembled stiffness matrix K: the upper triangle of a symmetric matrix on a shared pattern.
#[derive(Clone, Debug)]
pub struct Stiffness {
    /// The pattern the values belong to.
    pub pattern: Arc<StiffnessPattern>,
    /// Values, aligned with `pattern.row_idx`.
    pub values: Vec<f64>,
}

/// Assembly failed because a cell is inverted or flat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AssemblyError {
    /// The offending cell.
    pub cell: usize,
    /// Its smallest relative det J.
    pub inverted: InvertedCell,
}

struct SharedValues(*mut f64);
unsafe impl Send for SharedValues {}
unsafe impl Sync for SharedValues {}

/// Assembles K = Σ_e K_e (equation (3) composed into (5)) for the mesh at its current node
/// positions, with `materials[c]` the material of cell c.
pub fn assemble(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    materials: &[Material],
) -> Result<Stiffness, AssemblyError> {
    assemble_with(pattern, mesh, materials, None, None, Taken::default()).map(|(k, _)| k)
}

/// Which linear element stiffness [`assemble_kind`] uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ElementKind {
    /// The trilinear hexahedron with 2×2×2 Gauss points ([`element_stiffness`]): locks in
    /// bending when there are few elements through the thickness.
    #[default]
    Hex8,
    /// The hexahedron with Wilson–Taylor incompatible modes, condensed per element
    /// ([`super::incompatible::element_stiffness`]): bends without shear locking.
    IncompatibleModes,
}

/// As [`assemble`], with the element stiffness of `kind`.
pub fn assemble_kind(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    materials: &[Material],
    kind: ElementKind,
) -> Result<Stiffness, AssemblyError> {
    if kind == ElementKind::Hex8 {
        return assemble(pattern, mesh, materials);
    }
    assert_eq!(materials.len(), mesh.cell_count());
    scatter(pattern, mesh, false, &|c| {
        incompatible::element_stiffness(&mesh.cell_coords(c), &materials[c])
            .map(|k| (k, None))
            .map_err(|inverted| AssemblyError { cell: c, inverted })
    })
    .map(|(k, _)| k)
}

/// The warped (corotated) stiffness of an increment: each element's K_e turned by a rotation
/// R_e, K̃ = Σ_e R_e K_e R_eᵀ, and the vector b = Σ_e R_e K_e x_e for the current positions x.
/// The element forces f_e(y) = R_e K_e (R_eᵀ y_e − x_e) vanish when the element turns rigidly
/// by R_e, so that K̃·y = b, solved for the new positions y, has no spurious strain from the
/// rotation of flesh that turns with a bone (stiffness warping).
pub fn assemble_warped(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    materials: &[Material],
    rotations: &[Matrix3<f64>],
) -> Result<(Stiffness, Vec<f64>), AssemblyError> {
    assert_eq!(rotations.len(), mesh.cell_count());
    assemble_with(
        pattern,
        mesh,
        materials,
        Some(rotations),
        None,
        Taken::default(),
    )
    .map(|(k, b)| (k, b.unwrap()))
}

/// [`assemble_warped`] with the turn's stiffness K^t_e of the cells `displaced` gives nodal
/// displacements u_e for (`geometric::symmetric_turn_stiffness`: what their stress under those
/// displacements adds to the tangent) added to their K̃_e, and K^t_e·(X_e + u_e) to their b_e,
/// so that K·y − b is the corotated force at y = X + u as with [`assemble_warped`].
///
/// Only the cells `only` takes are assembled (all without it): the others add nothing to K
/// nor to b, and are only checked for inversion.
/// `taken`: which cells, and their K_e where kept.
pub fn assemble_warped_stressed(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    materials: &[Material],
    rotations: &[Matrix3<f64>],
    displaced: Displaced<'_>,
    taken: Taken<'_>,
) -> Result<(Stiffness, Vec<f64>), AssemblyError> {
    assert_eq!(rotations.len(), mesh.cell_count());
    assemble_with(
        pattern,
        mesh,
        materials,
        Some(rotations),
        Some(displaced),
        taken,
    )
    .map(|(k, b)| (k, b.unwrap()))
}

/// [`assemble`] of the cells `taken` takes (see [`Taken`]).
pub fn assemble_only(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    materials: &[Material],
    taken: Taken<'_>,
) -> Result<Stiffness, AssemblyError> {
    assemble_with(pattern, mesh, materials, None, None, taken).map(|(k, _)| k)
}

/// Which cells an assembly takes.
pub type Cells<'a> = &'a (dyn Fn(usize) -> bool + Sync);

/// The cells an assembly takes: those `take` takes (every cell without it), the others adding
/// nothing and only checked for inversion — but those `unchecked` takes (cells another
/// assembly of the same step takes or checks); a cell's K_e from `kept` where it holds it
/// (kept on the positions the assembly's mesh gives the cell).
#[derive(Clone, Copy, Default)]
pub struct Taken<'a> {
    pub take: Option<Cells<'a>>,
    pub unchecked: Option<Cells<'a>>,
    pub kept: Option<&'a KeptElements>,
}

/// Each cell's nodal displacements, where its turn's stiffness is wanted.
pub type Displaced<'a> = &'a (dyn Fn(usize) -> Option<[Vector3<f64>; 8]> + Sync);

fn assemble_with(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    materials: &[Material],
    rotations: Option<&[Matrix3<f64>]>,
    displaced: Option<Displaced<'_>>,
    taken: Taken<'_>,
) -> Result<(Stiffness, Option<Vec<f64>>), AssemblyError> {
    assert_eq!(materials.len(), mesh.cell_count());
    let Taken {
        take: only,
        unchecked,
        kept,
    } = taken;
    // A cell left out is still checked for inversion, as its element stiffness would have
    // (unless another assembly does).
    let check = |c: usize| {
        if unchecked.is_some_and(|u| u(c)) {
            return Ok(());
        }
        mapped_points(&mesh.cell_coords(c))
            .map(|_| ())
            .map_err(|inverted| AssemblyError { cell: c, inverted })
    };
    let only = only.map(|take| {
        (
            take,
            &check as &(dyn Fn(usize) -> Result<(), AssemblyError> + Sync),
        )
    });
    scatter_only(pattern, mesh, rotations.is_some(), only, &|c| {
        let coords = mesh.cell_coords(c);
        let mut ke = match kept.and_then(|k| k.get(c)) {
            Some(ke) => *ke,
            None => element_stiffness(&coords, &materials[c])
                .map_err(|inverted| AssemblyError { cell: c, inverted })?,
        };
        let Some(rot) = rotations else {
            return Ok((ke, None));
        };
        let r = rot[c];
        // K̃ = R·K̂·Rᵀ, block by block (the turn's stiffness reads it too).
        let turned_ke = ke.map(|row| row.map(|block| r * block * r.transpose()));
        let turn = match displaced.and_then(|d| d(c)) {
            Some(u) => Some((
                super::geometric::symmetric_turn_stiffness(&coords, (&ke, &turned_ke), &r, &u)
                    .map_err(|inverted| AssemblyError { cell: c, inverted })?,
                u,
            )),
            None => None,
        };
        let mut f = [Vector3::zeros(); 8];
        for a in 0..8 {
            for bb in 0..8 {
                f[a] += ke[a][bb] * coords[bb];
            }
            f[a] = r * f[a];
        }
        ke = turned_ke;
        if let Some((ks, u)) = turn {
            // b gains K^t·(X + u), so that K̃·y − b is still the corotated force at y.
            for (a, (row, srow)) in ke.iter_mut().zip(&ks).enumerate() {
                for (bb, (block, s)) in row.iter_mut().zip(srow).enumerate() {
                    *block += s;
                    f[a] += s * (coords[bb] + u[bb]);
                }
            }
        }
        Ok((ke, Some(f)))
    })
}

/// What an element routine hands to [`assemble_elements`]: its stiffness (3×3 blocks) and,
/// optionally, a nodal vector to sum into a global one.
pub type ElementContribution = (ElementStiffness, Option<[Vector3<f64>; 8]>);

/// Assembles Σ_e K_e, and Σ_e f_e when `with_vector`, from any element routine `element(c)`
/// (linear, incompatible modes, or a hyperelastic tangent): the same colour-parallel scatter as
/// [`assemble`].
pub fn assemble_elements<E: Send>(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    with_vector: bool,
    element: &(dyn Fn(usize) -> Result<ElementContribution, E> + Sync),
) -> Result<(Stiffness, Option<Vec<f64>>), E> {
    scatter(pattern, mesh, with_vector, element)
}

fn scatter<E: Send>(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    with_vector: bool,
    element: &(dyn Fn(usize) -> Result<ElementContribution, E> + Sync),
) -> Result<(Stiffness, Option<Vec<f64>>), E> {
    scatter_only(pattern, mesh, with_vector, None, element)
}

/// What an assembly does with the cells it does not take: nothing but `check` them.
type Skipped<'a, E> = (Cells<'a>, &'a (dyn Fn(usize) -> Result<(), E> + Sync));

/// [`scatter`] of the cells `only` takes (all without it); the others add nothing and are only
/// checked.
fn scatter_only<E: Send>(
    pattern: &Arc<StiffnessPattern>,
    mesh: &Mesh,
    with_vector: bool,
    only: Option<Skipped<'_, E>>,
    element: &(dyn Fn(usize) -> Result<ElementContribution, E> + Sync),
) -> Result<(Stiffness, Option<Vec<f64>>), E> {
    let mut values = vec![0.0; pattern.nnz()];
    let mut rhs = with_vector.then(|| vec![0.0; pattern.dofs]);
    let shared = SharedValues(values.as_mut_ptr());
    let shared = &shared;
    let shared_rhs = rhs.as_mut().map(|b| SharedValues(b.as_mut_ptr()));
    let shared_rhs = &shared_rhs;
    for (index, colour) in pattern.colours.iter().enumerate() {
        // Colour 63 collects the cells that found no free colour: they may share nodes.
        let serial = index == 63;
        let add = |&c: &usize| -> Result<(), E> {
            if let Some((take, check)) = only {
                if !take(c) {
                    return check(c);
                }
            }
            let cell = &mesh.cells[c];
            let (ke, fe) = element(c)?;
            if let (Some(f), Some(b)) = (fe, shared_rhs) {
                for a in 0..8 {
                    for i in 0..3 {
                        // SAFETY: as below, cells of one colour share no node.
                        unsafe { *b.0.add(3 * cell[a] + i) += f[a][i] };
                    }
                }
            }
            let ranks = &pattern.ranks[c];
            for a in 0..8 {
                for b in 0..8 {
                    let rank = ranks[a * 8 + b];
                    if rank == u32::MAX {
                        continue;
                    }
                    let (na, nb) = (cell[a], cell[b]);
                    let block = &ke[a][b];
                    for j in 0..3 {
                        let base = pattern.col_ptr[3 * nb + j] + 3 * rank as usize;
                        let rows = if na == nb { j + 1 } else { 3 };
                        for i in 0..rows {
                            // SAFETY: cells of one colour share no node, so no two threads write
                            // the same column; `base + i` lies inside column 3·nb + j.
                            unsafe { *shared.0.add(base + i) += block[(i, j)] };
                        }
                    }
                }
            }
            Ok(())
        };
        if serial {
            colour.iter().try_for_each(add)?;
        } else {
            colour.par_iter().try_for_each(add)?;
        }
    }
    Ok((
        Stiffness {
            pattern: pattern.clone(),
            values,
        },
        rhs,
    ))
}

impl Stiffness {
    /// y = K·x, using the symmetry of the stored upper triangle.
    pub fn mul(&self, x: &[f64]) -> Vec<f64> {
        let p = &self.pattern;
        let mut y = vec![0.0; p.dofs];
        for j in 0..p.dofs {
            let mut acc = 0.0;
            for k in p.col_ptr[j]..p.col_ptr[j + 1] {
                let i = p.row_idx[k];
                let v = self.values[k];
                y[i] += v * x[j];
                if i != j {
                    acc += v * x[i];
                }
            }
            y[j] += acc;
        }
        y
    }
}

impl Stiffness {
    /// Adds the 3×3 block coupling node `a`'s dofs (rows) to node `b`'s (columns), where the
    /// pattern holds it (nodes sharing a cell); only its upper-triangle entries are stored, so
    /// the block of (b, a) is its transpose and need not be added. Returns false, adding
    /// nothing, when the nodes share no cell.
    pub fn add_block(&mut self, a: usize, b: usize, block: &Matrix3<f64>) -> bool {
        let p = &self.pattern;
        if a != b && p.node_neighbours[b].binary_search(&a).is_err() {
            return false;
        }
        for j in 0..3 {
            let col = 3 * b + j;
            for i in 0..3 {
                let row = 3 * a + i;
                if row > col {
                    continue;
                }
                let range = p.col_ptr[col]..p.col_ptr[col + 1];
                if let Ok(k) = p.row_idx[range.clone()].binary_search(&row) {
                    self.values[range.start + k] += block[(i, j)];
                }
            }
        }
        true
    }

    /// Adds `value` to the diagonal entry of dof `d`.
    pub fn add_to_diagonal(&mut self, d: usize, value: f64) {
        let p = &self.pattern;
        let k = (p.col_ptr[d]..p.col_ptr[d + 1])
            .rev()
            .find(|&k| p.row_idx[k] == d)
            .expect("every dof has a diagonal entry");
        self.values[k] += value;
    }

    /// The diagonal entry of dof `d`.
    pub fn diagonal(&self, d: usize) -> f64 {
        let p = &self.pattern;
        (p.col_ptr[d]..p.col_ptr[d + 1])
            .rev()
            .find(|&k| p.row_idx[k] == d)
            .map_or(0.0, |k| self.values[k])
    }
}
