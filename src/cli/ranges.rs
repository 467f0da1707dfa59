//! The numeric options' ranges, checked by clap as the arguments are parsed — before any work —
//! so that a value out of range is a usage error naming the option and its range (exit 2), never
//! a panic, an abort or a measurement of nothing.

/// Cells per edge of `bench solver`'s cube: n³ within a body's 5 000 000 elements.
pub const CUBE_CELLS: std::ops::RangeInclusive<u64> = 1..=170;

/// Elements through the thickness of `bench elements`' cantilever (8k × k × k): k = 16 is
/// 32 768 elements, 112 000 dofs (k = 8 takes about 2 s; the mesh is built without the
/// memory check a scene's bodies have, and k = 100 000 aborted the allocator).
pub const CANTILEVER_CELLS: std::ops::RangeInclusive<u64> = 1..=16;

/// `bench render --spheres`: n × 2n quads, n = 1000 being 4 M triangles (about 100 MB of vertex
/// and index buffers, within a software adapter's 256 MB buffer).
pub const SPHERE_RINGS: std::ops::RangeInclusive<u64> = 1..=1000;

/// `bench flexion-refinement --offsets`: how many of its lattice offsets (six).
pub const LATTICE_OFFSETS: std::ops::RangeInclusive<u64> =
    1..=crate::bench::flexion_refinement::OFFSETS.len() as u64;

/// `bench flexion-refinement --subdivisions`: how many times a cell's edges are split.
pub const SUBDIVISIONS: std::ops::RangeInclusive<u64> = 1..=crate::hand::MAX_SUBDIVISIONS as u64;

/// A whole number within `range`.
pub fn count(
    range: std::ops::RangeInclusive<u64>,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync + 'static {
    move |text| {
        let value: u64 = text
            .trim()
            .parse()
            .map_err(|_| format!("\"{text}\" is not a whole number"))?;
        if !range.contains(&value) {
            return Err(format!(
                "{value} is out of range: from {} to {}",
                range.start(),
                range.end()
            ));
        }
        usize::try_from(value).map_err(|_| format!("{value} is too large"))
    }
}

/// A whole number of at least 1.
pub fn positive(text: &str) -> Result<usize, String> {
    let value: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("\"{text}\" is not a whole number"))?;
    if value == 0 {
        return Err("0 is out of range: at least 1".into());
    }
    Ok(value)
}

/// A hand mesh resolution within [`crate::hand::RESOLUTIONS`].
pub fn hand_resolution(text: &str) -> Result<f64, String> {
    let range = crate::hand::RESOLUTIONS;
    let value = number(text)?;
    if !range.contains(&value) {
        return Err(format!(
            "{value} is out of range: a hand resolution is from {} to {}",
            range.start(),
            range.end()
        ));
    }
    Ok(value)
}

/// A Coulomb friction coefficient: finite and at least 0 (as a scene's `mu`).
pub fn friction(text: &str) -> Result<f64, String> {
    let value = number(text)?;
    if !(value.is_finite() && value >= 0.0) {
        return Err(format!(
            "a friction coefficient is a finite number of at least 0, got {value}"
        ));
    }
    Ok(value)
}

/// A finite number.
pub fn finite(text: &str) -> Result<f64, String> {
    let value = number(text)?;
    if !value.is_finite() {
        return Err(format!("{value} is not a finite number"));
    }
    Ok(value)
}

fn number(text: &str) -> Result<f64, String> {
    text.trim()
        .parse::<f64>()
        .map_err(|_| format!("\"{text}\" is not a number"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_refuse_what_cannot_be_run() {
        assert_eq!(hand_resolution("1.25"), Ok(1.25));
        for bad in ["0", "nan", "99", "inf", "x"] {
            assert!(hand_resolution(bad).is_err(), "{bad}");
        }
        assert!(friction("-0.1").is_err() && friction("nan").is_err());
        assert_eq!(friction("0"), Ok(0.0));
        assert!(finite("inf").is_err() && finite("1.5").is_ok());
        assert_eq!(count(CUBE_CELLS)("170"), Ok(170));
        for bad in ["0", "171", "-1", "1.5", "100000000000000000000"] {
            assert!(count(CUBE_CELLS)(bad).is_err(), "{bad}");
        }
        assert_eq!(positive("1"), Ok(1));
        assert!(positive("0").is_err());
    }
}
