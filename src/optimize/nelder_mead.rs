//! argmin's Nelder–Mead on the projected penalty `F(x)` of `penalized.rs`, made fit for a small
//! budget: a simplex-size stopping test, restarts and an iteration cap.
//!
//! argmin's `NelderMead` stops when the standard deviation of the simplex's costs is below
//! `sd_tolerance`, which can happen on a large simplex straddling a level set (it was seen to stop
//! after 3 iterations far from the minimum of a plain quadratic). That test is disabled here
//! (`sd_tolerance = 0`): a run stops when the simplex's ∞-norm diameter `max_k ‖v_k − v_0‖∞` is
//! below `xtol`. The simplex is private to argmin, so [`SizedNelderMead`] mirrors it from the
//! points the solver evaluates and the action it reports (reflection, expansion, contractions,
//! shrink), which determine the new simplex exactly.
//!
//! After a converged run the method restarts from the best point with a fresh simplex of edge
//! `initial_step`; it stops when a restart improves the best cost by less than `ftol·(1 + |F|)`,
//! after `max_restarts`, or when the evaluation budget is spent. The result is the best
//! evaluation of the history in the feasibility-first order.

use crate::optimize::Stop;
use std::sync::{Arc, Mutex};

use argmin::core::{
    Error, Executor, IterState, KV, KvValue, Problem, Solver, State, TerminationReason,
    TerminationStatus, observers::ObserverMode,
};
use argmin::solver::neldermead::NelderMead;

use super::evaluation::{BlackBox, Evaluation, best_index};
use super::feasible::FeasibleSet;
use super::observer::{IterateCallback, PathLog, PathObserver, SharedCallback, take_path};
use super::penalized::{PenalizedProblem, PenaltyLog, PenaltyParams};
use super::{OptimizeError, OptimizeResult, error::from_argmin};

/// argmin state of the Nelder–Mead runs.
pub(crate) type NelderMeadState = IterState<Vec<f64>, (), (), (), (), f64>;

/// Options of [`minimize_nelder_mead`]. Lengths in (scaled) variable units.
#[derive(Clone, Debug, PartialEq)]
pub struct NelderMeadOptions {
    /// Edge of the initial (and every restart) simplex `x0 + step·e_i`. Default 0.1.
    pub initial_step: f64,
    /// A run stops when the simplex diameter (∞-norm) is below this. Default 1e-4.
    pub xtol: f64,
    /// A restart that improves the best cost by less than `ftol·(1 + |F|)` ends the method.
    /// Default 1e-8.
    pub ftol: f64,
    /// Number of restarts after the first run. Default 3.
    pub max_restarts: usize,
    /// Iteration cap of each run. Default 200.
    pub max_iterations: u64,
    /// Evaluation budget over all runs. Default 200.
    pub max_evaluations: usize,
    /// `μ`, ℓ1 penalty on black-box constraint violation. Default 10.
    pub penalty: f64,
    /// `ρ`, weight of the squared distance to the feasible set. Default 100.
    pub projection_weight: f64,
    /// Black-box constraints `≤ constraint_tol` count as satisfied when picking the result.
    /// Default 0.
    pub constraint_tol: f64,
}

impl Default for NelderMeadOptions {
    fn default() -> Self {
        NelderMeadOptions {
            initial_step: 0.1,
            xtol: 1e-4,
            ftol: 1e-8,
            max_restarts: 3,
            max_iterations: 200,
            max_evaluations: 200,
            penalty: 10.0,
            projection_weight: 100.0,
            constraint_tol: 0.0,
        }
    }
}

impl NelderMeadOptions {
    /// Checks every option against its legal range.
    pub fn validate(&self) -> Result<(), OptimizeError> {
        for (name, value) in [
            ("initial_step", self.initial_step),
            ("xtol", self.xtol),
            ("penalty", self.penalty),
            ("projection_weight", self.projection_weight),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(OptimizeError::InvalidOption {
                    name,
                    value,
                    reason: "must be finite and > 0",
                });
            }
        }
        for (name, value) in [("ftol", self.ftol), ("constraint_tol", self.constraint_tol)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(OptimizeError::InvalidOption {
                    name,
                    value,
                    reason: "must be finite and ≥ 0",
                });
            }
        }
        super::error::check_budget(self.max_evaluations)
    }
}

/// argmin's `NelderMead` plus a mirrored simplex for a size-based stopping test.
pub(crate) struct SizedNelderMead {
    inner: NelderMead<Vec<f64>, f64>,
    simplex: Vec<(Vec<f64>, f64)>,
    xtol: f64,
    budget: usize,
    spent: bool,
}

impl SizedNelderMead {
    fn new(vertices: Vec<Vec<f64>>, xtol: f64, budget: usize) -> Result<Self, OptimizeError> {
        let inner = NelderMead::new(vertices)
            .with_sd_tolerance(0.0)
            .map_err(from_argmin)?;
        Ok(SizedNelderMead {
            inner,
            simplex: Vec::new(),
            xtol,
            budget,
            spent: false,
        })
    }

    /// ∞-norm diameter of the simplex about its best vertex.
    pub(crate) fn size(&self) -> f64 {
        let Some((best, _)) = self.simplex.first() else {
            return f64::INFINITY;
        };
        self.simplex
            .iter()
            .flat_map(|(v, _)| v.iter().zip(best).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max)
    }

    fn sort(&mut self) {
        // Same stable order as argmin's `sort_param_vecs`.
        self.simplex
            .sort_by(|a, b| a.1.partial_cmp(&b.1).unwrap_or(std::cmp::Ordering::Equal));
    }

    /// Updates the mirror from the calls made during one argmin iteration.
    fn mirror(&mut self, action: &str, calls: &[(Vec<f64>, f64)]) {
        let last = self.simplex.len() - 1;
        match (action, calls.len()) {
            ("Reflection", 1..) => self.simplex[last] = calls[0].clone(),
            ("Expansion", 2..) => {
                self.simplex[last] = if calls[1].1 < calls[0].1 {
                    calls[1].clone()
                } else {
                    calls[0].clone()
                }
            }
            ("ContractionOutside" | "ContractionInside", 2..) => {
                self.simplex[last] = calls[1].clone()
            }
            ("Shrink", k) if k == last + 2 => {
                for (v, c) in self.simplex.iter_mut().skip(1).zip(&calls[2..]) {
                    *v = c.clone();
                }
            }
            _ => {}
        }
        self.sort();
    }
}

type NmProblem<'a, B> = PenalizedProblem<'a, B>;

fn calls_len<B: BlackBox + ?Sized>(problem: &Problem<NmProblem<'_, B>>) -> usize {
    problem
        .problem
        .as_ref()
        .map(|p| p.log.lock().map(|l| l.calls.len()).unwrap_or(0))
        .unwrap_or(0)
}

fn calls_since<B: BlackBox + ?Sized>(
    problem: &Problem<NmProblem<'_, B>>,
    from: usize,
) -> (Vec<(Vec<f64>, f64)>, usize, bool) {
    problem
        .problem
        .as_ref()
        .map(|p| {
            let l = p.log.lock().unwrap_or_else(|e| e.into_inner());
            (
                l.calls[from.min(l.calls.len())..].to_vec(),
                l.history.len(),
                l.budget_hit,
            )
        })
        .unwrap_or_default()
}

fn kv_evals(kv: Option<KV>, evals: usize) -> KV {
    let mut kv = kv.unwrap_or_default();
    kv.insert("evals", KvValue::Uint(evals as u64));
    kv
}

impl<B: BlackBox + ?Sized> Solver<NmProblem<'_, B>, NelderMeadState> for SizedNelderMead {
    fn name(&self) -> &str {
        "Nelder-Mead (argmin) with simplex-size test"
    }

    fn init(
        &mut self,
        problem: &mut Problem<NmProblem<'_, B>>,
        state: NelderMeadState,
    ) -> Result<(NelderMeadState, Option<KV>), Error> {
        let from = calls_len(problem);
        let (state, kv) = self.inner.init(problem, state)?;
        let (calls, evals, hit) = calls_since(problem, from);
        self.spent = hit || evals >= self.budget;
        self.simplex = calls;
        self.sort();
        Ok((state, Some(kv_evals(kv, evals))))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<NmProblem<'_, B>>,
        state: NelderMeadState,
    ) -> Result<(NelderMeadState, Option<KV>), Error> {
        let from = calls_len(problem);
        let (state, kv) = self.inner.next_iter(problem, state)?;
        let action = kv
            .as_ref()
            .and_then(|k| k.get("action"))
            .and_then(|a| a.get_string())
            .unwrap_or_default();
        let (calls, evals, hit) = calls_since(problem, from);
        self.spent = hit || evals >= self.budget;
        self.mirror(&action, &calls);
        let mut kv = kv_evals(kv, evals);
        kv.insert("simplex_size", KvValue::Float(self.size()));
        Ok((state, Some(kv)))
    }

    fn terminate(&mut self, _state: &NelderMeadState) -> TerminationStatus {
        if self.spent {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "evaluation budget exhausted".into(),
            ));
        }
        if self.size() < self.xtol {
            return TerminationStatus::Terminated(TerminationReason::SolverConverged);
        }
        TerminationStatus::NotTerminated
    }
}

/// Simplex `x0, x0 + step·e_i` (the step flips sign where it would leave the box).
fn initial_simplex(set: &FeasibleSet, x0: &[f64], step: f64) -> Vec<Vec<f64>> {
    let mut out = vec![x0.to_vec()];
    for i in 0..x0.len() {
        let mut v = x0.to_vec();
        v[i] += if x0[i] + step <= set.upper()[i] {
            step
        } else {
            -step
        };
        out.push(v);
    }
    out
}

/// Minimises `bb` over `set` from `x0` with restarted Nelder–Mead on the projected penalty.
pub fn minimize_nelder_mead<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    x0: &[f64],
    opts: &NelderMeadOptions,
    callback: Option<IterateCallback>,
) -> Result<OptimizeResult, OptimizeError> {
    opts.validate()?;
    OptimizeError::check_dim(bb.dim(), set.dim())?;
    if x0.len() != set.dim() {
        return Err(OptimizeError::dimension(
            "start point vs feasible set",
            set.dim(),
            x0.len(),
        ));
    }
    OptimizeError::check_finite("start point x0", x0)?;
    set.find_feasible_point()?;
    let mut start = set.project(x0)?;
    let log = Mutex::new(PenaltyLog::default());
    let params = PenaltyParams {
        penalty: opts.penalty,
        projection_weight: opts.projection_weight,
        budget: opts.max_evaluations,
    };
    let path: PathLog = Arc::new(Mutex::new(Vec::new()));
    let shared = SharedCallback(Arc::new(Mutex::new(callback)));
    let mut best_prev = f64::INFINITY;
    let mut termination = String::from("no run");
    let mut stop = Stop::IterationLimit;
    for run in 0..=opts.max_restarts {
        let problem = PenalizedProblem {
            bb,
            set,
            params,
            log: &log,
        };
        let solver = SizedNelderMead::new(
            initial_simplex(set, &start, opts.initial_step),
            opts.xtol,
            opts.max_evaluations,
        )?;
        let observer = PathObserver::new(Arc::clone(&path), shared.boxed());
        let res = Executor::new(problem, solver)
            .configure(|s| s.max_iters(opts.max_iterations))
            .add_observer(observer, ObserverMode::Always)
            .run()
            .map_err(from_argmin)?;
        let state = res.state();
        let best_cost = state.get_best_cost();
        if let Some(p) = state.get_best_param() {
            start = set.project(p)?;
        }
        let reason = state.get_termination_reason();
        stop = match reason {
            Some(TerminationReason::SolverConverged) => Stop::Converged,
            _ => Stop::IterationLimit,
        };
        let reason = reason.map(|r| r.text().to_string()).unwrap_or_default();
        let spent = log.lock().map(|l| l.budget_hit).unwrap_or(true);
        termination = format!("run {run}: {reason}");
        if spent || log.lock().map(|l| l.history.len()).unwrap_or(0) >= opts.max_evaluations {
            termination = format!("run {run}: evaluation budget exhausted");
            stop = Stop::BudgetExhausted;
            break;
        }
        if run > 0 && best_prev - best_cost <= opts.ftol * (1.0 + best_cost.abs()) {
            termination = format!("run {run}: restart gave no improvement (converged)");
            stop = Stop::Converged;
            break;
        }
        best_prev = best_prev.min(best_cost);
    }
    let log = log.into_inner().unwrap_or_else(|e| e.into_inner());
    finish(
        log.history,
        take_path(&path),
        termination,
        stop,
        bb.n_constraints(),
        opts.constraint_tol,
        &start,
    )
}

/// Builds the result from a history: the best evaluation in the feasibility-first order.
pub(crate) fn finish(
    history: Vec<(Vec<f64>, Evaluation)>,
    path: Vec<super::Iterate>,
    termination: String,
    stop: Stop,
    m: usize,
    tol: f64,
    fallback: &[f64],
) -> Result<OptimizeResult, OptimizeError> {
    let (x, evaluation) = match best_index(&history, tol) {
        Some(i) => history[i].clone(),
        None => (fallback.to_vec(), Evaluation::failure(m)),
    };
    let stop = if history.iter().all(|(_, e)| e.failed) {
        Stop::AllFailed
    } else {
        stop
    };
    Ok(OptimizeResult {
        x,
        evaluation,
        evaluations: history.len(),
        history,
        path,
        termination,
        stop,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use argmin::core::CostFunction;

    struct Bowl;
    impl BlackBox for Bowl {
        fn dim(&self) -> usize {
            2
        }
        fn n_constraints(&self) -> usize {
            0
        }
        fn evaluate(&self, x: &[f64]) -> Evaluation {
            Evaluation::new(
                (x[0] - 0.3).powi(2) + 3.0 * (x[1] - 0.6).powi(2) + x[0] * x[1],
                vec![],
            )
        }
    }

    /// The mirrored simplex is argmin's: its best vertex is the state's best parameter and every
    /// vertex's cost is F(vertex); the run stops on the simplex size, not on the cost spread.
    #[test]
    fn mirrored_simplex_matches_argmin() {
        let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let log = Mutex::new(PenaltyLog::default());
        let params = PenaltyParams {
            penalty: 10.0,
            projection_weight: 100.0,
            budget: 1000,
        };
        let problem = PenalizedProblem {
            bb: &Bowl,
            set: &set,
            params,
            log: &log,
        };
        let solver =
            SizedNelderMead::new(initial_simplex(&set, &[0.9, 0.1], 0.2), 1e-6, 1000).unwrap();
        let res = Executor::new(problem, solver)
            .configure(|s| s.max_iters(500))
            .run()
            .unwrap();
        let solver = res.solver();
        let state = res.state();
        assert_eq!(
            state.get_termination_reason(),
            Some(&TerminationReason::SolverConverged)
        );
        assert!(solver.size() < 1e-6);
        assert_eq!(Some(&solver.simplex[0].0), state.get_best_param());
        let check = PenalizedProblem {
            bb: &Bowl,
            set: &set,
            params,
            log: &log,
        };
        for (v, c) in &solver.simplex {
            assert_eq!(check.cost(v).unwrap(), *c);
        }
        // Minimum of the bowl: gradient (2(x−0.3) + y, 6(y−0.6) + x) = 0.
        let det = 2.0 * 6.0 - 1.0;
        let x = (0.6 * 6.0 - 3.6) / det;
        let y = (2.0 * 3.6 - 0.6) / det;
        let best = state.get_best_param().unwrap();
        assert!(
            (best[0] - x).abs() < 1e-5 && (best[1] - y).abs() < 1e-5,
            "{best:?}"
        );
    }
}
