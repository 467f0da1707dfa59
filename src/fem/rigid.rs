//! Detection of rigid-body motions left free by the prescribed displacements.
//!
//! A piece of a body is held when the prescribed dofs, seen as linear functionals on the six
//! rigid motions (three translations, three rotations), have rank six.

use nalgebra::{Matrix6, SymmetricEigen, Vector3, Vector6};

/// Names of the rigid motions a piece can still make, empty when it is held. `nodes` are the
/// nodes of the piece, `prescribed(dof)` tells whether a dof is prescribed. A piece of one node
/// (a node in no cell) has only the translations: a rotation about it does not move it.
pub fn free_rigid_motions(
    nodes: &[usize],
    positions: &[Vector3<f64>],
    prescribed: impl Fn(usize) -> bool,
) -> Vec<String> {
    if let [n] = nodes {
        const AXES: [&str; 3] = [
            "translation along x",
            "translation along y",
            "translation along z",
        ];
        return (0..3)
            .filter(|&i| !prescribed(3 * n + i))
            .map(|i| AXES[i].to_string())
            .collect();
    }
    // Rotations about the centroid of the held nodes, lengths in units of their spread: the
    // rank does not depend on the reference point or the unit, and so a clamped end of a body
    // 1e5 times longer than it is wide stays well conditioned (about the body's centroid, its
    // rotations would fall below the tolerance).
    let held: Vec<usize> = nodes
        .iter()
        .copied()
        .filter(|&n| (0..3).any(|i| prescribed(3 * n + i)))
        .collect();
    let reference = if held.is_empty() { nodes } else { &held[..] };
    let centroid = reference
        .iter()
        .map(|&n| positions[n])
        .sum::<Vector3<f64>>()
        / reference.len() as f64;
    let size = reference
        .iter()
        .map(|&n| (positions[n] - centroid).norm())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut gram = Matrix6::<f64>::zeros();
    for &n in nodes {
        let y = (positions[n] - centroid) / size;
        for i in 0..3 {
            if !prescribed(3 * n + i) {
                continue;
            }
            let mut row = Vector6::zeros();
            row[i] = 1.0;
            for k in 0..3 {
                let mut axis = Vector3::zeros();
                axis[k] = 1.0;
                row[3 + k] = axis.cross(&y)[i];
            }
            gram += row * row.transpose();
        }
    }
    let eigen = SymmetricEigen::new(gram);
    let largest = eigen.eigenvalues.amax();
    const NAMES: [&str; 6] = [
        "translation along x",
        "translation along y",
        "translation along z",
        "rotation about x",
        "rotation about y",
        "rotation about z",
    ];
    let mut free = Vec::new();
    for (k, &lambda) in eigen.eigenvalues.iter().enumerate() {
        if largest == 0.0 || lambda <= 1e-9 * largest {
            let v = eigen.eigenvectors.column(k);
            let mut name = NAMES[v.iamax()].to_string();
            while free.contains(&name) {
                // Two free modes dominated by the same component: name the next largest.
                let mut w = v.abs();
                for (j, n) in NAMES.iter().enumerate() {
                    if free.iter().any(|f| f == n) {
                        w[j] = 0.0;
                    }
                }
                name = NAMES[w.iamax()].to_string();
            }
            free.push(name);
        }
    }
    free.sort();
    free
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node in no cell is held by its three translations; rotating about it moves nothing.
    #[test]
    fn a_lone_node_is_held_by_its_translations() {
        let positions = [Vector3::new(5.0, 5.0, 5.0)];
        assert!(free_rigid_motions(&[0], &positions, |_| true).is_empty());
        assert_eq!(
            free_rigid_motions(&[0], &positions, |d| d != 1),
            vec!["translation along y".to_string()]
        );
    }
}
