//! `drillopt solve PROBLEM`: the robust optimum, written to `solution.json` with plots.

use super::study;
use crate::problem::Problem;
use crate::report::{self, SolutionJson, WorkJson};
use crate::solve::{self, NumericalCheck, SolveOutcome};
use crate::units::UnitSystem;
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct SolveArgs {
    /// Problem file (TOML) with [constraints] and, optionally, [uncertain], [objective], [optimizer].
    pub problem: PathBuf,
    /// Most design points the optimizer evaluates [default: optimizer.max_evaluations]; an
    /// integer in [3, 100000] (EGO: above optimizer.initial_design; not for method = "grid").
    /// Recorded in solution.json (`overrides`).
    #[arg(long, value_name = "N", value_parser = super::whole_number, allow_hyphen_values = true)]
    pub budget: Option<usize>,
    #[command(flatten)]
    pub run: super::study::RunArgs,
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
    units: UnitSystem,
) -> anyhow::Result<(SolveOutcome, Option<NumericalCheck>)> {
    let clock = Instant::now();
    let cache = study::open_cache(out, resume, quiet)?;
    let settings = &problem.study.optimizer;
    let per_point = problem.study.samples.max(1) as u64;
    // Multi-fidelity: the problem at [optimizer.explore]'s fidelity explores, the full confirms.
    let explore = problem.study.explore.as_ref().map(|e| e.apply(problem));
    let simulations = match (&explore, &problem.study.explore) {
        (Some(x), Some(e)) => {
            settings.budget() as u64 * x.study.samples.max(1) as u64
                + (e.confirm + e.refine) as u64 * per_point
        }
        _ => settings.budget() as u64 * per_point,
    };
    // Before any work: the points' samples, and the numerical check's runs at the optimum.
    let mut work = study::study_work(problem, 0);
    work.simulations = simulations + 8;
    study::check_cost(&work, problem_file, problem, "solve", quiet)?;
    let bar = study::progress_bar(
        quiet,
        simulations,
        problem.study.sequential.is_some(),
        "solve",
    );
    let ev = study::evaluator(problem, Some(&cache), &bar, quiet)?;
    let explore_ev = explore
        .as_ref()
        .map(|x| study::explore_evaluator(x, Some(&cache), &bar))
        .transpose()?;
    let bar2 = bar.clone();
    let on_iterate: Option<crate::optimize::IterateCallback> =
        Some(Box::new(move |it: &crate::optimize::Iterate| {
            bar2.set_message(format!("iteration {} merit {:.3}", it.iteration, it.merit));
        }));
    let outcome = match &explore_ev {
        Some(x) => solve::solve_multi_fidelity(problem, &ev, x, on_iterate)?,
        None => solve::solve(problem, &ev, on_iterate)?,
    };
    bar.finish_and_clear();
    let check = match outcome.best.as_ref() {
        Some(best) => {
            if !quiet {
                eprintln!(
                    "checking the numbers at the optimum (nominal parameters; verify's refinements: {} and the perturbation of Ω) …",
                    crate::verify::refinements(problem)
                        .iter()
                        .map(|r| r.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
            Some(
                solve::numerical_check(problem, best, |name| {
                    if !quiet {
                        eprintln!("  {name} run done");
                    }
                })
                .map_err(|e| {
                    anyhow::anyhow!(
                        "numerical check at the optimum of {}: {e}",
                        problem_file.display()
                    )
                })?,
            )
        }
        None => None,
    };
    let work = WorkJson::of_fidelities(&ev, explore_ev.as_ref(), clock.elapsed().as_secs_f64());
    // The report: solution.json (SI), evaluations.csv and the plots (in `units`).
    let json = SolutionJson::of(problem, problem_file, &outcome, work, check.as_ref());
    report::write_json_atomic(&out.join("solution.json"), &json)?;
    report::write_evaluations_csv(out, problem, &ev.samples, &outcome.evaluations, units)?;
    super::study_plots::solve_plots(problem, out, &outcome, units)?;
    if print {
        print_summary(
            problem,
            problem_file,
            out,
            &outcome,
            &ev,
            explore_ev.as_ref(),
            units,
        );
        if let Some(c) = &check {
            print_check(c, units);
        }
    }
    Ok((outcome, check))
}

fn print_summary(
    problem: &Problem,
    problem_file: &Path,
    out: &Path,
    outcome: &SolveOutcome,
    ev: &crate::study::RobustEvaluator,
    explore: Option<&crate::study::RobustEvaluator>,
    units: UnitSystem,
) {
    use std::sync::atomic::Ordering::Relaxed;
    let t = study::TableUnits::new(units, problem.study.quantity);
    let work = |ev: &crate::study::RobustEvaluator| {
        format!(
            "{} run, {} from the cache",
            crate::units::count(ev.counters.simulated.load(Relaxed), "simulation"),
            ev.counters.cached.load(Relaxed)
        )
    };
    let simulations = match explore {
        Some(x) => format!("explore fidelity: {}; full fidelity: {}", work(x), work(ev)),
        None => work(ev),
    };
    println!(
        "{}: {} evaluated by {} ({simulations}); {}",
        problem.name,
        crate::units::count(outcome.evaluations.len(), "point"),
        outcome.method.name(),
        outcome.termination
    );
    match &outcome.confirmation {
        Some(c) => {
            println!("  explore fidelity: {}", c.explore.describe());
            study::print_fidelity_table(&outcome.evaluations, &t);
        }
        None => study::print_table(&outcome.evaluations, &t),
    }
    // Points whose simulations failed are infeasible to the optimizer for a numerical reason,
    // not a physical one: said, so that an optimum next to them is read with care.
    let failed: Vec<&crate::study::PointEvaluation> = (outcome.evaluations.iter())
        .filter(|p| {
            p.samples
                .iter()
                .any(|s| matches!(s.outcome, crate::study::SampleOutcome::Failed(_)))
        })
        .collect();
    if let Some(first) = failed.first() {
        println!(
            "  note: {} of {} points had a simulation that failed (a numerical failure, counted infeasible; the first at Ω = {:.1} rpm: {}); evaluations.csv's `failure` column says each",
            failed.len(),
            outcome.evaluations.len(),
            first.omega_rpm,
            first
                .samples
                .iter()
                .find_map(|s| match &s.outcome {
                    crate::study::SampleOutcome::Failed(why) => Some(why.as_str()),
                    _ => None,
                })
                .unwrap_or("")
        );
    }
    let label = if outcome.status.is_optimum() {
        "optimum".to_string()
    } else {
        format!(
            "best point found, NOT an optimum ({})",
            outcome.status.text()
        )
    };
    let held_by = || {
        if let (Some(b), Some(k)) = (&outcome.best, &problem.study.constraints) {
            study::print_held_by(k, b, &outcome.evaluations, &t);
        }
        if let Some(b) = &outcome.best {
            for w in crate::solve::warnings(b, &problem.study.metrics_named()) {
                println!("  warning: {w}");
            }
        }
    };
    let Some(c) = &outcome.confirmation else {
        study::print_best(
            outcome.best.as_ref(),
            &label,
            "no feasible point was found",
            &t,
            problem_file,
        );
        held_by();
        println!("  results in {}", out.display());
        return;
    };
    study::print_best(
        outcome.best.as_ref(),
        &format!("{label} (full fidelity)"),
        "no confirmed candidate is feasible at full fidelity",
        &t,
        problem_file,
    );
    held_by();
    match outcome.best.as_ref().map(|b| c.explore_of(b)) {
        Some(Some(x)) => println!(
            "  the same point at the explore fidelity: score {:.3} ({})",
            t.score.1 * x.objective.unwrap_or(f64::NAN),
            crate::units::count(x.samples_used, "sample")
        ),
        Some(None) => println!(
            "  found by the full-fidelity refinement: not evaluated at the explore fidelity"
        ),
        None => {}
    }
    println!("  results in {}", out.display());
}

fn print_check(c: &NumericalCheck, units: UnitSystem) {
    let unused_moved: Vec<&str> = c
        .metrics
        .iter()
        .filter(|(_, m)| !m.used && !m.converged)
        .map(|(k, _)| *k)
        .collect();
    // Which refinements moved a metric the problem uses beyond its limit.
    let mut beyond: Vec<&str> = (c.metrics.values())
        .filter(|m| m.used)
        .flat_map(|m| m.beyond_limit.iter().copied())
        .collect();
    beyond.sort_unstable();
    beyond.dedup();
    let sensitive: Vec<&str> = (c.metrics.iter())
        .filter(|(_, m)| m.used && m.verdict == crate::verify::Verdict::Sensitive)
        .map(|(k, _)| *k)
        .collect();
    let verdict = match (c.converged, unused_moved.is_empty()) {
        (true, true) => "converged".to_string(),
        (true, false) => format!(
            "converged on every metric this problem uses (not converged, and not used by its \
             score or constraints: {})",
            unused_moved.join(", ")
        ),
        (false, _) => {
            let mut why = Vec::new();
            if !beyond.is_empty() {
                why.push(format!(
                    "moved beyond its limit by the {} refinement",
                    beyond.join(", ")
                ));
            }
            if !sensitive.is_empty() {
                why.push(format!(
                    "{} sensitive to a 1e-4 change of Ω: the window does not determine it",
                    sensitive.join(", ")
                ));
            }
            format!(
                "NOT converged (a metric this problem uses {})",
                why.join("; ")
            )
        }
    };
    println!(
        "numerical check at the optimum (nominal parameters; basis {} → {}; {}): {verdict}",
        c.basis,
        c.refined_basis,
        c.runs.join(", "),
    );
    print!("  {:<22} {:>7} {:>12}", "metric", "unit", "nominal");
    let refinements: Vec<&str> = c
        .runs
        .iter()
        .copied()
        .filter(|r| *r != "perturbed")
        .collect();
    for r in &refinements {
        print!(" {r:>12}");
    }
    println!(
        " {:>12} {:>9} {:>6} {:>5} {:>14}",
        "perturbed", "change", "limit", "used", "sample std dev"
    );
    for (key, m) in &c.metrics {
        // In the units of the rest of the terminal (kN, kN·m, MPa, m/h, % or their field units).
        let d = crate::report::MetricDisplay::of_in(key, units);
        let show = |si: f64| crate::units::significant(d.value(si));
        print!("  {key:<22} {:>7} {:>12}", d.unit, show(m.value));
        for r in &refinements {
            print!(
                " {:>12}",
                m.refined.get(r).map_or("-".to_string(), |&v| show(v))
            );
        }
        println!(
            " {:>12} {:>8.2}% {:>5.0}% {:>5} {:>14}",
            m.perturbed.map_or("-".to_string(), show),
            100.0 * m.rel_change,
            100.0 * m.limit,
            if m.used { "yes" } else { "no" },
            m.sample_std_dev.map_or("n/a (1 sample)".to_string(), show)
        );
    }
}

pub fn run(args: &SolveArgs, units: UnitSystem) -> anyhow::Result<()> {
    let mut problem = Problem::load(&args.problem)?;
    if let Some(w) = super::simulate::depth_of_cut_warning(&problem.model) {
        eprintln!("{w}");
    }
    study::apply_overrides(&mut problem, &args.problem, &args.run, args.budget)?;
    study::start_threads(args.run.threads)?;
    let (out, _out_lock) = study::out_dir(&args.run.out, &problem, "solve")?;
    let (outcome, _) = solve_and_report(
        &problem,
        &args.problem,
        &out,
        args.run.resume,
        args.run.quiet,
        true,
        units,
    )?;
    anyhow::ensure!(
        outcome.best.is_some(),
        "no feasible operating point was found; see {}",
        out.join("solution.json").display()
    );
    Ok(())
}
