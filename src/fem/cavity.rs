//! A cavity bounded by bilinear facets: whether the facets close it, and the volume they enclose
//! at any node positions (the gas of a sealed ball follows it).

use crate::mesh::Facet;
use nalgebra::Vector3;
use std::collections::HashMap;

/// Why facets do not bound a cavity.
#[derive(Clone, Debug, PartialEq)]
pub enum NotClosed {
    /// No facet at all.
    Empty,
    /// Edges bordered by one facet only (a hole in the surface).
    Open {
        /// How many such edges.
        edges: usize,
    },
    /// Edges bordered by more than two facets, or by two facets of the same orientation.
    Inconsistent {
        /// How many such edges.
        edges: usize,
    },
}

impl std::fmt::Display for NotClosed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotClosed::Empty => write!(f, "no facet"),
            NotClosed::Open { edges } => {
                write!(
                    f,
                    "{edges} edges border one facet only: the surface has a hole"
                )
            }
            NotClosed::Inconsistent { edges } => write!(
                f,
                "{edges} edges border more than two facets or two facets of the same \
                 orientation"
            ),
        }
    }
}

/// Checks that `facets` form a closed, consistently oriented surface: every edge a→b of a facet
/// is the edge b→a of exactly one other facet.
pub fn check_closed(facets: &[Facet]) -> Result<(), NotClosed> {
    if facets.is_empty() {
        return Err(NotClosed::Empty);
    }
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for f in facets {
        for i in 0..4 {
            let (a, b) = (f.nodes[i], f.nodes[(i + 1) % 4]);
            if a != b {
                *directed.entry((a, b)).or_default() += 1;
            }
        }
    }
    let mut open = 0;
    let mut inconsistent = 0;
    for (&(a, b), &count) in &directed {
        match (count, directed.get(&(b, a)).copied().unwrap_or(0)) {
            (1, 1) => {}
            (1, 0) => open += 1,
            _ => inconsistent += 1,
        }
    }
    if inconsistent > 0 {
        Err(NotClosed::Inconsistent {
            edges: inconsistent,
        })
    } else if open > 0 {
        Err(NotClosed::Open { edges: open })
    } else {
        Ok(())
    }
}

/// The signed volume the closed `facets` enclose with node positions `position(n)`, m³:
/// V = ⅓ ∮ (x − c)·n dA (divergence theorem, div x = 3), positive when the facets' normals
/// (x,s × x,t) point out of the enclosed region. On bilinear facets the integrand is of degree
/// two in each of s and t, so 2×2 Gauss points give it exactly: this is the exact volume the
/// deformed facets enclose. `c` (any point; the facets' first node) keeps round-off small.
pub fn enclosed_volume(facets: &[Facet], position: impl Fn(usize) -> Vector3<f64>) -> f64 {
    const CORNERS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let Some(first) = facets.first() else {
        return 0.0;
    };
    let c = position(first.nodes[0]);
    let g = 1.0 / 3f64.sqrt();
    let mut sum = 0.0;
    for facet in facets {
        let x = facet.nodes.map(|n| position(n) - c);
        for (s, t) in [(-g, -g), (g, -g), (g, g), (-g, g)] {
            let mut p = Vector3::zeros();
            let mut dxs = Vector3::zeros();
            let mut dxt = Vector3::zeros();
            for (a, k) in CORNERS.iter().enumerate() {
                p += x[a] * ((1.0 + k[0] * s) * (1.0 + k[1] * t) / 4.0);
                dxs += x[a] * (k[0] * (1.0 + k[1] * t) / 4.0);
                dxt += x[a] * (k[1] * (1.0 + k[0] * s) / 4.0);
            }
            sum += p.dot(&dxs.cross(&dxt));
        }
    }
    sum / 3.0
}
