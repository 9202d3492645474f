//! The JSON reports of the study commands (`solution.json`, `map.json`, `compare.json`) and the
//! record of the problem every report carries. Shapes only: the numbers come from
//! [`crate::study`] and [`crate::solve`]. Units are SI in the field names that say so
//! (`omega_rad_s`, `v0_m_s`), with the driller's units beside them (`omega_rpm`, `v0_m_per_h`).

use crate::problem::Problem;
use crate::problem::study::{Constraints, LinearConstraint, Quantity};
use crate::solve::{NumericalCheck, PathPoint, SolveOutcome, SolveStatus};
use crate::stats::Statistic;
use crate::study::{ChanceValue, PointEvaluation, RiskValue, RobustEvaluator, SampleResult};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The head of every report: the problem's name, the path it was read from, the file's text and
/// a stable hash of it (FNV-1a, 64 bits, hex), and drillopt's version, so that a result says
/// exactly what produced it.
#[derive(Debug, Clone, Serialize)]
pub struct ProblemRecord<'a> {
    pub problem: &'a str,
    pub problem_file: String,
    pub problem_hash: String,
    pub problem_toml: &'a str,
    pub version: &'static str,
}

impl<'a> ProblemRecord<'a> {
    /// The record of `problem`, read from `file`.
    pub fn of(problem: &'a Problem, file: &Path) -> Self {
        ProblemRecord {
            problem: &problem.name,
            problem_file: file.display().to_string(),
            problem_hash: format!("{:016x}", crate::hash::stable_hash(problem.text.as_bytes())),
            problem_toml: &problem.text,
            version: crate::VERSION,
        }
    }
}

/// The head of every study report: the problem's record, the seed and the samples.
#[derive(Debug, Clone, Serialize)]
pub struct StudyHeader<'a> {
    #[serde(flatten)]
    pub record: ProblemRecord<'a>,
    pub seed: u64,
    /// Monte Carlo samples per point that ran (the file's, or `--samples`); with sequential
    /// sampling, the most a point may use.
    pub samples: usize,
    /// `[uncertain.sequential]`: the stopping rule (null: every point uses `samples`).
    pub sequential: Option<crate::problem::study::Sequential>,
    /// What the command line changed (`samples`, `budget`, `threads`; null: the file's value).
    pub overrides: crate::problem::study::Overrides,
}

impl<'a> StudyHeader<'a> {
    pub fn of(problem: &'a Problem, file: &Path) -> Self {
        StudyHeader {
            record: ProblemRecord::of(problem, file),
            seed: problem.study.seed,
            samples: problem.study.samples,
            sequential: problem.study.sequential,
            overrides: problem.study.overrides,
        }
    }
}

/// An operating point in SI and driller units.
#[derive(Debug, Clone, Serialize)]
pub struct PointJson {
    pub omega_rad_s: f64,
    pub omega_rpm: f64,
    /// The set-point: V0 (`v0_m_s`, `v0_m_per_h`) or a hook load's WOB (`wob_n`, `wob_kn`).
    #[serde(flatten)]
    pub set_point: crate::model::SetPointValue,
}

impl PointJson {
    /// An operating point in both unit systems.
    pub fn at(op: crate::model::OperatingPoint) -> Self {
        PointJson {
            omega_rad_s: op.omega,
            omega_rpm: crate::units::to_rpm(op.omega),
            set_point: crate::model::SetPointValue::of(&op),
        }
    }

    /// The operating point of an evaluation.
    pub fn of(p: &PointEvaluation) -> Self {
        PointJson {
            omega_rad_s: p.omega_rad_s,
            omega_rpm: p.omega_rpm,
            set_point: p.set_point,
        }
    }
}

/// Work done, for the report and the terminal.
#[derive(Debug, Clone, Serialize)]
pub struct WorkJson {
    pub simulations_run: usize,
    pub simulations_from_cache: usize,
    pub simulations_failed: usize,
    /// Samples per point; with sequential sampling, the most a point may use (each point's
    /// count is its `samples_used`).
    pub samples_per_point: usize,
    /// What ran the simulations ("2 threads", "4 MPI ranks").
    pub executor: String,
    pub wall_time_s: f64,
    /// A multi-fidelity solve's simulations per fidelity (absent at one fidelity; the counts
    /// above are their sums).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub by_fidelity: Option<super::ByFidelity>,
}

impl WorkJson {
    pub fn of(ev: &RobustEvaluator, wall_time_s: f64) -> Self {
        use std::sync::atomic::Ordering::Relaxed;
        WorkJson {
            simulations_run: ev.counters.simulated.load(Relaxed),
            simulations_from_cache: ev.counters.cached.load(Relaxed),
            simulations_failed: ev.counters.failed.load(Relaxed),
            samples_per_point: ev.samples_per_point(),
            executor: ev.executor().describe(),
            wall_time_s,
            by_fidelity: None,
        }
    }

    /// The work of a solve on `full` and, multi-fidelity, on `explore` too: the counts summed
    /// over both, and each fidelity's in `by_fidelity`.
    pub fn of_fidelities(
        full: &RobustEvaluator,
        explore: Option<&RobustEvaluator>,
        wall_time_s: f64,
    ) -> Self {
        let mut work = WorkJson::of(full, wall_time_s);
        if let Some(x) = explore {
            let (f, e) = (super::FidelityWork::of(full), super::FidelityWork::of(x));
            work.simulations_run = f.simulations_run + e.simulations_run;
            work.simulations_from_cache = f.simulations_from_cache + e.simulations_from_cache;
            work.simulations_failed = f.simulations_failed + e.simulations_failed;
            work.by_fidelity = Some(super::ByFidelity {
                explore: e,
                full: f,
            });
        }
        work
    }
}

/// One evaluated point without its per-sample detail (`solve`'s evaluations, `map`'s nodes).
#[derive(Debug, Clone, Serialize)]
pub struct EvaluationJson {
    pub omega_rad_s: f64,
    pub omega_rpm: f64,
    /// The set-point: V0 or a hook load's WOB.
    #[serde(flatten)]
    pub set_point: crate::model::SetPointValue,
    pub objective: Option<f64>,
    /// Half-width of the score's bootstrap confidence interval (null: no score, or 1 sample).
    pub score_half_width: Option<f64>,
    /// Monte Carlo samples the point used.
    pub samples_used: usize,
    pub feasible: bool,
    pub failure: Option<String>,
    pub mean_metrics: BTreeMap<String, f64>,
    /// The fidelity that produced the numbers: "full", or "explore" in a multi-fidelity solve.
    pub fidelity: crate::study::Fidelity,
}

impl EvaluationJson {
    pub fn of(p: &PointEvaluation) -> Self {
        EvaluationJson {
            omega_rad_s: p.omega_rad_s,
            omega_rpm: p.omega_rpm,
            set_point: p.set_point,
            objective: p.objective,
            score_half_width: p.score_half_width,
            samples_used: p.samples_used,
            feasible: p.feasible,
            failure: p.failure.clone(),
            mean_metrics: p.mean_metrics.clone(),
            fidelity: p.fidelity,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct ObjectiveJson {
    /// The score (maximised): statistic of the quantity minus the weighted risk terms.
    pub score: f64,
    /// Half-width of its bootstrap confidence interval, at `score_confidence`.
    pub score_half_width: Option<f64>,
    /// That interval, [low, high].
    pub score_interval: Option<[f64; 2]>,
    /// The level of the interval.
    pub score_confidence: f64,
    /// Monte Carlo samples the optimum used.
    pub samples_used: usize,
    pub quantity: &'static str,
    pub quantity_unit: &'static str,
    pub statistic: Statistic,
    pub quantity_value: f64,
    pub risk: Vec<RiskValue>,
    /// The fidelity of these numbers: always "full" for a solve's optimum (multi-fidelity: the
    /// best of the candidates confirmed at full fidelity).
    pub fidelity: crate::study::Fidelity,
    /// Multi-fidelity: the score of the same point at the explore fidelity (null otherwise).
    pub explore_score: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct LinearJson {
    pub label: &'static str,
    pub omega_coefficient: f64,
    /// Per m/s (feed tops), or `wob_coefficient` per N under a hook load.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub v0_coefficient: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wob_coefficient: Option<f64>,
    pub upper: f64,
    pub value_at_optimum: f64,
    pub active: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct ConstraintsJson {
    pub omega_rad_s: [f64; 2],
    /// The bounds of V0 (feed tops) or, under a hook load, `wob_n` of the WOB.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub v0_m_s: Option<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wob_n: Option<[f64; 2]>,
    pub linear: Vec<LinearJson>,
    pub chance: Vec<ChanceValue>,
    /// Every bound, linear and chance constraint with its margin at the optimum and whether it is
    /// at its limit ([`crate::solve::activity`] states the rules).
    pub activity: Vec<crate::solve::Activity>,
    /// The names of those at their limit: what holds the optimum (`[expect] active`'s names).
    pub held_by: Vec<String>,
    /// The local slope of the score at the optimum ([`crate::solve::score_slope`]): what moving
    /// a binding bound would give; null when the evaluated points around it do not determine a
    /// plane.
    pub score_slope: Option<crate::solve::ScoreSlope>,
}

impl ConstraintsJson {
    /// The constraints with their values at `best`; a linear constraint is active within 1e-3
    /// of its scale.
    pub fn at(c: &Constraints, best: &PointEvaluation, evaluated: &[PointEvaluation]) -> Self {
        let scale = |l: &LinearConstraint| {
            (l.omega * c.omega[1]).abs() + (l.set_point * c.set_point[1]).abs() + l.upper.abs()
        };
        let activity = crate::solve::activity(c, best, evaluated);
        let feed = c.kind == crate::model::SetPoint::Feed;
        let s = best.op().set_point(c.kind);
        ConstraintsJson {
            omega_rad_s: c.omega,
            v0_m_s: feed.then_some(c.set_point),
            wob_n: (!feed).then_some(c.set_point),
            linear: c
                .linear
                .iter()
                .map(|l| {
                    let value = l.omega * best.omega_rad_s + l.set_point * s;
                    LinearJson {
                        label: l.label,
                        omega_coefficient: l.omega,
                        v0_coefficient: feed.then_some(l.set_point),
                        wob_coefficient: (!feed).then_some(l.set_point),
                        upper: l.upper,
                        value_at_optimum: value,
                        active: (l.upper - value).abs() <= 1e-3 * scale(l),
                    }
                })
                .collect(),
            chance: best.chance.clone(),
            score_slope: crate::solve::score_slope(c, best, evaluated),
            held_by: activity
                .iter()
                .filter(|a| a.at_limit)
                .map(|a| a.name.clone())
                .collect(),
            activity,
        }
    }
}

/// `solution.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SolutionJson<'a> {
    #[serde(flatten)]
    pub header: StudyHeader<'a>,
    pub method: &'a str,
    pub termination: &'a str,
    /// converged | grid_complete | budget_exhausted | iteration_limit | no_feasible_point.
    pub status: SolveStatus,
    pub optimum: Option<PointJson>,
    pub objective: Option<ObjectiveJson>,
    pub metrics: Option<BTreeMap<String, f64>>,
    pub metrics_per_sample: Option<Vec<SampleResult>>,
    pub constraints: Option<ConstraintsJson>,
    /// `[optimizer.explore]`: the explore fidelity's overrides (null: one fidelity).
    pub explore: Option<super::ExploreJson>,
    /// Multi-fidelity: the candidates confirmed at full fidelity (null: one fidelity).
    pub confirmation: Option<super::ConfirmationJson>,
    pub evaluations: Vec<EvaluationJson>,
    pub path: &'a [PathPoint],
    pub work: WorkJson,
    /// The basis refinement at the optimum (nominal parameters) beside the spread over samples.
    pub numerical_check: Option<&'a NumericalCheck>,
    /// Warnings on the dynamics at the optimum ([`crate::solve::warnings`]): sticking, a peak bit
    /// speed, a critical speed near Ω, that the study does not score.
    pub warnings: Vec<String>,
}

impl<'a> SolutionJson<'a> {
    /// The report of a solve.
    pub fn of(
        problem: &'a Problem,
        file: &Path,
        outcome: &'a SolveOutcome,
        work: WorkJson,
        check: Option<&'a NumericalCheck>,
    ) -> Self {
        let study = &problem.study;
        let best = outcome.best.as_ref();
        let (quantity, unit) = match study.quantity {
            Quantity::Rop => ("mean_rop_m_per_h", "m/h"),
            Quantity::Efficiency => ("efficiency", "1"),
        };
        SolutionJson {
            header: StudyHeader::of(problem, file),
            method: outcome.method.name(),
            termination: &outcome.termination,
            status: outcome.status,
            optimum: best.map(PointJson::of),
            objective: best.map(|b| ObjectiveJson {
                score: b.objective.expect("best is scored"),
                score_half_width: b.score_half_width,
                score_interval: b.score_interval,
                score_confidence: study.score_interval().confidence,
                samples_used: b.samples_used,
                quantity,
                quantity_unit: unit,
                statistic: study.statistic,
                quantity_value: b.quantity.expect("best is scored"),
                risk: b.risk.clone(),
                fidelity: b.fidelity,
                explore_score: super::explore_score_of(outcome.confirmation.as_ref(), b),
            }),
            metrics: best.map(|b| b.mean_metrics.clone()),
            metrics_per_sample: best.map(|b| b.samples.clone()),
            constraints: best.and_then(|b| {
                study
                    .constraints
                    .as_ref()
                    .map(|c| ConstraintsJson::at(c, b, &outcome.evaluations))
            }),
            explore: (outcome.confirmation.as_ref()).map(|c| super::ExploreJson::of(&c.explore)),
            confirmation: (outcome.confirmation.as_ref()).map(super::ConfirmationJson::of),
            evaluations: outcome.evaluations.iter().map(EvaluationJson::of).collect(),
            path: &outcome.path,
            work,
            numerical_check: check,
            warnings: best.map_or_else(Vec::new, |b| {
                crate::solve::warnings(b, &study.metrics_named())
            }),
        }
    }
}

/// `map.json`.
#[derive(Debug, Clone, Serialize)]
pub struct MapJson<'a> {
    #[serde(flatten)]
    pub header: StudyHeader<'a>,
    pub grid: [usize; 2],
    pub omega_rad_s: &'a [f64],
    /// The grid's set-points: V0 (feed tops) or, under a hook load, the WOB (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub v0_m_s: Option<&'a [f64]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wob_n: Option<&'a [f64]>,
    /// Row-major (set-point rows, Ω columns); null outside the linear constraints.
    pub points: Vec<Option<EvaluationJson>>,
    pub optimum: Option<PointJson>,
    pub optimum_objective: Option<f64>,
    pub work: WorkJson,
}

/// `compare.json`.
#[derive(Debug, Clone, Serialize)]
pub struct CompareJson<'a> {
    #[serde(flatten)]
    pub header: StudyHeader<'a>,
    pub points: &'a [PointEvaluation],
    pub work: WorkJson,
}
