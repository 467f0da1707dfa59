//! The split of the degrees of freedom into unknown (free) and prescribed ones, equation (6):
//! [K11 K12; K21 K22]·[Uu; Uk] = [Rk; Ru].

/// Which degrees of freedom are prescribed. Free dofs are numbered 0..NBEQ in increasing global
/// order, so the upper triangle of K restricted to them stays an upper triangle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DofPartition {
    /// `true` for a prescribed dof (a U_k).
    pub prescribed: Vec<bool>,
    /// Equation number of each free dof, `usize::MAX` for a prescribed one.
    pub equation: Vec<usize>,
    /// Global indices of the free dofs (the U_u), in equation order.
    pub free: Vec<usize>,
}

impl DofPartition {
    /// Partition of `dofs` degrees of freedom with the given prescribed mask.
    pub fn new(prescribed: Vec<bool>) -> Self {
        let mut equation = vec![usize::MAX; prescribed.len()];
        let mut free = Vec::new();
        for (d, &p) in prescribed.iter().enumerate() {
            if !p {
                equation[d] = free.len();
                free.push(d);
            }
        }
        Self {
            prescribed,
            equation,
            free,
        }
    }

    /// NBEQ = NB − NP, the number of unknown displacements.
    pub fn free_count(&self) -> usize {
        self.free.len()
    }

    /// NP, the number of prescribed displacements.
    pub fn prescribed_count(&self) -> usize {
        self.prescribed.len() - self.free.len()
    }
}
