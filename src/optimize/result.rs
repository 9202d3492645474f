//! The result shared by every optimiser of this module.

use super::evaluation::Evaluation;
use super::observer::Iterate;

/// Outcome of an optimisation run. Reaching the budget or failing everywhere is an outcome, not
/// an error: read [`OptimizeResult::termination`] and `evaluation.failed`.
#[derive(Clone, Debug, PartialEq)]
pub struct OptimizeResult {
    /// Best point found (trust region: the final centre; others: the best evaluation in the
    /// feasibility-first order of [`Evaluation::better_than`]).
    pub x: Vec<f64>,
    /// The black-box evaluation at `x`.
    pub evaluation: Evaluation,
    /// Number of black-box evaluations spent (cache hits not counted).
    pub evaluations: usize,
    /// Every evaluation in the order made: the point actually evaluated and its result.
    pub history: Vec<(Vec<f64>, Evaluation)>,
    /// The optimiser's path, one entry per iteration (see [`Iterate`]).
    pub path: Vec<Iterate>,
    /// Why the run stopped, in words.
    pub termination: String,
}

impl OptimizeResult {
    /// The best point is a successful evaluation with every black-box constraint `≤ tol`.
    pub fn is_feasible(&self, tol: f64) -> bool {
        self.evaluation.is_feasible(tol)
    }
}
