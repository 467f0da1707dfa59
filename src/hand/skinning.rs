//! Geometric skinning, the fast path: each flesh node follows a weighted blend of the rigid
//! motions of the bones nearest to it (today's equivalent of the paper's Joint-dependent Local
//! Deformations). Dual-quaternion blending keeps volume near joints; linear blending is the
//! classic alternative (and shrinks flexed joints, the "candy wrapper").

use super::skeleton::Skeleton;
use nalgebra::{
    DualQuaternion, Isometry3, Point3, Quaternion, UnitDualQuaternion, UnitQuaternion, Vector3,
};

/// How bone motions are blended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Blend {
    /// Linear blend skinning: x = Σ w_b T_b x.
    Linear,
    /// Dual-quaternion skinning: x = normalise(Σ w_b q_b) x.
    #[default]
    DualQuaternion,
}

/// Up to three bone weights per node.
#[derive(Clone, Debug)]
pub struct SkinningWeights {
    /// (bone, weight) per node; weights sum to one.
    pub weights: Vec<Vec<(usize, f64)>>,
}

/// Distance over which a node's weight falls off, m.
const FALLOFF: f64 = 0.0005;

impl SkinningWeights {
    /// Weights for rest positions `nodes`: a node attached to a bone follows that bone only;
    /// any other node blends its nearest bone with that bone's parent and children, with weights
    /// proportional to (distance + 0.5 mm)⁻⁴.
    pub fn new(
        skeleton: &Skeleton,
        nodes: &[Vector3<f64>],
        attached: &[Option<usize>],
    ) -> SkinningWeights {
        let children = skeleton.children();
        let weights = nodes
            .iter()
            .zip(attached)
            .map(|(p, bone)| {
                if let Some(b) = bone {
                    return vec![(*b, 1.0)];
                }
                let d: Vec<f64> = skeleton
                    .bones
                    .iter()
                    .map(|b| b.distance(p).max(0.0))
                    .collect();
                let nearest = (0..d.len()).min_by(|&a, &b| d[a].total_cmp(&d[b])).unwrap();
                let mut candidates = vec![nearest];
                if let Some(parent) = skeleton.bones[nearest].parent {
                    candidates.push(parent);
                }
                candidates.extend(children[nearest].iter().copied());
                let mut w: Vec<(usize, f64)> = candidates
                    .into_iter()
                    .map(|b| (b, (d[b] + FALLOFF).powi(-4)))
                    .collect();
                w.sort_by(|a, b| b.1.total_cmp(&a.1));
                w.truncate(3);
                let total: f64 = w.iter().map(|e| e.1).sum();
                for e in &mut w {
                    e.1 /= total;
                }
                w.retain(|e| e.1 > 1e-4);
                let total: f64 = w.iter().map(|e| e.1).sum();
                for e in &mut w {
                    e.1 /= total;
                }
                w
            })
            .collect();
        SkinningWeights { weights }
    }

    /// The rotation node `n` follows under `motions`: its bones' rotations weighted, on one
    /// hemisphere, normalised.
    pub fn blended_rotation(&self, n: usize, motions: &[Isometry3<f64>]) -> UnitQuaternion<f64> {
        let w = &self.weights[n];
        let first = motions[w[0].0].rotation.into_inner();
        let mut sum = Quaternion::new(0.0, 0.0, 0.0, 0.0);
        for &(b, wb) in w {
            let q = motions[b].rotation.into_inner();
            sum += q * if q.dot(&first) < 0.0 { -wb } else { wb };
        }
        UnitQuaternion::new_normalize(sum)
    }

    /// Moves `points` (one per node) by the blended bone motions `motions`.
    pub fn apply(
        &self,
        blend: Blend,
        motions: &[Isometry3<f64>],
        points: &[Vector3<f64>],
        nodes: impl Iterator<Item = usize>,
        out: &mut [Vector3<f64>],
    ) {
        let dual: Vec<UnitDualQuaternion<f64>> = match blend {
            Blend::DualQuaternion => motions
                .iter()
                .map(UnitDualQuaternion::from_isometry)
                .collect(),
            Blend::Linear => Vec::new(),
        };
        for n in nodes {
            let w = &self.weights[n];
            let p = Point3::from(points[n]);
            out[n] = match blend {
                Blend::Linear => w.iter().map(|&(b, wb)| (motions[b] * p).coords * wb).sum(),
                Blend::DualQuaternion => {
                    if w.len() == 1 {
                        (motions[w[0].0] * p).coords
                    } else {
                        let first = dual[w[0].0].as_ref().real;
                        let mut sum = DualQuaternion::from_real_and_dual(
                            nalgebra::Quaternion::new(0.0, 0.0, 0.0, 0.0),
                            nalgebra::Quaternion::new(0.0, 0.0, 0.0, 0.0),
                        );
                        for &(b, wb) in w {
                            let q = dual[b].as_ref();
                            // Take the quaternion on the same hemisphere as the first.
                            let s = if q.real.dot(&first) < 0.0 { -wb } else { wb };
                            sum.real += q.real * s;
                            sum.dual += q.dual * s;
                        }
                        let unit = UnitDualQuaternion::new_normalize(sum);
                        (unit.to_isometry() * p).coords
                    }
                }
            };
        }
    }
}
