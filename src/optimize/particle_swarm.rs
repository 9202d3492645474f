//! argmin's particle swarm on the projected penalty `F(x)` of `penalized.rs` (linear
//! constraints by projection, black-box constraints by the ℓ1 penalty), seeded, with an
//! evaluation budget and a swarm-spread stopping test.
//!
//! The swarm is argmin's `ParticleSwarm` (SPSO 2011, Zambrano-Bigiarini et al. 2013):
//! `v ← w v + c₁ U∘(p_best − x) + c₂ U∘(g_best − x)`, `x ← clip(x + v)` to the box,
//! `w = 1/(2 ln 2)`, `c₁ = c₂ = ½ + ln 2`, initial positions uniform in the box and velocities
//! uniform in `±(upper − lower)`. Its bounds handling (clipping the position to the box, the
//! velocity kept) is all the box needs; the linear constraints are the penalty's projection.
//! argmin draws from a rand 0.9 `SmallRng` seeded with [`SwarmOptions::seed`] (its default
//! generator is seeded from the OS), so a run is reproducible.
//!
//! argmin evaluates each generation with one `bulk_cost` call, which [`PenalizedProblem`]
//! implements as one [`BlackBox::evaluate_batch`] (parallel if the black box is).
//! [`SeededSwarm`] wraps argmin's solver as [`super::nelder_mead`] wraps Nelder–Mead: it keeps
//! argmin's population between iterations, reports the swarm's best as the iterate (so the
//! path observer sees it), and stops when the budget is spent or every particle lies within
//! `xtol` (∞-norm) of the best.

use crate::optimize::Stop;
use std::sync::{Arc, Mutex};

use argmin::core::{
    Error, Executor, IterState, KV, KvValue, PopulationState, Problem, Solver, State,
    TerminationReason, TerminationStatus, observers::ObserverMode,
};
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use rand09::SeedableRng;
use rand09::rngs::SmallRng;

use super::evaluation::BlackBox;
use super::feasible::FeasibleSet;
use super::nelder_mead::finish;
use super::observer::{IterateCallback, PathLog, PathObserver, take_path};
use super::penalized::{PenalizedProblem, PenaltyLog, PenaltyParams};
use super::{OptimizeError, OptimizeResult, error::from_argmin};

/// argmin state seen by the executor: parameter = best position so far, cost = its `F`.
pub(crate) type SwarmState = IterState<Vec<f64>, (), (), (), (), f64>;

/// argmin's own state of the swarm (its particles), kept by [`SeededSwarm`].
type Population = PopulationState<Particle<Vec<f64>, f64>, f64>;

/// Options of [`minimize_particle_swarm`].
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmOptions {
    /// Particles per generation. Default 12; at least 2.
    pub particles: usize,
    /// Generations after the initial one. Default 20.
    pub max_iterations: u64,
    /// Evaluation budget. Default 250; at least 1.
    pub max_evaluations: usize,
    /// Seed of the rand 0.9 `SmallRng` driving argmin's swarm. Default 0.
    pub seed: u64,
    /// Stop when every particle is within this ∞-distance of the best. Default 1e-4.
    pub xtol: f64,
    /// `μ`, ℓ1 penalty on black-box constraint violation. Default 10.
    pub penalty: f64,
    /// `ρ`, weight of the squared distance to the feasible set. Default 100.
    pub projection_weight: f64,
    /// Black-box constraints `≤ constraint_tol` count as satisfied. Default 0.
    pub constraint_tol: f64,
}

impl Default for SwarmOptions {
    fn default() -> Self {
        SwarmOptions {
            particles: 12,
            max_iterations: 20,
            max_evaluations: 250,
            seed: 0,
            xtol: 1e-4,
            penalty: 10.0,
            projection_weight: 100.0,
            constraint_tol: 0.0,
        }
    }
}

impl SwarmOptions {
    /// Checks every option against its legal range.
    pub fn validate(&self) -> Result<(), OptimizeError> {
        if self.particles < 2 || self.max_evaluations == 0 {
            return Err(OptimizeError::InvalidOption {
                name: "particles / max_evaluations",
                value: self.particles.min(self.max_evaluations) as f64,
                reason: "need at least 2 particles and 1 evaluation",
            });
        }
        for (name, value) in [
            ("penalty", self.penalty),
            ("projection_weight", self.projection_weight),
            ("xtol", self.xtol),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(OptimizeError::InvalidOption {
                    name,
                    value,
                    reason: "must be finite and > 0",
                });
            }
        }
        super::error::check_constraint_tol(self.constraint_tol)
    }
}

/// argmin's `ParticleSwarm` with a seeded generator, an evaluation budget and a spread test.
pub(crate) struct SeededSwarm {
    inner: ParticleSwarm<Vec<f64>, f64, SmallRng>,
    /// argmin's population between iterations (`None` before `init`).
    population: Option<Population>,
    xtol: f64,
    budget: usize,
    spent: bool,
}

impl SeededSwarm {
    /// A swarm of `particles` over the box of `set`, drawing from `SmallRng::seed_from_u64(seed)`.
    pub(crate) fn new(
        set: &FeasibleSet,
        particles: usize,
        seed: u64,
        xtol: f64,
        budget: usize,
    ) -> Self {
        let bounds = (set.lower().to_vec(), set.upper().to_vec());
        SeededSwarm {
            inner: ParticleSwarm::new(bounds, particles)
                .with_rng_generator(SmallRng::seed_from_u64(seed)),
            population: None,
            xtol,
            budget,
            spent: false,
        }
    }

    /// The best particle and the swarm's cost (argmin keeps both in its population state).
    fn best(&self) -> Option<(&[f64], f64)> {
        let p = self.population.as_ref()?;
        let best = p.get_param()?;
        Some((best.position.as_slice(), p.get_cost()))
    }

    /// Largest ∞-distance of a particle from the best position (+∞ before `init`).
    pub(crate) fn spread(&self) -> f64 {
        let (Some((best, _)), Some(particles)) = (
            self.best(),
            self.population.as_ref().and_then(|p| p.get_population()),
        ) else {
            return f64::INFINITY;
        };
        particles
            .iter()
            .flat_map(|p| p.position.iter().zip(best).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max)
    }

    /// Keeps argmin's population after a generation and reports its best as the iterate.
    fn record<B: BlackBox + ?Sized>(
        &mut self,
        problem: &Problem<PenalizedProblem<'_, B>>,
        population: Population,
        state: SwarmState,
    ) -> Result<(SwarmState, Option<KV>), Error> {
        let mut evals = 0;
        if let Some(p) = problem.problem.as_ref() {
            evals = p.evaluations();
            let hit = p.log.lock().map_or(true, |l| l.budget_hit);
            self.spent = hit || evals >= self.budget;
        }
        self.population = Some(population);
        let (x, cost) = self
            .best()
            .map(|(x, c)| (x.to_vec(), c))
            .ok_or_else(|| Error::msg("particle swarm: argmin returned no best particle"))?;
        let mut kv = KV::new();
        kv.insert("evals", KvValue::Uint(evals as u64));
        kv.insert("spread", KvValue::Float(self.spread()));
        Ok((state.param(x).cost(cost), Some(kv)))
    }
}

impl<B: BlackBox + ?Sized> Solver<PenalizedProblem<'_, B>, SwarmState> for SeededSwarm {
    fn name(&self) -> &str {
        "particle swarm (argmin, seeded, with budget and spread test)"
    }

    fn init(
        &mut self,
        problem: &mut Problem<PenalizedProblem<'_, B>>,
        state: SwarmState,
    ) -> Result<(SwarmState, Option<KV>), Error> {
        let (population, _) = self.inner.init(problem, Population::new())?;
        self.record(problem, population, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<PenalizedProblem<'_, B>>,
        state: SwarmState,
    ) -> Result<(SwarmState, Option<KV>), Error> {
        let population = self
            .population
            .take()
            .ok_or_else(|| Error::msg("particle swarm: next_iter before init"))?;
        let (population, _) = self.inner.next_iter(problem, population)?;
        self.record(problem, population, state)
    }

    fn terminate(&mut self, _state: &SwarmState) -> TerminationStatus {
        if self.spent {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "evaluation budget exhausted".into(),
            ));
        }
        if self.spread() < self.xtol {
            return TerminationStatus::Terminated(TerminationReason::SolverExit(
                "swarm collapsed to within xtol of its best".into(),
            ));
        }
        TerminationStatus::NotTerminated
    }
}

/// Minimises `bb` over `set` with a seeded particle swarm.
pub fn minimize_particle_swarm<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    opts: &SwarmOptions,
    callback: Option<IterateCallback>,
) -> Result<OptimizeResult, OptimizeError> {
    OptimizeError::check_dim(bb.dim(), set.dim())?;
    opts.validate()?;
    let fallback = set.find_feasible_point()?;
    let log = Mutex::new(PenaltyLog::default());
    let problem = PenalizedProblem {
        bb,
        set,
        params: PenaltyParams {
            penalty: opts.penalty,
            projection_weight: opts.projection_weight,
            budget: opts.max_evaluations,
        },
        log: &log,
    };
    let solver = SeededSwarm::new(
        set,
        opts.particles,
        opts.seed,
        opts.xtol,
        opts.max_evaluations,
    );
    let path: PathLog = Arc::new(Mutex::new(Vec::new()));
    let res = Executor::new(problem, solver)
        .configure(|s| s.max_iters(opts.max_iterations))
        .add_observer(
            PathObserver::new(Arc::clone(&path), callback),
            ObserverMode::Always,
        )
        .run()
        .map_err(from_argmin)?;
    let reason = res.state().get_termination_reason();
    let termination = reason.map(|r| r.text().to_string()).unwrap_or_default();
    let stop = if res.solver().spent {
        Stop::BudgetExhausted
    } else if matches!(reason, Some(TerminationReason::SolverExit(_))) {
        Stop::Converged // the swarm collapsed to within xtol of its best
    } else {
        Stop::IterationLimit
    };
    drop(res);
    let log = log.into_inner().unwrap_or_else(|e| e.into_inner());
    finish(
        log.history,
        take_path(&path),
        termination,
        stop,
        bb.n_constraints(),
        opts.constraint_tol,
        &fallback,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::Evaluation;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A bowl with its minimum at (0.3, 0.6), counting batches, their sizes and single calls.
    #[derive(Default)]
    struct CountingBowl {
        batches: Mutex<Vec<usize>>,
        singles: AtomicUsize,
    }

    impl BlackBox for CountingBowl {
        fn dim(&self) -> usize {
            2
        }
        fn n_constraints(&self) -> usize {
            0
        }
        fn evaluate(&self, x: &[f64]) -> Evaluation {
            self.singles.fetch_add(1, Ordering::Relaxed);
            Evaluation::new((x[0] - 0.3).powi(2) + 2.0 * (x[1] - 0.6).powi(2), vec![])
        }
        fn evaluate_batch(&self, xs: &[Vec<f64>]) -> Vec<Evaluation> {
            self.batches.lock().unwrap().push(xs.len());
            let before = self.singles.load(Ordering::Relaxed);
            let out = xs.iter().map(|x| self.evaluate(x)).collect();
            self.singles.store(before, Ordering::Relaxed);
            out
        }
    }

    /// argmin evaluates every generation through one `bulk_cost`, which reaches the black box
    /// as one `evaluate_batch` of at most `particles` points (fewer only when a clipped point
    /// repeats one already evaluated); nothing is evaluated one by one.
    #[test]
    fn each_generation_is_one_batch() {
        let bb = CountingBowl::default();
        let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let opts = SwarmOptions {
            max_evaluations: 10_000,
            ..SwarmOptions::default()
        };
        let r = minimize_particle_swarm(&bb, &set, &opts, None).unwrap();
        let batches = bb.batches.lock().unwrap().clone();
        assert_eq!(bb.singles.load(Ordering::Relaxed), 0);
        assert_eq!(batches[0], opts.particles, "initial generation");
        assert!(batches.iter().all(|&k| k <= opts.particles), "{batches:?}");
        // One argmin iteration per generation: the path has the initial generation plus one
        // entry per later generation, and no generation makes two batches.
        assert!(
            batches.len() <= r.path.len(),
            "{} > {}",
            batches.len(),
            r.path.len()
        );
        assert_eq!(batches.iter().sum::<usize>(), r.evaluations);
        assert_eq!(r.path.len() as u64, opts.max_iterations + 1);
    }

    /// The seed fixes the run; another seed gives another run; the budget is a hard cap.
    #[test]
    fn seeded_and_budgeted() {
        let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let run = |seed, max_evaluations| {
            let opts = SwarmOptions {
                seed,
                max_evaluations,
                ..SwarmOptions::default()
            };
            minimize_particle_swarm(&CountingBowl::default(), &set, &opts, None).unwrap()
        };
        let (a, b, c) = (run(5, 250), run(5, 250), run(6, 250));
        assert_eq!(a.history, b.history);
        assert_ne!(a.history[0].0, c.history[0].0);
        let short = run(5, 30);
        assert_eq!(short.evaluations, 30);
        assert_eq!(short.stop, Stop::BudgetExhausted);
        assert_eq!(short.history[..], a.history[..30]);
    }

    #[test]
    fn options_are_validated() {
        assert!(SwarmOptions::default().validate().is_ok());
        for bad in [
            SwarmOptions {
                particles: 1,
                ..SwarmOptions::default()
            },
            SwarmOptions {
                xtol: 0.0,
                ..SwarmOptions::default()
            },
            SwarmOptions {
                constraint_tol: f64::NAN,
                ..SwarmOptions::default()
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}
