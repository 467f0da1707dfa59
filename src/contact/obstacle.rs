//! Rigid obstacles: where their surface is nearest a point, and on which side the point lies.

use nalgebra::Vector3;

/// A rigid obstacle that bodies may not enter.
#[derive(Clone, Debug, PartialEq)]
pub enum Obstacle {
    /// The half-space below a plane (bodies stay on the side `normal` points to).
    Plane {
        /// A point of the plane, m.
        point: Vector3<f64>,
        /// Unit normal, pointing out of the obstacle.
        normal: Vector3<f64>,
    },
    /// A rigid ball (bodies stay outside).
    Sphere {
        /// Centre, m.
        center: Vector3<f64>,
        /// Radius, m.
        radius: f64,
    },
}

impl Obstacle {
    /// For a point `x`: the signed gap (positive outside the obstacle, negative when it
    /// penetrates), the outward unit normal of the surface at the nearest point, and that point.
    pub fn nearest(&self, x: &Vector3<f64>) -> (f64, Vector3<f64>, Vector3<f64>) {
        match self {
            Obstacle::Plane { point, normal } => {
                let g = (x - point).dot(normal);
                (g, *normal, x - normal * g)
            }
            Obstacle::Sphere { center, radius } => {
                let d = x - center;
                let r = d.norm();
                let n = if r > 0.0 { d / r } else { Vector3::z() };
                (r - radius, n, center + n * *radius)
            }
        }
    }
}
