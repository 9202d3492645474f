//! `drillopt solve PROBLEM`: the robust optimum, written to `solution.json` with plots.

use super::study::{self, PointJson, WorkJson};
use crate::objective::PointEvaluation;
use crate::objective::robust::{ChanceValue, RiskValue};
use crate::problem::Problem;
use crate::problem::study::{Constraints, Quantity};
use crate::report;
use crate::solve::{self, PathPoint, SolveOutcome};
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
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Serialize)]
struct ObjectiveJson {
    /// The score (maximised): statistic of the quantity minus the weighted risk terms.
    score: f64,
    quantity: &'static str,
    quantity_unit: &'static str,
    statistic: crate::objective::statistic::Statistic,
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
    version: &'a str,
    seed: u64,
    samples: usize,
    method: &'a str,
    termination: &'a str,
    status: &'a str,
    optimum: Option<PointJson>,
    objective: Option<ObjectiveJson>,
    metrics: Option<BTreeMap<String, f64>>,
    metrics_per_sample: Option<Vec<crate::objective::SampleResult>>,
    constraints: Option<ConstraintsJson>,
    evaluations: Vec<EvaluationJson>,
    path: &'a [PathPoint],
    work: WorkJson,
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

/// Run the optimisation and write its report; returns the outcome for `batch`.
pub fn solve_and_report(
    problem: &Problem,
    problem_file: &Path,
    out: &Path,
    resume: bool,
    quiet: bool,
) -> anyhow::Result<SolveOutcome> {
    let clock = Instant::now();
    let cache = study::open_cache(out, resume)?;
    let settings = &problem.study.optimizer;
    let per_point = problem.study.samples.max(1) as u64;
    let bar = study::progress_bar(quiet, settings.max_evaluations as u64 * per_point, "solve");
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
    let work = WorkJson::of(&ev, clock.elapsed().as_secs_f64());
    write_report(problem, problem_file, out, &outcome, work)?;
    if !quiet {
        print_summary(problem, out, &outcome, &ev);
    }
    Ok(outcome)
}

fn write_report(
    problem: &Problem,
    problem_file: &Path,
    out: &Path,
    outcome: &SolveOutcome,
    work: WorkJson,
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
        version: crate::VERSION,
        seed: study_.seed,
        samples: study_.samples,
        method: outcome.method.name(),
        termination: &outcome.termination,
        status: if best.is_some() {
            "solved"
        } else {
            "no feasible point"
        },
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
    };
    report::write_json_atomic(&out.join("solution.json"), &json)?;
    super::study_plots::solve_plots(problem, out, outcome)?;
    Ok(())
}

fn print_summary(
    problem: &Problem,
    out: &Path,
    outcome: &SolveOutcome,
    ev: &crate::objective::RobustEvaluator,
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
    study::print_best(
        outcome.best.as_ref(),
        "optimum",
        "no feasible point was found",
    );
    println!("  results in {}", out.display());
}

pub fn run(args: &SolveArgs) -> anyhow::Result<()> {
    let problem = Problem::load(&args.problem)?;
    let out = study::out_dir(&args.out, &problem, "solve");
    let outcome = solve_and_report(&problem, &args.problem, &out, args.resume, args.quiet)?;
    anyhow::ensure!(
        outcome.best.is_some(),
        "no feasible operating point was found; see {}",
        out.join("solution.json").display()
    );
    Ok(())
}
