//! `drillopt solve PROBLEM`: the robust optimum, written to `solution.json` with plots.

use super::study::{self, PointJson, WorkJson};
use crate::problem::Problem;
use crate::problem::study::{Constraints, Quantity};
use crate::report;
use crate::solve::{self, PathPoint, SolveOutcome};
use crate::study::PointEvaluation;
use crate::study::{ChanceValue, RiskValue};
use clap::Args;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Problem file (TOML) with [constraints] and, optionally, [uncertain], [objective], [optimizer].
    pub problem: PathBuf,
    /// Output directory (default results/<problem>/solve).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Continue an interrupted run: reuse every finished simulation of the evaluation cache.
    #[arg(long)]
    pub resume: bool,
    /// No progress bar or progress messages (the result table and the numerical check are
    /// still printed).
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Serialize)]
struct ObjectiveJson {
    /// The score (maximised): statistic of the quantity minus the weighted risk terms.
    score: f64,
    quantity: &'static str,
    quantity_unit: &'static str,
    statistic: crate::stats::Statistic,
    quantity_value: f64,
    risk: Vec<RiskValue>,
}

#[derive(Serialize)]
struct LinearJson {
    label: &'static str,
    omega_coefficient: f64,
    v0_coefficient: f64,
    upper: f64,
    value_at_optimum: f64,
    active: bool,
}

#[derive(Serialize)]
struct ConstraintsJson {
    omega_rad_s: [f64; 2],
    v0_m_s: [f64; 2],
    linear: Vec<LinearJson>,
    chance: Vec<ChanceValue>,
}

/// One evaluated point without its per-sample detail (also used by `map`).
#[derive(Serialize)]
pub(super) struct EvaluationJson {
    omega_rad_s: f64,
    v0_m_s: f64,
    omega_rpm: f64,
    v0_m_per_h: f64,
    objective: Option<f64>,
    feasible: bool,
    failure: Option<String>,
    mean_metrics: BTreeMap<String, f64>,
}

#[derive(Serialize)]
struct SolutionJson<'a> {
    problem: &'a str,
    problem_file: String,
    #[serde(flatten)]
    record: super::ProblemRecord<'a>,
    version: &'a str,
    seed: u64,
    samples: usize,
    method: &'a str,
    termination: &'a str,
    /// converged | grid_complete | budget_exhausted | iteration_limit | no_feasible_point.
    status: crate::solve::SolveStatus,
    optimum: Option<PointJson>,
    objective: Option<ObjectiveJson>,
    metrics: Option<BTreeMap<String, f64>>,
    metrics_per_sample: Option<Vec<crate::study::SampleResult>>,
    constraints: Option<ConstraintsJson>,
    evaluations: Vec<EvaluationJson>,
    path: &'a [PathPoint],
    work: WorkJson,
    /// The basis refinement at the optimum (nominal parameters) beside the spread over samples.
    numerical_check: Option<&'a NumericalCheckJson>,
}

/// One decision metric at the optimum: the numerical change under basis refinement (nominal
/// parameters) against the statistical spread over the Monte Carlo samples.
#[derive(Serialize)]
struct CheckedMetric {
    /// The nominal model's value with the problem's basis.
    value: f64,
    /// The same with every family of the basis enriched 1.5×.
    refined_basis: f64,
    /// |refined − value| / max(|value|, floor), as in `verify`.
    rel_change: f64,
    limit: f64,
    converged: bool,
    /// Standard deviation of the metric over the samples at the optimum (none with one sample).
    sample_std_dev: Option<f64>,
}

#[derive(Serialize)]
struct NumericalCheckJson {
    basis: crate::rom::BasisCounts,
    refined_basis: crate::rom::BasisCounts,
    converged: bool,
    metrics: BTreeMap<&'static str, CheckedMetric>,
}

/// Run the basis check of `verify` at the optimum and set it beside the sample spread.
fn numerical_check(
    problem: &Problem,
    best: &PointEvaluation,
) -> Result<NumericalCheckJson, crate::verify::VerifyError> {
    use crate::verify::{Refinement, VerifySettings, verify_with};
    let settings = VerifySettings {
        op: crate::model::OperatingPoint {
            omega: best.omega_rad_s,
            v0: best.v0_m_s,
        },
        duration: problem.simulation.duration,
        settling: problem.simulation.settling_time,
    };
    let report = verify_with(problem, settings, &[Refinement::Basis], |_| {})?;
    let spread = |key: &str| {
        let values: Vec<f64> = best
            .samples
            .iter()
            .filter_map(|s| match &s.outcome {
                crate::study::SampleOutcome::Metrics(m) => m.get(key).copied(),
                _ => None,
            })
            .collect();
        let n = values.len() as f64;
        if n < 2.0 {
            return None;
        }
        let mean = values.iter().sum::<f64>() / n;
        Some((values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt())
    };
    let metrics = report
        .metrics
        .iter()
        .map(|(&key, v)| {
            (
                key,
                CheckedMetric {
                    value: v.value,
                    refined_basis: v.refined[Refinement::Basis.name()],
                    rel_change: v.max_rel_change,
                    limit: v.limit,
                    converged: v.converged,
                    sample_std_dev: spread(key),
                },
            )
        })
        .collect();
    Ok(NumericalCheckJson {
        basis: report.basis,
        refined_basis: report.refined_basis,
        converged: report.converged,
        metrics,
    })
}

fn constraints_json(c: &Constraints, best: &PointEvaluation) -> ConstraintsJson {
    let scale = |l: &crate::problem::study::LinearConstraint| {
        (l.omega * c.omega[1]).abs() + (l.v0 * c.v0[1]).abs() + l.upper.abs()
    };
    ConstraintsJson {
        omega_rad_s: c.omega,
        v0_m_s: c.v0,
        linear: c
            .linear
            .iter()
            .map(|l| {
                let value = l.omega * best.omega_rad_s + l.v0 * best.v0_m_s;
                LinearJson {
                    label: l.label,
                    omega_coefficient: l.omega,
                    v0_coefficient: l.v0,
                    upper: l.upper,
                    value_at_optimum: value,
                    active: (l.upper - value).abs() <= 1e-3 * scale(l),
                }
            })
            .collect(),
        chance: best.chance.clone(),
    }
}

pub(super) fn evaluation_json(p: &PointEvaluation) -> EvaluationJson {
    EvaluationJson {
        omega_rad_s: p.omega_rad_s,
        v0_m_s: p.v0_m_s,
        omega_rpm: p.omega_rpm,
        v0_m_per_h: p.v0_m_per_h,
        objective: p.objective,
        feasible: p.feasible,
        failure: p.failure.clone(),
        mean_metrics: p.mean_metrics.clone(),
    }
}

/// Run the optimisation and write its report; returns the outcome for `batch`. `quiet`: no
/// progress; `print`: the result table and the numerical check on the terminal.
pub fn solve_and_report(
    problem: &Problem,
    problem_file: &Path,
    out: &Path,
    resume: bool,
    quiet: bool,
    print: bool,
) -> anyhow::Result<SolveOutcome> {
    let clock = Instant::now();
    let cache = study::open_cache(out, resume)?;
    let settings = &problem.study.optimizer;
    let per_point = problem.study.samples.max(1) as u64;
    let bar = study::progress_bar(quiet, settings.budget() as u64 * per_point, "solve");
    let ev = study::evaluator(problem, Some(&cache), &bar)?;
    let bar2 = bar.clone();
    let outcome = solve::solve(
        problem,
        &ev,
        Some(Box::new(move |it: &crate::optimize::Iterate| {
            bar2.set_message(format!("iteration {} merit {:.3}", it.iteration, it.merit));
        })),
    )?;
    bar.finish_and_clear();
    let check = match outcome.best.as_ref() {
        Some(best) => {
            if !quiet {
                eprintln!("checking the basis at the optimum (nominal parameters, basis x1.5) …");
            }
            Some(numerical_check(problem, best).map_err(|e| {
                anyhow::anyhow!(
                    "basis check at the optimum of {}: {e}",
                    problem_file.display()
                )
            })?)
        }
        None => None,
    };
    let work = WorkJson::of(&ev, clock.elapsed().as_secs_f64());
    write_report(problem, problem_file, out, &outcome, work, check.as_ref())?;
    if print {
        print_summary(problem, out, &outcome, &ev);
        if let Some(c) = &check {
            print_check(c);
        }
    }
    Ok(outcome)
}

fn write_report(
    problem: &Problem,
    problem_file: &Path,
    out: &Path,
    outcome: &SolveOutcome,
    work: WorkJson,
    check: Option<&NumericalCheckJson>,
) -> anyhow::Result<()> {
    let study_ = &problem.study;
    let constraints = study_
        .constraints
        .as_ref()
        .expect("solve checked constraints");
    let best = outcome.best.as_ref();
    let (quantity, unit) = match study_.quantity {
        Quantity::Rop => ("mean_rop_m_per_h", "m/h"),
        Quantity::Efficiency => ("efficiency", "1"),
    };
    let json = SolutionJson {
        problem: &problem.name,
        problem_file: problem_file.display().to_string(),
        record: super::ProblemRecord::of(problem),
        version: crate::VERSION,
        seed: study_.seed,
        samples: study_.samples,
        method: outcome.method.name(),
        termination: &outcome.termination,
        status: outcome.status,
        optimum: best.map(PointJson::of),
        objective: best.map(|b| ObjectiveJson {
            score: b.objective.expect("best is scored"),
            quantity,
            quantity_unit: unit,
            statistic: study_.statistic,
            quantity_value: b.quantity.expect("best is scored"),
            risk: b.risk.clone(),
        }),
        metrics: best.map(|b| b.mean_metrics.clone()),
        metrics_per_sample: best.map(|b| b.samples.clone()),
        constraints: best.map(|b| constraints_json(constraints, b)),
        evaluations: outcome.evaluations.iter().map(evaluation_json).collect(),
        path: &outcome.path,
        work,
        numerical_check: check,
    };
    report::write_json_atomic(&out.join("solution.json"), &json)?;
    super::study_plots::solve_plots(problem, out, outcome)?;
    Ok(())
}

fn print_summary(
    problem: &Problem,
    out: &Path,
    outcome: &SolveOutcome,
    ev: &crate::study::RobustEvaluator,
) {
    use std::sync::atomic::Ordering::Relaxed;
    println!(
        "{}: {} points evaluated by {} ({} simulations run, {} from the cache); {}",
        problem.name,
        outcome.evaluations.len(),
        outcome.method.name(),
        ev.counters.simulated.load(Relaxed),
        ev.counters.cached.load(Relaxed),
        outcome.termination
    );
    study::print_table(&outcome.evaluations);
    let label = if outcome.status.is_optimum() {
        "optimum".to_string()
    } else {
        format!(
            "best point found, NOT an optimum ({})",
            outcome.status.text()
        )
    };
    study::print_best(outcome.best.as_ref(), &label, "no feasible point was found");
    println!("  results in {}", out.display());
}

fn print_check(c: &NumericalCheckJson) {
    println!(
        "numerical check at the optimum (nominal parameters; basis {} → {}): {}",
        c.basis,
        c.refined_basis,
        if c.converged {
            "converged"
        } else {
            "NOT converged"
        }
    );
    println!(
        "  {:<22} {:>12} {:>12} {:>9} {:>6} {:>14}",
        "metric", "nominal", "refined", "change", "limit", "sample std dev"
    );
    for (key, m) in &c.metrics {
        println!(
            "  {key:<22} {:>12} {:>12} {:>8.2}% {:>5.0}% {:>14}",
            super::verify::significant(m.value),
            super::verify::significant(m.refined_basis),
            100.0 * m.rel_change,
            100.0 * m.limit,
            m.sample_std_dev
                .map_or("n/a (1 sample)".to_string(), super::verify::significant)
        );
    }
}

pub fn run(args: &SolveArgs) -> anyhow::Result<()> {
    let problem = Problem::load(&args.problem)?;
    let out = study::out_dir(&args.out, &problem, "solve");
    let outcome = solve_and_report(&problem, &args.problem, &out, args.resume, args.quiet, true)?;
    anyhow::ensure!(
        outcome.best.is_some(),
        "no feasible operating point was found; see {}",
        out.join("solution.json").display()
    );
    Ok(())
}
