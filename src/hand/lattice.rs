//! The flesh mesh: a graded hexahedral lattice filling the skin, minus the bones.
//!
//! Cells whose centre is inside the skin and outside every bone are kept. Nodes inside a bone,
//! or on a face shared with a cell inside a bone, are attached to that bone (their displacement is
//! prescribed by its rigid motion). The lattice is twice as fine over the finger-tip pads and the
//! thumb tip (tensor-product grading, so every cell stays a conforming hexahedron). Nodes on the
//! skin are projected onto the skin surface, as far as the cells they touch stay well shaped.
//! Cells of two different digits never share a node: a lattice node touched by both is split,
//! so fingers lying side by side stay separate bodies of flesh joined only through the palm.

use super::shape::SkinShape;
use super::skeleton::{BoneShape, Side, Skeleton};
use crate::fem::hex8::scaled_jacobian;
use crate::mesh::{Mesh, HEX_FACES};
use nalgebra::Vector3;

/// Corner offsets of a lattice cell in VTK node order.
pub(super) const CORNERS: [[usize; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [1, 1, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [1, 1, 1],
    [0, 1, 1],
];

/// Neighbour offsets matching [`HEX_FACES`] (−x, +x, −y, +y, −z, +z).
const FACE_DIRS: [[i64; 3]; 6] = [
    [-1, 0, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [0, 0, -1],
    [0, 0, 1],
];

/// Smallest relative Jacobian a cell may be left with after projecting skin nodes.
const MIN_QUALITY: f64 = 0.3;

/// The meshed flesh of a hand.
#[derive(Clone, Debug)]
pub struct FleshMesh {
    /// Hexahedra in the rest pose.
    pub mesh: Mesh,
    /// The bone each node is attached to, if any.
    pub node_bone: Vec<Option<usize>>,
    /// The digit (0 = thumb … 4 = little) each cell belongs to; `None` for the palm.
    pub cell_digit: Vec<Option<usize>>,
    /// Skin quadrilaterals (outward normals), node indices.
    pub skin_quads: Vec<[usize; 4]>,
    /// The cell each skin quadrilateral bounds.
    pub skin_cells: Vec<usize>,
    /// Whether each skin quadrilateral is on the outer skin (towards outside or another digit),
    /// not a wall of a joint space: the surface that can touch objects.
    pub skin_outer: Vec<bool>,
    /// Control net of the display skin: quads over `display_vertices` (the boundary of flesh,
    /// bones and joint spaces together, outward normals).
    pub display_quads: Vec<[usize; 4]>,
    /// Rest positions of the control net's vertices (lattice points), m.
    pub display_vertices: Vec<Vector3<f64>>,
    /// The flesh cell each display quad is embedded in.
    pub display_cells: Vec<usize>,
    /// Base lattice spacing, m.
    pub spacing: f64,
}

#[derive(Clone, Copy, PartialEq)]
enum CellState {
    Outside,
    Bone(usize),
    /// Between two bones that move relative to each other: the joint space, not flesh (the
    /// nearest bone kept for the display skin's regions).
    Joint(usize),
    Kept(usize),
}

/// Lattice coordinates from `lo` to at least `hi`, spacing `h`, halved inside `fine` intervals.
fn graded(lo: f64, hi: f64, h: f64, fine: &[(f64, f64)]) -> Vec<f64> {
    let mut s = lo;
    let mut out = vec![s];
    while s < hi {
        let probe = s + h * 0.25;
        let step = if fine.iter().any(|&(a, b)| probe >= a && probe <= b) {
            h * 0.5
        } else {
            h
        };
        s += step;
        out.push(s);
    }
    out
}

/// Errors of meshing.
#[derive(Debug, thiserror::Error)]
pub enum MeshingError {
    /// A bone got no node.
    #[error("resolution {resolution} is too coarse: bone \"{bone}\" holds no flesh node (use a higher resolution)")]
    BoneWithoutNodes {
        /// The bone.
        bone: String,
        /// The resolution asked for.
        resolution: f64,
    },
    /// Bad number of subdivisions (outside 1 ..= [`super::MAX_SUBDIVISIONS`]).
    #[error(
        "subdivisions must be a whole number from 1 (the lattice as it is) to {max}, got {0}",
        max = super::MAX_SUBDIVISIONS
    )]
    Subdivisions(usize),
    /// Bad resolution (outside [`RESOLUTIONS`]).
    #[error("resolution must be a number between 0.5 and 4, got {0}")]
    Resolution(f64),
    /// A size that is not a human hand's.
    #[error("size: {0}")]
    Size(String),
    /// The lattice would not fit the memory a solve may take.
    #[error(
        "meshing the hand at resolution {resolution} takes a lattice of {points} points, about \
         {needed} of memory, but {available} is free ({limit}): {advice}"
    )]
    TooLarge {
        /// The resolution asked for.
        resolution: f64,
        /// Lattice points.
        points: u64,
        /// Memory the meshing needs, in words.
        needed: String,
        /// Memory available, in words.
        available: String,
        /// What limits it.
        limit: String,
        /// What to do: the largest resolution that fits, or what frees memory.
        advice: String,
    },
}

/// Memory the meshing takes per lattice point, bytes (measured on an imported hand at twice
/// the built-in hand's size, the whole model's build: 0.44 M lattice points peaked at 0.58 GB,
/// 3.44 M at 3.0 GB — 875 B a point, 810 B for each point more; a sixth kept in hand).
pub const LATTICE_BYTES: u64 = 1000;

/// Refuses to mesh the hand of `skeleton` in `skin` at `resolution` when its lattice would take
/// more memory than a solve may (`max_memory`, `[solver] max_memory`; the machine's free memory
/// and the address space left otherwise): an error naming the resolution that fits, instead of
/// the allocator aborting the process. With its cells split into `subdivisions`³ each
/// ([`super::subdivide`]) it counts `subdivisions`³ times the lattice's points.
pub fn check_memory(
    skeleton: &Skeleton,
    skin: &SkinShape,
    resolution: f64,
    subdivisions: usize,
    max_memory: Option<u64>,
) -> Result<(), MeshingError> {
    if !RESOLUTIONS.contains(&resolution) {
        return Err(MeshingError::Resolution(resolution));
    }
    let Some((available, limit)) = crate::fem::memory::budget_with(max_memory) else {
        return Ok(());
    };
    let points = |r: f64| {
        let [xs, ys, zs] = lattice_axes(skeleton, skin, r, Vector3::zeros());
        let split = subdivisions as u64;
        (xs.len() as u64)
            .saturating_mul(ys.len() as u64)
            .saturating_mul(zs.len() as u64)
            .saturating_mul(split.saturating_mul(split).saturating_mul(split))
    };
    let fits = |r: f64| points(r).saturating_mul(LATTICE_BYTES) <= available;
    let asked = points(resolution);
    if fits(resolution) {
        return Ok(());
    }
    // The largest resolution (to a hundredth, rounded down) whose lattice fits: the lattice
    // grows about as the resolution's cube, but its grading and rounding make it step.
    let (mut lo, mut hi) = (0.5, resolution);
    for _ in 0..20 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mut advised = (lo * 100.0).floor() / 100.0;
    while advised > 0.5 && !fits(advised) {
        advised -= 0.01;
    }
    use crate::fem::memory::human;
    Err(MeshingError::TooLarge {
        resolution,
        points: asked,
        needed: human(asked.saturating_mul(LATTICE_BYTES)),
        available: human(available),
        limit: limit.to_string(),
        advice: if fits(advised) && subdivisions > 1 {
            format!(
                "use fewer subdivisions, or a resolution of at most {advised:.2} with \
                 {subdivisions}, or {}",
                limit.remedy()
            )
        } else if fits(advised) {
            format!(
                "use a resolution of at most {advised:.2}, or {}",
                limit.remedy()
            )
        } else {
            format!("no resolution from 0.5 fits: {}", limit.remedy())
        },
    })
}

/// The resolutions a hand is meshed at (a scene's `resolution`, the benches' and `export-hand`'s
/// `--resolution`): 0.5 (a lattice spacing of 6.4 mm) to 4 (0.8 mm).
pub const RESOLUTIONS: std::ops::RangeInclusive<f64> = 0.5..=4.0;

/// Base lattice spacing at resolution 1, m.
pub const BASE_SPACING: f64 = 0.0032;

/// The lattice's coordinates along x, y and z for the hand of `skeleton` in `skin` at
/// `resolution`: spacing `BASE_SPACING / resolution`, halved over the finger-tip pads and the
/// thumb's distal phalanx; moved by `offset` (m, each component taken modulo the spacing)
/// towards −x, −z and the little finger's side (a left hand's lattice stays the mirror of the
/// right one's).
fn lattice_axes(
    skeleton: &Skeleton,
    skin: &SkinShape,
    resolution: f64,
    offset: Vector3<f64>,
) -> [Vec<f64>; 3] {
    let h = BASE_SPACING / resolution;
    let (mut lo, mut hi) = skin.bounds();
    // Lines through the skin's anchor, if it has one (a right hand's: a left hand's lattice
    // starts from the mirror of its upper bound, below): the start moved down onto them.
    if let Some(anchor) = skin.lattice_anchor() {
        let mut start = lo;
        if skeleton.side == Side::Left {
            start.y = -hi.y;
        }
        let snapped = anchor - ((anchor - start) / h).map(f64::ceil) * h;
        (lo.x, lo.z) = (snapped.x, snapped.z);
        match skeleton.side {
            Side::Right => lo.y = snapped.y,
            Side::Left => hi.y = -snapped.y,
        }
    }
    // Taken modulo a cell: the lattice's lines fall alike, and it grows by one row at most
    // (the memory check's count holds).
    let offset = offset.map(|c| if c.is_finite() { c.rem_euclid(h) } else { 0.0 });
    (lo.x, lo.z) = (lo.x - offset.x, lo.z - offset.z);
    match skeleton.side {
        Side::Right => lo.y -= offset.y,
        Side::Left => hi.y += offset.y,
    }
    // Fine windows: the finger-tip pads (distal phalanges) and the thumb's distal phalanx.
    let dip_x = skeleton
        .bones
        .iter()
        .filter(|b| b.name.ends_with(".distal") && b.digit != Some(0))
        .map(|b| b.start.x)
        .fold(f64::INFINITY, f64::min);
    let thumb_ip = skeleton.bones[skeleton.bone_index("thumb.distal").unwrap()].start;
    // Across the hand (y) the lattice starts on the little finger's side and is graded on the
    // thumb's: a left hand's is the right hand's mirrored (the mirror of its bounds and thumb),
    // so that the two hands are meshed alike — a lattice started at the left hand's own lower
    // bound cut the skin elsewhere and left its surface a hole where the right one had none.
    let ys = match skeleton.side {
        Side::Right => graded(lo.y, hi.y, h, &[(thumb_ip.y - 0.004, hi.y + 1.0)]),
        Side::Left => {
            let fine = (-thumb_ip.y - 0.004, -lo.y + 1.0);
            let mut ys: Vec<f64> = graded(-hi.y, -lo.y, h, &[fine])
                .into_iter()
                .map(|y| -y)
                .collect();
            ys.reverse();
            ys
        }
    };
    let xs = graded(lo.x, hi.x, h, &[(dip_x - 0.004, hi.x + 1.0)]);
    let zs = graded(lo.z, hi.z, h, &[]);
    [xs, ys, zs]
}

/// Meshes the flesh of the hand of `skeleton` (rest pose); `resolution` scales the number of
/// cells per unit length (1 = 3.2 mm base spacing, 1.6 mm on the pads).
pub fn mesh_flesh(
    skeleton: &Skeleton,
    skin: &SkinShape,
    resolution: f64,
) -> Result<FleshMesh, MeshingError> {
    mesh_flesh_offset(skeleton, skin, resolution, Vector3::zeros())
}

/// [`mesh_flesh`] with the lattice moved by `offset` (m, each component taken modulo the
/// spacing) towards −x, −z and the little finger's side: where the lattice falls on the hand
/// changes, nothing else (a study of how much the results depend on it: docs/hand.md).
pub fn mesh_flesh_offset(
    skeleton: &Skeleton,
    skin: &SkinShape,
    resolution: f64,
    offset: Vector3<f64>,
) -> Result<FleshMesh, MeshingError> {
    if !RESOLUTIONS.contains(&resolution) {
        return Err(MeshingError::Resolution(resolution));
    }
    let h = BASE_SPACING / resolution;
    let [xs, ys, zs] = lattice_axes(skeleton, skin, resolution, offset);
    let (nx, ny, nz) = (xs.len() - 1, ys.len() - 1, zs.len() - 1);
    let cell_id = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
    let point = |i: usize, j: usize, k: usize| Vector3::new(xs[i], ys[j], zs[k]);

    // Region of a bone: its digit for phalanges and the thumb; the palm for the carpus and the
    // finger metacarpals.
    let region_of = |b: usize| {
        let bone = &skeleton.bones[b];
        match (bone.digit, bone.name.ends_with(".metacarpal")) {
            (Some(0), _) => Some(0),
            (Some(d), false) => Some(d),
            _ => None,
        }
    };
    let nearest_bone = |p: &Vector3<f64>| {
        let mut best = (f64::INFINITY, 0);
        for (b, bone) in skeleton.bones.iter().enumerate() {
            let d = bone.distance(p);
            if d < best.0 {
                best = (d, b);
            }
        }
        best
    };

    // Classify cells.
    let mut state = vec![CellState::Outside; nx * ny * nz];
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = (point(i, j, k) + point(i + 1, j + 1, k + 1)) / 2.0;
                if skin.distance(&c) >= 0.0 {
                    continue;
                }
                let (d, b) = nearest_bone(&c);
                state[cell_id(i, j, k)] = if d < 0.0 {
                    CellState::Bone(b)
                } else {
                    CellState::Kept(b)
                };
            }
        }
    }
    let compatible = |a: usize, b: usize| {
        let (ra, rb) = (region_of(a), region_of(b));
        ra == rb || ra.is_none() || rb.is_none()
    };

    // Nodes: one per lattice node and group of face-connected compatible incident cells.
    let (mx, my) = (nx + 1, ny + 1);
    let lattice_node = |i: usize, j: usize, k: usize| i + mx * (j + my * k);
    let (node_lattice, node_of) =
        split_lattice_nodes([nx, ny, nz], &compatible, |c| match state[c] {
            CellState::Kept(bone) => Some(bone),
            _ => None,
        });
    let mut nodes: Vec<Vector3<f64>> = node_lattice
        .iter()
        .map(|&[i, j, k]| point(i, j, k))
        .collect();

    // Cells.
    let mut cells = Vec::new();
    let mut cell_bone = Vec::new();
    let mut cell_lattice = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let CellState::Kept(bone) = state[cell_id(i, j, k)] else {
                    continue;
                };
                let hex = CORNERS.map(|[a, b, c]| {
                    let octant = (1 - a) + 2 * (1 - b) + 4 * (1 - c);
                    node_of[lattice_node(i + a, j + b, k + c) * 8 + octant] as usize
                });
                cells.push(hex);
                cell_bone.push(bone);
                cell_lattice.push([i, j, k]);
            }
        }
    }

    // Attach nodes to bones: inside a bone, or corner of a cell inside a bone. These nodes bound
    // the flesh where it meets the bone; they are moved onto the bone's surface below.
    let mut node_bone: Vec<Option<usize>> = vec![None; nodes.len()];
    let mut on_bone = vec![false; nodes.len()];
    for (n, p) in nodes.iter().enumerate() {
        let (d, b) = nearest_bone(p);
        if d < 0.0 {
            node_bone[n] = Some(b);
            on_bone[n] = true;
            continue;
        }
        let [i, j, k] = node_lattice[n];
        for o in 0..8 {
            let (a, bb, c) = (o & 1, (o >> 1) & 1, (o >> 2) & 1);
            let (ci, cj, ck) = (i + a, j + bb, k + c);
            if ci == 0 || cj == 0 || ck == 0 || ci > nx || cj > ny || ck > nz {
                continue;
            }
            if let CellState::Bone(b) = state[cell_id(ci - 1, cj - 1, ck - 1)] {
                node_bone[n] = Some(b);
                on_bone[n] = true;
                break;
            }
        }
    }
    let group = rigid_groups(skeleton);
    // Nodes in a joint space (within `joint_band` of two bones that move relative to each
    // other) follow the nearer bone; the cells between them are then left out below. The band
    // reaches as far from the bones at every resolution as at resolution 1, where it is half a
    // cell and the cells it leaves out reach a cell from the bones: BASE_SPACING − h/2, and never
    // less than half a cell. A finer lattice used to keep cells in the palmar recess of a joint,
    // wedged between the cupped base of one phalanx and the head of the other, and crushed as
    // the joint flexes: at resolution 2 the index's PIP crease cell turned inside out at 30.6°
    // with a band of half a cell, at 56.9° with 1.6 mm.
    let joint_band = (0.5 * h).max(BASE_SPACING - 0.5 * h);
    for (n, p) in nodes.iter().enumerate() {
        if node_bone[n].is_some() {
            continue;
        }
        let mut near: Vec<(f64, usize)> = skeleton
            .bones
            .iter()
            .enumerate()
            .map(|(b, bone)| (bone.distance(p), b))
            .filter(|(d, _)| *d < joint_band)
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        if near.len() >= 2 && near.iter().any(|(_, b)| group[*b] != group[near[0].1]) {
            node_bone[n] = Some(near[0].1);
        }
    }
    // Fallback for thin bones on coarse lattices: the node nearest to points along the axis.
    for (b, bone) in skeleton.bones.iter().enumerate() {
        if node_bone.contains(&Some(b)) {
            continue;
        }
        if let BoneShape::Long { .. } = bone.shape {
            for s in 1..8 {
                let p = bone.start + (bone.end - bone.start) * (s as f64 / 8.0);
                let best = nodes
                    .iter()
                    .enumerate()
                    .filter(|(n, _)| node_bone[*n].is_none())
                    .min_by(|a, b| (a.1 - p).norm().total_cmp(&(b.1 - p).norm()));
                if let Some((n, q)) = best {
                    if (q - p).norm() < h {
                        node_bone[n] = Some(b);
                    }
                }
            }
        }
        if !node_bone.contains(&Some(b)) {
            return Err(MeshingError::BoneWithoutNodes {
                bone: bone.name.clone(),
                resolution,
            });
        }
    }

    // The joint spaces: a cell holding nodes of two bones that can move relative to each other
    // would be sheared across the joint as it flexes; articular surfaces slide instead. Such
    // cells are left out.
    let mut keep = vec![true; cells.len()];
    for (c, cell) in cells.iter().enumerate() {
        let mut groups = cell.iter().filter_map(|&n| node_bone[n].map(|b| group[b]));
        if let Some(first) = groups.next() {
            if groups.any(|g| g != first) {
                keep[c] = false;
                let [i, j, k] = cell_lattice[c];
                state[cell_id(i, j, k)] = CellState::Joint(cell_bone[c]);
            }
        }
    }
    let mut kept = 0;
    for c in 0..cells.len() {
        if keep[c] {
            cells[kept] = cells[c];
            cell_bone[kept] = cell_bone[c];
            cell_lattice[kept] = cell_lattice[c];
            kept += 1;
        }
    }
    cells.truncate(kept);
    cell_bone.truncate(kept);
    cell_lattice.truncate(kept);

    // Skin quads: faces towards outside cells, or towards a cell of another digit.
    let mut skin_quads = Vec::new();
    let mut skin_cells = Vec::new();
    let mut skin_outer = Vec::new();
    let mut on_skin = vec![false; nodes.len()];
    for (c, &[i, j, k]) in cell_lattice.iter().enumerate() {
        for (f, dir) in FACE_DIRS.iter().enumerate() {
            let (ni, nj, nk) = (i as i64 + dir[0], j as i64 + dir[1], k as i64 + dir[2]);
            let outside =
                ni < 0 || nj < 0 || nk < 0 || ni >= nx as i64 || nj >= ny as i64 || nk >= nz as i64;
            let neighbour = if outside {
                CellState::Outside
            } else {
                state[cell_id(ni as usize, nj as usize, nk as usize)]
            };
            let quad = HEX_FACES[f].map(|l| cells[c][l]);
            match neighbour {
                CellState::Outside | CellState::Joint(_) => {
                    skin_quads.push(quad);
                    skin_cells.push(c);
                    skin_outer.push(matches!(neighbour, CellState::Outside));
                    for n in quad {
                        on_skin[n] = true;
                    }
                }
                CellState::Kept(other) if !compatible(cell_bone[c], other) => {
                    skin_quads.push(quad);
                    skin_cells.push(c);
                    skin_outer.push(true);
                }
                _ => {}
            }
        }
    }

    // Project free skin nodes onto the skin; back off where cells would be spoiled. Then the
    // nodes where the flesh meets a bone onto the bone's surface, backing off those alone: the
    // flesh's inner boundary is then the bone, not the staircase of the cells inside it, which
    // thickened the bones by 1.2 mm on average at resolution 1 (0.6 mm at 2) and so stiffened
    // the pads under them, the more so the coarser the lattice.
    let mut skin_target: Vec<Option<Vector3<f64>>> = vec![None; nodes.len()];
    let mut bone_target: Vec<Option<Vector3<f64>>> = vec![None; nodes.len()];
    for n in 0..nodes.len() {
        let (p, target) = match node_bone[n] {
            None if on_skin[n] => (skin.project(&nodes[n]), &mut skin_target[n]),
            // (An attached node on the skin stays: moved onto the bone, it would pull the skin's
            // cells away from the skin points embedded in them; the ring fingertip of the Fist
            // then went through the ball.)
            Some(b) if on_bone[n] && !on_skin[n] => (
                project_on_bone(&skeleton.bones[b], &nodes[n]),
                &mut bone_target[n],
            ),
            _ => continue,
        };
        if (p - nodes[n]).norm() < h {
            *target = Some(p);
        }
    }
    move_within_quality(&mut nodes, &cells, &skin_target);
    move_within_quality(&mut nodes, &cells, &bone_target);

    // Islands of flesh that lost their hold on the bones (a few cells cut off by the joint
    // spaces) would float: they are left out.
    let held = {
        let mesh = Mesh {
            nodes: nodes.clone(),
            cells: cells.clone(),
        };
        let (piece, pieces) = mesh.connected_pieces();
        let mut attached = vec![0usize; pieces];
        for (n, b) in node_bone.iter().enumerate() {
            if b.is_some() {
                attached[piece[n]] += 1;
            }
        }
        let held: Vec<bool> = cells.iter().map(|c| attached[piece[c[0]]] >= 4).collect();
        held
    };
    let mut kept = 0;
    let mut quad_kept = Vec::new();
    let mut new_cell = vec![usize::MAX; cells.len()];
    for c in 0..cells.len() {
        if held[c] {
            new_cell[c] = kept;
            cells[kept] = cells[c];
            cell_bone[kept] = cell_bone[c];
            cell_lattice[kept] = cell_lattice[c];
            kept += 1;
        } else {
            let [i, j, k] = cell_lattice[c];
            state[cell_id(i, j, k)] = CellState::Outside;
        }
    }
    cells.truncate(kept);
    cell_bone.truncate(kept);
    cell_lattice.truncate(kept);
    for ((q, &c), &outer) in skin_quads.iter().zip(&skin_cells).zip(&skin_outer) {
        if new_cell[c] != usize::MAX {
            quad_kept.push(((*q, new_cell[c]), outer));
        }
    }
    let (kept, skin_outer): (Vec<([usize; 4], usize)>, Vec<bool>) = quad_kept.into_iter().unzip();
    let (mut skin_quads, skin_cells): (Vec<[usize; 4]>, Vec<usize>) = kept.into_iter().unzip();

    // Drop the nodes no cell uses any more.
    let mut new_index = vec![usize::MAX; nodes.len()];
    let mut used_nodes = Vec::new();
    let mut used_bone = Vec::new();
    for cell in &mut cells {
        for n in cell.iter_mut() {
            if new_index[*n] == usize::MAX {
                new_index[*n] = used_nodes.len();
                used_nodes.push(nodes[*n]);
                used_bone.push(node_bone[*n]);
            }
            *n = new_index[*n];
        }
    }
    for q in &mut skin_quads {
        for n in q.iter_mut() {
            *n = new_index[*n];
        }
    }
    let (nodes, node_bone) = (used_nodes, used_bone);
    for (b, bone) in skeleton.bones.iter().enumerate() {
        if !node_bone.contains(&Some(b)) {
            return Err(MeshingError::BoneWithoutNodes {
                bone: bone.name.clone(),
                resolution,
            });
        }
    }

    // The display skin's control net: the boundary of everything inside the skin (flesh, bones,
    // joint spaces), so that a bone flush with the skin leaves no hole, each quad tied to the
    // nearest flesh cell, in which its vertices will be embedded.
    let mut sim_cell = vec![usize::MAX; nx * ny * nz];
    for (c, &[i, j, k]) in cell_lattice.iter().enumerate() {
        sim_cell[cell_id(i, j, k)] = c;
    }
    let solid = |st: CellState| match st {
        CellState::Outside => None,
        CellState::Kept(b) | CellState::Bone(b) | CellState::Joint(b) => Some(b),
    };
    let (vertex_lattice, vertex_of) =
        split_lattice_nodes([nx, ny, nz], &compatible, |c| solid(state[c]));
    let display_vertices: Vec<Vector3<f64>> = vertex_lattice
        .iter()
        .map(|&[i, j, k]| point(i, j, k))
        .collect();
    let mut display_quads = Vec::new();
    let mut display_cells = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let Some(bone) = solid(state[cell_id(i, j, k)]) else {
                    continue;
                };
                for (f, dir) in FACE_DIRS.iter().enumerate() {
                    let (ni, nj, nk) = (i as i64 + dir[0], j as i64 + dir[1], k as i64 + dir[2]);
                    let inside_grid = ni >= 0
                        && nj >= 0
                        && nk >= 0
                        && ni < nx as i64
                        && nj < ny as i64
                        && nk < nz as i64;
                    let neighbour = if inside_grid {
                        solid(state[cell_id(ni as usize, nj as usize, nk as usize)])
                    } else {
                        None
                    };
                    if neighbour.is_some_and(|other| compatible(bone, other)) {
                        continue;
                    }
                    let quad = HEX_FACES[f].map(|l| {
                        let [a, b, c] = CORNERS[l];
                        let octant = (1 - a) + 2 * (1 - b) + 4 * (1 - c);
                        vertex_of[lattice_node(i + a, j + b, k + c) * 8 + octant] as usize
                    });
                    // The flesh cell to embed in: this one, or the nearest compatible one around.
                    let here = sim_cell[cell_id(i, j, k)];
                    let host = if here != usize::MAX {
                        Some(here)
                    } else {
                        let mut best: Option<(i64, usize)> = None;
                        for r in 1..=3i64 {
                            for dk in -r..=r {
                                for dj in -r..=r {
                                    for di in -r..=r {
                                        let (a, b, c) =
                                            (i as i64 + di, j as i64 + dj, k as i64 + dk);
                                        if a < 0
                                            || b < 0
                                            || c < 0
                                            || a >= nx as i64
                                            || b >= ny as i64
                                            || c >= nz as i64
                                        {
                                            continue;
                                        }
                                        let id = cell_id(a as usize, b as usize, c as usize);
                                        let sc = sim_cell[id];
                                        if sc == usize::MAX || !compatible(bone, cell_bone[sc]) {
                                            continue;
                                        }
                                        let d = di * di + dj * dj + dk * dk;
                                        if best.is_none_or(|(bd, _)| d < bd) {
                                            best = Some((d, sc));
                                        }
                                    }
                                }
                            }
                            if best.is_some() {
                                break;
                            }
                        }
                        best.map(|b| b.1)
                    };
                    if let Some(host) = host {
                        display_quads.push(quad);
                        display_cells.push(host);
                    }
                }
            }
        }
    }

    Ok(FleshMesh {
        mesh: Mesh { nodes, cells },
        display_quads,
        display_vertices,
        display_cells,
        node_bone,
        cell_digit: cell_bone.iter().map(|&b| region_of(b)).collect(),
        skin_quads,
        skin_cells,
        skin_outer,
        spacing: h,
    })
}

/// The group of every bone: a bone without joint degrees of freedom of its own moves with its
/// parent, so they are one group.
pub(super) fn rigid_groups(skeleton: &Skeleton) -> Vec<usize> {
    let mut group: Vec<usize> = (0..skeleton.bones.len()).collect();
    for (b, bone) in skeleton.bones.iter().enumerate() {
        if let Some(p) = bone.parent {
            if !skeleton.dofs.iter().any(|d| d.bone == b) {
                group[b] = group[p];
            }
        }
    }
    group
}

/// One node per lattice node and group of face-connected, `compatible` incident cells (cells
/// are numbered i + nx·(j + ny·k); `bone_of(cell)` is `None` for a cell that is not there).
/// Returns the lattice position of every node, and the node of every (lattice node, octant)
/// pair (`u32::MAX` where the octant holds no cell), indexed (lattice node)·8 + octant.
fn split_lattice_nodes(
    [nx, ny, nz]: [usize; 3],
    compatible: &impl Fn(usize, usize) -> bool,
    bone_of: impl Fn(usize) -> Option<usize>,
) -> (Vec<[usize; 3]>, Vec<u32>) {
    let (mx, my) = (nx + 1, ny + 1);
    let mut node_of = vec![u32::MAX; mx * my * (nz + 1) * 8];
    let mut positions = Vec::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let mut incident = [None; 8];
                for (o, slot) in incident.iter_mut().enumerate() {
                    let (ci, cj, ck) = (i + (o & 1), j + ((o >> 1) & 1), k + ((o >> 2) & 1));
                    if ci == 0 || cj == 0 || ck == 0 || ci > nx || cj > ny || ck > nz {
                        continue;
                    }
                    *slot = bone_of(ci - 1 + nx * (cj - 1 + ny * (ck - 1)));
                }
                let group = octant_groups(&incident, compatible);
                let base = (i + mx * (j + my * k)) * 8;
                let mut id_of_root = [u32::MAX; 8];
                for o in 0..8 {
                    if incident[o].is_none() {
                        continue;
                    }
                    let r = group[o];
                    if id_of_root[r] == u32::MAX {
                        id_of_root[r] = positions.len() as u32;
                        positions.push([i, j, k]);
                    }
                    node_of[base + o] = id_of_root[r];
                }
            }
        }
    }
    (positions, node_of)
}

/// The eight cells around a lattice node (octant o = a + 2b + 4c, `None` where there is no
/// cell) grouped by face adjacency between cells whose bones are `compatible`: the group
/// representative of every octant. One node (or display vertex) is made per group.
fn octant_groups(
    incident: &[Option<usize>; 8],
    compatible: &impl Fn(usize, usize) -> bool,
) -> [usize; 8] {
    let mut group: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    fn root(g: &[usize; 8], mut x: usize) -> usize {
        while g[x] != x {
            x = g[x];
        }
        x
    }
    for o1 in 0..8 {
        for bit in [1, 2, 4] {
            let o2 = o1 ^ bit;
            if let (Some(a), Some(b)) = (incident[o1], incident[o2]) {
                if compatible(a, b) {
                    let (r1, r2) = (root(&group, o1), root(&group, o2));
                    if r1 != r2 {
                        group[r2] = r1;
                    }
                }
            }
        }
    }
    std::array::from_fn(|o| root(&group, o))
}

/// Moves each node that has a target towards it as far as the cells around it stay of quality
/// [`MIN_QUALITY`]: the nodes of a cell that would be spoiled go half as far, up to six times,
/// then stay where they were.
fn move_within_quality(
    nodes: &mut [Vector3<f64>],
    cells: &[[usize; 8]],
    target: &[Option<Vector3<f64>>],
) {
    let rest = nodes.to_vec();
    let mut scale = vec![1.0f64; nodes.len()];
    let place = |nodes: &mut [Vector3<f64>], scale: &[f64]| {
        for (n, t) in target.iter().enumerate() {
            if let Some(p) = t {
                nodes[n] = rest[n] + (p - rest[n]) * scale[n];
            }
        }
    };
    // From the seventh round on, the nodes of a spoiled cell stay where they were; a cell whose
    // nodes all stay is as good as before, so the rounds end (at the latest when every node of
    // a spoiled cell stays). Until 2026-11-27 they ended after eight rounds unchecked: a node
    // sent back in the last one could spoil a neighbour it had shared a move with (a cell of
    // scaled Jacobian 0.21 in the 5th-percentile woman's hand).
    let mut round = 0;
    loop {
        place(nodes, &scale);
        let mut bad = false;
        for cell in cells {
            if cell.iter().any(|&n| target[n].is_some() && scale[n] > 0.0)
                && scaled_jacobian(&cell.map(|n| nodes[n])) < MIN_QUALITY
            {
                bad = true;
                for &n in cell {
                    scale[n] = if round >= 6 { 0.0 } else { scale[n] * 0.5 };
                }
            }
        }
        if !bad {
            break;
        }
        round += 1;
    }
}

/// `p` moved onto the surface of `bone` (Newton steps on its signed distance, whose gradient is
/// taken by central differences).
fn project_on_bone(bone: &super::skeleton::Bone, p: &Vector3<f64>) -> Vector3<f64> {
    const EPS: f64 = 1e-7;
    let mut q = *p;
    for _ in 0..8 {
        let d = bone.distance(&q);
        if d.abs() < 1e-8 {
            break;
        }
        let g = Vector3::from_fn(|a, _| {
            let mut e = Vector3::zeros();
            e[a] = EPS;
            (bone.distance(&(q + e)) - bone.distance(&(q - e))) / (2.0 * EPS)
        });
        let g2 = g.norm_squared();
        if g2 < 1e-12 {
            break;
        }
        q -= g * (d / g2);
    }
    q
}
