//! The adaptive step of a keyframe: the motion is marched from fraction 0 to 1 in steps of
//! 1 / (planned increments); a step that fails is retried at half its size, a bounded number of
//! times; optionally, after two easy steps in a row, the step doubles back towards its planned
//! size.

/// Where a keyframe's march stands, and how large its next step is.
pub(crate) struct StepControl {
    /// Fraction of the keyframe done.
    done: f64,
    /// Size of the next step, as a fraction of the keyframe.
    step: f64,
    /// Halvings in force (0 = the planned step).
    depth: usize,
    /// Halvings allowed.
    max_depth: usize,
    /// Easy steps in a row since the last change of size.
    easy: usize,
    /// Whether easy steps let the step grow back.
    grows: bool,
}

impl StepControl {
    /// A march of `steps` planned increments, halving up to `max_halvings` times; with `grows`,
    /// two easy steps in a row undo one halving.
    pub(crate) fn new(steps: usize, max_halvings: usize, grows: bool) -> Self {
        StepControl {
            done: 0.0,
            step: 1.0 / steps as f64,
            depth: 0,
            max_depth: max_halvings,
            easy: 0,
            grows,
        }
    }

    /// Whether the whole keyframe is done.
    pub(crate) fn finished(&self) -> bool {
        self.done >= 1.0 - 1e-12
    }

    /// The fraction of the keyframe done (the steps accepted).
    pub(crate) fn reached(&self) -> f64 {
        self.done
    }

    /// The fraction the next step reaches.
    pub(crate) fn target(&self) -> f64 {
        (self.done + self.step).min(1.0)
    }

    /// Whether a step to `target` ends the keyframe.
    pub(crate) fn finished_with(&self, target: f64) -> bool {
        target >= 1.0 - 1e-12
    }

    /// The size of the next step, as a fraction of the keyframe.
    pub(crate) fn step(&self) -> f64 {
        self.step
    }

    /// The step failed: halves it and returns `true`, or `false` when no halving is left.
    pub(crate) fn halve(&mut self) -> bool {
        if self.depth >= self.max_depth {
            return false;
        }
        self.depth += 1;
        self.step *= 0.5;
        self.easy = 0;
        true
    }

    /// The step to `target` succeeded; `easy` says it converged without trouble.
    pub(crate) fn accept(&mut self, target: f64, easy: bool) {
        self.done = target;
        if !self.grows {
            return;
        }
        self.easy = if easy { self.easy + 1 } else { 0 };
        if self.easy >= 2 && self.depth > 0 {
            self.depth -= 1;
            self.step *= 2.0;
            self.easy = 0;
        }
    }
}

/// Adds what one Newton increment cost (`record`: its iterations, retried factorizations and
/// times) to a keyframe's statistics.
pub(crate) fn count_newton(
    stats: &mut crate::state::KeyframeStats,
    record: &crate::fem::newton::StepRecord,
) {
    let cost = record.cost;
    stats.factorizations += record.iterations + record.regularised;
    stats.assembly_ms += cost.tangent_ms + cost.forces_ms;
    stats.symbolic_ms += cost.symbolic_ms;
    stats.factorization_ms += cost.factorization_ms;
    stats.solve_ms += cost.solve_ms;
}

#[cfg(test)]
mod tests {
    use super::StepControl;

    #[test]
    fn halvings_are_bounded_and_easy_steps_grow_back() {
        let mut s = StepControl::new(4, 2, true);
        assert_eq!(s.target(), 0.25);
        assert!(s.halve() && s.halve() && !s.halve());
        assert_eq!(s.step(), 0.0625);
        s.accept(s.target(), true);
        s.accept(s.target(), true);
        assert_eq!(s.step(), 0.125);
        let mut fixed = StepControl::new(2, 1, false);
        assert!(fixed.halve());
        fixed.accept(fixed.target(), true);
        fixed.accept(fixed.target(), true);
        assert_eq!(fixed.step(), 0.25);
        fixed.accept(fixed.target(), true);
        fixed.accept(fixed.target(), true);
        assert!(fixed.finished());
    }
}
