//! Knots of a hand's flexion flexed ahead, while the solver had nothing to do, for a keyframe
//! that may be asked next (the viewer's pose presets from the pose shown: issue 20). A knot is
//! one flexion from a state to joint angles (its parts left to skinning, its FEM region chosen
//! on given flesh: [`super::path`]); the same knot asked again — the same state to the same
//! angles, bit for bit — is the same computation, so its result is taken from here instead.
//!
//! Kept per hand with its flexion caches. Bounded in memory ([`KnotMemo::BUDGET`]): a knot that
//! does not fit is not kept. Emptied when the work ahead starts from another pose.

use super::proximity::PARTS;
use crate::state::{HandState, KeyframeStats};
use nalgebra::Vector3;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

/// What a knot is flexed from: the state, the joint angles, the parts left to skinning, the
/// flesh its FEM region is chosen on.
pub(super) type KnotFrom<'a> = (&'a HandState, &'a [f64], [bool; PARTS], &'a [Vector3<f64>]);

/// One knot kept: what it was flexed from (compared in full on a hit) and what it reached.
struct Kept {
    hash: u64,
    state: HandState,
    target: Vec<f64>,
    far: [bool; PARTS],
    region_at: Vec<Vector3<f64>>,
    reached: (HandState, KeyframeStats),
}

/// The knots kept (see the module).
pub struct KnotMemo {
    kept: Vec<Kept>,
    bytes: usize,
    /// The memory the knots kept may take, bytes.
    budget: usize,
}

impl Default for KnotMemo {
    fn default() -> Self {
        KnotMemo {
            kept: Vec::new(),
            bytes: 0,
            budget: Self::BUDGET,
        }
    }
}

impl KnotMemo {
    /// The memory the knots kept may take, bytes (at resolution 1 a knot takes ≈ 1.5 MB; a
    /// preset's motion is 5–11 knots).
    pub const BUDGET: usize = 256 << 20;

    /// The knot flexed from `from` (bit for bit), if kept: its state, and its stats with the
    /// time and the factorizations it took counted where it was flexed ahead, not now.
    pub(super) fn get(&self, from: KnotFrom<'_>) -> Option<(HandState, KeyframeStats)> {
        let hash = fingerprint(from);
        let (state, target, far, region_at) = from;
        let kept = self.kept.iter().find(|k| {
            k.hash == hash
                && k.far == far
                && same_bits(&k.target, target)
                && same_state(&k.state, state)
                && same_points(&k.region_at, region_at)
        })?;
        let (state, stats) = kept.reached.clone();
        Some((state, flexed_ahead(stats)))
    }

    /// Keeps the knot flexed from `from` to `reached`, if it fits in the budget ([`Self::BUDGET`]). Returns
    /// whether it was kept.
    pub(super) fn put(&mut self, from: KnotFrom<'_>, reached: &(HandState, KeyframeStats)) -> bool {
        let (state, target, far, region_at) = from;
        let bytes = state_bytes(state) + state_bytes(&reached.0) + 24 * region_at.len();
        if self.bytes.saturating_add(bytes) > self.budget || self.get(from).is_some() {
            return false;
        }
        self.bytes += bytes;
        self.kept.push(Kept {
            hash: fingerprint(from),
            state: state.clone(),
            target: target.to_vec(),
            far,
            region_at: region_at.to_vec(),
            reached: reached.clone(),
        });
        true
    }

    /// Forgets every knot kept.
    pub(super) fn clear(&mut self) {
        self.kept.clear();
        self.bytes = 0;
    }

    /// How many knots are kept.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.kept.len()
    }

    /// Whether none is kept.
    #[cfg(test)]
    pub fn is_empty(&self) -> bool {
        self.kept.is_empty()
    }
}

/// `stats` of a knot taken from the memo: its times and factorizations were spent ahead.
fn flexed_ahead(mut stats: KeyframeStats) -> KeyframeStats {
    stats.factorizations = 0;
    stats.assembly_ms = 0.0;
    stats.symbolic_ms = 0.0;
    stats.factorization_ms = 0.0;
    stats.solve_ms = 0.0;
    stats.update_ms = 0.0;
    stats.total_ms = 0.0;
    stats.knots_flexed_ahead = 1;
    stats
}

/// The bytes a hand state holds (its vectors).
fn state_bytes(s: &HandState) -> usize {
    8 * (s.angles.len() + s.self_contact.len())
        + 24 * (s.positions.len() + s.reaction.len())
        + std::mem::size_of::<nalgebra::Isometry3<f64>>() * s.transforms.len()
}

/// A hash of every bit of what a knot is flexed from (a fast first comparison).
fn fingerprint((state, target, far, region_at): KnotFrom<'_>) -> u64 {
    let mut h = DefaultHasher::new();
    let mut floats = |xs: &mut dyn Iterator<Item = f64>| {
        for x in xs {
            x.to_bits().hash(&mut h);
        }
    };
    floats(&mut state.angles.iter().copied());
    floats(&mut target.iter().copied());
    floats(&mut state.positions.iter().flat_map(|p| p.iter().copied()));
    floats(&mut state.reaction.iter().flat_map(|p| p.iter().copied()));
    floats(&mut state.self_contact.iter().copied());
    floats(&mut region_at.iter().flat_map(|p| p.iter().copied()));
    far.hash(&mut h);
    h.finish()
}

pub(super) fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

pub(super) fn same_points(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.iter()
                .zip(y.iter())
                .all(|(p, q)| p.to_bits() == q.to_bits())
        })
}

pub(super) fn same_state(a: &HandState, b: &HandState) -> bool {
    same_bits(&a.angles, &b.angles)
        && same_points(&a.positions, &b.positions)
        && same_points(&a.reaction, &b.reaction)
        && same_bits(&a.self_contact, &b.self_contact)
        && a.far_strained == b.far_strained
        && a.transforms.len() == b.transforms.len()
        && a.transforms.iter().zip(&b.transforms).all(|(x, y)| {
            same_bits(
                x.translation.vector.as_slice(),
                y.translation.vector.as_slice(),
            ) && same_bits(x.rotation.coords.as_slice(), y.rotation.coords.as_slice())
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;

    fn state(x: f64) -> HandState {
        HandState {
            angles: vec![x, 2.0],
            transforms: vec![Isometry3::identity(); 2],
            positions: vec![Vector3::new(x, 0.0, 1.0); 3],
            reaction: vec![Vector3::zeros(); 3],
            self_contact: Vec::new(),
            far_strained: Vec::new(),
        }
    }

    /// A knot is found only from the same state to the same angles, bit for bit, and its cost
    /// is said to have been spent ahead.
    #[test]
    fn a_knot_is_taken_only_from_the_same_state_to_the_same_angles() {
        let mut memo = KnotMemo::default();
        let (from, region) = (state(1.0), vec![Vector3::new(0.0, 0.0, 0.0)]);
        let stats = KeyframeStats {
            factorizations: 3,
            total_ms: 120.0,
            increments_taken: 2,
            ..Default::default()
        };
        let reached = (state(5.0), stats);
        let far = [false; PARTS];
        assert!(memo.put((&from, &[5.0, 2.0], far, &region), &reached));
        let (got, stats) = memo.get((&from, &[5.0, 2.0], far, &region)).unwrap();
        assert_eq!(got.angles, vec![5.0, 2.0]);
        assert_eq!(
            (stats.factorizations, stats.total_ms, stats.increments_taken),
            (0, 0.0, 2)
        );
        assert_eq!(stats.knots_flexed_ahead, 1);
        // Another target, another start one ulp away, other far parts, another region: none.
        assert!(memo.get((&from, &[5.0, 2.5], far, &region)).is_none());
        let mut moved = from.clone();
        moved.positions[2].x = f64::from_bits(moved.positions[2].x.to_bits() + 1);
        assert!(memo.get((&moved, &[5.0, 2.0], far, &region)).is_none());
        let mut skinned = far;
        skinned[3] = true;
        assert!(memo.get((&from, &[5.0, 2.0], skinned, &region)).is_none());
        assert!(memo
            .get((&from, &[5.0, 2.0], far, &[Vector3::x()]))
            .is_none());
        // Kept once; cleared, gone.
        assert!(!memo.put((&from, &[5.0, 2.0], far, &region), &reached));
        assert_eq!(memo.len(), 1);
        memo.clear();
        assert!(memo.is_empty());
        assert!(memo.get((&from, &[5.0, 2.0], far, &region)).is_none());
    }

    /// Knots beyond the memory budget are not kept.
    #[test]
    fn the_memo_keeps_within_its_budget() {
        let mut memo = KnotMemo {
            budget: 1000,
            ..Default::default()
        };
        let reached = (state(2.0), KeyframeStats::default());
        let far = [false; PARTS];
        // A knot of these small states takes 2 × (16 + 144 + 2 isometries) bytes.
        let mut kept = 0;
        for i in 0..10 {
            kept += usize::from(memo.put((&state(i as f64), &[1.0, 2.0], far, &[]), &reached));
        }
        let each = 2 * (16 + 144 + 2 * std::mem::size_of::<nalgebra::Isometry3<f64>>());
        assert_eq!(kept, 1000 / each);
        assert_eq!(memo.len(), kept);
        assert!(memo.get((&state(9.0), &[1.0, 2.0], far, &[])).is_none());
    }
}
