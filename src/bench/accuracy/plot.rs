//! The plot of the bench: one panel per problem, log time against log error, one curve per
//! tier (and option) through its three resolutions. Drawn with `plotters` into memory (text with
//! the bundled Ubuntu Light of `epaint_default_fonts`, so no system font is needed), written
//! as PNG atomically.

use super::{ProblemId, Results, Row, Variant, HAND_TIERS};
use crate::export::png::write_png_atomic;
use crate::scene::TierName;
use image::RgbaImage;
use plotters::coord::combinators::BindKeyPoints;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// Width and height of one panel, pixels.
const PANEL: (u32, u32) = (660, 520);
/// Panels per line.
const COLUMNS: usize = 3;
/// Heights of the title and the legend bands, pixels.
const TITLE_H: u32 = 56;
const LEGEND_H: u32 = 150;
/// Font family registered for the plot.
const FONT: &str = "sans-serif";

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bundled font always parses; if it ever did not, text would be missing, not wrong.
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

/// The colour of a tier.
fn colour(tier: TierName) -> RGBColor {
    match tier {
        TierName::Skinning => RGBColor(110, 110, 110),
        TierName::Linear => RGBColor(31, 100, 200),
        TierName::Incremental => RGBColor(230, 120, 0),
        TierName::Corotational => RGBColor(30, 150, 60),
        TierName::Nonlinear => RGBColor(210, 30, 40),
    }
}

/// Marker of a variant: 0 circle (hex8, the 10° step or none), 1 triangle (incompatible
/// modes, a step above 10°), 2 square (a step below 10°).
fn marker(v: &Variant) -> usize {
    if v.element == crate::scene::ElementName::IncompatibleModes {
        return 1;
    }
    match v.step_deg {
        Some(s) if s > 10.0 => 1,
        Some(s) if s < 10.0 => 2,
        _ => 0,
    }
}

/// Draws a marker of kind `kind` at pixel `(x, y)`.
fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    kind: usize,
    (x, y): (i32, i32),
    c: RGBColor,
) {
    let style = c.filled();
    let _ = match kind {
        1 => area.draw(&Polygon::new(
            vec![(x, y - 8), (x - 7, y + 5), (x + 7, y + 5)],
            style,
        )),
        2 => area.draw(&Rectangle::new([(x - 6, y - 6), (x + 6, y + 6)], style)),
        _ => area.draw(&Circle::new((x, y), 6, style)),
    };
}

/// The measured (time, error) points of a variant on a problem, in resolution order.
fn curve(rows: &[&Row], v: &Variant) -> Vec<(f64, f64)> {
    rows.iter()
        .filter(|r| &r.variant == v)
        .filter_map(|r| Some((r.ms()?, r.error()?)))
        .filter(|(t, e)| *t > 0.0 && *e > 0.0 && t.is_finite() && e.is_finite())
        .collect()
}

/// The variants measured somewhere, in first-seen order.
fn measured_variants(results: &Results) -> Vec<Variant> {
    let mut out: Vec<Variant> = Vec::new();
    for r in &results.rows {
        if r.error().is_some() && !out.contains(&r.variant) {
            out.push(r.variant.clone());
        }
    }
    out
}

/// A log range around `values`, padded by a factor on each side.
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        return 0.1..10.0;
    }
    let (lo, hi) = if hi / lo < 10.0 {
        let mid = (lo * hi).sqrt();
        (mid / 3.5, mid * 3.5)
    } else {
        (lo / 1.6, hi * 1.6)
    };
    lo..hi
}

/// Tick values for a log axis over `range`: 1, 2, 5 per decade (1, 2, 3, 5, 7 when the range
/// spans less than a decade and a half, so that every panel has a few labels).
fn ticks(range: &std::ops::Range<f64>) -> Vec<f64> {
    let (lo, hi) = (range.start, range.end);
    let mantissas: &[f64] = if hi / lo < 30.0 {
        &[1.0, 2.0, 3.0, 5.0, 7.0]
    } else if hi / lo < 3000.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let mut out = Vec::new();
    for d in lo.log10().floor() as i32..=hi.log10().ceil() as i32 {
        for m in mantissas {
            let v = m * 10f64.powi(d);
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
    }
    out
}

/// A tick value written briefly: 0.01, 0.5, 3, 120, 1e4.
fn tick(v: f64) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    if !(1e-3..1e5).contains(&v) {
        return format!("{v:.0e}");
    }
    let digits = (-(v.log10().floor()) as i32).max(0) as usize;
    format!("{v:.digits$}")
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    results: &Results,
    problem: ProblemId,
) -> Result<(), String> {
    let rows: Vec<&Row> = results
        .rows
        .iter()
        .filter(|r| r.problem == problem)
        .collect();
    let points: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| Some((r.ms()?, r.error()?)))
        .filter(|(t, e)| *t > 0.0 && *e > 0.0)
        .collect();
    let column = &problem.columns()[problem.plotted()];
    let x_label = if problem.is_hand() {
        "ms per keyframe"
    } else {
        "ms per solve"
    };
    let (xr, yr) = (
        log_range(points.iter().map(|p| p.0)),
        log_range(points.iter().map(|p| p.1)),
    );
    let (xt, yt) = (ticks(&xr), ticks(&yr));
    let mut chart = ChartBuilder::on(area)
        .caption(problem.short_title(), (FONT, 24))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(78)
        .build_cartesian_2d(
            xr.log_scale().with_key_points(xt),
            yr.log_scale().with_key_points(yt),
        )
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(column.axis())
        .label_style((FONT, 17))
        .axis_desc_style((FONT, 19))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(|e| e.to_string())?;
    if points.is_empty() {
        let _ = area.draw(&Text::new(
            "no run measured",
            (PANEL.0 as i32 / 3, PANEL.1 as i32 / 2),
            (FONT, 20),
        ));
        return Ok(());
    }
    let mut seen: Vec<Variant> = Vec::new();
    for r in &rows {
        if seen.contains(&r.variant) {
            continue;
        }
        seen.push(r.variant.clone());
        let c = curve(&rows, &r.variant);
        if c.is_empty() {
            continue;
        }
        let col = colour(r.variant.tier);
        chart
            .draw_series(LineSeries::new(c.clone(), col.stroke_width(2)))
            .map_err(|e| e.to_string())?;
        let style = col.filled();
        let result = match marker(&r.variant) {
            1 => chart
                .draw_series(c.iter().map(|&p| {
                    EmptyElement::at(p) + Polygon::new(vec![(0, -8), (-7, 5), (7, 5)], style)
                }))
                .map(|_| ()),
            2 => chart
                .draw_series(
                    c.iter()
                        .map(|&p| EmptyElement::at(p) + Rectangle::new([(-6, -6), (6, 6)], style)),
                )
                .map(|_| ()),
            _ => chart
                .draw_series(
                    c.iter()
                        .map(|&p| EmptyElement::at(p) + Circle::new((0, 0), 6, style)),
                )
                .map(|_| ()),
        };
        result.map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, results: &Results) {
    let mut variants = measured_variants(results);
    let order = |v: &Variant| {
        let tier = HAND_TIERS.iter().position(|t| *t == v.tier).unwrap_or(0);
        (
            tier,
            v.element != crate::scene::ElementName::Hex8,
            -v.step_deg.unwrap_or(0.0) as i64,
        )
    };
    variants.sort_by_key(order);
    let per_line = 4;
    let width = area.dim_in_pixel().0 as i32 / per_line as i32;
    for (i, v) in variants.iter().enumerate() {
        let (x, y) = (
            30 + (i % per_line) as i32 * width,
            22 + (i / per_line) as i32 * 34,
        );
        let c = colour(v.tier);
        let _ = area.draw(&PathElement::new(
            vec![(x, y), (x + 44, y)],
            c.stroke_width(2),
        ));
        draw_marker(area, marker(v), (x + 22, y), c);
        let _ = area.draw(&Text::new(
            v.label(),
            (x + 54, y - 10),
            (FONT, 20).into_font().color(&BLACK),
        ));
    }
    let lines = variants.len().div_ceil(per_line) as i32;
    let _ = area.draw(&Text::new(
        "Each curve: one tier through its three mesh resolutions, coarse to fine. Circle: hex8 or \
         a 10° step; triangle: incompatible modes or a 20° step; square: a 5° step.",
        (30, 12 + lines * 34),
        (FONT, 18).into_font().color(&RGBColor(80, 80, 80)),
    ));
}

/// The plot as an image.
pub fn plot_png(results: &Results, title: &str) -> Result<RgbaImage, String> {
    register_font();
    let problems: Vec<ProblemId> = ProblemId::ALL
        .into_iter()
        .filter(|p| results.rows.iter().any(|r| r.problem == *p))
        .collect();
    if problems.is_empty() {
        return Err("nothing to plot: no problem was run".into());
    }
    let lines = problems.len().div_ceil(COLUMNS);
    let cols = problems.len().min(COLUMNS);
    let (w, h) = (
        PANEL.0 * cols as u32,
        TITLE_H + PANEL.1 * lines as u32 + LEGEND_H,
    );
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let (top, rest) = root.split_vertically(TITLE_H);
        let (body, bottom) = rest.split_vertically(PANEL.1 * lines as u32);
        let _ = top.draw(&Text::new(title, (20, 14), (FONT, 26)));
        let panels = body.split_evenly((lines, cols));
        for (p, area) in problems.iter().zip(&panels) {
            panel(area, results, *p)?;
        }
        legend(&bottom, results);
        root.present().map_err(|e| e.to_string())?;
    }
    let mut image = RgbaImage::new(w, h);
    for (i, px) in image.pixels_mut().enumerate() {
        px.0 = [buffer[3 * i], buffer[3 * i + 1], buffer[3 * i + 2], 255];
    }
    Ok(image)
}

/// Writes the plot to `path` (temporary file, then rename).
pub fn write_plot(path: &Path, results: &Results, title: &str) -> Result<(), String> {
    let image = plot_png(results, title)?;
    write_png_atomic(path, &image).map_err(|e| format!("{}: {e}", path.display()))
}
