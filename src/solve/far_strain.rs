//! Which flesh cells skinning strains where a part of the hand is left to it far from contact
//! (`[solver] far_from_contact = "skinning"`): their positions are no equilibrium, so the
//! internal force there is no reaction of the bones.

use crate::hand::HandModel;
use nalgebra::Isometry3;

/// The flesh cells (by index) that skinning strains as the bones move from `from` to `to`:
/// those whose nodes follow, by their skinning weights, a bone of a part marked `far` (0 palm,
/// 1 thumb … 5 little, a bone's part its digit's: a finger's metacarpal is its finger's, where
/// the flesh around it is the palm's) and another bone, of a far part or of the palm, that
/// moves apart from it: a bending joint of a skinned finger, its blend into the palm. A far
/// finger that keeps still strains nothing; a cell between a far finger and another (their
/// web), where only the other moves, is left to it.
pub(super) fn strained_by_far_skinning(
    hand: &HandModel,
    (from, to): (&[Isometry3<f64>], &[Isometry3<f64>]),
    far: &[bool; 6],
) -> Vec<bool> {
    let cells = &hand.flesh.mesh.cells;
    if !far.iter().any(|&f| f) {
        return vec![false; cells.len()];
    }
    let bones = &hand.skeleton.bones;
    // Bones grouped by their motion.
    let motion: Vec<Isometry3<f64>> = from.iter().zip(to).map(|(a, b)| b * a.inverse()).collect();
    let class = super::self_contact::motion_classes(&motion);
    let part = |b: usize| bones[b].digit.map_or(0, |d| d + 1);
    let weights = &hand.weights.weights;
    cells
        .iter()
        .map(|cell| {
            let mut followed: Vec<usize> = cell
                .iter()
                .flat_map(|&n| weights[n].iter().filter(|w| w.1 > 0.0).map(|w| w.0))
                .collect();
            followed.sort_unstable();
            followed.dedup();
            followed.iter().any(|&f| {
                far[part(f)]
                    && followed
                        .iter()
                        .any(|&b| class[b] != class[f] && (far[part(b)] || part(b) == 0))
            })
        })
        .collect()
}
