//! Small checks and message pieces shared by the steps of `Model::build`.

/// Whether every value is a finite number.
pub fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// Names for an error message: comma-separated, or "none".
pub fn list(names: &[&str]) -> String {
    if names.is_empty() {
        "none".into()
    } else {
        names.join(", ")
    }
}
