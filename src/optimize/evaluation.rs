//! One evaluation of the black box, and the trait the black box implements.
//!
//! Conventions: the objective is **minimised**; a black-box constraint value `c_j(x) ≤ 0` is
//! satisfied (e.g. a chance constraint `P(m > t) − p`). An evaluation that did not produce
//! numbers (diverged simulation, NaN objective) is `failed` and is treated as infeasible and
//! worse than every successful evaluation — never as a crash.

/// Result of evaluating the black box at one point.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Objective value to minimise.
    pub objective: f64,
    /// Black-box constraint values; `c_j ≤ 0` is feasible.
    pub constraints: Vec<f64>,
    /// The evaluation failed; `objective` and `constraints` are meaningless.
    pub failed: bool,
}

impl Evaluation {
    /// A successful evaluation (marked failed if any value is not finite).
    pub fn new(objective: f64, constraints: Vec<f64>) -> Self {
        let failed = !objective.is_finite() || constraints.iter().any(|c| !c.is_finite());
        Evaluation {
            objective,
            constraints,
            failed,
        }
    }

    /// A failed evaluation with `n_constraints` constraint slots (all +∞).
    pub fn failure(n_constraints: usize) -> Self {
        Evaluation {
            objective: f64::INFINITY,
            constraints: vec![f64::INFINITY; n_constraints],
            failed: true,
        }
    }

    /// The evaluation as the optimisers see it: a non-finite value or a constraint vector of the
    /// wrong length turns it into a failure.
    pub fn sanitized(self, n_constraints: usize) -> Self {
        if self.failed
            || !self.objective.is_finite()
            || self.constraints.len() != n_constraints
            || self.constraints.iter().any(|c| !c.is_finite())
        {
            Evaluation::failure(n_constraints)
        } else {
            self
        }
    }

    /// Total constraint violation `Σ_j max(0, c_j)` (+∞ for a failure).
    pub fn violation(&self) -> f64 {
        if self.failed {
            return f64::INFINITY;
        }
        self.constraints.iter().map(|c| c.max(0.0)).sum()
    }

    /// Not failed and every `c_j ≤ tol`.
    pub fn is_feasible(&self, tol: f64) -> bool {
        !self.failed && self.constraints.iter().all(|&c| c <= tol)
    }

    /// Exact ℓ1 penalty merit `f + μ Σ_j max(0, c_j)` (+∞ for a failure).
    pub fn merit(&self, penalty: f64) -> f64 {
        if self.failed {
            return f64::INFINITY;
        }
        self.objective + penalty * self.violation()
    }

    /// Feasibility-first order (Deb's rules): a feasible evaluation beats an infeasible one,
    /// two feasible ones compare by objective, two infeasible ones by violation, failures last.
    pub fn better_than(&self, other: &Evaluation, tol: f64) -> bool {
        match (self.failed, other.failed) {
            (true, _) => return false,
            (false, true) => return true,
            _ => {}
        }
        match (self.is_feasible(tol), other.is_feasible(tol)) {
            (true, false) => true,
            (false, true) => false,
            (true, true) => self.objective < other.objective,
            (false, false) => self.violation() < other.violation(),
        }
    }
}

/// An expensive, possibly failing function of `dim()` variables returning an objective and
/// `n_constraints()` constraint values.
///
/// `Sync` so that [`BlackBox::evaluate_batch`] may evaluate points in parallel (e.g. with rayon);
/// the optimisers call `evaluate_batch` wherever several points are independent (initial
/// designs, swarms, grids).
pub trait BlackBox: Sync {
    /// Number of variables.
    fn dim(&self) -> usize;
    /// Number of black-box constraints `c_j(x) ≤ 0`.
    fn n_constraints(&self) -> usize;
    /// Evaluates one point. Must not panic on a bad point: return a failed [`Evaluation`].
    fn evaluate(&self, x: &[f64]) -> Evaluation;
    /// Evaluates several points; the default is sequential.
    fn evaluate_batch(&self, xs: &[Vec<f64>]) -> Vec<Evaluation> {
        xs.iter().map(|x| self.evaluate(x)).collect()
    }
}

/// Index of the best evaluation of `history` in the feasibility-first order, if any.
pub(crate) fn best_index(history: &[(Vec<f64>, Evaluation)], tol: f64) -> Option<usize> {
    let mut best: Option<usize> = None;
    for (i, (_, e)) in history.iter().enumerate() {
        match best {
            None => best = Some(i),
            Some(b) if e.better_than(&history[b].1, tol) => best = Some(i),
            _ => {}
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_values_are_failures() {
        assert!(Evaluation::new(f64::NAN, vec![]).failed);
        assert!(Evaluation::new(1.0, vec![f64::INFINITY]).failed);
        assert!(!Evaluation::new(1.0, vec![-1.0]).failed);
        assert!(Evaluation::new(1.0, vec![]).sanitized(1).failed);
    }

    #[test]
    fn feasibility_first_order() {
        let feasible_bad = Evaluation::new(10.0, vec![-1.0]);
        let feasible_good = Evaluation::new(1.0, vec![-1.0]);
        let infeasible = Evaluation::new(-5.0, vec![0.5]);
        let less_infeasible = Evaluation::new(-4.0, vec![0.1]);
        let failed = Evaluation::failure(1);
        assert!(feasible_good.better_than(&feasible_bad, 0.0));
        assert!(feasible_bad.better_than(&infeasible, 0.0));
        assert!(less_infeasible.better_than(&infeasible, 0.0));
        assert!(infeasible.better_than(&failed, 0.0));
        assert!(!failed.better_than(&infeasible, 0.0));
        assert_eq!(infeasible.merit(2.0), -4.0);
        assert_eq!(failed.merit(2.0), f64::INFINITY);
    }
}
