//! `prehensile bench flexion-refinement`: how a free flexion's bone reactions converge under
//! refinement, and where the lattice falls. The index PIP is flexed from rest to each angle
//! (corotated, 10° increments, the local region, no contact) on the flesh lattice moved by up
//! to six offsets at each resolution (`HandModel::build_offset`); per angle and resolution the
//! middle phalanx's reaction — its mean over the offsets, the lowest and the highest — and, over
//! each three successive resolutions, the observed order of the mean in the lattice spacing and
//! the limit it points to (`util::convergence`).
//!
//! With `subdivisions` (`--subdivisions 1,2,3`) each lattice is also split, every cell into n³
//! (`hand::subdivide`: the nested refinement, which keeps the lattice's hand); the orders are
//! then read along the splits of each resolution's lattices.

use crate::bench::hand::flex_index_pip;
use crate::hand::{HandModel, Side, Skeleton, SkinShape, BASE_SPACING};
use crate::model::FlexionSettings;
use crate::util::convergence::{convergence, Convergence, LARGEST_ORDER};
use crate::util::timing::ms;
use nalgebra::Vector3;
use std::fmt::Write;
use std::time::Instant;

/// The lattice's offsets, in cells: none, half a cell along x, y or z, and two oblique ones.
pub const OFFSETS: [[f64; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [0.5, 0.0, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.25, 0.5, 0.75],
    [0.75, 0.25, 0.5],
];

/// The bone whose reaction is read: the middle phalanx, which the flexion turns.
const BONE: &str = "index.middle";

/// One angle at one resolution.
#[derive(Clone, Debug)]
pub struct RefinementRow {
    /// The PIP's angle, degrees.
    pub angle_deg: f64,
    /// The hand's resolution.
    pub resolution: f64,
    /// How many times each edge of the lattice's cells was split (1: not split).
    pub subdivisions: usize,
    /// Flesh cells of the lattice without offset.
    pub cells: usize,
    /// The middle phalanx's reaction on each offset's lattice, N.
    pub reactions: Vec<f64>,
    /// Wall time of the flexions (all offsets; the lattices' building left out), ms.
    pub ms: f64,
}

impl RefinementRow {
    /// The spacing of the cells, m.
    pub fn spacing(&self) -> f64 {
        BASE_SPACING / (self.resolution * self.subdivisions as f64)
    }

    /// The mesh, as the table names it: the resolution, split n × n × n when it is.
    fn mesh(&self) -> String {
        match self.subdivisions {
            1 => format!("{}", self.resolution),
            n => format!("{} split {n}", self.resolution),
        }
    }

    /// The mean over the offsets, N.
    pub fn mean(&self) -> f64 {
        self.reactions.iter().sum::<f64>() / self.reactions.len() as f64
    }

    /// The lowest and the highest, N.
    pub fn range(&self) -> (f64, f64) {
        let lo = self.reactions.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self
            .reactions
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    }
}

/// The middle phalanx's reaction after flexing the index PIP of `hand` from rest to `angle`.
fn flexed(hand: &HandModel, angle: f64) -> Result<f64, String> {
    let bone = hand
        .skeleton
        .bone_index(BONE)
        .ok_or_else(|| format!("the hand has no bone {BONE}"))?;
    let (state, _) = flex_index_pip(hand, FlexionSettings::default(), angle)?;
    Ok(state.bone_reactions(hand)[bone].norm())
}

/// Runs the benchmark: every angle at every resolution (each once, coarse to fine) on the
/// first `offsets` lattice offsets (1 to 6; more are the six, none is the first). A resolution
/// the hand cannot be built at, or an angle it cannot be flexed to, is the error, naming them.
pub fn refinement_rows(
    angles: &[f64],
    resolutions: &[f64],
    offsets: usize,
) -> anyhow::Result<Vec<RefinementRow>> {
    nested_refinement_rows(angles, resolutions, &[1], offsets)
}

/// [`refinement_rows`] with each lattice also split into each of `subdivisions`
/// (`hand::subdivide`), coarse to fine within each resolution.
pub fn nested_refinement_rows(
    angles: &[f64],
    resolutions: &[f64],
    subdivisions: &[usize],
    offsets: usize,
) -> anyhow::Result<Vec<RefinementRow>> {
    let offsets = &OFFSETS[..offsets.clamp(1, OFFSETS.len())];
    // Coarse to fine, each once: a row's change is then against the next coarser mesh, and
    // three successive spacings decrease.
    let sorted = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (angles, resolutions) = (sorted(angles), sorted(resolutions));
    let mut subdivisions = subdivisions.to_vec();
    subdivisions.sort_unstable();
    subdivisions.dedup();
    let mut rows = Vec::new();
    for (&resolution, &split) in resolutions
        .iter()
        .flat_map(|r| subdivisions.iter().map(move |n| (r, n)))
    {
        let h = BASE_SPACING / resolution;
        let first = rows.len();
        rows.extend(angles.iter().map(|&angle_deg| RefinementRow {
            angle_deg,
            resolution,
            subdivisions: split,
            cells: 0,
            reactions: Vec::new(),
            ms: 0.0,
        }));
        // One lattice at a time (at resolution 4 it and its flexion take up to 4.8 GB), every
        // angle on it.
        for o in offsets {
            let hand = HandModel::build_nested(
                Skeleton::new(Side::Right),
                SkinShape::new(Side::Right),
                resolution,
                split,
                None,
                Vector3::from(*o) * h,
            )
            .map_err(|e| {
                anyhow::anyhow!("--resolutions {resolution} --subdivisions {split}: {e}")
            })?;
            for row in &mut rows[first..] {
                let t = Instant::now();
                let reaction = flexed(&hand, row.angle_deg).map_err(|e| {
                    anyhow::anyhow!(
                        "--resolutions {resolution}, --subdivisions {split}, --angles {}, the \
                         lattice moved by {o:?} cells: {e}",
                        row.angle_deg
                    )
                })?;
                row.reactions.push(reaction);
                row.ms += ms(t);
                if row.cells == 0 {
                    row.cells = hand.flesh.mesh.cells.len();
                }
            }
        }
    }
    Ok(rows)
}

/// `part` as a percentage of `whole` (signed when `signed`); a dash where `whole` is no
/// reaction to speak of (below 1 µN: a joint no flesh bridges, or no flexion).
fn percent(part: f64, whole: f64, signed: bool) -> String {
    if whole.abs() < 1e-6 || !part.is_finite() {
        return "—".to_string();
    }
    let p = 100.0 * part / whole;
    if signed {
        format!("{p:+.1} %")
    } else {
        format!("{p:.1} %")
    }
}

/// The table: a row per angle and resolution (coarse to fine), then per angle the observed
/// order of each three successive resolutions' means.
pub fn refinement_table(rows: &[RefinementRow]) -> String {
    let mut s = String::from(
        "| PIP | mesh | cells | lattices | middle phalanx: mean (N) | lowest – highest (N) \
         | spread / mean | change of the mean | time (s) |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut angles: Vec<f64> = Vec::new();
    for r in rows {
        if !angles.contains(&r.angle_deg) {
            angles.push(r.angle_deg);
        }
    }
    // Split lattices: a series per angle and resolution, along the splits; lattices alone: a
    // series per angle, along the resolutions.
    let nested = rows.iter().any(|r| r.subdivisions > 1);
    let mut keys: Vec<(f64, f64)> = Vec::new();
    for r in rows {
        let key = (r.angle_deg, if nested { r.resolution } else { 0.0 });
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let mut orders = String::new();
    let mut each = String::new();
    for &(angle, base) in &keys {
        let mut series: Vec<&RefinementRow> = rows
            .iter()
            .filter(|r| r.angle_deg == angle && (!nested || r.resolution == base))
            .collect();
        series.sort_by(|a, b| b.spacing().total_cmp(&a.spacing()));
        for (i, r) in series.iter().enumerate() {
            let (lo, hi) = r.range();
            let change = match i {
                0 => "—".to_string(),
                _ => percent(r.mean() - series[i - 1].mean(), series[i - 1].mean(), true),
            };
            let _ = writeln!(
                s,
                "| {angle}° | {} | {} | {} | {:.3} | {lo:.3} – {hi:.3} | {} | {change} | {:.1} |",
                r.mesh(),
                r.cells,
                r.reactions.len(),
                r.mean(),
                percent(hi - lo, r.mean(), false),
                r.ms * 1e-3
            );
        }
        for w in series.windows(3) {
            let h = [0, 1, 2].map(|k| w[k].spacing());
            let meshes = format!("{}, {}, {}", w[0].mesh(), w[1].mesh(), w[2].mesh());
            if let Some(read) = order_read(h, [0, 1, 2].map(|k| w[k].mean())) {
                let _ = writeln!(orders, "| {angle}° | {meshes} | {read} |");
            }
            // Split, each lattice is its own hand: its own series, its own limit.
            let lattices = w.iter().map(|r| r.reactions.len()).min().unwrap_or(0);
            if nested && lattices > 1 {
                for (l, offset) in OFFSETS.iter().enumerate().take(lattices) {
                    let f = [0, 1, 2].map(|k| w[k].reactions[l]);
                    if let Some(read) = order_read(h, f) {
                        let _ = writeln!(
                            each,
                            "| {angle}° | {offset:?} | {meshes} | {:.3} / {:.3} / {:.3} | {read} |",
                            f[0], f[1], f[2]
                        );
                    }
                }
            }
        }
    }
    if !orders.is_empty() {
        s.push_str(
            "\n| PIP | meshes | observed order of the mean in the spacing | Richardson's \
             limit (N) | finest from it |\n|---|---|---|---|---|\n",
        );
        s.push_str(&orders);
    }
    if !each.is_empty() {
        s.push_str(
            "\n| PIP | lattice moved by (cells) | meshes | middle phalanx (N) | observed order in \
             the spacing | Richardson's limit (N) | finest from it |\n|---|---|---|---|---|---|---|\n",
        );
        s.push_str(&each);
    }
    s
}

/// The observed order of `f` at spacings `h`, Richardson's limit and how far the finest is
/// from it, as table cells; `None` where some mesh has no reaction to speak of (no flesh across
/// the joint).
fn order_read(h: [f64; 3], f: [f64; 3]) -> Option<String> {
    if f.iter().any(|x| x.abs() < 1e-6) {
        return None;
    }
    Some(match convergence(h, f) {
        Convergence::Order { order, limit } => {
            let order = match order >= LARGEST_ORDER {
                true => format!("≥ {LARGEST_ORDER}"),
                false => format!("{order:.2}"),
            };
            let off = percent(f[2] - limit, limit, true);
            format!("{order} | {limit:.3} | {off}")
        }
        Convergence::NotMonotone => "not monotone | — | —".to_string(),
        Convergence::NotShrinking => "no positive order | — | —".to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(angle_deg: f64, resolution: f64, reactions: Vec<f64>) -> RefinementRow {
        RefinementRow {
            angle_deg,
            resolution,
            subdivisions: 1,
            cells: 1,
            reactions,
            ms: 1.0,
        }
    }

    /// Split lattices: the orders are read along the splits of each resolution, for the mean
    /// and for each lattice (each its own hand, its own limit).
    #[test]
    fn the_table_reads_each_split_lattice_s_order() {
        // Lattice 0: 2 + (h/mm), order 1, limit 2; lattice 1: 3 − (h/mm)², order 2, limit 3.
        let rows: Vec<RefinementRow> = [1usize, 2, 4]
            .iter()
            .map(|&n| {
                let h = 3.2 / n as f64;
                RefinementRow {
                    subdivisions: n,
                    ..row(20.0, 1.0, vec![2.0 + h, 3.0 - h * h])
                }
            })
            .collect();
        let t = refinement_table(&rows);
        assert!(t.contains("| 20° | 1 split 4 | 1 | 2 |"), "{t}");
        assert!(
            t.contains("| 20° | [0.0, 0.0, 0.0] | 1, 1 split 2, 1 split 4 | 5.200 / 3.600 / 2.800 | 1.00 | 2.000 |"),
            "{t}"
        );
        assert!(
            t.contains("| [0.5, 0.0, 0.0] | 1, 1 split 2, 1 split 4 | -7.240 / 0.440 / 2.360 | 2.00 | 3.000 |"),
            "{t}"
        );
    }

    #[test]
    fn the_table_reads_the_order_of_the_means() {
        // Means 4 − (h/mm)² at resolutions 1, 2, 4: order 2, limit 4.
        let mean = |r: f64| 4.0 - (3.2 / r) * (3.2 / r);
        let rows: Vec<RefinementRow> = [1.0, 2.0, 4.0]
            .iter()
            .map(|&r| row(20.0, r, vec![mean(r) - 0.1, mean(r) + 0.1]))
            .chain([row(45.0, 1.0, vec![1.0]), row(45.0, 2.0, vec![2.0])])
            .collect();
        let t = refinement_table(&rows);
        assert!(t.contains("| 20° | 1, 2, 4 | 2.00 | 4.000 |"), "{t}");
        assert!(
            !t.contains("| 45° | 1, 2"),
            "two resolutions give no order: {t}"
        );
        let scatter = [
            row(20.0, 1.0, vec![1.0]),
            row(20.0, 2.0, vec![2.0]),
            row(20.0, 4.0, vec![1.5]),
        ];
        assert!(refinement_table(&scatter).contains("not monotone"));
        // No flexion, or no flesh across the joint: no reaction, and no NaN or infinity shown.
        let none: Vec<RefinementRow> = [1.0, 2.0, 4.0]
            .iter()
            .map(|&r| row(0.0, r, vec![0.0, 0.0]))
            .collect();
        let t = refinement_table(&none);
        assert!(!t.contains("NaN") && !t.contains("inf"), "{t}");
        assert!(
            t.contains("| 0° | 2 | 1 | 2 | 0.000 | 0.000 – 0.000 | — | — |"),
            "{t}"
        );
    }
}
