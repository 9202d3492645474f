//! The study driver: the robust evaluator ([`crate::objective`]) seen by the optimizers
//! ([`crate::optimize`]) as a black box on the unit box, and the three jobs built on it: the
//! robust optimum ([`solve`]), a grid of the feasible box ([`map`]) and given points ([`compare`]
//! is just [`RobustEvaluator::evaluate`]).

mod activity;
mod check;
mod multi_fidelity;
mod scaling;
mod slope;

#[cfg(test)]
pub(crate) use activity::tests as activity_tests;
pub use activity::{
    Activity, BOX_TOLERANCE, CHANCE_TOLERANCE, CRITICAL_SPEED_WARNING, PEAK_SPEED_WARNING,
    STICK_WARNING, activity, deciding_quantile, warnings,
};
pub use check::{CheckedMetric, NumericalCheck, numerical_check};
pub use multi_fidelity::{Candidate, Confirmation, Refinement, candidates, solve_multi_fidelity};
pub use scaling::Scaling;
pub use slope::{FIT_RADIUS, MIN_SPREAD, ScoreSlope, score_slope};

use crate::model::OperatingPoint;
use crate::optimize::{
    BlackBox, EgoOptions, EgoTrustRegionOptions, Evaluation, IterateCallback, NelderMeadOptions,
    OptimizeError, SwarmOptions, TrustRegionOptions, grid_search, minimize_ego,
    minimize_ego_trust_region, minimize_nelder_mead, minimize_particle_swarm,
    minimize_trust_region,
};
use crate::problem::Problem;
use crate::problem::study::{Constraints, Method, OptimizerSettings};
use crate::study::{PointEvaluation, RobustEvaluator};
use serde::Serialize;
use std::sync::Mutex;

/// Why a study could not run.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    #[error(
        "{file}: the problem has no [constraints] section; solve and map need the bounds constraints.omega and constraints.v0 (e.g. omega = [\"30 rpm\", \"150 rpm\"], v0 = [\"2 m/h\", \"20 m/h\"]; under top = \"hook_load\" constraints.wob, e.g. wob = [\"20 kN\", \"120 kN\"]; problems/seed_robust.toml is the seed with a whole study section)"
    )]
    NoConstraints { file: String },
    #[error("{file}: [constraints]: {message}")]
    Infeasible { file: String, message: String },
    #[error("optimizer: {0}")]
    Optimize(#[from] OptimizeError),
    #[error("{file}: a multi-fidelity solve needs an [optimizer.explore] section")]
    NoExplore { file: String },
    #[error("{file}: key `{key}`: {message}")]
    Explore {
        file: String,
        key: &'static str,
        message: String,
    },
}

/// The evaluator as a black box on the unit box: minimise −score subject to the chance
/// constraints P_k − p_k ≤ 0. Every point evaluated is kept, in order.
pub struct StudyBlackBox<'a, 'e> {
    pub evaluator: &'a RobustEvaluator<'e>,
    pub scaling: Scaling,
    n_chance: usize,
    pub log: Mutex<Vec<PointEvaluation>>,
}

impl<'a, 'e> StudyBlackBox<'a, 'e> {
    pub fn new(evaluator: &'a RobustEvaluator<'e>, constraints: &Constraints) -> Self {
        StudyBlackBox {
            evaluator,
            scaling: Scaling::of(constraints),
            n_chance: constraints.chance.len(),
            log: Mutex::new(Vec::new()),
        }
    }

    fn to_evaluation(&self, p: &PointEvaluation) -> Evaluation {
        match p.objective {
            None => Evaluation::failure(self.n_chance),
            Some(score) => Evaluation::new(
                -score,
                p.chance
                    .iter()
                    .map(|c| c.probability - c.max_probability)
                    .collect(),
            ),
        }
    }
}

impl BlackBox for StudyBlackBox<'_, '_> {
    fn dim(&self) -> usize {
        2
    }
    fn n_constraints(&self) -> usize {
        self.n_chance
    }
    fn evaluate(&self, x: &[f64]) -> Evaluation {
        self.evaluate_batch(&[x.to_vec()]).remove(0)
    }
    fn evaluate_batch(&self, xs: &[Vec<f64>]) -> Vec<Evaluation> {
        let ops: Vec<OperatingPoint> = xs.iter().map(|x| self.scaling.from_unit(x)).collect();
        let points = self.evaluator.evaluate(&ops);
        let out = points.iter().map(|p| self.to_evaluation(p)).collect();
        self.log
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .extend(points);
        out
    }
}

/// One step of the optimizer's path, in physical units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathPoint {
    pub iteration: usize,
    pub omega_rad_s: f64,
    /// The set-point: V0 or a hook load's WOB.
    #[serde(flatten)]
    pub set_point: crate::model::SetPointValue,
    /// −merit: the score, less any chance-constraint penalty.
    pub score: f64,
    /// Trust-region radius as a fraction of the bounds box (trust region only).
    pub radius: Option<f64>,
    pub evaluations: usize,
}

impl PathPoint {
    /// The operating point of the step.
    pub fn op(&self) -> OperatingPoint {
        self.set_point.at(self.omega_rad_s)
    }
}

/// How a solve ended (`solution.json` → `status`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolveStatus {
    /// The optimiser's convergence test held at a feasible point: the optimum.
    Converged,
    /// Every node of a grid evaluated; the best feasible node.
    GridComplete,
    /// The evaluation budget ran out first: the best feasible point seen, not an optimum.
    BudgetExhausted,
    /// The iteration cap ran out first: the best feasible point seen, not an optimum.
    IterationLimit,
    /// No evaluated point was feasible.
    NoFeasiblePoint,
}

impl SolveStatus {
    fn of(stop: crate::optimize::Stop, best: Option<&PointEvaluation>) -> SolveStatus {
        use crate::optimize::Stop;
        match (best, stop) {
            (None, _) | (_, Stop::AllFailed) => SolveStatus::NoFeasiblePoint,
            (Some(_), Stop::Converged) => SolveStatus::Converged,
            (Some(_), Stop::GridComplete) => SolveStatus::GridComplete,
            (Some(_), Stop::BudgetExhausted) => SolveStatus::BudgetExhausted,
            (Some(_), Stop::IterationLimit) => SolveStatus::IterationLimit,
        }
    }

    /// Whether the best point is an optimum in the method's own sense.
    pub fn is_optimum(self) -> bool {
        matches!(self, SolveStatus::Converged | SolveStatus::GridComplete)
    }

    /// In words, for terminals.
    pub fn text(self) -> &'static str {
        match self {
            SolveStatus::Converged => "converged",
            SolveStatus::GridComplete => "every grid node evaluated",
            SolveStatus::BudgetExhausted => "evaluation budget exhausted before convergence",
            SolveStatus::IterationLimit => "iteration limit reached before convergence",
            SolveStatus::NoFeasiblePoint => "no feasible point",
        }
    }
}

/// What [`solve`] found.
#[derive(Debug, Clone)]
pub struct SolveOutcome {
    pub method: Method,
    /// The best feasible point evaluated (None if no point was feasible).
    pub best: Option<PointEvaluation>,
    /// Every point evaluated, in order.
    pub evaluations: Vec<PointEvaluation>,
    pub path: Vec<PathPoint>,
    pub termination: String,
    pub status: SolveStatus,
    /// Multi-fidelity (`[optimizer.explore]`): the explore candidates and their full-fidelity
    /// confirmation; None for a solve at one fidelity.
    pub confirmation: Option<Confirmation>,
}

fn constraints_of(problem: &Problem) -> Result<&Constraints, SolveError> {
    problem
        .study
        .constraints
        .as_ref()
        .ok_or_else(|| SolveError::NoConstraints {
            file: problem.source.display().to_string(),
        })
}

/// The feasible set in unit coordinates, refusing constraints that leave no feasible point.
fn feasible_set(problem: &Problem) -> Result<crate::optimize::FeasibleSet, SolveError> {
    let c = constraints_of(problem)?;
    let set = Scaling::of(c).feasible_set(c)?;
    set.find_feasible_point()
        .map_err(|e| SolveError::Infeasible {
            file: problem.source.display().to_string(),
            message: infeasible_message(c, &e),
        })?;
    Ok(set)
}

/// Why the bounds and linear constraints leave no (Ω, set-point), in words and the user's units:
/// the constraint the optimizer could not meet, by its key, and the bounds.
fn infeasible_message(c: &Constraints, e: &OptimizeError) -> String {
    use crate::units::{short, to_rpm};
    let (symbol, key, unit) = (c.kind.symbol(), c.kind.key(), c.kind.unit());
    let bounds = format!(
        "within the bounds Ω ∈ [{}, {}] rpm (constraints.omega), {symbol} ∈ [{}, {}] {unit} (constraints.{key})",
        short(to_rpm(c.omega[0])),
        short(to_rpm(c.omega[1])),
        short(c.kind.to_unit(c.set_point[0])),
        short(c.kind.to_unit(c.set_point[1]))
    );
    let OptimizeError::Infeasible { row, .. } = e else {
        return format!("the bounds and linear constraints leave no feasible (Ω, {symbol}): {e}");
    };
    let which = row.and_then(|i| c.linear.get(i).map(|l| (i, l)));
    let detail = match which {
        Some((_, l)) if l.label == "max_depth_of_cut" => {
            let (limit, least) = (
                -l.omega,
                2.0 * std::f64::consts::PI * c.set_point[0] / c.omega[1],
            );
            let why = if least > limit {
                format!(
                    ": even the lowest V0 at the highest Ω cuts {} mm per revolution",
                    short(1e3 * least)
                )
            } else {
                String::new()
            };
            format!(
                "constraints.max_depth_of_cut (depth of cut 2π V0/Ω ≤ {} mm) cannot hold {bounds}{why}",
                short(1e3 * limit)
            )
        }
        Some((i, l)) => {
            // The i-th row counts the depth-of-cut row first; the file's index does not.
            let file_index = c.linear[..i].iter().filter(|r| r.label == l.label).count();
            format!(
                "constraints.linear[{file_index}] ({} Ω + {} {symbol} ≤ {}, SI) cannot hold {bounds}",
                l.omega, l.set_point, l.upper
            )
        }
        None => format!(
            "the constraints of [[constraints.linear]] and max_depth_of_cut cannot hold together {bounds}"
        ),
    };
    format!("the bounds and linear constraints leave no feasible (Ω, {symbol}): {detail}")
}

/// The best of a list of evaluations: feasible first, then by score.
pub fn best_point(points: &[PointEvaluation]) -> Option<PointEvaluation> {
    points
        .iter()
        .filter(|p| p.feasible && p.objective.is_some())
        .max_by(|a, b| {
            a.objective
                .partial_cmp(&b.objective)
                .expect("finite scores")
        })
        .cloned()
}

/// The robust optimum of a problem with the method of its `[optimizer]` section, every point on
/// `evaluator` (one fidelity: `[optimizer.explore]` is [`solve_multi_fidelity`]'s).
/// `on_iterate` is called with every iterate (e.g. to update a progress bar).
pub fn solve(
    problem: &Problem,
    evaluator: &RobustEvaluator,
    on_iterate: Option<IterateCallback>,
) -> Result<SolveOutcome, SolveError> {
    let constraints = constraints_of(problem)?;
    let set = feasible_set(problem)?;
    let settings = &problem.study.optimizer;
    let bb = StudyBlackBox::new(evaluator, constraints);
    let start = settings.start().map_or(problem.operating_point, |s| {
        OperatingPoint::of(constraints.kind, s[0], s[1])
    });
    let x0 = set.project(&bb.scaling.to_unit(start))?;
    let result = match settings {
        OptimizerSettings::TrustRegion(s) => {
            let opts = TrustRegionOptions {
                initial_radius: s.initial_radius,
                min_radius: s.min_radius,
                max_radius: 0.5_f64.max(s.initial_radius),
                max_evaluations: s.max_evaluations,
                ..TrustRegionOptions::default()
            };
            Some(minimize_trust_region(&bb, &set, &x0, &opts, on_iterate)?)
        }
        OptimizerSettings::Grid(s) => {
            let n = s.grid[0].max(s.grid[1]);
            Some(grid_search(&bb, &set, n, 0.0)?)
        }
        OptimizerSettings::NelderMead(s) => {
            let opts = NelderMeadOptions {
                initial_step: s.initial_radius,
                xtol: s.min_radius,
                max_evaluations: s.max_evaluations,
                ..NelderMeadOptions::default()
            };
            Some(minimize_nelder_mead(&bb, &set, &x0, &opts, on_iterate)?)
        }
        OptimizerSettings::ParticleSwarm(s) => {
            let opts = SwarmOptions {
                max_evaluations: s.max_evaluations,
                seed: s.seed,
                xtol: s.min_radius,
                ..SwarmOptions::default()
            };
            Some(minimize_particle_swarm(&bb, &set, &opts, on_iterate)?)
        }
        OptimizerSettings::Ego(s) => {
            let opts = EgoOptions {
                initial_design: s.initial_design,
                max_evaluations: s.max_evaluations,
                seed: s.seed,
                ..EgoOptions::default()
            };
            Some(minimize_ego(&bb, &set, &opts, on_iterate)?)
        }
        OptimizerSettings::EgoTrustRegion(s) => {
            let opts = EgoTrustRegionOptions {
                ego: EgoOptions {
                    initial_design: s.initial_design,
                    max_evaluations: s.ego_evaluations(),
                    seed: s.seed,
                    ..EgoOptions::default()
                },
                trust_region: TrustRegionOptions {
                    initial_radius: s.initial_radius,
                    min_radius: s.min_radius,
                    max_radius: 0.5_f64.max(s.initial_radius),
                    max_evaluations: s.max_evaluations,
                    ..TrustRegionOptions::default()
                },
            };
            Some(minimize_ego_trust_region(&bb, &set, &opts, on_iterate)?)
        }
    };
    let evaluations = bb.log.into_inner().unwrap_or_else(|e| e.into_inner());
    let stop = result
        .as_ref()
        .map_or(crate::optimize::Stop::GridComplete, |r| r.stop);
    let (path, termination) = match &result {
        Some(r) => (
            r.path
                .iter()
                .map(|it| {
                    let op = Scaling::of(constraints).from_unit(&it.x);
                    PathPoint {
                        iteration: it.iteration,
                        omega_rad_s: op.omega,
                        set_point: crate::model::SetPointValue::of(&op),
                        score: -it.merit,
                        radius: it.radius,
                        evaluations: it.evaluations,
                    }
                })
                .collect(),
            r.termination.clone(),
        ),
        None => (Vec::new(), "grid exhausted".to_string()),
    };
    let best = best_point(&evaluations);
    Ok(SolveOutcome {
        method: settings.method(),
        status: SolveStatus::of(stop, best.as_ref()),
        best,
        evaluations,
        path,
        termination,
        confirmation: None,
    })
}

/// The objective and metrics over a grid of the feasible box.
#[derive(Debug, Clone)]
pub struct MapOutcome {
    pub grid: [usize; 2],
    /// What the second axis is.
    pub kind: crate::model::SetPoint,
    /// Grid values of Ω (rad/s) and of the set-point (SI: V0 in m/s, or the WOB in N).
    pub omega: Vec<f64>,
    pub set_point: Vec<f64>,
    /// Per grid node (row-major in the set-point, then Ω): the evaluation, None outside the
    /// linear constraints.
    pub points: Vec<Option<PointEvaluation>>,
    pub best: Option<PointEvaluation>,
}

/// Evaluate every grid node inside the constraints (all simulations in parallel).
pub fn map(
    problem: &Problem,
    evaluator: &RobustEvaluator,
    grid: [usize; 2],
) -> Result<MapOutcome, SolveError> {
    let constraints = constraints_of(problem)?;
    let set = feasible_set(problem)?;
    let scaling = Scaling::of(constraints);
    let mut nodes = Vec::new();
    for j in 0..grid[1] {
        for i in 0..grid[0] {
            nodes.push(vec![
                i as f64 / (grid[0] - 1) as f64,
                j as f64 / (grid[1] - 1) as f64,
            ]);
        }
    }
    let inside: Vec<bool> = nodes.iter().map(|x| set.contains(x, 1e-12)).collect();
    let ops: Vec<OperatingPoint> = nodes
        .iter()
        .zip(&inside)
        .filter(|(_, ok)| **ok)
        .map(|(x, _)| scaling.from_unit(x))
        .collect();
    let mut evaluated = evaluator.evaluate(&ops).into_iter();
    let points: Vec<Option<PointEvaluation>> = inside
        .iter()
        .map(|ok| if *ok { evaluated.next() } else { None })
        .collect();
    let flat: Vec<PointEvaluation> = points.iter().flatten().cloned().collect();
    Ok(MapOutcome {
        grid,
        kind: constraints.kind,
        omega: (0..grid[0])
            .map(|i| {
                scaling
                    .from_unit(&[i as f64 / (grid[0] - 1) as f64, 0.0])
                    .omega
            })
            .collect(),
        set_point: (0..grid[1])
            .map(|j| {
                scaling
                    .from_unit(&[0.0, j as f64 / (grid[1] - 1) as f64])
                    .set_point(constraints.kind)
            })
            .collect(),
        best: best_point(&flat),
        points,
    })
}
