//! The scalar cost seen by the direct-search methods (Nelder–Mead, particle swarm): a projected
//! exact-penalty function
//!
//! `F(x) = φ(P(x)) + ρ ‖x − P(x)‖₂²,   φ(y) = f(y) + μ Σ_j max(0, c_j(y))`,
//!
//! with `P` the Euclidean projection onto the [`FeasibleSet`] (Clarabel QP), so the black box is
//! only ever evaluated inside the linear constraints. A failed evaluation costs
//! [`FAILURE_COST`] (finite so that simplex arithmetic stays finite; both methods only compare
//! costs). Evaluations are cached on the exact projected point (a simplex pushed against a bound
//! projects many points onto the same one), and a hard budget is enforced: past it the cost is
//! `FAILURE_COST` without evaluating, and the driving solver stops at its next termination test.

use std::borrow::Borrow;
use std::collections::HashMap;
use std::sync::Mutex;

use argmin::core::{CostFunction, Error, SendAlias, SyncAlias};

use super::evaluation::{BlackBox, Evaluation};
use super::feasible::FeasibleSet;

/// Cost of a failed (or not evaluated, budget spent) point.
pub const FAILURE_COST: f64 = 1e10;

/// Mutable bookkeeping shared by successive runs (restarts) on the same black box.
#[derive(Default)]
pub(crate) struct PenaltyLog {
    /// Every real evaluation: projected point and result.
    pub(crate) history: Vec<(Vec<f64>, Evaluation)>,
    /// Projected point (bit pattern) → index into `history`.
    cache: HashMap<Vec<u64>, usize>,
    /// Every cost call: the raw point and the cost returned.
    pub(crate) calls: Vec<(Vec<f64>, f64)>,
    /// A cost was requested after the budget was spent.
    pub(crate) budget_hit: bool,
}

/// Penalty parameters.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PenaltyParams {
    /// `μ`, weight of black-box constraint violation.
    pub(crate) penalty: f64,
    /// `ρ`, weight of the squared distance to the feasible set.
    pub(crate) projection_weight: f64,
    /// Evaluation budget.
    pub(crate) budget: usize,
}

/// The argmin problem `F(x)` (see the module doc).
pub(crate) struct PenalizedProblem<'a, B: ?Sized> {
    pub(crate) bb: &'a B,
    pub(crate) set: &'a FeasibleSet,
    pub(crate) params: PenaltyParams,
    pub(crate) log: &'a Mutex<PenaltyLog>,
}

fn key(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

fn dist2(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

impl<B: BlackBox + ?Sized> PenalizedProblem<'_, B> {
    fn lock(&self) -> std::sync::MutexGuard<'_, PenaltyLog> {
        self.log.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Evaluations spent so far.
    pub(crate) fn evaluations(&self) -> usize {
        self.lock().history.len()
    }

    fn value(&self, x: &[f64], p: &[f64], e: Option<&Evaluation>) -> f64 {
        let phi = match e {
            Some(e) if !e.failed => e.merit(self.params.penalty).min(FAILURE_COST),
            _ => FAILURE_COST,
        };
        phi + self.params.projection_weight * dist2(x, p)
    }

    fn project(&self, x: &[f64]) -> Vec<f64> {
        // The set was checked non-empty; a projection failure falls back to the box clip.
        self.set
            .project(x)
            .unwrap_or_else(|_| self.set.clip_to_box(x))
    }

    /// Costs of several points, evaluating the new projected points in one batch.
    fn costs(&self, xs: &[&Vec<f64>]) -> Vec<f64> {
        let m = self.bb.n_constraints();
        let projected: Vec<Vec<f64>> = xs.iter().map(|x| self.project(x)).collect();
        let mut log = self.lock();
        let mut todo: Vec<Vec<f64>> = Vec::new();
        for p in &projected {
            let k = key(p);
            let known = log.cache.contains_key(&k) || todo.iter().any(|t| key(t) == k);
            if !known && log.history.len() + todo.len() < self.params.budget {
                todo.push(p.clone());
            }
        }
        if !todo.is_empty() {
            drop(log);
            let mut evals = self.bb.evaluate_batch(&todo);
            evals.resize(todo.len(), Evaluation::failure(m));
            log = self.lock();
            for (p, e) in todo.into_iter().zip(evals) {
                let idx = log.history.len();
                log.cache.insert(key(&p), idx);
                log.history.push((p, e.sanitized(m)));
            }
        }
        let mut out = Vec::with_capacity(xs.len());
        for (x, p) in xs.iter().zip(&projected) {
            let e = log.cache.get(&key(p)).map(|&i| log.history[i].1.clone());
            if e.is_none() {
                log.budget_hit = true;
            }
            let v = self.value(x, p, e.as_ref());
            log.calls.push(((*x).clone(), v));
            out.push(v);
        }
        out
    }
}

impl<B: BlackBox + ?Sized> CostFunction for PenalizedProblem<'_, B> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, Error> {
        Ok(self.costs(&[x])[0])
    }

    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<f64>, Error>
    where
        P: Borrow<Vec<f64>> + SyncAlias,
        Self::Output: SendAlias,
        Self: SyncAlias,
    {
        let xs: Vec<&Vec<f64>> = params.iter().map(|p| p.borrow()).collect();
        Ok(self.costs(&xs))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Sphere;
    impl BlackBox for Sphere {
        fn dim(&self) -> usize {
            2
        }
        fn n_constraints(&self) -> usize {
            1
        }
        fn evaluate(&self, x: &[f64]) -> Evaluation {
            if x[0] > 0.9 {
                return Evaluation::failure(1);
            }
            Evaluation::new(x[0] * x[0] + x[1] * x[1], vec![x[1] - 0.5])
        }
    }

    #[test]
    fn projection_penalty_cache_and_budget() {
        let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let log = Mutex::new(PenaltyLog::default());
        let p = PenalizedProblem {
            bb: &Sphere,
            set: &set,
            params: PenaltyParams {
                penalty: 10.0,
                projection_weight: 100.0,
                budget: 3,
            },
            log: &log,
        };
        // Inside: f = 0.25 + 0.04.
        assert!((p.cost(&vec![0.5, 0.2]).unwrap() - 0.29).abs() < 1e-12);
        // Outside: projected to (0.5, 0) plus 100·0.1².
        assert!((p.cost(&vec![0.5, -0.1]).unwrap() - (0.25 + 1.0)).abs() < 1e-12);
        // Same projection: cached, no new evaluation.
        assert!((p.cost(&vec![0.5, -0.2]).unwrap() - (0.25 + 4.0)).abs() < 1e-12);
        assert_eq!(p.evaluations(), 2);
        // Black-box constraint violated by 0.25: merit 0.01 + 0.5625 + 10·0.25.
        assert!((p.cost(&vec![0.1, 0.75]).unwrap() - (0.01 + 0.5625 + 2.5)).abs() < 1e-12);
        // Budget (3) spent: no evaluation, failure cost.
        assert_eq!(p.cost(&vec![0.3, 0.3]).unwrap(), FAILURE_COST);
        assert!(log.lock().unwrap().budget_hit);
        assert_eq!(p.evaluations(), 3);
    }

    #[test]
    fn failure_is_finite_and_large() {
        let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let log = Mutex::new(PenaltyLog::default());
        let p = PenalizedProblem {
            bb: &Sphere,
            set: &set,
            params: PenaltyParams {
                penalty: 10.0,
                projection_weight: 1.0,
                budget: 10,
            },
            log: &log,
        };
        let c = p.bulk_cost(&[vec![0.95, 0.1], vec![0.1, 0.1]]).unwrap();
        assert_eq!(c[0], FAILURE_COST);
        assert!((c[1] - 0.02).abs() < 1e-12);
    }
}
