//! (d) The index finger of a right hand flexed at its PIP joint from rest to 30° or 90° in one
//! keyframe (flesh E = 50 kPa, ν = 0.45, as in `bench hand`). The error is measured against the
//! reference solution (finest resolution, smallest step, most exact tier): every free flesh node
//! of the solved hand (bone nodes move exactly with their bones in every tier) that lies inside
//! the reference's flesh at rest is located in its cell, and its flexed position compared with
//! the reference's flexed flesh there; and the flesh volume change compared with the
//! reference's.

use super::{Column, Embedding, Solved, Unit};
use crate::scene::Scene;
use nalgebra::Vector3;

/// Distance outside the reference's flesh, in lattice spacings of the reference, within which a
/// node is still compared (at the nearest point of the reference's flesh).
const REACH: f64 = 0.25;

/// Largest and RMS node distance from the finest reference, largest from the same mesh's, the
/// volume change and its gap to the finest reference's, the nodes compared.
pub const COLUMNS: &[Column] = &[
    Column {
        name: "largest node distance, mm",
        unit: Unit::Millimetre,
    },
    Column {
        name: "RMS node distance, mm",
        unit: Unit::Millimetre,
    },
    Column {
        name: "largest distance from the same mesh's reference, mm",
        unit: Unit::Millimetre,
    },
    Column {
        name: "flesh volume change",
        unit: Unit::SignedPercent,
    },
    Column {
        name: "volume change − reference's",
        unit: Unit::SignedPercent,
    },
    Column {
        name: "free nodes compared",
        unit: Unit::Percent,
    },
];

/// The flexion scene at hand `resolution`, to `angle` degrees.
pub fn scene(resolution: f64, angle: f64) -> Scene {
    let text = format!(
        r#"
[solver]
max_step_deg = 10.0
[[material]]
name = "flesh"
young = 5.0e4
poisson = 0.45
density = 1050.0
[[body]]
name = "hand"
material = "flesh"
shape = {{ hand = {{ side = "right", resolution = {resolution} }} }}
[[keyframe]]
time = 1.0
pose = {{ "index.pip" = {angle} }}
"#
    );
    Scene::parse(&text, "flexion").expect("the flexion scene parses")
}

/// The hand of a solved scene: its rest flesh mesh, free nodes, last flexed positions, volume
/// change.
pub(super) struct HandResult<'a> {
    pub hand: &'a crate::hand::HandModel,
    pub positions: &'a [Vector3<f64>],
    pub volume_change: f64,
}

/// The first hand body's state in the last frame.
pub(super) fn hand_result(solved: &Solved) -> Result<HandResult<'_>, String> {
    let frame = solved.frames.last().ok_or("no frame")?;
    let h = frame.hands.first().ok_or("no hand in the frame")?;
    let body = &solved.model.bodies[h.body];
    let hand = body.hand.as_deref().ok_or("the body is not a hand")?;
    Ok(HandResult {
        hand,
        positions: &h.positions,
        volume_change: h.volume / body.volume - 1.0,
    })
}

/// Distances of the solved hand's free flesh nodes that lie inside the reference's flesh at
/// rest from the reference's flesh at the same material points: (largest, RMS) in m, and the
/// fraction of free nodes compared.
pub(super) fn node_distances(
    test: &HandResult,
    reference: &HandResult,
) -> Result<(f64, f64, f64), String> {
    let free: Vec<usize> = (0..test.positions.len())
        .filter(|&n| test.hand.flesh.node_bone[n].is_none())
        .collect();
    let rest: Vec<Vector3<f64>> = free
        .iter()
        .map(|&n| test.hand.flesh.mesh.nodes[n])
        .collect();
    // Nodes on the skin lie up to a fraction of a cell outside the other mesh's skin.
    let reach = REACH * reference.hand.flesh.spacing;
    // Fingers touching at rest are meshed apart along a seam (coincident, unjoined nodes) whose
    // place moves with the resolution: a node is compared with the reference's flesh of its
    // own digit (or palm) only.
    let mut digits: Vec<Vec<Option<usize>>> = vec![Vec::new(); test.positions.len()];
    for (c, cell) in test.hand.flesh.mesh.cells.iter().enumerate() {
        for &n in cell {
            digits[n].push(test.hand.flesh.cell_digit[c]);
        }
    }
    let embedding = Embedding::new(&reference.hand.flesh.mesh, &rest, reach, |i, c| {
        digits[free[i]].contains(&reference.hand.flesh.cell_digit[c])
    });
    let reference_u: Vec<Vector3<f64>> = reference
        .positions
        .iter()
        .zip(&reference.hand.flesh.mesh.nodes)
        .map(|(x, x0)| x - x0)
        .collect();
    let d: Vec<f64> = embedding
        .interpolate(&reference_u)
        .iter()
        .zip(free.iter().zip(&rest))
        .filter_map(|(u, (&n, x0))| Some((test.positions[n] - (x0 + (*u)?)).norm()))
        .collect();
    let fraction = d.len() as f64 / free.len().max(1) as f64;
    if fraction < 0.5 {
        return Err(format!(
            "only {:.0} % of the free flesh nodes lie inside the reference's flesh",
            fraction * 100.0
        ));
    }
    let max = d.iter().copied().fold(0.0, f64::max);
    let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
    Ok((max, rms, fraction))
}

/// The errors of a solved flexion against the finest reference and the same mesh's.
pub fn measure(solved: &Solved, finest: &Solved, same_mesh: &Solved) -> Result<Vec<f64>, String> {
    let (test, refr) = (hand_result(solved)?, hand_result(finest)?);
    let (max, rms, fraction) = node_distances(&test, &refr)?;
    let same = hand_result(same_mesh)?;
    if same.positions.len() != test.positions.len() {
        return Err("the same-mesh reference has another mesh".into());
    }
    let local = test
        .positions
        .iter()
        .zip(same.positions)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max);
    Ok(vec![
        max,
        rms,
        local,
        test.volume_change,
        test.volume_change - refr.volume_change,
        fraction,
    ])
}
