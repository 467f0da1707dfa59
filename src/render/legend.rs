//! The colour bar with its title and tick labels, rasterised on the CPU (text with `ab_glyph`,
//! font Ubuntu Light from `epaint_default_fonts`) into an sRGB RGBA image that the renderer lays
//! over the frame.

use super::colormap::guard_range;
use super::draw_list::Legend;
use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};
use image::{Rgba, RgbaImage};

/// The legend font.
fn font() -> FontRef<'static> {
    FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).expect("the bundled font parses")
}

/// `value` with three significant digits and an SI prefix on `unit`: 12345 Pa → "12.3 kPa",
/// 0.004 m → "4.00 mm". Zero prints as "0 unit"; non-finite values as "n/a".
pub fn format_si(value: f32, unit: &str) -> String {
    if !value.is_finite() {
        return "n/a".into();
    }
    if value == 0.0 {
        return format!("0 {unit}");
    }
    const PREFIXES: [(&str, i32); 9] = [
        ("p", -12),
        ("n", -9),
        ("µ", -6),
        ("m", -3),
        ("", 0),
        ("k", 3),
        ("M", 6),
        ("G", 9),
        ("T", 12),
    ];
    let exp = (value.abs() as f64).log10().floor() as i32;
    let group = exp.div_euclid(3).clamp(-4, 4) * 3;
    let prefix = PREFIXES
        .iter()
        .find(|(_, e)| *e == group)
        .map_or("", |p| p.0);
    let mantissa = value as f64 / 10f64.powi(group);
    // Rounding may carry into the next group (999.7 → 1000): print it in that group.
    let decimals = match mantissa.abs() {
        m if m >= 99.95 => 0,
        m if m >= 9.995 => 1,
        _ => 2,
    };
    let text = format!("{mantissa:.decimals$}");
    if text.trim_start_matches('-') == "1000" && group < 12 {
        return format_si((value as f64 * 1.0005) as f32, unit);
    }
    format!("{text} {prefix}{unit}")
}

/// Width and height in pixels of `text` at size `px`.
fn measure(font: &FontRef, px: f32, text: &str) -> (f32, f32) {
    let f = font.as_scaled(PxScale::from(px));
    let mut w = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    (w, f.ascent() - f.descent())
}

/// Composites straight-alpha `src` over the pixel at (x, y) of `img`.
fn blend(img: &mut RgbaImage, x: i64, y: i64, src: [u8; 3], alpha: f32) {
    if x < 0 || y < 0 || x >= img.width() as i64 || y >= img.height() as i64 || alpha <= 0.0 {
        return;
    }
    let d = img.get_pixel_mut(x as u32, y as u32);
    let da = d[3] as f32 / 255.0;
    let a = alpha.min(1.0);
    let out_a = a + da * (1.0 - a);
    let mut out = [0u8; 4];
    for k in 0..3 {
        let c = (src[k] as f32 * a + d[k] as f32 * da * (1.0 - a)) / out_a.max(1e-6);
        out[k] = c.round().clamp(0.0, 255.0) as u8;
    }
    out[3] = (out_a * 255.0).round() as u8;
    *d = Rgba(out);
}

/// Draws `text` with its top-left corner at (x, y).
fn draw_text(
    img: &mut RgbaImage,
    font: &FontRef,
    px: f32,
    x: f32,
    y: f32,
    text: &str,
    rgb: [u8; 3],
) {
    let f = font.as_scaled(PxScale::from(px));
    let mut caret = point(x, y + f.ascent());
    let mut prev = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = prev {
            caret.x += f.kern(p, id);
        }
        let glyph = id.with_scale_and_position(PxScale::from(px), caret);
        caret.x += f.h_advance(id);
        prev = Some(id);
        if let Some(outline) = font.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, cov| {
                blend(
                    img,
                    b.min.x as i64 + gx as i64,
                    b.min.y as i64 + gy as i64,
                    rgb,
                    cov,
                );
            });
        }
    }
}

/// Fills a rectangle, with corners rounded by `radius`.
fn fill_rect(img: &mut RgbaImage, x0: f32, y0: f32, w: f32, h: f32, radius: f32, rgba: [u8; 4]) {
    for y in y0.floor() as i64..(y0 + h).ceil() as i64 {
        for x in x0.floor() as i64..(x0 + w).ceil() as i64 {
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            // Distance outside the rounded rectangle, for a one-pixel soft edge.
            let qx = (x0 + radius - px).max(px - (x0 + w - radius)).max(0.0);
            let qy = (y0 + radius - py).max(py - (y0 + h - radius)).max(0.0);
            let d = (qx * qx + qy * qy).sqrt() - radius;
            let cover = (0.5 - d).clamp(0.0, 1.0);
            blend(
                img,
                x,
                y,
                [rgba[0], rgba[1], rgba[2]],
                cover * rgba[3] as f32 / 255.0,
            );
        }
    }
}

/// Number of tick labels along the bar.
pub const TICKS: usize = 5;

/// The legend as an image for a frame `frame_height` pixels high (sizes scale with it; 720
/// gives a 20 px title and 16 px labels).
pub fn legend_image(legend: &Legend, frame_height: u32) -> RgbaImage {
    let s = (frame_height as f32 / 720.0).max(0.5);
    let font = font();
    let [lo, hi] = guard_range(legend.range);
    let (title_px, label_px) = (21.0 * s, 17.0 * s);
    let pad = 12.0 * s;
    let (bar_w, bar_h) = (22.0 * s, (frame_height as f32 * 0.42).max(60.0));
    let labels: Vec<String> = (0..TICKS)
        .map(|i| format_si(hi - (hi - lo) * i as f32 / (TICKS - 1) as f32, &legend.unit))
        .collect();
    let (title_w, title_h) = measure(&font, title_px, &legend.title);
    let label_h = measure(&font, label_px, "0").1;
    let label_w = labels
        .iter()
        .map(|l| measure(&font, label_px, l).0)
        .fold(0.0, f32::max);
    let tick = 6.0 * s;
    let content_w = title_w.max(bar_w + tick + 4.0 * s + label_w);
    let width = (content_w + 2.0 * pad).ceil() as u32;
    let bar_y = pad + title_h + 6.0 * s + label_h * 0.5;
    let height = (bar_y + bar_h + label_h * 0.5 + pad).ceil() as u32;
    let mut img = RgbaImage::new(width, height);
    fill_rect(
        &mut img,
        0.0,
        0.0,
        width as f32,
        height as f32,
        8.0 * s,
        [255, 255, 255, 215],
    );
    let ink = [28, 30, 36];
    draw_text(&mut img, &font, title_px, pad, pad, &legend.title, ink);
    // The bar: maximum at the top.
    let (x0, y0) = (pad, bar_y);
    for y in y0.floor() as u32..(y0 + bar_h).ceil() as u32 {
        let t = 1.0 - ((y as f32 + 0.5 - y0) / bar_h).clamp(0.0, 1.0);
        let c = legend.colormap.srgb8(t);
        for x in x0.floor() as u32..(x0 + bar_w).ceil() as u32 {
            blend(&mut img, x as i64, y as i64, c, 1.0);
        }
    }
    let outline = [60, 60, 70];
    let line = s.max(1.0);
    fill_rect(
        &mut img,
        x0 - line,
        y0 - line,
        bar_w + 2.0 * line,
        line,
        0.0,
        [60, 60, 70, 255],
    );
    fill_rect(
        &mut img,
        x0 - line,
        y0 + bar_h,
        bar_w + 2.0 * line,
        line,
        0.0,
        [60, 60, 70, 255],
    );
    fill_rect(&mut img, x0 - line, y0, line, bar_h, 0.0, [60, 60, 70, 255]);
    fill_rect(
        &mut img,
        x0 + bar_w,
        y0,
        line,
        bar_h,
        0.0,
        [60, 60, 70, 255],
    );
    for (i, label) in labels.iter().enumerate() {
        let y = y0 + bar_h * i as f32 / (TICKS - 1) as f32;
        let rgba = [outline[0], outline[1], outline[2], 255];
        fill_rect(&mut img, x0 + bar_w, y - line * 0.5, tick, line, 0.0, rgba);
        draw_text(
            &mut img,
            &font,
            label_px,
            x0 + bar_w + tick + 4.0 * s,
            y - label_h * 0.5,
            label,
            ink,
        );
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Colormap;

    #[test]
    fn si_labels() {
        assert_eq!(format_si(12345.0, "Pa"), "12.3 kPa");
        assert_eq!(format_si(0.004, "m"), "4.00 mm");
        assert_eq!(format_si(-2.5e6, "Pa"), "-2.50 MPa");
        assert_eq!(format_si(999.96, "N"), "1.00 kN");
        assert_eq!(format_si(0.0, "Pa"), "0 Pa");
        assert_eq!(format_si(f32::NAN, "Pa"), "n/a");
        assert_eq!(format_si(150.0, "N"), "150 N");
    }

    #[test]
    fn legend_has_ink_and_colours() {
        let legend = Legend {
            title: "von Mises stress".into(),
            unit: "Pa".into(),
            range: [0.0, 3.2e5],
            colormap: Colormap::Viridis,
        };
        let img = legend_image(&legend, 720);
        assert!(
            img.width() > 120 && img.height() > 300,
            "{}x{}",
            img.width(),
            img.height()
        );
        // Dark text pixels exist, and the top of the bar is the colormap's maximum.
        let dark = img.pixels().filter(|p| p[0] < 80 && p[3] > 200).count();
        assert!(dark > 200, "{dark}");
        let near_top = |p: &&image::Rgba<u8>| {
            p.0[3] == 255 && (0..3).all(|k| p.0[k].abs_diff([253, 231, 37][k]) <= 3)
        };
        let top = img.pixels().filter(near_top).count();
        assert!(top > 20, "{top}");
    }
}
