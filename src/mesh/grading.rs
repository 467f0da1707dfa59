//! Grading: element sizes growing geometrically away from the point where a body is touched.
//!
//! A size that grows by the factor g from one element to the next, starting at h₀ on the touched
//! point, is h(d) = h₀ + (g − 1)·d at the distance d from it; it stops growing at the base size.

use nalgebra::{Matrix3, Rotation3, Vector3};

/// The ratio of the sizes of two neighbouring elements along a graded line.
pub const GROWTH: f64 = 1.25;

/// Where and how finely a ball is refined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refinement {
    /// Unit vector from the ball's centre toward the touched point of its surface.
    pub direction: Vector3<f64>,
    /// Element size at the touched point, m.
    pub size: f64,
}

/// Positions from 0 to `length` along a line whose origin lies at the distance `start` from the
/// touched point: steps of h(d) = `first` + (GROWTH − 1)·d, at most `largest`, all scaled by one
/// factor ≤ 1 so the last position is `length` exactly (neighbouring steps keep their ratio).
pub fn graded_positions(start: f64, length: f64, first: f64, largest: f64) -> Vec<f64> {
    let mut positions = vec![0.0];
    let mut s = 0.0;
    while s < length * (1.0 - 1e-9) {
        s += (first + (GROWTH - 1.0) * (start + s)).min(largest);
        positions.push(s);
    }
    let scale = length / s;
    for p in &mut positions {
        *p *= scale;
    }
    *positions.last_mut().expect("two positions at least") = length;
    positions
}

/// Coordinates of a cube face's lattice lines, from −1 to 1, graded by the angle from the face's
/// centre (the touched pole): tan θ for θ graded in arc length on the sphere of radius
/// `radius`, with arcs of `first` at the pole growing to `largest`. Symmetric about 0, which is a
/// line; the ends are ±1 exactly, so nodes there lie on the cube's surface.
pub fn polar_face_coordinates(radius: f64, first: f64, largest: f64) -> Vec<f64> {
    let quarter = std::f64::consts::FRAC_PI_4 * radius;
    let half: Vec<f64> = graded_positions(0.0, quarter, first, largest)
        .iter()
        .map(|d| (d / radius).tan())
        .collect();
    let mut coords: Vec<f64> = half.iter().rev().map(|x| -x).collect();
    coords.extend_from_slice(&half[1..]);
    let last = coords.len() - 1;
    (coords[0], coords[last]) = (-1.0, 1.0);
    coords
}

/// Coordinates of the side faces' lattice lines along the pole's axis, from −1 (the edge next to
/// the touched face) to 1: tan θ, θ from −π/4 to π/4, graded in arc length from the pole at the
/// angle π/4 + θ.
pub fn side_face_coordinates(radius: f64, first: f64, largest: f64) -> Vec<f64> {
    let quarter = std::f64::consts::FRAC_PI_4 * radius;
    let mut coords: Vec<f64> = graded_positions(quarter, 2.0 * quarter, first, largest)
        .iter()
        .map(|d| (d / radius - std::f64::consts::FRAC_PI_4).tan())
        .collect();
    let last = coords.len() - 1;
    (coords[0], coords[last]) = (-1.0, 1.0);
    coords
}

/// The rotation taking −z (the pole a graded mesh is built around) onto `direction` (a unit
/// vector); exact (a permutation with signs) when `direction` is ±z.
pub fn pole_rotation(direction: &Vector3<f64>) -> Matrix3<f64> {
    let down = -Vector3::z();
    if *direction == down {
        Matrix3::identity()
    } else if *direction == Vector3::z() {
        Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0))
    } else {
        Rotation3::rotation_between(&down, direction)
            .unwrap_or_else(|| Rotation3::from_matrix_unchecked(Matrix3::identity()))
            .into_inner()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_grow_by_the_ratio_and_end_on_the_length() {
        let p = graded_positions(0.0, 1.0, 0.01, 0.1);
        assert_eq!(p[0], 0.0);
        assert_eq!(*p.last().unwrap(), 1.0);
        let steps: Vec<f64> = p.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(steps[0] <= 0.01 && steps[0] > 0.008, "{steps:?}");
        for w in steps.windows(2) {
            let ratio = w[1] / w[0];
            assert!((1.0 - 1e-9..=GROWTH + 1e-9).contains(&ratio), "{steps:?}");
        }
        assert!(steps.iter().all(|&h| h <= 0.1));
    }

    #[test]
    fn face_coordinates_are_symmetric_and_end_on_the_cube() {
        let x = polar_face_coordinates(0.05, 0.001, 0.006);
        assert_eq!((x[0], x[x.len() - 1]), (-1.0, 1.0));
        let mid = x.len() / 2;
        assert_eq!(x[mid], 0.0);
        // The first arc is the size asked, or a little less (every step scaled alike).
        let first = x[mid + 1].atan() * 0.05;
        assert!(first <= 0.001 * (1.0 + 1e-12) && first > 0.0008, "{first}");
        let z = side_face_coordinates(0.05, 0.001, 0.006);
        assert_eq!((z[0], z[z.len() - 1]), (-1.0, 1.0));
        assert!(z.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn the_pole_turns_onto_the_direction() {
        for d in [
            Vector3::new(1.0, 2.0, -0.5).normalize(),
            Vector3::z(),
            -Vector3::z(),
            Vector3::x(),
        ] {
            let q = pole_rotation(&d);
            assert!((q * -Vector3::z() - d).norm() < 1e-12);
            assert!((q.determinant() - 1.0).abs() < 1e-12);
        }
    }
}
