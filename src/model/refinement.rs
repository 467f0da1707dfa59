//! A ball's `refine` key checked and turned into the mesh's `Refinement`: the touched point is the
//! point of the surface nearest `toward`.

use super::check::finite;
use crate::mesh::Refinement;
use crate::scene::Refine;
use nalgebra::Vector3;

/// The default size at the touched point, as a fraction of the touched surface's radius.
pub const DEFAULT_SIZE_OF_RADIUS: f64 = 1.0 / 32.0;

/// The smallest size accepted, as a fraction of the radius (finer cells lose digits in the map).
const SMALLEST_SIZE_OF_RADIUS: f64 = 1e-4;

/// Where a ball is touched: its refinement, and whether the touched surface is the outer one
/// (else a shell's cavity). `radii` are the inner (0 for a solid ball) and outer radii; the
/// error is (the field under `refine`, the message).
pub fn refinement(
    refine: &Refine,
    center: &[f64; 3],
    (inner, outer): (f64, f64),
) -> Result<(Refinement, bool), (&'static str, String)> {
    if !finite(&refine.toward) {
        return Err((
            "toward",
            format!("toward = {:?} must be a finite point", refine.toward),
        ));
    }
    let offset = Vector3::from(refine.toward) - Vector3::from(*center);
    let distance = offset.norm();
    if distance <= 1e-9 * outer {
        return Err((
            "toward",
            format!(
                "toward = {:?} is the ball's centre: every point of the surface is as near; \
                 give a point off the centre, toward (or on) the touched side",
                refine.toward
            ),
        ));
    }
    // On a shell, a point in the cavity is nearest the inner surface.
    let on_outer = inner <= 0.0 || distance >= 0.5 * (inner + outer);
    let touched = if on_outer { outer } else { inner };
    let size = refine.size.unwrap_or(DEFAULT_SIZE_OF_RADIUS * touched);
    if !(size.is_finite() && size >= SMALLEST_SIZE_OF_RADIUS * touched && size <= touched) {
        return Err((
            "size",
            format!(
                "size = {} m must be a finite length from {} m to the touched radius {} m",
                crate::util::readable(size),
                crate::util::readable(SMALLEST_SIZE_OF_RADIUS * touched),
                crate::util::readable(touched)
            ),
        ));
    }
    Ok((
        Refinement {
            direction: offset / distance,
            size,
        },
        on_outer,
    ))
}
