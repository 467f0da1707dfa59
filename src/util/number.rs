//! Numbers written for people in messages: a value far from 1 in scientific notation, so that
//! an angle of 1e300 (a hostile scene) is 1.000e300, not a line of three hundred digits.

/// `x` for a message: plain (to at most 6 significant digits) between 1e-3 and 1e6 in size,
/// scientific outside, and NaN/inf as Rust writes them.
pub fn readable(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if a == 0.0 {
        return "0".into();
    }
    if (1e-3..1e6).contains(&a) {
        // Six significant digits, trailing zeros dropped.
        let digits = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        let text = format!("{x:.digits$}");
        // Rounded up to a million (999999.9): scientific, as a million is.
        if text.parse::<f64>().is_ok_and(|r| r.abs() < 1e6) {
            return if text.contains('.') {
                text.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                text
            };
        }
    }
    format!("{x:.3e}")
}

#[cfg(test)]
mod tests {
    use super::readable;

    #[test]
    fn numbers_are_short() {
        assert_eq!(readable(1e300), "1.000e300");
        assert_eq!(readable(-2.5e-7), "-2.500e-7");
        assert_eq!(readable(95.0), "95");
        assert_eq!(readable(12.345678), "12.3457");
        assert_eq!(readable(0.0), "0");
        assert_eq!(readable(1e30), "1.000e30");
        assert_eq!(readable(f64::NAN), "NaN");
        assert_eq!(readable(-0.0), "0");
        assert_eq!(readable(999999.9), "1.000e6");
        assert_eq!(readable(0.001), "0.001");
        assert_eq!(readable(-45.5), "-45.5");
    }
}
