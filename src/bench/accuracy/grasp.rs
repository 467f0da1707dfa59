//! (e) The ball grasp of `assets/scenes/hand-grasp-ball.toml` (Figure 4 of the paper): a right
//! hand closes its fingers and thumb on a pressurised rubber shell. The hand's `resolution` and
//! the ball's mesh are refined together (12·r cells per cube-face edge, rounded to even, and
//! 2·r layers, at least 2). The error is that of the contact force the hand receives against
//! the reference solution (finest resolution, smallest step, most exact tier): the total grip
//! Σ|F_part| over palm and digits, and the largest error of one part's force vector, both
//! relative to the reference's total grip; and the grip against the same tier and step on the
//! row's own mesh (the tier's error alone).

use super::{Column, Solved, Unit};
use crate::scene::{Scene, Shape};
use crate::state::outcome::{part_of_bone, PARTS};
use nalgebra::Vector3;

/// The scene file of the grasp, built into the binary.
const GRASP: &str = include_str!("../../../assets/scenes/hand-grasp-ball.toml");

/// Total grip error, largest part error, total grip.
pub const COLUMNS: &[Column] = &[
    Column {
        name: "grip force error",
        unit: Unit::Percent,
    },
    Column {
        name: "largest per-part force error / reference grip",
        unit: Unit::Percent,
    },
    Column {
        name: "grip error against the same mesh's reference",
        unit: Unit::Percent,
    },
    Column {
        name: "grip Σ|F| (N)",
        unit: Unit::Newton,
    },
];

/// The grasp scene with the hand at `resolution` and the ball refined alike.
pub fn scene(resolution: f64) -> Scene {
    let mut scene =
        Scene::parse(GRASP, "assets/scenes/hand-grasp-ball.toml").expect("the grasp scene parses");
    for body in &mut scene.body {
        match &mut body.shape {
            Shape::Hand { resolution: r, .. } => *r = resolution,
            Shape::Shell { cells, layers, .. } => {
                *cells = 2 * ((6.0 * resolution).round() as usize).max(1);
                *layers = ((2.0 * resolution).round() as usize).max(2);
            }
            _ => {}
        }
    }
    scene
}

/// The contact force on each part of the first hand (palm, thumb, index, …) in the last frame.
fn part_forces(solved: &Solved) -> Result<Vec<Vector3<f64>>, String> {
    let frame = solved.frames.last().ok_or("no frame")?;
    let h = frame.hands.first().ok_or("no hand in the frame")?;
    let hand = solved.model.bodies[h.body]
        .hand
        .as_deref()
        .ok_or("the body is not a hand")?;
    let mut parts = vec![Vector3::zeros(); PARTS.len()];
    for (b, f) in h.contact_force.iter().enumerate() {
        parts[part_of_bone(hand, b)] += f;
    }
    Ok(parts)
}

/// Σ|F_part|, N.
fn grip(parts: &[Vector3<f64>]) -> f64 {
    parts.iter().map(|f| f.norm()).sum()
}

/// The errors of a solved grasp against the finest reference and the same mesh's.
pub fn measure(solved: &Solved, finest: &Solved, same_mesh: &Solved) -> Result<Vec<f64>, String> {
    let (test, refr) = (part_forces(solved)?, part_forces(finest)?);
    let same = grip(&part_forces(same_mesh)?);
    if same <= 0.0 {
        return Err("the same-mesh reference grasp has no contact force".into());
    }
    let total = grip(&refr);
    if total <= 0.0 {
        return Err("the reference grasp has no contact force".into());
    }
    let part = test
        .iter()
        .zip(&refr)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    Ok(vec![
        (grip(&test) - total).abs() / total,
        part / total,
        (grip(&test) - same).abs() / same,
        grip(&test),
    ])
}

/// Force magnitude on each named part of the hand, N.
pub type PartForces = Vec<(&'static str, f64)>;

/// The reference's grip and its parts' force magnitudes, N (for the document).
pub fn reference_forces(reference: &Solved) -> Result<(f64, PartForces), String> {
    let parts = part_forces(reference)?;
    Ok((
        grip(&parts),
        PARTS
            .iter()
            .copied()
            .zip(parts.iter().map(|f| f.norm()))
            .collect(),
    ))
}
