//! Triangle surfaces of the bones in the rest pose, for display: long bones as surfaces of
//! revolution following their radius profile (shaft and condyles), the carpus as a rounded block.

use super::anatomy::JOINT_GAP;
use super::skeleton::{cup_radius, long_bone_radius, Bone, BoneShape};
use nalgebra::Vector3;

/// A triangle surface: positions and triangles.
pub type TriangleSurface = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

/// Rings along the axis and points around each ring.
const RINGS: usize = 24;
const AROUND: usize = 16;

/// The surface of `bone` at rest.
pub fn bone_surface(bone: &Bone) -> TriangleSurface {
    match bone.shape {
        BoneShape::Long { shaft, distal } => {
            let axis = bone.end - bone.start;
            let len = axis.norm();
            let dir = axis / len;
            let helper = if dir.z.abs() < 0.9 {
                Vector3::z()
            } else {
                Vector3::x()
            };
            let u = dir.cross(&helper).normalize();
            let v = dir.cross(&u);
            let r0 = long_bone_radius(0.0, shaft, distal);
            let r1 = long_bone_radius(1.0, shaft, distal);
            let mut profile = Vec::new();
            let cap = 6;
            let (a, l) = if let Some((c, inner)) = bone.cup {
                // Cupped base: a ring around the parent's head, narrowing into the shaft.
                let base = cup_radius(inner, shaft);
                let b = bone.end - dir * (JOINT_GAP + r1);
                let l = (b - c).norm();
                profile.push((inner * 0.55, inner * 0.83));
                for i in 0..RINGS {
                    let s = inner * 0.6 + (l - inner * 0.6) * i as f64 / RINGS as f64;
                    let t = s / l;
                    let r = long_bone_radius(s / len, shaft, distal).max(base * (1.0 - t / 0.35));
                    profile.push((s, r));
                }
                (c, l)
            } else {
                let a = bone.start + dir * (JOINT_GAP + r0);
                // Profile: (position along the axis from `a`, radius), caps as quarter circles.
                for i in 0..=cap {
                    let phi = std::f64::consts::FRAC_PI_2 * (1.0 - i as f64 / cap as f64);
                    profile.push((-r0 * phi.sin(), r0 * phi.cos()));
                }
                let l = len - 2.0 * JOINT_GAP - r0 - r1;
                for i in 1..RINGS {
                    let s = l * i as f64 / RINGS as f64;
                    profile.push((s, long_bone_radius((s + r0) / len, shaft, distal)));
                }
                (a, l)
            };
            for i in 0..=cap {
                let phi = std::f64::consts::FRAC_PI_2 * i as f64 / cap as f64;
                profile.push((l + r1 * phi.sin(), r1 * phi.cos()));
            }
            revolve(&profile, a, dir, u, v)
        }
        BoneShape::Block { half, axes } => {
            let c = (bone.start + bone.end) / 2.0;
            let (mut pos, tri) = revolve(
                &(0..=12)
                    .map(|i| {
                        let phi = std::f64::consts::PI * i as f64 / 12.0;
                        (-phi.cos(), phi.sin())
                    })
                    .collect::<Vec<_>>(),
                Vector3::zeros(),
                Vector3::x(),
                Vector3::y(),
                Vector3::z(),
            );
            for p in &mut pos {
                // A superellipsoid-like block: push the unit sphere towards the box.
                let q = p.map(|x| x.signum() * x.abs().powf(0.5));
                *p = c + axes * q.component_mul(&Vector3::from(half));
            }
            (pos, tri)
        }
    }
}

fn revolve(
    profile: &[(f64, f64)],
    a: Vector3<f64>,
    dir: Vector3<f64>,
    u: Vector3<f64>,
    v: Vector3<f64>,
) -> TriangleSurface {
    let mut pos = Vec::new();
    for &(s, r) in profile {
        for k in 0..AROUND {
            let t = std::f64::consts::TAU * k as f64 / AROUND as f64;
            pos.push(a + dir * s + (u * t.cos() + v * t.sin()) * r);
        }
    }
    let mut tri = Vec::new();
    for i in 0..profile.len() - 1 {
        for k in 0..AROUND {
            let k1 = (k + 1) % AROUND;
            let p = |i: usize, k: usize| (i * AROUND + k) as u32;
            tri.push([p(i, k), p(i + 1, k), p(i + 1, k1)]);
            tri.push([p(i, k), p(i + 1, k1), p(i, k1)]);
        }
    }
    (pos, tri)
}
