//! Errors of the optimisation layer.
//!
//! A run that ends without a good point (budget exhausted, every evaluation failed) is not an
//! error: it is reported in [`crate::optimize::OptimizeResult::termination`]. Errors are for
//! problems that cannot be started (bad dimensions, empty feasible set, bad options) and for
//! sub-solver breakdowns that leave no meaningful result.

use thiserror::Error;

/// Why an optimisation problem could not be set up or solved.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum OptimizeError {
    /// Two inputs that must agree in length do not.
    #[error("dimension mismatch in {what}: expected {expected}, found {found}")]
    Dimension {
        /// Which input is wrong.
        what: String,
        /// Length required.
        expected: usize,
        /// Length given.
        found: usize,
    },
    /// A bound, constraint coefficient or start point is NaN or infinite.
    #[error("non-finite value in {what} at index {index}: {value}")]
    NonFinite {
        /// Which input holds the value.
        what: String,
        /// Index of the offending entry.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A box bound has `lower > upper`.
    #[error("bound {index} is empty: lower = {lower} > upper = {upper}")]
    EmptyBound {
        /// Variable index.
        index: usize,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// The box and the linear constraints admit no common point.
    #[error(
        "the feasible set is empty: the box and the linear constraints a·x ≤ b have no common \
         point (the best point found violates them by {violation:.3e}{})",
        row.map_or(String::new(), |i| format!("; linear constraint {i} cannot be met"))
    )]
    Infeasible {
        /// Smallest achievable violation (a distance in variable units; see
        /// [`crate::optimize::FeasibleSet::violation`]).
        violation: f64,
        /// Index of a linear-constraint row that cannot be satisfied, when known.
        row: Option<usize>,
    },
    /// An option is outside its legal range.
    #[error("invalid option {name} = {value}: {reason}")]
    InvalidOption {
        /// Option name as in the options struct.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The legal range.
        reason: &'static str,
    },
    /// Clarabel could not solve a QP or LP sub-problem.
    #[error("QP sub-problem not solved: {status}")]
    Qp {
        /// Clarabel's status or setup error.
        status: String,
    },
    /// The argmin executor reported an error.
    #[error("optimiser error: {0}")]
    Solver(String),
}

impl OptimizeError {
    pub(crate) fn dimension(what: impl Into<String>, expected: usize, found: usize) -> Self {
        OptimizeError::Dimension {
            what: what.into(),
            expected,
            found,
        }
    }

    /// Checks that the black box has the dimension `expected` of the feasible set.
    pub(crate) fn check_dim(found: usize, expected: usize) -> Result<(), Self> {
        if found == expected {
            Ok(())
        } else {
            Err(Self::dimension(
                "black box dimension vs feasible set",
                expected,
                found,
            ))
        }
    }

    /// Checks that every entry of `v` is finite.
    pub(crate) fn check_finite(what: &str, v: &[f64]) -> Result<(), Self> {
        match v.iter().position(|x| !x.is_finite()) {
            Some(index) => Err(OptimizeError::NonFinite {
                what: what.to_string(),
                index,
                value: v[index],
            }),
            None => Ok(()),
        }
    }
}

/// Converts an argmin error back into ours when it wraps one, else keeps its message.
pub(crate) fn from_argmin(e: argmin::core::Error) -> OptimizeError {
    match e.downcast::<OptimizeError>() {
        Ok(ours) => ours,
        Err(other) => OptimizeError::Solver(other.to_string()),
    }
}

/// An evaluation budget of at least one point.
pub(crate) fn check_budget(max_evaluations: usize) -> Result<(), OptimizeError> {
    if max_evaluations == 0 {
        return Err(OptimizeError::InvalidOption {
            name: "max_evaluations",
            value: 0.0,
            reason: "must be ≥ 1",
        });
    }
    Ok(())
}

/// A constraint tolerance (how far a point may violate a linear limit and still count as
/// feasible): finite and ≥ 0.
pub(crate) fn check_constraint_tol(constraint_tol: f64) -> Result<(), OptimizeError> {
    if !(constraint_tol.is_finite() && constraint_tol >= 0.0) {
        return Err(OptimizeError::InvalidOption {
            name: "constraint_tol",
            value: constraint_tol,
            reason: "must be finite and ≥ 0",
        });
    }
    Ok(())
}
