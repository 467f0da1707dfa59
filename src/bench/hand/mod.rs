//! `prehensile bench hand`: the index finger flexed 0° → 90° at the PIP joint in 10° increments,
//! at several mesh resolutions — milliseconds per increment and per keyframe for the local and
//! whole-hand FEM regions, the skinning fast path for the same pose, and how far skinning is from
//! the FEM result; the linear tier against the corotated increments (`linear`); and the
//! nonlinear tier against them (`nonlinear`).

mod linear;
mod nonlinear;
pub use linear::{linear_row, linear_table, LinearRow};
pub use nonlinear::{nonlinear_row, nonlinear_table, NonlinearRow};

use crate::fem::solve::FillOrdering;
use crate::fem::Material;
use crate::hand::{Blend, HandModel, Pose, Side};
use crate::model::{FleshMethod, FleshRegion, FlexionSettings};
use crate::solve::Flexion;
use crate::state::{HandState, KeyframeStats};
use crate::util::timing::ms;
use nalgebra::Vector3;
use std::fmt::Write;
use std::time::Instant;

/// One resolution's figures.
#[derive(Clone, Debug)]
pub struct HandRow {
    /// Resolution.
    pub resolution: f64,
    /// Flesh cells and nodes.
    pub cells: usize,
    /// Nodes.
    pub nodes: usize,
    /// Free dofs of the whole hand.
    pub free_dofs: usize,
    /// Hand model build (mesh, skin, weights), ms.
    pub build_ms: f64,
    /// Local-region keyframe.
    pub local: KeyframeStats,
    /// Whole-hand keyframe (None when skipped).
    pub whole: Option<KeyframeStats>,
    /// Dual-quaternion skinning of the same keyframe, ms.
    pub skinning_ms: f64,
    /// Linear-blend skinning of the same keyframe, ms.
    pub linear_ms: f64,
    /// Skin-vertex distance, skinning (dual quaternion) vs local FEM: max and RMS, m.
    pub skin_distance: (f64, f64),
    /// Same for linear-blend skinning, m.
    pub linear_distance: (f64, f64),
    /// Relative flesh volume change: FEM (local), dual quaternion, linear blend.
    pub volume_change: [f64; 3],
    /// The linear tier against the corotated increments.
    pub linear: LinearRow,
    /// The nonlinear tier against the corotated increments.
    pub nonlinear: NonlinearRow,
}

/// Flesh of the benchmark.
pub(crate) const FLESH: Material = Material {
    young: 5.0e4,
    poisson: 0.45,
    density: 1050.0,
};

/// [`run`], its failure the benchmark's error (naming the resolution and the case).
fn run_or_stop(
    hand: &HandModel,
    settings: FlexionSettings,
    (resolution, case): (f64, &str),
) -> anyhow::Result<(HandState, KeyframeStats)> {
    run(hand, settings).map_err(|e| {
        anyhow::anyhow!("--resolutions {resolution}: the index flexion ({case}) failed: {e}")
    })
}

/// Index PIP 0° → 90° in one keyframe, or the error.
pub(crate) fn run(
    hand: &HandModel,
    settings: FlexionSettings,
) -> Result<(HandState, KeyframeStats), String> {
    flex_index_pip(hand, settings, 90.0)
}

/// Index PIP from rest to `angle` (degrees) in one keyframe, or the error.
pub(crate) fn flex_index_pip(
    hand: &HandModel,
    settings: FlexionSettings,
    angle: f64,
) -> Result<(HandState, KeyframeStats), String> {
    let mut stepper = Flexion::new(
        hand,
        "hand",
        vec![FLESH; hand.flesh.mesh.cells.len()],
        settings,
        FillOrdering::Auto,
    );
    let mut state = HandState::rest(hand);
    let pose: Pose = [("index.pip".to_string(), angle)].into_iter().collect();
    let target = hand
        .skeleton
        .apply_pose(&state.angles, &pose)
        .map_err(|e| e.to_string())?;
    let stats = stepper
        .move_to(&mut state, &target)
        .map_err(|e| e.to_string())?;
    Ok((state, stats))
}

pub(crate) fn distances(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> (f64, f64) {
    let d: Vec<f64> = a.iter().zip(b).map(|(p, q)| (p - q).norm()).collect();
    let max = d.iter().copied().fold(0.0, f64::max);
    let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
    (max, rms)
}

/// Runs the benchmark; the whole-hand region is skipped above `whole_limit` resolution. A
/// resolution the hand cannot be built at (outside [`crate::hand::RESOLUTIONS`], beyond the
/// memory free) or flexed at is the error, naming it.
pub fn hand_rows(resolutions: &[f64], whole_limit: f64) -> anyhow::Result<Vec<HandRow>> {
    let mut rows = Vec::new();
    for &resolution in resolutions {
        let t = Instant::now();
        let hand = HandModel::new(Side::Right, resolution)
            .map_err(|e| anyhow::anyhow!("--resolutions {resolution}: {e}"))?;
        let build_ms = ms(t);
        let attached = hand.flesh.node_bone.iter().filter(|b| b.is_some()).count();
        let at = |case| (resolution, case);
        let (fem, local) = run_or_stop(&hand, FlexionSettings::default(), at("local region"))?;
        let nonlinear = nonlinear_row(&hand, resolution, &(fem.clone(), local.clone()));
        let whole = match resolution <= whole_limit {
            true => Some(
                run_or_stop(
                    &hand,
                    FlexionSettings {
                        region: FleshRegion::Whole,
                        ..Default::default()
                    },
                    at("whole hand"),
                )?
                .1,
            ),
            false => None,
        };
        let skinning = |blend| FlexionSettings {
            methods: [FleshMethod::Skinning; 6],
            blend,
            ..Default::default()
        };
        let (dq, dq_stats) = run_or_stop(
            &hand,
            skinning(Blend::DualQuaternion),
            at("dual-quaternion skinning"),
        )?;
        let (lb, lb_stats) = run_or_stop(&hand, skinning(Blend::Linear), at("linear skinning"))?;
        let skin = |s: &HandState| hand.skin.positions(&s.positions);
        let fem_skin = skin(&fem);
        let v0 = HandState::rest(&hand).flesh_volume(&hand);
        rows.push(HandRow {
            resolution,
            cells: hand.flesh.mesh.cells.len(),
            nodes: hand.flesh.mesh.nodes.len(),
            free_dofs: 3 * (hand.flesh.mesh.nodes.len() - attached),
            build_ms,
            local,
            whole,
            skinning_ms: dq_stats.total_ms,
            linear_ms: lb_stats.total_ms,
            skin_distance: distances(&skin(&dq), &fem_skin),
            linear_distance: distances(&skin(&lb), &fem_skin),
            volume_change: [
                fem.flesh_volume(&hand) / v0 - 1.0,
                dq.flesh_volume(&hand) / v0 - 1.0,
                lb.flesh_volume(&hand) / v0 - 1.0,
            ],
            linear: linear_row(&hand, resolution),
            nonlinear,
        });
    }
    Ok(rows)
}

/// The two Markdown tables: speed, and skinning against FEM.
pub fn hand_tables(rows: &[HandRow]) -> String {
    let mut s = String::new();
    s.push_str(
        "| resolution | cells | nodes | free dofs (whole hand) | build ms | local: FEM cells | \
         local: free dofs | local: ms / increment | local: ms / keyframe | whole: ms / increment \
         | whole: ms / keyframe | skinning ms / keyframe (DQ / linear) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let per = |k: &KeyframeStats| k.total_ms / k.increments.max(1) as f64;
        let (wi, wk) = match &r.whole {
            Some(w) => (format!("{:.0}", per(w)), format!("{:.0}", w.total_ms)),
            None => ("—".into(), "—".into()),
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.0} | {} | {} | {:.1} | {:.0} | {} | {} | {:.1} / {:.1} |",
            r.resolution,
            r.cells,
            r.nodes,
            r.free_dofs,
            r.build_ms,
            r.local.fem_cells,
            r.local.free_dofs,
            per(&r.local),
            r.local.total_ms,
            wi,
            wk,
            r.skinning_ms,
            r.linear_ms
        );
    }
    s.push_str(
        "\n| resolution | skin vs FEM, DQ: max mm | DQ: RMS mm | linear: max mm | linear: RMS mm \
         | volume change FEM | DQ | linear | FEM / DQ time |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {:.2} | {:.3} | {:.2} | {:.3} | {:+.3} % | {:+.3} % | {:+.3} % | {:.0}× |",
            r.resolution,
            r.skin_distance.0 * 1e3,
            r.skin_distance.1 * 1e3,
            r.linear_distance.0 * 1e3,
            r.linear_distance.1 * 1e3,
            r.volume_change[0] * 100.0,
            r.volume_change[1] * 100.0,
            r.volume_change[2] * 100.0,
            r.local.total_ms / r.skinning_ms.max(1e-9)
        );
    }
    let linear: Vec<LinearRow> = rows.iter().map(|r| r.linear.clone()).collect();
    s.push_str(&linear_table(&linear));
    let nonlinear: Vec<NonlinearRow> = rows.iter().map(|r| r.nonlinear.clone()).collect();
    s.push_str(&nonlinear_table(&nonlinear));
    s
}
