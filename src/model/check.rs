//! Small checks and message pieces shared by the steps of `Model::build`.

/// Whether every value is a finite number.
pub fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// Names for an error message: comma-separated (each as [`shown`](super::names::shown)), or
/// "none".
pub fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names
            .iter()
            .map(|n| super::names::shown(n))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Largest placement angle either way, degrees: a turn more is the same placement, and far
/// beyond it the angle's round-off exceeds a degree (1e20° is a random direction).
pub const MAX_ROTATION_DEG: f64 = 360.0;

/// A placement's rotation: finite angles in degrees, each within ±[`MAX_ROTATION_DEG`].
pub fn rotation(r: &[f64; 3]) -> Result<(), String> {
    if r.iter()
        .all(|x| x.is_finite() && x.abs() <= MAX_ROTATION_DEG)
    {
        Ok(())
    } else {
        Err(format!(
            "`placement.rotation` must be finite angles in degrees, each within \
             ±{MAX_ROTATION_DEG}° (about x, y, z), got [{}]",
            r.map(crate::util::readable).join(", ")
        ))
    }
}
