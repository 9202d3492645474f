//! Derivative-free model-based trust-region method for an expensive, noisy, failing black box
//! inside linear constraints, in the family of Powell's BOBYQA/COBYQA (see also Conn, Scheinberg
//! & Vicente, *Introduction to Derivative-Free Optimization*, 2009, ch. 10–11), written as an
//! argmin [`Solver`].
//!
//! Problem: minimise `f(x)` subject to `c_j(x) ≤ 0` (black box) and `x ∈ X` (box + `A x ≤ b`,
//! the [`FeasibleSet`]). Every evaluated point lies in `X`.
//!
//! One iteration, about the centre `x_c` (best merit so far) with radius `Δ`:
//! 1. **Geometry.** Among the successful evaluations with `‖y − x_c‖∞ ≤ 2Δ` (at most
//!    `(n+1)(n+2)`, nearest first), if fewer than `n+1`, or `σ_min` of the displacements
//!    `(y − x_c)/Δ` is below [`TrustRegionOptions::poisedness_threshold`], a **geometry step**
//!    evaluates the candidate `x_c + Δ u` (u among the singular vectors and the axes, projected
//!    onto `X`) that most increases `σ_min`, and the iteration ends.
//! 2. **Models.** Distance-weighted quadratic regression models of `f` and of every `c_j` (see
//!    `model.rs`) on the successful points within `4Δ` (at most `(n+1)(n+2)`, nearest first):
//!    the minimum-Frobenius-norm Hessian on the `2n+1` initial design, a least-squares full
//!    quadratic once there are enough points; extra points average noise.
//! 3. **Sub-problem (Sℓ1QP, Fletcher).** With ∞-norm trust region (so it stays a QP) and elastic
//!    slacks `t ≥ 0` on the linearised black-box constraints:
//!    `min gᵀd + ½dᵀWd + μ Σ t_j  s.t.  c_j + ∇c_jᵀd ≤ t_j,  A(x_c + d) ≤ b,  ‖d‖∞ ≤ Δ,
//!    lo ≤ x_c + d ≤ hi`, where `W = ∇²m_f + Σ λ_j ∇²m_cj` (multipliers of the previous
//!    sub-problem), convexified by eigenvalue clipping in `qp.rs`. The elastic form is always
//!    feasible (`d = 0`, `t = max(0, c)`), so an infeasible linearisation needs no special case.
//!    **Steering:** if the step leaves slack that the trust region could remove (checked by the
//!    LP `min Σt` over the same constraints), `μ ← 10μ` (up to `max_penalty`) and re-solve.
//! 4. **Acceptance by the exact ℓ1 merit** `φ(x) = f + μ Σ max(0, c_j)`, ratio
//!    `ρ = (φ(x_c) − φ(x_t)) / (q(0) − q(d))` with `q` the sub-problem objective. Accept if
//!    `ρ ≥ 0.1`, or if merely `φ(x_t) < φ(x_c)`. Radius (as NEWUOA): `ρ < 0.1` halves `Δ`;
//!    `0.1 ≤ ρ < 0.7` gives `max(Δ/2, ‖d‖∞)`; `ρ ≥ 0.7` gives `min(max(Δ, 2‖d‖∞), max_radius)`.
//!    Geometry points that happen to improve the merit also become the centre.
//! 5. **Failures** (`failed = true`) are a hidden constraint: a failed trial is rejected with
//!    `Δ ← ½ min(Δ, ‖d‖∞)` and never enters a model. Each failed point `f` within `4Δ` of the
//!    centre adds the **cut** `(f − x_c)ᵀd ≤ ¼‖f − x_c‖²` to the sub-problem (move at most a
//!    quarter of the way towards a failure; ½ would be the Voronoi bisector, ¼ is more cautious
//!    about the unknown extent of the failing region), and geometry candidates must satisfy the
//!    same cuts, so the iterates slide along a failing region instead of stalling at its edge.
//! 6. **Short steps.** A step with negligible predicted reduction, or shorter than
//!    `min_radius/2`, is not evaluated: `Δ` is halved (Powell's radius reduction without
//!    evaluation). Other steps shorter than `Δ/10` are evaluated and then
//!    `Δ ← max(Δ/4, 2‖d‖∞)`: the model is nearly stationary at this scale, so the next model is
//!    built closer to the step's scale. (Cutting `Δ` faster saves a few geometry evaluations on
//!    smooth problems but lets noise stop the method early.)
//!
//! Stops when `Δ < min_radius` (converged), the evaluation budget is spent, or the iteration cap
//! is reached. Duplicate points are not re-evaluated. The initial `2n+1` design
//! (`x0, x0 ± Δ0 e_i`, projected onto `X`) is evaluated with one [`BlackBox::evaluate_batch`].
//!
//! Files: this one holds the options, the solver's state and its argmin `Solver` impl;
//! `iteration.rs` one model-based iteration (steps 1–6) as named steps; `geometry.rs` the sample
//! sets, poisedness, geometry points and failure cuts; `subproblem.rs` the Sℓ1QP;
//! `problem.rs` the argmin problem around the black box.

mod geometry;
mod iteration;
mod problem;
mod subproblem;

use crate::optimize::Stop;
use std::sync::{Arc, Mutex};

use argmin::core::{
    CostFunction, Error, Executor, IterState, KV, KvValue, Problem, Solver, State,
    TerminationReason, TerminationStatus,
};

use super::evaluation::{BlackBox, Evaluation};
use super::feasible::FeasibleSet;
use super::observer::{IterateCallback, PathLog, PathObserver, take_path};
use super::{OptimizeError, OptimizeResult, error::from_argmin};
pub use problem::BlackBoxProblem;

/// argmin state used by the trust-region solver: parameter = centre, cost = merit at the centre.
pub type TrustRegionState = IterState<Vec<f64>, (), (), (), (), f64>;

/// Options of [`minimize_trust_region`]. Lengths are in (scaled) variable units.
#[derive(Clone, Debug, PartialEq)]
pub struct TrustRegionOptions {
    /// Initial radius `Δ0` and step of the `2n+1` design. Default 0.1; range (0, ∞).
    pub initial_radius: f64,
    /// Stop when `Δ < min_radius`. Default 1e-3 (set it above the noise-dominated scale).
    pub min_radius: f64,
    /// Largest radius. Default 0.5.
    pub max_radius: f64,
    /// Evaluation budget (initial design included). Default 60; at least 1.
    pub max_evaluations: usize,
    /// argmin iteration cap (geometry and radius-only iterations count). Default 500.
    pub max_iterations: u64,
    /// Initial ℓ1 penalty `μ` on black-box constraint violation (objective units per constraint
    /// unit). Default 10; should exceed the constraint multipliers, and is raised by steering.
    pub penalty: f64,
    /// Largest penalty reached by steering. Default 1e6.
    pub max_penalty: f64,
    /// Minimum `σ_min` of the scaled displacement matrix before a step is taken. Default 0.2;
    /// range (0, 1].
    pub poisedness_threshold: f64,
}

impl Default for TrustRegionOptions {
    fn default() -> Self {
        TrustRegionOptions {
            initial_radius: 0.1,
            min_radius: 1e-3,
            max_radius: 0.5,
            max_evaluations: 60,
            max_iterations: 500,
            penalty: 10.0,
            max_penalty: 1e6,
            poisedness_threshold: 0.2,
        }
    }
}

impl TrustRegionOptions {
    /// Checks every option against its legal range.
    pub fn validate(&self) -> Result<(), OptimizeError> {
        let positive = |name, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(OptimizeError::InvalidOption {
                    name,
                    value,
                    reason: "must be finite and > 0",
                })
            }
        };
        positive("initial_radius", self.initial_radius)?;
        positive("min_radius", self.min_radius)?;
        positive("max_radius", self.max_radius)?;
        positive("penalty", self.penalty)?;
        positive("max_penalty", self.max_penalty)?;
        positive("poisedness_threshold", self.poisedness_threshold)?;
        if self.min_radius > self.initial_radius || self.initial_radius > self.max_radius {
            return Err(OptimizeError::InvalidOption {
                name: "initial_radius",
                value: self.initial_radius,
                reason: "need min_radius ≤ initial_radius ≤ max_radius",
            });
        }
        crate::optimize::error::check_budget(self.max_evaluations)
    }
}

/// The trust-region solver (see the module doc). Run it through argmin's [`Executor`], or use
/// [`minimize_trust_region`].
#[derive(Clone, Debug)]
pub struct TrustRegion {
    opts: TrustRegionOptions,
    set: FeasibleSet,
    x0: Vec<f64>,
    m: usize,
    history: Vec<(Vec<f64>, Evaluation)>,
    centre: Option<usize>,
    radius: f64,
    penalty: f64,
    multipliers: Vec<f64>,
    evals: usize,
    stop: Option<String>,
    last_step: &'static str,
}

fn dist_inf(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |acc, (x, y)| acc.max((x - y).abs()))
}

fn norm_inf(a: &[f64]) -> f64 {
    a.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()))
}

/// Successful points within `SAMPLE_RADIUS·Δ` (∞-norm) of the centre may enter the models.
const SAMPLE_RADIUS: f64 = 4.0;
/// Poisedness is required of the points within `POISED_RADIUS·Δ`.
const POISED_RADIUS: f64 = 2.0;
/// A failed point `f` allows steps of at most `CUT_FRACTION·‖f − x_c‖` towards it.
const CUT_FRACTION: f64 = 0.25;

const BUDGET_SPENT: &str = "evaluation budget exhausted";
const ALL_FAILED: &str = "every evaluation failed";
const CONVERGED: &str = "trust-region radius below min_radius (converged)";

impl TrustRegion {
    /// A solver for `m` black-box constraints starting at `x0` (projected onto `set` if
    /// outside).
    pub fn new(
        set: FeasibleSet,
        x0: &[f64],
        m: usize,
        opts: TrustRegionOptions,
    ) -> Result<Self, OptimizeError> {
        opts.validate()?;
        if x0.len() != set.dim() {
            return Err(OptimizeError::dimension(
                "start point x0",
                set.dim(),
                x0.len(),
            ));
        }
        OptimizeError::check_finite("start point x0", x0)?;
        set.find_feasible_point()?;
        let x0 = set.project(x0)?;
        Ok(TrustRegion {
            radius: opts.initial_radius,
            penalty: opts.penalty,
            opts,
            set,
            x0,
            m,
            history: Vec::new(),
            centre: None,
            multipliers: vec![0.0; m],
            evals: 0,
            stop: None,
            last_step: "init",
        })
    }

    /// Starts from earlier evaluations of the same black box (e.g. a global search's): they
    /// enter the models and the choice of the centre as if evaluated here, are never evaluated
    /// again, and do not count against `max_evaluations`.
    pub fn with_history(mut self, prior: Vec<(Vec<f64>, Evaluation)>) -> Self {
        let m = self.m;
        self.history = prior
            .into_iter()
            .map(|(x, e)| (x, e.sanitized(m)))
            .collect();
        self
    }

    /// Every evaluation so far, in order (after the earlier ones of [`TrustRegion::with_history`]).
    pub fn history(&self) -> &[(Vec<f64>, Evaluation)] {
        &self.history
    }

    /// Number of black-box evaluations so far.
    pub fn evaluations(&self) -> usize {
        self.evals
    }

    /// Current trust-region radius.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Current ℓ1 penalty `μ`.
    pub fn penalty(&self) -> f64 {
        self.penalty
    }

    /// The centre and its evaluation (`None` while every evaluation has failed).
    pub fn centre(&self) -> Option<(&[f64], &Evaluation)> {
        self.centre
            .map(|c| (self.history[c].0.as_slice(), &self.history[c].1))
    }

    fn n(&self) -> usize {
        self.set.dim()
    }

    fn merit(&self, i: usize) -> f64 {
        self.history[i].1.merit(self.penalty)
    }

    /// Evaluates a batch (truncated to the budget) and records it.
    fn evaluate_many<O>(&mut self, problem: &mut Problem<O>, xs: Vec<Vec<f64>>) -> Result<(), Error>
    where
        O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
    {
        let room = self.opts.max_evaluations.saturating_sub(self.evals);
        let xs: Vec<Vec<f64>> = xs.into_iter().take(room).collect();
        if xs.is_empty() {
            self.stop = Some(BUDGET_SPENT.into());
            return Ok(());
        }
        let evals = problem.bulk_cost(&xs)?;
        self.evals += xs.len();
        for (x, e) in xs.into_iter().zip(evals) {
            let e = e.sanitized(self.m);
            self.history.push((x, e));
        }
        Ok(())
    }

    /// Evaluates one point (or reuses a duplicate); `None` when the budget is spent.
    fn evaluate_one<O>(
        &mut self,
        problem: &mut Problem<O>,
        x: Vec<f64>,
    ) -> Result<Option<usize>, Error>
    where
        O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
    {
        if let Some(i) = self.duplicate(&x) {
            return Ok(Some(i));
        }
        if self.evals >= self.opts.max_evaluations {
            self.stop = Some(BUDGET_SPENT.into());
            return Ok(None);
        }
        let e = problem.cost(&x)?.sanitized(self.m);
        self.evals += 1;
        self.history.push((x, e));
        Ok(Some(self.history.len() - 1))
    }

    /// The best successful evaluation by merit.
    fn best_by_merit(&self) -> Option<usize> {
        (0..self.history.len())
            .filter(|&i| !self.history[i].1.failed)
            .min_by(|&a, &b| self.merit(a).total_cmp(&self.merit(b)))
    }

    /// Re-samples a smaller design about `x0` while every evaluation has failed.
    fn recover<O>(&mut self, problem: &mut Problem<O>) -> Result<(), Error>
    where
        O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
    {
        self.radius *= 0.5;
        if self.radius < self.opts.min_radius {
            self.stop = Some(ALL_FAILED.into());
            return Ok(());
        }
        let x0 = self.x0.clone();
        let pts: Vec<Vec<f64>> = self
            .design(&x0, self.radius)
            .into_iter()
            .filter(|p| self.duplicate(p).is_none())
            .collect();
        self.last_step = "recovery design";
        self.evaluate_many(problem, pts)?;
        self.centre = self.best_by_merit();
        Ok(())
    }

    fn kv(&self, rho: f64) -> KV {
        let mut kv = KV::new();
        kv.insert("evals", KvValue::Uint(self.evals as u64));
        kv.insert("radius", KvValue::Float(self.radius));
        kv.insert("penalty", KvValue::Float(self.penalty));
        kv.insert("rho", KvValue::Float(rho));
        kv.insert("step", KvValue::Str(self.last_step.to_string()));
        kv
    }

    fn with_centre(&self, state: TrustRegionState) -> TrustRegionState {
        match self.centre {
            Some(c) => state.param(self.history[c].0.clone()).cost(self.merit(c)),
            None => state.param(self.x0.clone()).cost(f64::INFINITY),
        }
    }
}

impl<O> Solver<O, TrustRegionState> for TrustRegion
where
    O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
{
    fn name(&self) -> &str {
        "derivative-free trust region (Sl1QP, quadratic regression models)"
    }

    fn init(
        &mut self,
        problem: &mut Problem<O>,
        state: TrustRegionState,
    ) -> Result<(TrustRegionState, Option<KV>), Error> {
        let x0 = self.x0.clone();
        let design: Vec<Vec<f64>> = self
            .design(&x0, self.radius)
            .into_iter()
            .filter(|p| self.duplicate(p).is_none())
            .collect();
        if !design.is_empty() {
            self.evaluate_many(problem, design)?;
        }
        self.centre = self.best_by_merit();
        self.stop = None;
        Ok((self.with_centre(state), Some(self.kv(f64::NAN))))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<O>,
        state: TrustRegionState,
    ) -> Result<(TrustRegionState, Option<KV>), Error> {
        let rho = match self.centre {
            None => {
                self.recover(problem)?;
                f64::NAN
            }
            Some(c) => self.model_iteration(problem, c)?,
        };
        Ok((self.with_centre(state), Some(self.kv(rho))))
    }

    fn terminate(&mut self, _state: &TrustRegionState) -> TerminationStatus {
        if let Some(reason) = &self.stop {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(reason.clone()));
        }
        if self.evals >= self.opts.max_evaluations {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                BUDGET_SPENT.into(),
            ));
        }
        if self.radius < self.opts.min_radius {
            let reason = if self.centre.is_some() {
                CONVERGED
            } else {
                ALL_FAILED
            };
            return TerminationStatus::Terminated(TerminationReason::SolverExit(reason.into()));
        }
        TerminationStatus::NotTerminated
    }
}

/// Minimises `bb` over `set` from `x0` with the trust-region method. `callback` is called with
/// every iterate (e.g. to drive a progress bar). Errors only for an invalid set-up (dimensions,
/// options, empty feasible set) or a sub-solver breakdown; failed evaluations are handled.
pub fn minimize_trust_region<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    x0: &[f64],
    opts: &TrustRegionOptions,
    callback: Option<IterateCallback>,
) -> Result<OptimizeResult, OptimizeError> {
    minimize_trust_region_after(bb, set, x0, opts, Vec::new(), callback)
}

/// [`minimize_trust_region`] after earlier evaluations `prior` of the same black box (see
/// [`TrustRegion::with_history`]); the result's `history` and `evaluations` are this run's only.
pub fn minimize_trust_region_after<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    x0: &[f64],
    opts: &TrustRegionOptions,
    prior: Vec<(Vec<f64>, Evaluation)>,
    callback: Option<IterateCallback>,
) -> Result<OptimizeResult, OptimizeError> {
    OptimizeError::check_dim(bb.dim(), set.dim())?;
    let n_prior = prior.len();
    let solver =
        TrustRegion::new(set.clone(), x0, bb.n_constraints(), opts.clone())?.with_history(prior);
    let log: PathLog = Arc::new(Mutex::new(Vec::new()));
    let observer = PathObserver::new(Arc::clone(&log), callback);
    let res = Executor::new(BlackBoxProblem::new(bb), solver)
        .configure(|s| s.max_iters(opts.max_iterations))
        .add_observer(observer, argmin::core::observers::ObserverMode::Always)
        .run()
        .map_err(from_argmin)?;
    let termination = res
        .state()
        .get_termination_reason()
        .map(|r| r.text().to_string())
        .unwrap_or_else(|| "unknown".into());
    let solver = res.solver();
    let stop = match termination.as_str() {
        BUDGET_SPENT => Stop::BudgetExhausted,
        ALL_FAILED => Stop::AllFailed,
        CONVERGED => Stop::Converged,
        _ => Stop::IterationLimit,
    };
    let (x, evaluation) = match solver.centre() {
        Some((x, e)) => (x.to_vec(), e.clone()),
        None => (solver.x0.clone(), Evaluation::failure(solver.m)),
    };
    Ok(OptimizeResult {
        x,
        evaluation,
        evaluations: solver.evaluations(),
        history: solver.history()[n_prior..].to_vec(),
        path: take_path(&log),
        termination,
        stop,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_validated() {
        assert!(TrustRegionOptions::default().validate().is_ok());
        let bad = TrustRegionOptions {
            min_radius: 1.0,
            ..Default::default()
        };
        assert!(matches!(
            bad.validate(),
            Err(OptimizeError::InvalidOption {
                name: "initial_radius",
                ..
            })
        ));
        let bad = TrustRegionOptions {
            penalty: f64::NAN,
            ..Default::default()
        };
        assert!(bad.validate().is_err());
    }

    /// A start outside the linear constraints is projected; a start of the wrong length is an
    /// error.
    #[test]
    fn start_point_is_projected() {
        let set = FeasibleSet::new(
            vec![0.0, 0.0],
            vec![1.0, 1.0],
            vec![vec![1.0, 1.0]],
            vec![1.0],
        )
        .unwrap();
        let tr =
            TrustRegion::new(set.clone(), &[1.0, 1.0], 0, TrustRegionOptions::default()).unwrap();
        assert!((tr.x0[0] - 0.5).abs() < 1e-7 && (tr.x0[1] - 0.5).abs() < 1e-7);
        assert!(matches!(
            TrustRegion::new(set, &[1.0], 0, TrustRegionOptions::default()),
            Err(OptimizeError::Dimension { .. })
        ));
    }
}
