//! Efficient global optimisation (EGO) of an expensive, noisy, possibly failing black box inside
//! linear constraints, on the `egobox-ego` crate (0.42, `Egor`).
//!
//! Algorithm (Jones, Schonlau & Welch 1998, *J. Global Optim.* 13, 455–492): fit a Gaussian
//! process (kriging: constant trend, squared-exponential kernel, hyper-parameters by maximum
//! likelihood) to every successful evaluation, evaluate next the point that maximises the expected
//! improvement `EI(x) = E[max(f_min − Y(x), 0)]` over the best feasible value `f_min`, refit,
//! repeat. egobox maximises `log EI` (Ament et al. 2023: the same maximiser, without EI's flat
//! underflowing plateaus) by multistart SLSQP.
//!
//! Constraints, as this problem states them:
//! - **box** (the [`FeasibleSet`]'s bounds): egobox's design space;
//! - **linear rows** `a·x ≤ b`, known exactly: given to egobox as cheap *function constraints*
//!   (`EgorFactory::subject_to`, evaluated exactly, with their gradients, inside the infill
//!   optimisation), tightened by [`LINEAR_MARGIN`]; a suggested point still outside the set
//!   (egobox's last-resort random infill point) is replaced by its projection before it is
//!   evaluated, so no evaluation leaves the set;
//! - **black-box constraints** `c_j(x) ≤ 0` (e.g. chance constraints from the simulations): given
//!   to egobox as constraint outputs, each modelled by its own Gaussian process. The infill point
//!   maximises EI subject to the constraint models' means `ĉ_j(x) ≤ 0` (Sasena, Papalambros &
//!   Goovaerts 2002, egobox's `MeanConstraint`); when no point satisfies the models egobox falls
//!   back to EI × the probability of feasibility `Π_j P(C_j(x) ≤ 0)` (Schonlau, Welch & Jones
//!   1998; Schonlau 1997).
//!
//! Failures (`failed` evaluations) are given to egobox as NaN rows: it drops them from the
//! surrogates (its `Rejection` failsafe). Noise: egobox's Egor exposes no noise (nugget) term,
//! so its surrogates interpolate the noisy values; the noise is averaged only by the trust region
//! of `ego+trust_region`, which fits regression models ([`super::minimize_trust_region`]).
//!
//! Budget and stop: the initial design ([`design`]) is `initial_design` points, then one point
//! per EGO iteration, `max_evaluations − initial_design` iterations at most. The run ends
//! [`Stop::BudgetExhausted`] when they are spent, and [`Stop::Converged`] only when egobox's own
//! rule stops it first: in 3 successive tries it could not find an infill point at L1 distance
//! ≥ 1e-10 from every evaluated point (or, with a feasible point known, the infill optimisation
//! failed). egobox has no EI-tolerance stop; none is added here.
//!
//! Signal handling: `Egor::run` installs a process-wide Ctrl-C handler (the `ctrlc` crate) that
//! turns SIGINT into "stop after this iteration" for the rest of the process. drillopt restores
//! SIGINT's default action before every evaluation ([`keep_default_sigint`]), so Ctrl-C ends a
//! `solve` as it does with the other methods (the disk cache keeps the finished simulations
//! for `--resume`).

mod design;
mod hybrid;

pub use hybrid::{EgoTrustRegionOptions, minimize_ego_trust_region};

use std::sync::{Arc, Mutex};

use egobox_ego::{EgoError, EgorFactory, InfillObjData, TerminationReason};
use ndarray::{Array1, Array2, ArrayView2};

use super::evaluation::{BlackBox, Evaluation, best_index};
use super::feasible::FeasibleSet;
use super::nelder_mead::finish;
use super::observer::{Iterate, IterateCallback, SharedCallback};
use super::{OptimizeError, OptimizeResult, Stop};

/// Linear rows are given to egobox as `a·x − b + LINEAR_MARGIN·‖a‖ ≤ 0` (variable units), so that
/// an infill point that meets them to the infill optimiser's tolerance is inside the set.
pub const LINEAR_MARGIN: f64 = 1e-7;

/// ℓ1 penalty of the merit reported on the path of an infeasible best point (as the other
/// methods' default).
const PATH_PENALTY: f64 = 10.0;

/// Options of [`minimize_ego`]. Lengths are in (scaled) variable units.
#[derive(Clone, Debug, PartialEq)]
pub struct EgoOptions {
    /// Points of the initial Latin-hypercube design. Default 10 (5 per variable in 2-D; Jones et
    /// al. suggest 10n, cut for expensive simulations); at least 3 and below `max_evaluations`.
    pub initial_design: usize,
    /// Evaluation budget, initial design included. Default 40.
    pub max_evaluations: usize,
    /// Seed of the initial design and of egobox's generator (Xoshiro256+). Default 0.
    pub seed: u64,
    /// Black-box constraints `≤ constraint_tol` count as satisfied. Default 0.
    pub constraint_tol: f64,
}

impl Default for EgoOptions {
    fn default() -> Self {
        EgoOptions {
            initial_design: 10,
            max_evaluations: 40,
            seed: 0,
            constraint_tol: 0.0,
        }
    }
}

impl EgoOptions {
    /// Checks every option against its legal range.
    pub fn validate(&self) -> Result<(), OptimizeError> {
        if self.initial_design < 3 {
            return Err(OptimizeError::InvalidOption {
                name: "initial_design",
                value: self.initial_design as f64,
                reason: "must be ≥ 3",
            });
        }
        if self.initial_design >= self.max_evaluations {
            return Err(OptimizeError::InvalidOption {
                name: "max_evaluations",
                value: self.max_evaluations as f64,
                reason: "must exceed initial_design (EGO needs at least one infill point)",
            });
        }
        crate::optimize::error::check_constraint_tol(self.constraint_tol)
    }
}

/// Restores SIGINT's default action (see the module doc).
fn keep_default_sigint() {
    #[cfg(unix)]
    // SAFETY: `signal` with `SIG_DFL` installs no Rust code as a handler; it only resets the
    // disposition that egobox's `ctrlc` handler replaced.
    unsafe {
        libc::signal(libc::SIGINT, libc::SIG_DFL);
    }
}

/// What the objective closure records while egobox runs.
struct Log {
    history: Vec<(Vec<f64>, Evaluation)>,
    path: Vec<Iterate>,
}

/// The closure egobox evaluates: projects the rows into `set`, evaluates them (one batch), records
/// them and the path, and returns `[f, c_1 … c_m]` per row (NaN for a failure).
struct Objective<'a, B: BlackBox + ?Sized> {
    bb: &'a B,
    set: &'a FeasibleSet,
    budget: usize,
    tol: f64,
    log: &'a Mutex<Log>,
    callback: &'a SharedCallback,
}

impl<B: BlackBox + ?Sized> Clone for Objective<'_, B> {
    fn clone(&self) -> Self {
        Objective { ..*self }
    }
}

impl<B: BlackBox + ?Sized> Objective<'_, B> {
    fn eval(&self, x: &ArrayView2<f64>) -> Array2<f64> {
        keep_default_sigint();
        let m = self.bb.n_constraints();
        let mut y = Array2::from_elem((x.nrows(), 1 + m), f64::NAN);
        let spent = self.log.lock().map_or(self.budget, |l| l.history.len());
        let room = self.budget.saturating_sub(spent);
        let points: Vec<Vec<f64>> = x
            .rows()
            .into_iter()
            .take(room) // never past the budget (max_iters keeps egobox inside it)
            .map(|r| {
                let r = r.to_vec();
                self.set.project(&r).unwrap_or(r)
            })
            .collect();
        if points.is_empty() {
            return y;
        }
        let mut evals = self.bb.evaluate_batch(&points);
        evals.resize(points.len(), Evaluation::failure(m));
        let mut log = self.log.lock().unwrap_or_else(|p| p.into_inner());
        for (i, (p, e)) in points.into_iter().zip(evals).enumerate() {
            let e = e.sanitized(m);
            if !e.failed {
                y[[i, 0]] = e.objective;
                for (j, c) in e.constraints.iter().enumerate() {
                    y[[i, 1 + j]] = *c;
                }
            }
            log.history.push((p, e));
        }
        let best = best_index(&log.history, self.tol).expect("just recorded");
        let (bx, be) = &log.history[best];
        let it = Iterate {
            iteration: log.path.len(),
            x: bx.clone(),
            merit: be.merit(PATH_PENALTY),
            radius: None,
            evaluations: log.history.len(),
            step: Some(if log.path.is_empty() { "design" } else { "ego" }.into()),
        };
        log.path.push(it.clone());
        drop(log);
        if let Some(mut cb) = self.callback.boxed() {
            cb(&it);
        }
        y
    }
}

/// The linear row `a·x ≤ b` as an egobox function constraint (`≤ 0` feasible, with gradient).
fn linear_row(
    a: Vec<f64>,
    b: f64,
) -> impl Fn(&[f64], Option<&mut [f64]>, &mut InfillObjData<f64>) -> f64 + Clone + Sync {
    let margin = LINEAR_MARGIN * a.iter().map(|v| v * v).sum::<f64>().sqrt();
    move |x: &[f64], grad: Option<&mut [f64]>, _: &mut InfillObjData<f64>| {
        if let Some(g) = grad {
            g.copy_from_slice(&a);
        }
        a.iter().zip(x).map(|(ai, xi)| ai * xi).sum::<f64>() - b + margin
    }
}

/// Minimises `bb` over `set` by EGO (see the module doc). `callback` is called after the initial
/// design and after every EGO iteration with the best point so far. Errors for an invalid set-up
/// or when egobox itself fails (a message with the evaluations already made).
pub fn minimize_ego<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    opts: &EgoOptions,
    callback: Option<IterateCallback>,
) -> Result<OptimizeResult, OptimizeError> {
    OptimizeError::check_dim(bb.dim(), set.dim())?;
    opts.validate()?;
    let fallback = set.find_feasible_point()?;
    let doe = design::initial_design(set, opts.initial_design, opts.seed)?;
    let n = set.dim();
    let doe = Array2::from_shape_fn((doe.len(), n), |(i, j)| doe[i][j]);
    let xlimits = Array2::from_shape_fn((n, 2), |(j, k)| [set.lower()[j], set.upper()[j]][k]);
    let rows: Vec<_> = set
        .a()
        .iter()
        .zip(set.b())
        .map(|(a, b)| linear_row(a.clone(), *b))
        .collect();
    let log = Mutex::new(Log {
        history: Vec::new(),
        path: Vec::new(),
    });
    let shared = SharedCallback(Arc::new(Mutex::new(callback)));
    let objective = Objective {
        bb,
        set,
        budget: opts.max_evaluations,
        tol: opts.constraint_tol,
        log: &log,
        callback: &shared,
    };
    let f = move |x: &ArrayView2<f64>| objective.eval(x);
    let iterations = opts.max_evaluations - opts.initial_design;
    let m = bb.n_constraints();
    let run = EgorFactory::optimize(f)
        .subject_to(rows)
        .configure(|c| {
            c.n_cstr(m)
                .doe(&doe)
                .max_iters(iterations)
                .seed(opts.seed)
                .cstr_tol(Array1::from_elem(m + set.a().len(), opts.constraint_tol))
        })
        .min_within(&xlimits)
        .and_then(|egor| egor.run());
    let log = log.into_inner().unwrap_or_else(|p| p.into_inner());
    let (termination, stop) = match run {
        Ok(res) => match res.state.get_termination_reason() {
            Some(TerminationReason::MaxItersReached) => (
                format!(
                    "EGO: evaluation budget exhausted ({} initial design + {iterations} iterations)",
                    opts.initial_design
                ),
                Stop::BudgetExhausted,
            ),
            Some(TerminationReason::SolverConverged) => (
                "EGO converged: egobox found no new infill point distinct from the evaluated ones"
                    .to_string(),
                Stop::Converged,
            ),
            other => (
                format!(
                    "egobox stopped: {}",
                    other.map_or("without a reason".to_string(), |r| r.to_string())
                ),
                Stop::IterationLimit,
            ),
        },
        Err(EgoError::ObjectiveFunctionError(_)) if log.history.iter().all(|(_, e)| e.failed) => (
            "every evaluation of the initial design failed".to_string(),
            Stop::AllFailed,
        ),
        Err(e) => {
            return Err(OptimizeError::Solver(format!(
                "egobox failed after {} evaluations: {e}",
                log.history.len()
            )));
        }
    };
    finish(
        log.history,
        log.path,
        termination,
        stop,
        m,
        opts.constraint_tol,
        &fallback,
    )
}
