//! Particle swarm over the box, on the projected penalty `F(x)` of `penalized.rs` (linear
//! constraints by projection, black-box constraints by the ℓ1 penalty), seeded.
//!
//! argmin's own `ParticleSwarm` is compiled only with argmin's `rand` feature, which this crate
//! does not enable (`argmin = { default-features = false }`). This module is therefore a small
//! argmin [`Solver`] implementing the same canonical update (SPSO 2011, Zambrano-Bigiarini et
//! al. 2013, as in argmin): `v ← w v + c₁ U∘(p_best − x) + c₂ U∘(g_best − x)`, `x ← clip(x + v)`,
//! `w = 1/(2 ln 2)`, `c₁ = c₂ = ½ + ln 2`, `U` uniform on `[0, 1)` per component. Randomness comes
//! from a rand 0.9 `SmallRng` seeded with [`SwarmOptions::seed`], so a run is reproducible. Each
//! generation is evaluated with one [`BlackBox::evaluate_batch`] (parallel if the black box is).

use crate::optimize::Stop;
use std::sync::{Arc, Mutex};

use argmin::core::{
    Error, Executor, IterState, KV, KvValue, Problem, Solver, State, TerminationReason,
    TerminationStatus, observers::ObserverMode,
};
use rand09::rngs::SmallRng;
use rand09::{Rng, SeedableRng};

use super::evaluation::BlackBox;
use super::feasible::FeasibleSet;
use super::nelder_mead::finish;
use super::observer::{IterateCallback, PathLog, PathObserver, take_path};
use super::penalized::{PenalizedProblem, PenaltyLog, PenaltyParams};
use super::{OptimizeError, OptimizeResult, error::from_argmin};

/// argmin state of the swarm: parameter = best position so far, cost = its `F`.
pub(crate) type SwarmState = IterState<Vec<f64>, (), (), (), (), f64>;

/// Options of [`minimize_particle_swarm`].
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmOptions {
    /// Particles per generation. Default 12.
    pub particles: usize,
    /// Generations after the initial one. Default 20.
    pub max_iterations: u64,
    /// Evaluation budget. Default 250.
    pub max_evaluations: usize,
    /// Seed of the rand 0.9 `SmallRng`. Default 0.
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

struct Particle {
    x: Vec<f64>,
    v: Vec<f64>,
    best_x: Vec<f64>,
    best_cost: f64,
}

/// The swarm as an argmin solver.
pub(crate) struct ParticleSwarmSolver {
    lower: Vec<f64>,
    upper: Vec<f64>,
    n_particles: usize,
    rng: SmallRng,
    particles: Vec<Particle>,
    best: (Vec<f64>, f64),
    xtol: f64,
    budget: usize,
    spent: bool,
}

const INERTIA: f64 = 0.721_347_520_444_481_7; // 1/(2 ln 2)
const ATTRACTION: f64 = 1.193_147_180_559_945_3; // ½ + ln 2

impl ParticleSwarmSolver {
    fn spread(&self) -> f64 {
        self.particles
            .iter()
            .flat_map(|p| p.x.iter().zip(&self.best.0).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max)
    }

    fn evaluate<B: BlackBox + ?Sized>(
        &mut self,
        problem: &mut Problem<PenalizedProblem<'_, B>>,
        xs: &[Vec<f64>],
    ) -> Result<Vec<f64>, Error> {
        let costs = problem.bulk_cost(xs)?;
        if let Some(p) = problem.problem.as_ref() {
            let l = p.log.lock().unwrap_or_else(|e| e.into_inner());
            self.spent = l.budget_hit || l.history.len() >= self.budget;
        }
        Ok(costs)
    }

    fn kv(&self, problem: &Problem<PenalizedProblem<'_, impl BlackBox + ?Sized>>) -> KV {
        let evals = problem
            .problem
            .as_ref()
            .map(|p| p.evaluations())
            .unwrap_or(0);
        let mut kv = KV::new();
        kv.insert("evals", KvValue::Uint(evals as u64));
        kv.insert("spread", KvValue::Float(self.spread()));
        kv
    }
}

impl<B: BlackBox + ?Sized> Solver<PenalizedProblem<'_, B>, SwarmState> for ParticleSwarmSolver {
    fn name(&self) -> &str {
        "particle swarm (SPSO 2011 update, seeded)"
    }

    fn init(
        &mut self,
        problem: &mut Problem<PenalizedProblem<'_, B>>,
        state: SwarmState,
    ) -> Result<(SwarmState, Option<KV>), Error> {
        let n = self.lower.len();
        let mut xs = Vec::with_capacity(self.n_particles);
        let mut vs = Vec::with_capacity(self.n_particles);
        for _ in 0..self.n_particles {
            let x: Vec<f64> = (0..n)
                .map(|i| self.lower[i] + self.rng.random::<f64>() * (self.upper[i] - self.lower[i]))
                .collect();
            let v: Vec<f64> = (0..n)
                .map(|i| (2.0 * self.rng.random::<f64>() - 1.0) * (self.upper[i] - self.lower[i]))
                .collect();
            xs.push(x);
            vs.push(v);
        }
        let costs = self.evaluate(problem, &xs)?;
        self.particles = xs
            .into_iter()
            .zip(vs)
            .zip(&costs)
            .map(|((x, v), &c)| Particle {
                best_x: x.clone(),
                x,
                v,
                best_cost: c,
            })
            .collect();
        let b = (0..costs.len())
            .min_by(|&a, &b| costs[a].total_cmp(&costs[b]))
            .unwrap_or(0);
        self.best = (self.particles[b].x.clone(), costs[b]);
        let kv = self.kv(problem);
        Ok((state.param(self.best.0.clone()).cost(self.best.1), Some(kv)))
    }

    fn next_iter(
        &mut self,
        problem: &mut Problem<PenalizedProblem<'_, B>>,
        state: SwarmState,
    ) -> Result<(SwarmState, Option<KV>), Error> {
        let n = self.lower.len();
        let mut xs = Vec::with_capacity(self.particles.len());
        for k in 0..self.particles.len() {
            for i in 0..n {
                let (u1, u2) = (self.rng.random::<f64>(), self.rng.random::<f64>());
                let p = &mut self.particles[k];
                p.v[i] = INERTIA * p.v[i]
                    + ATTRACTION * u1 * (p.best_x[i] - p.x[i])
                    + ATTRACTION * u2 * (self.best.0[i] - p.x[i]);
                p.x[i] = (p.x[i] + p.v[i]).clamp(self.lower[i], self.upper[i]);
            }
            xs.push(self.particles[k].x.clone());
        }
        let costs = self.evaluate(problem, &xs)?;
        for (p, &c) in self.particles.iter_mut().zip(&costs) {
            if c < p.best_cost {
                p.best_cost = c;
                p.best_x = p.x.clone();
                if c < self.best.1 {
                    self.best = (p.x.clone(), c);
                }
            }
        }
        let kv = self.kv(problem);
        Ok((state.param(self.best.0.clone()).cost(self.best.1), Some(kv)))
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
    if opts.particles < 2 || opts.max_evaluations == 0 {
        return Err(OptimizeError::InvalidOption {
            name: "particles / max_evaluations",
            value: opts.particles.min(opts.max_evaluations) as f64,
            reason: "need at least 2 particles and 1 evaluation",
        });
    }
    for (name, value) in [
        ("penalty", opts.penalty),
        ("projection_weight", opts.projection_weight),
        ("xtol", opts.xtol),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(OptimizeError::InvalidOption {
                name,
                value,
                reason: "must be finite and > 0",
            });
        }
    }
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
    let solver = ParticleSwarmSolver {
        lower: set.lower().to_vec(),
        upper: set.upper().to_vec(),
        n_particles: opts.particles,
        rng: SmallRng::seed_from_u64(opts.seed),
        particles: Vec::new(),
        best: (fallback.clone(), f64::INFINITY),
        xtol: opts.xtol,
        budget: opts.max_evaluations,
        spent: false,
    };
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
