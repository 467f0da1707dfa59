//! Contact points embedded in a body: vertices that are fixed linear combinations of mesh nodes
//! (the smooth skin's vertices, each inside a flesh cell, weighted by that cell's trilinear shape
//! functions). A contact on such a point moves with Σ w_i U_i and its force goes to the nodes as
//! w_i·R_C — Figure 5's R_i = h_i·R_C extended to the cell's nodes (the embedded-surface contact
//! of McAdams et al. 2011).
//!
//! Contact indices below `first` are mesh nodes; index `first + i` is embedded point `i`.

use nalgebra::Vector3;

/// Points embedded in the mesh, numbered after its nodes.
#[derive(Clone, Debug, Default)]
pub struct EmbeddedPoints {
    /// Number of mesh nodes: the first embedded point's index.
    first: usize,
    /// Start of each point's terms (CSR), one more than points.
    offsets: Vec<usize>,
    /// (node, weight) of every point, in order.
    terms: Vec<(usize, f64)>,
}

impl EmbeddedPoints {
    /// No embedded point over a mesh of `nodes` nodes.
    pub fn none(nodes: usize) -> EmbeddedPoints {
        EmbeddedPoints {
            first: nodes,
            offsets: vec![0],
            terms: Vec::new(),
        }
    }

    /// Appends a point with the given (node, weight) terms; returns its contact index.
    pub fn push(&mut self, terms: impl IntoIterator<Item = (usize, f64)>) -> usize {
        let start = self.terms.len();
        self.terms.extend(terms);
        assert!(
            self.terms.len() > start && self.terms[start..].iter().all(|t| t.0 < self.first),
            "an embedded point is a combination of mesh nodes"
        );
        self.offsets.push(self.terms.len());
        self.first + self.offsets.len() - 2
    }

    /// Number of mesh nodes (the index of the first embedded point).
    pub fn first(&self) -> usize {
        self.first
    }

    /// Number of embedded points.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Whether there is no embedded point.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The (node, weight) terms of embedded point `v` (empty for a node: see [`Self::for_each`]).
    pub fn terms(&self, v: usize) -> &[(usize, f64)] {
        if v < self.first {
            return &[];
        }
        let i = v - self.first;
        &self.terms[self.offsets[i]..self.offsets[i + 1]]
    }

    /// How many (node, weight) terms contact index `v` has (1 for a node).
    pub fn term_count(&self, v: usize) -> usize {
        if v < self.first {
            1
        } else {
            self.terms(v).len()
        }
    }

    /// Calls `f(node, weight)` for every term of contact index `v` ((v, 1) for a node).
    pub fn for_each(&self, v: usize, mut f: impl FnMut(usize, f64)) {
        if v < self.first {
            f(v, 1.0);
        } else {
            for &(n, w) in self.terms(v) {
                f(n, w);
            }
        }
    }

    /// The node that carries most of contact index `v` (itself for a node): for naming it.
    pub fn main_node(&self, v: usize) -> usize {
        if v < self.first {
            return v;
        }
        heaviest(self.terms(v), v)
    }

    /// The positions of the nodes `nodes` (one per mesh node) followed by those of every
    /// embedded point.
    pub fn extend(&self, nodes: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        assert_eq!(nodes.len(), self.first, "one position per mesh node");
        let mut out = nodes.to_vec();
        out.extend((0..self.len()).map(|i| {
            self.terms[self.offsets[i]..self.offsets[i + 1]]
                .iter()
                .map(|&(n, w)| nodes[n] * w)
                .sum::<Vector3<f64>>()
        }));
        out
    }

    /// The displacement of contact index `v` for nodal displacements `u` (3 per node).
    pub fn displacement(&self, u: &[f64], v: usize) -> Vector3<f64> {
        let mut d = Vector3::zeros();
        self.for_each(v, |n, w| {
            d += Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]) * w
        });
        d
    }
}

/// The node of the largest weight among `terms` (`none` when there is none).
pub(super) fn heaviest(terms: &[(usize, f64)], none: usize) -> usize {
    terms
        .iter()
        .fold(
            (none, f64::NEG_INFINITY),
            |a, &(n, w)| if w > a.1 { (n, w) } else { a },
        )
        .0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_moves_and_is_placed_by_its_weights() {
        let nodes = vec![Vector3::new(0.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0)];
        let mut e = EmbeddedPoints::none(2);
        let v = e.push([(0, 0.25), (1, 0.75)]);
        assert_eq!(v, 2);
        assert_eq!(e.extend(&nodes)[2], Vector3::new(1.5, 0.0, 0.0));
        let u = [0.0, 0.0, 4.0, 0.0, 0.0, 0.0];
        assert_eq!(e.displacement(&u, v), Vector3::new(0.0, 0.0, 1.0));
        assert_eq!(e.displacement(&u, 0), Vector3::new(0.0, 0.0, 4.0));
        assert_eq!(e.main_node(v), 1);
        assert_eq!(e.main_node(1), 1);
    }
}
