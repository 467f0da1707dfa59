//! Fill-reducing ordering by geometric nested dissection.
//!
//! On 3D meshes nested dissection leaves far less fill in the Cholesky factor than minimum degree:
//! split the nodes by a plane through the median of the longest axis, take as separator the nodes
//! of one half that touch the other, order both halves recursively and the separator last.

use nalgebra::Vector3;

/// Below this many nodes a part is ordered as it comes.
const LEAF: usize = 64;

/// Orders the nodes listed in `nodes` (a subset of the mesh) by nested dissection over the graph
/// `neighbours` (neighbours outside the subset are ignored). Returns the nodes in elimination
/// order.
pub fn nested_dissection(
    nodes: &[usize],
    positions: &[Vector3<f64>],
    neighbours: &[Vec<usize>],
) -> Vec<usize> {
    let mut stamp = vec![0u32; positions.len()];
    let mut next_stamp = 1u32;
    let mut order = Vec::with_capacity(nodes.len());
    let mut work = nodes.to_vec();
    dissect(
        &mut work,
        positions,
        neighbours,
        &mut stamp,
        &mut next_stamp,
        &mut order,
    );
    order
}

fn dissect(
    part: &mut [usize],
    positions: &[Vector3<f64>],
    neighbours: &[Vec<usize>],
    stamp: &mut [u32],
    next_stamp: &mut u32,
    order: &mut Vec<usize>,
) {
    if part.len() <= LEAF {
        order.extend_from_slice(part);
        return;
    }
    let mut lo = positions[part[0]];
    let mut hi = lo;
    for &n in part.iter() {
        lo = lo.inf(&positions[n]);
        hi = hi.sup(&positions[n]);
    }
    let axis = (hi - lo).imax();
    let mid = part.len() / 2;
    part.select_nth_unstable_by(mid, |&a, &b| {
        positions[a][axis].total_cmp(&positions[b][axis])
    });
    let median = positions[part[mid]][axis];
    // Left: strictly below the median plane; right: on or above it.
    let split = partition_in_place(part, |n| positions[n][axis] < median);
    if split == 0 || split == part.len() {
        order.extend_from_slice(part);
        return;
    }
    let (left, right) = part.split_at_mut(split);
    let left_stamp = *next_stamp;
    *next_stamp += 1;
    for &n in left.iter() {
        stamp[n] = left_stamp;
    }
    // Separator: right-hand nodes with a neighbour on the left; moved to the end of `right`.
    let keep = partition_in_place(right, |n| {
        !neighbours[n].iter().any(|&m| stamp[m] == left_stamp)
    });
    let (right_inner, separator) = right.split_at_mut(keep);
    let separator = separator.to_vec();
    dissect(left, positions, neighbours, stamp, next_stamp, order);
    dissect(right_inner, positions, neighbours, stamp, next_stamp, order);
    order.extend_from_slice(&separator);
}

/// Moves the elements satisfying `pred` to the front; returns how many there are.
fn partition_in_place(items: &mut [usize], pred: impl Fn(usize) -> bool) -> usize {
    let mut k = 0;
    for i in 0..items.len() {
        if pred(items[i]) {
            items.swap(i, k);
            k += 1;
        }
    }
    k
}
