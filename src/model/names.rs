//! The names a scene gives its bodies, materials, constraints, obstacles, probes and cameras:
//! what keyframes, loads, selections and the report refer to them by.

/// `name` refused when it is empty or only spaces (`name = ""` was accepted, and its body then
/// reported as `""`): the error to give with the entry's field.
pub(super) fn named(kind: &str, name: &str) -> Result<(), String> {
    if name.trim().is_empty() {
        return Err(format!(
            "has no name: give the {kind} a name (`name = \"…\"`), which the scene and the \
             report refer to it by"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::named;

    #[test]
    fn an_empty_or_blank_name_is_refused() {
        assert!(named("body", "")
            .unwrap_err()
            .contains("give the body a name"));
        assert!(named("probe", "  ").is_err());
        assert!(named("body", "ball").is_ok());
    }
}
