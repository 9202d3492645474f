//! The result shared by every optimiser of this module.

use super::evaluation::Evaluation;
use super::observer::Iterate;

/// Why an optimiser stopped: outcome as data (Clarabel's `SolverStatus`, argmin's
/// `TerminationReason`), with [`OptimizeResult::termination`] saying it in words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// The method's own convergence test held (trust radius, simplex size, swarm spread, no gain
    /// from a restart).
    Converged,
    /// The evaluation budget was spent before convergence: the best point is the best seen.
    BudgetExhausted,
    /// The iteration cap was reached before convergence.
    IterationLimit,
    /// Every evaluation failed.
    AllFailed,
    /// A grid search evaluated every node (exhaustive, no convergence test).
    GridComplete,
}

impl Stop {
    /// Whether the result is an optimum in the method's own sense.
    pub fn is_converged(self) -> bool {
        matches!(self, Stop::Converged | Stop::GridComplete)
    }

    /// In words, for terminals.
    pub fn text(self) -> &'static str {
        match self {
            Stop::Converged => "converged",
            Stop::BudgetExhausted => "evaluation budget exhausted (not converged)",
            Stop::IterationLimit => "iteration limit reached (not converged)",
            Stop::AllFailed => "every evaluation failed",
            Stop::GridComplete => "every grid node evaluated",
        }
    }
}

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
    /// Why the run stopped.
    pub stop: Stop,
}

impl OptimizeResult {
    /// The best point is a successful evaluation with every black-box constraint `≤ tol`.
    pub fn is_feasible(&self, tol: f64) -> bool {
        self.evaluation.is_feasible(tol)
    }
}
