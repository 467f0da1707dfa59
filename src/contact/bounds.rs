//! Axis-aligned boxes around points: what a facet or a path may reach, for rejecting pairs that
//! cannot meet before any exact test.

use nalgebra::Vector3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vec3;

/// The box `lo`–`hi` (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub lo: Vector3<f64>,
    pub hi: Vector3<f64>,
}

impl Bounds {
    /// The smallest box holding `points` (at least one).
    pub fn of<'a>(points: impl IntoIterator<Item = &'a Vector3<f64>>) -> Bounds {
        let mut points = points.into_iter();
        let first = *points.next().expect("a box around at least one point");
        points.fold(
            Bounds {
                lo: first,
                hi: first,
            },
            |b, p| Bounds {
                lo: b.lo.inf(p),
                hi: b.hi.sup(p),
            },
        )
    }

    /// The box grown by `margin` on every side.
    pub fn grown(&self, margin: f64) -> Bounds {
        let m = Vector3::repeat(margin);
        Bounds {
            lo: self.lo - m,
            hi: self.hi + m,
        }
    }

    /// Whether `x` lies in the box (its faces included).
    pub fn holds(&self, x: &Vector3<f64>) -> bool {
        (0..3).all(|i| x[i] >= self.lo[i] && x[i] <= self.hi[i])
    }

    /// Whether the two boxes overlap (touching included).
    pub fn meets(&self, other: &Bounds) -> bool {
        (0..3).all(|i| self.lo[i] <= other.hi[i] && self.hi[i] >= other.lo[i])
    }

    /// Its largest side, m.
    pub fn largest_side(&self) -> f64 {
        (self.hi - self.lo).amax()
    }

    /// As a box of the hierarchies.
    pub fn aabb(&self) -> Aabb {
        Aabb::new(
            Vec3::new(self.lo.x, self.lo.y, self.lo.z),
            Vec3::new(self.hi.x, self.hi.y, self.hi.z),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_holds_its_points_and_meets_what_overlaps_it() {
        let v = Vector3::new;
        let b = Bounds::of(&[v(0.0, 1.0, 2.0), v(1.0, -1.0, 3.0), v(0.5, 0.0, 2.5)]);
        assert_eq!((b.lo, b.hi), (v(0.0, -1.0, 2.0), v(1.0, 1.0, 3.0)));
        assert!(b.holds(&v(1.0, 1.0, 3.0)) && !b.holds(&v(1.1, 0.0, 2.5)));
        assert!(b.grown(0.1).holds(&v(1.1, 0.0, 2.5)));
        let beside = Bounds::of(&[v(1.5, 0.0, 2.5)]);
        assert!(!b.meets(&beside) && b.grown(0.5).meets(&beside) && beside.grown(0.5).meets(&b));
        assert_eq!(b.largest_side(), 2.0);
    }
}
