//! Wall-clock timing of the solver's phases.

use std::time::Instant;

/// Milliseconds elapsed since `t`.
pub fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
