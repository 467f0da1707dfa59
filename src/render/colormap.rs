//! Colormaps: scalar in [0, 1] to linear RGB. Each is a few control colours (sRGB, as published
//! for the map) interpolated linearly in sRGB, then converted to linear light.

/// A colormap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Colormap {
    /// Perceptually uniform dark blue → green → yellow (for stress and displacement).
    #[default]
    Viridis,
    /// White → orange → dark red (for contact pressure: zero pressure is the skin's own tone).
    Heat,
    /// Green → yellow → red: a ratio of a load to its threshold (arrows of bone forces).
    Traffic,
}

const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];
const HEAT: [[u8; 3]; 5] = [
    [255, 247, 236],
    [253, 212, 158],
    [252, 141, 89],
    [215, 48, 31],
    [127, 0, 0],
];
const TRAFFIC: [[u8; 3]; 3] = [[26, 152, 80], [254, 224, 80], [215, 48, 39]];

/// sRGB component in [0, 1] to linear light.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light in [0, 1] to an sRGB component.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

impl Colormap {
    fn stops(self) -> &'static [[u8; 3]] {
        match self {
            Colormap::Viridis => &VIRIDIS,
            Colormap::Heat => &HEAT,
            Colormap::Traffic => &TRAFFIC,
        }
    }

    /// sRGB colour (0–255) at `t` (clamped to [0, 1]; NaN maps to 0).
    pub fn srgb8(self, t: f32) -> [u8; 3] {
        let stops = self.stops();
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let x = t * (stops.len() - 1) as f32;
        let i = (x.floor() as usize).min(stops.len() - 2);
        let f = x - i as f32;
        let (a, b) = (stops[i], stops[i + 1]);
        [0, 1, 2].map(|k| (a[k] as f32 + (b[k] as f32 - a[k] as f32) * f).round() as u8)
    }

    /// Linear RGBA colour at `t`, opaque.
    pub fn linear(self, t: f32) -> [f32; 4] {
        let c = self.srgb8(t);
        [
            srgb_to_linear(c[0] as f32 / 255.0),
            srgb_to_linear(c[1] as f32 / 255.0),
            srgb_to_linear(c[2] as f32 / 255.0),
            1.0,
        ]
    }

    /// Colour of a load against its threshold: `ratio` = load / threshold, green at 0, yellow at
    /// 0.5, red at 1 and above.
    pub fn force_ratio(ratio: f32) -> [f32; 4] {
        Colormap::Traffic.linear(ratio)
    }

    /// 256 sRGB texels (RGBA8) for the GPU lookup texture.
    pub fn texels(self) -> Vec<u8> {
        (0..256)
            .flat_map(|i| {
                let c = self.srgb8(i as f32 / 255.0);
                [c[0], c[1], c[2], 255]
            })
            .collect()
    }
}

/// A usable scalar range from `range`: finite, increasing, and not empty (an all-equal range is
/// widened around its value so that it maps to the middle of the colormap).
pub fn guard_range(range: [f32; 2]) -> [f32; 2] {
    let [mut lo, mut hi] = range;
    if !lo.is_finite() || !hi.is_finite() {
        let finite: Vec<f32> = [lo, hi].into_iter().filter(|v| v.is_finite()).collect();
        match finite.as_slice() {
            [] => return [0.0, 1.0],
            [v] | [v, _] => {
                lo = *v;
                hi = *v;
            }
            _ => unreachable!(),
        }
    }
    if lo > hi {
        std::mem::swap(&mut lo, &mut hi);
    }
    if hi - lo <= f32::EPSILON * lo.abs().max(hi.abs()).max(f32::MIN_POSITIVE) {
        // A field that is zero everywhere (von Mises stress or displacement at rest) is shown
        // on [0, 1]: a legend never offers a negative magnitude.
        if lo == 0.0 {
            return [0.0, 1.0];
        }
        let pad = lo.abs() * 0.5;
        return [lo - pad, hi + pad];
    }
    [lo, hi]
}

/// Minimum and maximum of the finite values, or `None` when there is none.
pub fn finite_range(values: impl IntoIterator<Item = f32>) -> Option<[f32; 2]> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some([v, v]),
            Some([lo, hi]) => Some([lo.min(v), hi.max(v)]),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_and_middle() {
        assert_eq!(Colormap::Viridis.srgb8(0.0), [68, 1, 84]);
        assert_eq!(Colormap::Viridis.srgb8(1.0), [253, 231, 37]);
        assert_eq!(Colormap::Viridis.srgb8(0.5), [33, 144, 141]);
        assert_eq!(Colormap::Viridis.srgb8(-3.0), [68, 1, 84]);
        assert_eq!(Colormap::Viridis.srgb8(f32::NAN), [68, 1, 84]);
        assert_eq!(Colormap::Traffic.srgb8(7.0), [215, 48, 39]);
        // Halfway between the first two heat stops.
        assert_eq!(Colormap::Heat.srgb8(0.125), [254, 230, 197]);
        let t = Colormap::Heat.texels();
        assert_eq!(t.len(), 1024);
        assert_eq!(&t[1020..], &[127, 0, 0, 255]);
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255 {
            let c = i as f32 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-5);
        }
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
    }

    #[test]
    fn ranges_are_guarded() {
        assert_eq!(guard_range([1.0, 3.0]), [1.0, 3.0]);
        assert_eq!(guard_range([3.0, 1.0]), [1.0, 3.0]);
        assert_eq!(guard_range([2.0, 2.0]), [1.0, 3.0]);
        assert_eq!(guard_range([0.0, 0.0]), [0.0, 1.0]);
        assert_eq!(guard_range([-2.0, -2.0]), [-3.0, -1.0]);
        assert_eq!(guard_range([f32::NAN, f32::INFINITY]), [0.0, 1.0]);
        assert_eq!(guard_range([f32::NAN, 4.0]), [2.0, 6.0]);
        assert_eq!(
            finite_range([3.0, f32::NAN, -1.0, f32::INFINITY]),
            Some([-1.0, 3.0])
        );
        assert_eq!(finite_range([f32::NAN]), None);
    }
}
