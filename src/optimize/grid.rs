//! Exhaustive grid search: `per_dim` points per variable over the box (endpoints included),
//! points outside the linear constraints skipped, all evaluated in one
//! [`BlackBox::evaluate_batch`]. The result is the best evaluation in the feasibility-first order
//! (feasible beats infeasible, then objective; failures last). Useful as a reference and to map
//! the objective for plots; its cost is `per_dimⁿ` evaluations.

use super::evaluation::{BlackBox, Evaluation};
use super::feasible::FeasibleSet;
use super::nelder_mead::finish;
use super::observer::Iterate;
use super::result::Stop;
use super::{OptimizeError, OptimizeResult};

/// Evaluates the grid and returns every point (`history`) and the best one.
/// `constraint_tol`: black-box constraints `≤ constraint_tol` count as satisfied.
pub fn grid_search<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    per_dim: usize,
    constraint_tol: f64,
) -> Result<OptimizeResult, OptimizeError> {
    OptimizeError::check_dim(bb.dim(), set.dim())?;
    if per_dim == 0 {
        return Err(OptimizeError::InvalidOption {
            name: "per_dim",
            value: 0.0,
            reason: "must be ≥ 1",
        });
    }
    let fallback = set.find_feasible_point()?;
    let points = set.grid(per_dim);
    if points.is_empty() {
        return Err(OptimizeError::InvalidOption {
            name: "per_dim",
            value: per_dim as f64,
            reason: "no grid point lies inside the linear constraints; use more points",
        });
    }
    let m = bb.n_constraints();
    let mut evals = bb.evaluate_batch(&points);
    evals.resize(points.len(), Evaluation::failure(m));
    let history: Vec<(Vec<f64>, Evaluation)> = points
        .into_iter()
        .zip(evals)
        .map(|(x, e)| (x, e.sanitized(m)))
        .collect();
    let n_points = history.len();
    let mut result = finish(
        history,
        Vec::new(),
        format!("grid of {n_points} points evaluated"),
        Stop::GridComplete,
        m,
        constraint_tol,
        &fallback,
    )?;
    result.path = vec![Iterate {
        iteration: 0,
        x: result.x.clone(),
        merit: result.evaluation.objective,
        radius: None,
        evaluations: n_points,
        step: Some("grid".into()),
    }];
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Paraboloid;
    impl BlackBox for Paraboloid {
        fn dim(&self) -> usize {
            2
        }
        fn n_constraints(&self) -> usize {
            1
        }
        fn evaluate(&self, x: &[f64]) -> Evaluation {
            if x[0] < 0.1 {
                return Evaluation::failure(1);
            }
            // Minimum at (1, 1), but c = x + y − 1.5 ≤ 0 forbids it.
            let f = (x[0] - 1.0).powi(2) + (x[1] - 1.0).powi(2);
            Evaluation::new(f, vec![x[0] + x[1] - 1.5])
        }
    }

    /// On the 5×5 grid of [0, 1]² with x + y ≤ 1.5 (black box) the best feasible points are
    /// (0.75, 0.75), (0.5, 1) and (1, 0.5) with f = 0.125, 0.25, 0.25: (0.75, 0.75) wins.
    #[test]
    fn best_feasible_grid_point() {
        let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let r = grid_search(&Paraboloid, &set, 5, 0.0).unwrap();
        assert_eq!(r.evaluations, 25);
        assert_eq!(r.x, vec![0.75, 0.75]);
        assert_eq!(r.history.iter().filter(|(_, e)| e.failed).count(), 5);
        // A linear row x ≤ 0.5 removes points before evaluation.
        let cut = FeasibleSet::new(
            vec![0.0, 0.0],
            vec![1.0, 1.0],
            vec![vec![1.0, 0.0]],
            vec![0.5],
        )
        .unwrap();
        let r = grid_search(&Paraboloid, &cut, 5, 0.0).unwrap();
        assert_eq!(r.evaluations, 15);
        assert_eq!(r.x, vec![0.5, 1.0]);
    }
}
