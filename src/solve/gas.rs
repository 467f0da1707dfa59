//! The pressure of a gas cavity: the one scalar unknown p (gauge, Pa) with
//!
//!   (p + p_ambient)·V(U(p)) = P0·V0            (isothermal gas, Boyle–Mariotte)
//!
//! where U(p) is the solve with the cavity's load at p (the load is p·a, a the unit-pressure
//! nodal load) and V(U) the exact volume of the deformed cavity. f(p) = (p + p_amb)·V/(P0·V0) − 1
//! rises with p (more pressure, more volume), so a secant iteration kept inside a bracket
//! converges in a few solves; without contact U is affine in p and V cubic in it.

use super::error::SimError;
use crate::model::GasCavity;

/// Relative tolerance on the gas law: |p_abs·V / (P0·V0) − 1| below it.
pub const GAS_TOLERANCE: f64 = 1e-9;

/// The advice where no pressure satisfies the gas law: the solve at the rest pressure, the first
/// one tried, succeeded, so the load at a fixed pressure solves the frame.
const FIXED_PRESSURE: &str = "Without the gas law the cavity keeps its rest pressure, the first \
     one tried here, which solved: set gas = false on this load (the pressure then no longer \
     follows the volume)";

/// Solves of the cavity's pressure before giving up.
const MAX_SOLVES: usize = 40;

/// Finds the gauge pressure of `cavity` by solving with `solve(p)` (the solve with the cavity's
/// gauge pressure p) and measuring `volume(result)` (the cavity's volume in it), starting from
/// the rest pressure; returns the solve at the pressure that satisfies the gas law.
pub fn solve_with_gas<T>(
    cavity: &GasCavity,
    mut solve: impl FnMut(f64) -> Result<T, SimError>,
    volume: impl Fn(&T) -> f64,
) -> Result<T, SimError> {
    let ambient = cavity.ambient;
    let p0v0 = cavity.rest_absolute() * cavity.rest_volume;
    let mut p = cavity.rest_gauge;
    let mut result = solve(p)?;
    let mut v = volume(&result);
    let mut f = cavity.gas_law_residual(p, v);
    // The bracket: the largest pressure found too low (f < 0), the smallest too high (f > 0).
    let mut low: Option<(f64, f64)> = None;
    let mut high: Option<(f64, f64)> = None;
    let mut previous: Option<(f64, f64)> = None;
    for _ in 0..MAX_SOLVES {
        if !(v.is_finite() && v > 0.0) {
            return Err(gas_error(
                cavity,
                format!(
                    "its volume is {v:e} m³ at gauge pressure {p:.6e} Pa: the wall collapses \
                     the cavity (the squeeze is beyond what small-strain elasticity of this \
                     wall can carry; squeeze less)"
                ),
            ));
        }
        if f.abs() < GAS_TOLERANCE {
            return Ok(result);
        }
        if f < 0.0 {
            low = Some(low.map_or((p, f), |l| if p > l.0 { (p, f) } else { l }));
        } else {
            high = Some(high.map_or((p, f), |h| if p < h.0 { (p, f) } else { h }));
        }
        if let (Some(l), Some(h)) = (low, high) {
            if l.0 >= h.0 {
                return Err(gas_error(
                    cavity,
                    format!(
                        "the cavity's p·V does not rise with its pressure (p·V/(P0·V0) − 1 = \
                         {:.3e} at {:.6e} Pa but {:.3e} at {:.6e} Pa): its wall is not held, or \
                         the selection is not the cavity's surface",
                        l.1, l.0, h.1, h.0
                    ),
                ));
            }
            if h.0 - l.0 <= 1e-14 * (p.abs() + ambient) {
                return Err(gas_error(
                    cavity,
                    format!(
                        "p·V/(P0·V0) − 1 jumps from {:.3e} to {:.3e} between gauge pressures \
                         {:.9e} and {:.9e} Pa: the contact changes there (a node on the edge of \
                         touching, or friction switching between stick and slip), so no \
                         pressure satisfies the gas law to {GAS_TOLERANCE:e}. {FIXED_PRESSURE}",
                        l.1, h.1, l.0, h.0
                    ),
                ));
            }
        }
        // The next pressure: the secant through the last two solves; first, the pressure the
        // gas would have if the wall stayed where it is (p_abs = P0·V0/V).
        let mut next = match previous {
            Some((q, g)) if g != f => p - f * (p - q) / (f - g),
            _ => p0v0 / v - ambient,
        };
        if let (Some(l), Some(h)) = (low, high) {
            if !(next > l.0 && next < h.0) {
                next = 0.5 * (l.0 + h.0);
            }
        }
        if !next.is_finite() {
            next = p0v0 / v - ambient;
        }
        if next <= -ambient {
            // The absolute pressure stays positive: halfway to vacuum.
            next = 0.5 * (p - ambient);
        }
        previous = Some((p, f));
        p = next;
        result = solve(p)?;
        v = volume(&result);
        f = cavity.gas_law_residual(p, v);
    }
    Err(gas_error(
        cavity,
        format!(
            "no pressure satisfies the gas law to {GAS_TOLERANCE:e} after {MAX_SOLVES} solves \
             (p·V/(P0·V0) − 1 = {f:.3e} at gauge pressure {p:.6e} Pa): the contact's active set \
             keeps changing with the pressure. {FIXED_PRESSURE}"
        ),
    ))
}

fn gas_error(cavity: &GasCavity, reason: String) -> SimError {
    SimError::Gas {
        load: cavity.name.clone(),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{boundary_facets, box_mesh};
    use nalgebra::Vector3;

    /// A cavity of 1 m³ (a unit cube's boundary, its facets turned to face into it as a wall
    /// around it would) at gauge 0 Pa, ambient 1e5 Pa.
    fn cube_cavity() -> GasCavity {
        let mesh = box_mesh(Vector3::zeros(), Vector3::repeat(1.0), [1, 1, 1]);
        let mut facets = boundary_facets(&mesh);
        for f in &mut facets {
            f.nodes.reverse();
        }
        GasCavity::new("air".into(), 0, &mesh, facets, 0.0, 1e5).unwrap()
    }

    /// The message of the solve where the volume follows `volume(p)` (a stand-in for the
    /// solve at gauge pressure p), and the pressures tried.
    fn failure(volume: impl Fn(f64) -> f64) -> (String, Vec<f64>) {
        let cavity = cube_cavity();
        let mut tried = Vec::new();
        let result = solve_with_gas(
            &cavity,
            |p| {
                tried.push(p);
                Ok(p)
            },
            |&p| volume(p),
        );
        (
            result.expect_err("no pressure satisfies it").to_string(),
            tried,
        )
    }

    /// A volume that jumps across the root (a contact switching on at 5 kPa): the bracket
    /// closes on the jump (told as a jump once it is within round-off, else after the solves
    /// allowed, here), and the advice (the fixed rest pressure) is the first pressure tried,
    /// which solved.
    #[test]
    fn a_volume_jumping_across_the_gas_law_is_told_with_advice_that_solves() {
        let (message, tried) = failure(|p| if p < 5e3 { 0.9 } else { 0.99 });
        assert!(message.contains("5.000000e3 Pa"), "{message}");
        assert!(message.contains("set gas = false"), "{message}");
        assert_eq!(tried[0], 0.0);
    }

    /// A wall that gives way so that p·V stays half the gas's (no pressure satisfies the law):
    /// told after the solves allowed, with the same advice.
    #[test]
    fn a_gas_law_without_a_root_is_told_with_advice_that_solves() {
        let (message, tried) = failure(|p| 0.5e5 / (p + 1e5));
        assert!(message.contains("after 40 solves"), "{message}");
        assert!(message.contains("set gas = false"), "{message}");
        assert_eq!(tried[0], 0.0);
    }
}
