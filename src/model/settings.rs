//! The settings of `[solver]`: contact iteration, friction table, flexion of the hands, the
//! warnings they deserve, and the fill-reducing ordering.

use super::flexion_settings::{FleshRegion, FlexionSettings};
use super::names::shown;
use super::tier;
use super::{BodyModel, FrictionTable};
use crate::contact::{ContactSettings, Relaxation};
use crate::fem::solve::FillOrdering;
use crate::scene::{
    FarFromContact, FleshRegionName, MemorySize, RelaxationDef, Scene, SolverSettings,
};

/// The contact settings of `[solver]`.
/// `smallest`: the smallest body contact can meet between bodies, its name and size (m), where
/// there are two bodies or more.
pub fn contact_settings(
    s: &SolverSettings,
    largest: f64,
    smallest: Option<(&str, f64)>,
) -> Result<ContactSettings, (String, String)> {
    let mut out = ContactSettings {
        tolerance: s.contact_tolerance.unwrap_or(1e-7 * largest),
        max_iterations: s
            .contact_max_iterations
            .unwrap_or(crate::contact::DEFAULT_MAX_ITERATIONS),
        method: s.contact.unwrap_or_default().into(),
        pairs: s.contact_pairs.unwrap_or_default().into(),
        ..ContactSettings::default()
    };
    if !(out.tolerance.is_finite() && out.tolerance >= 0.0) {
        return Err((
            "solver.contact_tolerance".into(),
            format!("must be a length ≥ 0 m, got {}", out.tolerance),
        ));
    }
    if out.max_iterations == 0 {
        return Err((
            "solver.contact_max_iterations".into(),
            "must be at least 1".into(),
        ));
    }
    if let Some(c) = s.contact_change_tolerance {
        if !(c.is_finite() && c > 0.0) {
            return Err((
                "solver.contact_change_tolerance".into(),
                format!("must be a length > 0 m, got {c}"),
            ));
        }
        out.change_tolerance = c;
    }
    if let Some(d) = s.contact_search {
        if !(d.is_finite() && d > 0.0) {
            return Err((
                "solver.contact_search".into(),
                format!("must be a length > 0 m, got {d}"),
            ));
        }
        // How deep a point may be inside a body and still be pushed out of it: no point is
        // deeper inside a body than its size. Deeper searches met far facets and invented
        // contact (1 m: the grasp's ball diverged; 1e300 m: "element 2 inverted").
        if let Some((name, size)) = smallest.filter(|&(_, size)| d > size) {
            return Err((
                "solver.contact_search".into(),
                format!(
                    "must be at most the size of the smallest body contact meets, \"{}\" \
                     ({size:.3e} m across), got {d:e} m: it is how deep a point may be inside a \
                     body and still be pushed out (the default is {:.0e} m)",
                    shown(name),
                    ContactSettings::default().search_depth
                ),
            ));
        }
        out.search_depth = d;
    }
    out.relaxation = match &s.contact_relaxation {
        None => Relaxation::QuasiNewton,
        Some(RelaxationDef::Name(n)) if n == "aitken" => Relaxation::Aitken,
        Some(RelaxationDef::Name(n)) if n == "quasi_newton" => Relaxation::QuasiNewton,
        Some(RelaxationDef::Factor(w)) if w.is_finite() && *w > 0.0 && *w <= 1.0 => {
            Relaxation::Fixed(*w)
        }
        Some(other) => {
            let got = match other {
                RelaxationDef::Name(n) => format!("\"{}\"", shown(n)),
                RelaxationDef::Factor(w) => format!("{w}"),
            };
            return Err((
                "solver.contact_relaxation".into(),
                format!("must be \"quasi_newton\", \"aitken\" or a factor in (0, 1], got {got}"),
            ));
        }
    };
    Ok(out)
}

/// The friction coefficients: `[solver] friction` and the `[[friction]]` pairs.
pub fn friction_table(scene: &Scene) -> Result<FrictionTable, (String, String)> {
    let default = scene.solver.friction.unwrap_or(0.0);
    if !(default.is_finite() && default >= 0.0) {
        return Err((
            "solver.friction".into(),
            format!("μ must be ≥ 0, got {default}"),
        ));
    }
    let mut pairs = Vec::new();
    for (i, f) in scene.friction.iter().enumerate() {
        let field = format!("friction[{i}]");
        if f.between.len() != 2 {
            return Err((
                format!("{field}.between"),
                format!(
                    "names two materials (or a material and an obstacle), got {} names",
                    f.between.len()
                ),
            ));
        }
        let obstacle = |name: &String| scene.obstacle.iter().any(|o| &o.name == name);
        for name in &f.between {
            let known = scene.material.iter().any(|m| &m.name == name) || obstacle(name);
            if !known {
                return Err((
                    format!("{field}.between"),
                    format!("\"{}\" is neither a material nor an obstacle", shown(name)),
                ));
            }
        }
        // Obstacles are rigid and fixed: contact is between a body and an obstacle (or two
        // bodies), never two obstacles, so such a μ would be used nowhere.
        if f.between.iter().all(obstacle) {
            return Err((
                format!("{field}.between"),
                format!(
                    "\"{}\" and \"{}\" are both obstacles, which never touch each other: a \
                     friction pair names two materials, or a material and an obstacle",
                    shown(&f.between[0]),
                    shown(&f.between[1])
                ),
            ));
        }
        if !(f.mu.is_finite() && f.mu >= 0.0) {
            return Err((
                format!("{field}.mu"),
                format!("μ must be ≥ 0, got {}", f.mu),
            ));
        }
        let (a, b) = (&f.between[0], &f.between[1]);
        if let Some(j) = pairs
            .iter()
            .position(|(x, y, _)| (x == a && y == b) || (x == b && y == a))
        {
            return Err((
                format!("{field}.between"),
                format!(
                    "the pair \"{}\", \"{}\" is already given a μ by friction[{j}]",
                    shown(a),
                    shown(b)
                ),
            ));
        }
        pairs.push((a.clone(), b.clone(), f.mu));
    }
    Ok((default, pairs))
}

/// The smallest flexion increment a scene may ask for, degrees: a joint's whole range (at most
/// 180°) in 1 800 increments; smaller ones would only make a solve that never ends.
pub const MIN_STEP_DEG: f64 = 0.1;

/// The flexion settings of `[solver]`.
pub fn flexion_settings(s: &SolverSettings) -> Result<FlexionSettings, (String, String)> {
    let mut out = FlexionSettings::default();
    if let Some(step) = s.max_step_deg {
        if !(step.is_finite() && (MIN_STEP_DEG..=45.0).contains(&step)) {
            return Err((
                "solver.max_step_deg".into(),
                format!("must be in [{MIN_STEP_DEG}, 45] degrees, got {step}"),
            ));
        }
        out.max_step_deg = step;
    }
    if let Some(m) = s.flesh {
        out.methods = [m.into(); 6];
    }
    tier::apply_tier(s, &mut out)?;
    const PARTS: [&str; 6] = ["palm", "thumb", "index", "middle", "ring", "little"];
    for (name, &m) in &s.flesh_digits {
        let Some(i) = PARTS.iter().position(|p| p == name) else {
            return Err((
                format!("solver.flesh_digits.{}", shown(name)),
                format!("is not a part of the hand ({})", PARTS.join(", ")),
            ));
        };
        out.methods[i] = m.into();
    }
    let radius = s.flesh_region_radius.unwrap_or(0.012);
    if !(radius.is_finite() && radius > 0.0) {
        return Err((
            "solver.flesh_region_radius".into(),
            format!("must be a positive length in metres, got {radius}"),
        ));
    }
    out.region = match s.flesh_region {
        Some(FleshRegionName::Whole) => FleshRegion::Whole,
        _ => FleshRegion::Local { radius },
    };
    if let Some(b) = s.skinning {
        out.blend = b.into();
    }
    if let Some(v) = s.volumetric {
        out.volumetric = v.into();
    }
    let near = s.near_contact.unwrap_or(0.01);
    if !(near.is_finite() && near > 0.0) {
        return Err((
            "solver.near_contact".into(),
            format!("must be a positive distance in metres, got {near}"),
        ));
    }
    out.near_contact = match s.far_from_contact {
        Some(FarFromContact::Solve) => None,
        _ => Some(near),
    };
    if let Some(f) = s.flexion {
        out.scheme = f.into();
    }
    Ok(out)
}

/// Warnings about the flexion settings for the bodies of the model (`nonlinear`: `[solver] tier
/// = "nonlinear"`).
pub fn warnings(nonlinear: bool, flexion: &FlexionSettings, bodies: &[BodyModel]) -> Vec<String> {
    let has_hand = bodies.iter().any(|b| b.hand.is_some());
    let mut warnings = tier::flexion_warnings(flexion, has_hand);
    let has_object = bodies.iter().any(|b| b.hand.is_none());
    warnings.extend(tier::nonlinear_contact_warning(
        nonlinear, has_hand, has_object,
    ));
    warnings
}

/// The fill-reducing ordering of `[solver]` (the lesser fill of the two unless one is named).
pub fn ordering(s: &SolverSettings) -> FillOrdering {
    s.ordering.map_or(FillOrdering::Auto, FillOrdering::from)
}

/// `[solver] max_memory` in bytes; the error is (field, message).
pub fn max_memory(s: &SolverSettings) -> Result<Option<u64>, (String, String)> {
    let field = || "solver.max_memory".to_string();
    let bytes = match &s.max_memory {
        None => return Ok(None),
        Some(MemorySize::Bytes(b)) => *b,
        Some(MemorySize::Text(given)) => {
            let t = given.trim();
            let text = shown(given);
            // A sign, NaN or infinity is no size: told as such, not as an unknown unit.
            if t.starts_with(['-', '+']) || t.to_ascii_lowercase().starts_with(['n', 'i']) {
                return Err((
                    field(),
                    format!("max_memory = \"{text}\" is not a size: give a positive number of bytes with a unit, e.g. \"8 GB\""),
                ));
            }
            let split = t
                .find(|c: char| {
                    !(c.is_ascii_digit() || c == '.' || c == 'e' || c == 'E' || c == '+')
                })
                .unwrap_or(t.len());
            let (number, unit) = t.split_at(split);
            let scale = match unit.trim() {
                "" | "B" => 1.0,
                "kB" | "KB" => 1e3,
                "MB" => 1e6,
                "GB" => 1e9,
                "TB" => 1e12,
                "KiB" => 1024.0,
                "MiB" => 1024.0 * 1024.0,
                "GiB" => 1024.0 * 1024.0 * 1024.0,
                "TiB" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
                other => {
                    return Err((
                        field(),
                        format!(
                            "max_memory = \"{text}\": unknown unit \"{}\" (use B, kB, \
                             MB, GB, TB, KiB, MiB, GiB or TiB)",
                            shown(other)
                        ),
                    ))
                }
            };
            let value: f64 = number.trim().parse().map_err(|_| {
                (
                    field(),
                    format!("max_memory = \"{text}\" is not a number with a unit, e.g. \"8 GB\""),
                )
            })?;
            value * scale
        }
    };
    if !(1e6..1.8e19).contains(&bytes) {
        return Err((
            field(),
            format!(
                "max_memory = {} bytes must be a finite size from 1 MB up",
                crate::util::readable(bytes)
            ),
        ));
    }
    Ok(Some(bytes as u64))
}
