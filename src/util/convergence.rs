//! A quantity's convergence under mesh refinement, read from three meshes: the observed order p
//! of f(h) = f∞ + C·hᵖ and the limit f∞ it points to (Richardson extrapolation), for spacings in
//! any ratio (the hand's resolutions 2.5, 3, 3.5 are not a geometric series).

/// The observed order and limit of three values `f` at the spacings `h` (decreasing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Convergence {
    /// The changes keep their sign and shrink as f∞ + C·hᵖ's do for this p > 0.
    Order {
        /// p, the observed order in the spacing.
        order: f64,
        /// f∞, Richardson's limit.
        limit: f64,
    },
    /// The changes change sign: no order (the values scatter about their limit, or have not
    /// reached the range where one power of h governs them).
    NotMonotone,
    /// The changes keep their sign but do not shrink as fast as any positive power of h would
    /// (no positive order: the values diverge, or are not yet converging), or the spacings do
    /// not decrease, or a value is not finite.
    NotShrinking,
}

/// The largest order looked for: an order read as this is at least this (the middle value is
/// then as good as the finest).
pub const LARGEST_ORDER: f64 = 20.0;

/// Reads the convergence of `f` (at spacings `h`, decreasing, positive).
pub fn convergence(h: [f64; 3], f: [f64; 3]) -> Convergence {
    let (d1, d2) = (f[0] - f[1], f[1] - f[2]);
    if !(h[0].is_finite() && h[0] > h[1] && h[1] > h[2] && h[2] > 0.0)
        || f.iter().any(|x| !x.is_finite())
    {
        return Convergence::NotShrinking;
    }
    if d2 == 0.0 {
        return Convergence::Order {
            order: LARGEST_ORDER,
            limit: f[2],
        };
    }
    if d1 * d2 < 0.0 {
        return Convergence::NotMonotone;
    }
    // (h₁ᵖ − h₂ᵖ)/(h₂ᵖ − h₃ᵖ) = d1/d2 rises with p from ln(h₁/h₂)/ln(h₂/h₃) at p → 0 (the
    // spacings taken relative to the coarsest, so no power of them underflows).
    let h = h.map(|x| x / h[0]);
    let ratio = |p: f64| (h[0].powf(p) - h[1].powf(p)) / (h[1].powf(p) - h[2].powf(p));
    let wanted = d1 / d2;
    let floor = (h[0] / h[1]).ln() / (h[1] / h[2]).ln();
    if wanted <= floor {
        return Convergence::NotShrinking;
    }
    let (mut lo, mut hi) = (0.0_f64, LARGEST_ORDER);
    if ratio(hi) < wanted {
        lo = hi;
    } else {
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if ratio(mid.max(1e-9)) < wanted {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }
    let p = 0.5 * (lo + hi);
    let limit = f[2] - d2 * h[2].powf(p) / (h[1].powf(p) - h[2].powf(p));
    Convergence::Order { order: p, limit }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn order_and_limit(c: Convergence) -> (f64, f64) {
        match c {
            Convergence::Order { order, limit } => (order, limit),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_power_of_the_spacing_gives_its_order_and_limit_back() {
        // The hand's spacings at resolutions 2.5, 3, 3.5 (not a geometric series).
        let h = [3.2 / 2.5, 3.2 / 3.0, 3.2 / 3.5];
        for (p, c) in [(1.0, 0.7), (2.0, -0.3), (0.5, 2.0), (3.7, 1.0)] {
            let f = h.map(|h: f64| 4.0 + c * h.powf(p));
            let (order, limit) = order_and_limit(convergence(h, f));
            assert!((order - p).abs() < 1e-9, "p {p}: {order}");
            assert!((limit - 4.0).abs() < 1e-9, "p {p}: {limit}");
        }
    }

    #[test]
    fn scatter_and_growth_have_no_order() {
        let h = [1.0, 0.5, 0.25];
        assert_eq!(convergence(h, [1.0, 2.0, 1.5]), Convergence::NotMonotone);
        // Changes equal on a geometric series (ln(1/h) — the order → 0) and growing a little:
        // no positive order.
        assert_eq!(convergence(h, [0.0, 1.0, 2.05]), Convergence::NotShrinking);
        // Spacings not decreasing, a value not finite.
        assert_eq!(
            convergence([0.5, 1.0, 0.25], [1.0, 2.0, 2.5]),
            Convergence::NotShrinking
        );
        assert_eq!(
            convergence(h, [1.0, f64::NAN, 2.5]),
            Convergence::NotShrinking
        );
        // Settled on the middle mesh: the order read as the largest, the limit the finest.
        assert_eq!(
            convergence(h, [1.0, 2.0, 2.0]),
            Convergence::Order {
                order: LARGEST_ORDER,
                limit: 2.0
            }
        );
        // Growing changes (the shipped fist's largest bone reaction at resolutions 1, 1.5, 2).
        assert_eq!(
            convergence([3.2, 3.2 / 1.5, 1.6], [10.210, 10.990, 12.452]),
            Convergence::NotShrinking
        );
        assert_eq!(
            convergence([1.0, 1.0, 0.5], [1.0, 2.0, 3.0]),
            Convergence::NotShrinking
        );
    }
}
