//! glTF is Y-up, the scenes are Z-up: the axes turned as Blender's exporter and importer turn them.

use nalgebra::Vector3;

/// Scene (Z-up) to glTF (Y-up): (x, y, z) → (x, z, −y).
pub fn to_gltf_axes(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, v.z, -v.y)
}

/// glTF (Y-up) to the scene (Z-up): (x, y, z) → (x, −z, y), the inverse of [`to_gltf_axes`]
/// (Blender's importer turns glTF's axes so).
pub fn from_gltf_axes(v: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(v.x, -v.z, v.y)
}
