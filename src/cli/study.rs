//! What `solve`, `compare`, `map` and `batch` share: the output folder, the evaluation cache, the
//! robust evaluator with its progress bar, and the terminal table (the JSON shapes are
//! [`crate::report`]'s).

use crate::cache::EvalCache;
use crate::problem::Problem;
use crate::study::{PointEvaluation, RobustEvaluator};
use crate::units::UnitSystem;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Where a study command writes and whether it resumes: the options `solve`, `map`, `compare` and
/// `batch` share.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// Output directory [default: results/<problem>/<command>; for batch, <out>/<problem> per
    /// problem, default results/batch/<problem>]: the JSON report, plots and the evaluation
    /// cache (cache.jsonl).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Continue an interrupted run: reuse every finished simulation of the evaluation cache in the
    /// output directory.
    #[arg(long)]
    pub resume: bool,
    /// No progress bar or messages; the result is still printed (solve: the table and the
    /// optimum; map: every node and the best; compare: the table; batch: the pass/fail table).
    #[arg(long)]
    pub quiet: bool,
    /// Monte Carlo samples per point [default: the problem's uncertain.samples]; an integer in
    /// [1, 10000], more than 1 only with [[uncertain.parameter]]. Recorded in the report's
    /// header (`samples`, `overrides`).
    #[arg(long, value_name = "N", value_parser = super::whole_number, allow_hyphen_values = true)]
    pub samples: Option<usize>,
    /// Threads that run the simulations [default: every core, or RAYON_NUM_THREADS]; an integer
    /// in [1, 1024]. Results do not depend on it; recorded in the report (`overrides`,
    /// `work.executor`).
    #[arg(long, value_name = "N", value_parser = super::whole_number, allow_hyphen_values = true)]
    pub threads: Option<usize>,
}

/// Apply the command-line overrides to a loaded problem: `--samples` (and `budget`, solve's
/// `--budget`) checked under their keys' rules, each refusal naming the flag, the key and the
/// problem file; `--threads` is only recorded here (see [`start_threads`]).
pub fn apply_overrides(
    problem: &mut Problem,
    file: &Path,
    run: &RunArgs,
    budget: Option<usize>,
) -> anyhow::Result<()> {
    if let Some(n) = run.samples {
        problem.study.override_samples(n).map_err(|why| {
            anyhow::anyhow!(
                "--samples (key `uncertain.samples` of {}): {why}",
                file.display()
            )
        })?;
        // More samples draw more values: each is checked as at load.
        if let Some(bad) = problem.study.inadmissible_draw(&problem.model) {
            anyhow::bail!(
                "--samples {n} (key `uncertain.samples` of {}): {bad}; narrow the law of uncertain.parameter[{}] or use fewer samples",
                file.display(),
                bad.parameter
            );
        }
    }
    if let Some(n) = budget {
        problem.study.override_budget(n).map_err(|e| {
            anyhow::anyhow!(
                "--budget (key `optimizer.max_evaluations` of {}): {}",
                file.display(),
                if e.key == "max_evaluations" {
                    e.message
                } else {
                    format!("{e}")
                }
            )
        })?;
    }
    problem.study.overrides.threads = run.threads;
    Ok(())
}

/// Run the simulations on `--threads` threads (rayon's global pool), once per process; the
/// count is checked against [1, 1024].
pub fn start_threads(threads: Option<usize>) -> anyhow::Result<()> {
    let Some(n) = threads else {
        return Ok(());
    };
    anyhow::ensure!(
        crate::problem::study::THREADS.contains(&n),
        "--threads must be an integer in [1, 1024], got {n}"
    );
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| anyhow::anyhow!("--threads {n}: {e}"))
}

/// Where a command writes, created and locked for this run (see [`super::OutDirLock`]): `--out`
/// or `results/<problem>/<command>/`.
pub fn out_dir(
    out: &Option<PathBuf>,
    problem: &Problem,
    command: &str,
) -> anyhow::Result<(PathBuf, super::OutDirLock)> {
    let dir = out
        .clone()
        .unwrap_or_else(|| Path::new("results").join(&problem.name).join(command));
    let lock = super::create_out_dir(&dir)?;
    Ok((dir, lock))
}

/// The work of a study of `points` operating points on `problem` (its samples, mesh, basis and
/// window; the threads of the pool).
pub fn study_work(problem: &Problem, points: usize) -> crate::study::cost::Work {
    let samples = problem.study.samples.max(1);
    // Samples that change the linear operators are built each, in parallel; else the nominal
    // model is built once and copied.
    let rebuild = problem
        .study
        .uncertain
        .iter()
        .any(|u| u.key.enters(&problem.model) == crate::model::Enters::LinearOperators);
    crate::study::cost::Work {
        elements: problem.mesh.elements,
        modes: crate::study::cost::basis_size(&problem.mesh.basis),
        simulations: (points as u64).saturating_mul(samples as u64),
        seconds_each: problem.simulation.duration,
        // One model per sample (built, or the nominal one copied).
        models_held: samples,
        concurrent: if rebuild {
            rayon::current_num_threads()
        } else {
            1
        },
        holds_results: true,
        unreduced: false,
        eigensolves: 0,
    }
}

/// Refuses `work` when its estimated peak memory exceeds what the machine has available,
/// naming the input that drives it and its value; warns (unless `quiet`) when its CPU time may
/// pass [`crate::study::cost::WARN_CPU_HOURS`]. `file` and `command` name the run.
pub fn check_cost(
    work: &crate::study::cost::Work,
    file: &Path,
    problem: &Problem,
    command: &str,
    quiet: bool,
) -> anyhow::Result<()> {
    use crate::study::cost::{self, Driver};
    let e = work.estimate();
    let elements = work.elements;
    if let Some(available) = cost::available_memory()
        && e.peak_bytes > available
    {
        let (driver, bytes) = e.largest;
        let what = match driver {
            Driver::Mesh => format!(
                "{} to assemble and project the {elements}-element mesh ({} DOFs, dense){}; lower mesh.elements",
                cost::bytes_text(bytes),
                work.dofs(),
                if work.concurrent > 1 {
                    format!(
                        ", {} models at once on {} threads (--threads)",
                        work.concurrent, work.concurrent
                    )
                } else {
                    String::new()
                },
            ),
            Driver::Models => format!(
                "{} for {} models of {} basis vectors on {elements} elements; fewer uncertain.samples (--samples) or a smaller mesh.basis",
                cost::bytes_text(bytes),
                work.models_held,
                work.modes,
            ),
            Driver::Eigensolve => format!(
                "{} for the dense eigen-solve of {} states at each rotation speed{}",
                cost::bytes_text(bytes),
                work.states(),
                if work.unreduced {
                    format!(
                        " (the unreduced {elements}-element model); drop --unreduced or lower mesh.elements"
                    )
                } else {
                    "; a smaller mesh.basis".to_string()
                }
            ),
            Driver::Results => format!(
                "{} for the results of {} simulations; fewer uncertain.samples (--samples) or fewer points ({})",
                cost::bytes_text(bytes),
                work.simulations,
                match command {
                    "map" => "--grid",
                    "compare" => "fewer --point",
                    _ => "--budget, optimizer.max_evaluations",
                }
            ),
        };
        anyhow::bail!(
            "{}: {command} would need about {} of memory, more than the {} available to it (the machine's free memory, or the process's limit): {what}",
            file.display(),
            cost::bytes_text(e.peak_bytes),
            cost::bytes_text(available),
        );
    }
    if !quiet && e.cpu_seconds > cost::WARN_CPU_HOURS * 3600.0 && work.eigensolves > 0 {
        eprintln!(
            "note: {command} of {} may take up to about {} of CPU time ({} dense eigen-solves of {} states{}; an upper estimate)",
            problem.name,
            cost::seconds_text(e.cpu_seconds),
            work.eigensolves,
            work.states(),
            if work.unreduced {
                format!(", the unreduced {elements}-element model")
            } else {
                String::new()
            },
        );
    } else if !quiet && e.cpu_seconds > cost::WARN_CPU_HOURS * 3600.0 {
        let threads = work.concurrent.max(1) as f64;
        eprintln!(
            "note: {command} of {} may take up to about {} of CPU time ({} simulation{} of {} s on {elements} elements and {} basis vectors{}; an upper estimate from the seed string's stick-slipping cost, a steady string costs far less), about {} on {} thread{}",
            problem.name,
            cost::seconds_text(e.cpu_seconds),
            work.simulations,
            if work.simulations == 1 { "" } else { "s" },
            crate::units::short(work.seconds_each),
            work.modes,
            if work.unreduced { ", unreduced" } else { "" },
            cost::seconds_text(e.cpu_seconds / threads),
            threads,
            if threads == 1.0 { "" } else { "s" },
        );
    }
    Ok(())
}

/// Open the evaluation cache `<out>/cache.jsonl`: continued with `resume`, else started afresh
/// (an old cache is kept beside as `cache.jsonl.old`).
/// Without `resume`, an earlier run's cache in `out` is moved aside to `cache.jsonl.old` (said on
/// standard error unless `quiet`), so that nothing is lost and the run starts afresh.
pub fn open_cache(out: &Path, resume: bool, quiet: bool) -> anyhow::Result<EvalCache> {
    let path = out.join("cache.jsonl");
    anyhow::ensure!(
        !EvalCache::in_use(&path)?,
        "{} is in use by another drillopt run; wait for it to finish or choose another --out",
        path.display()
    );
    if !resume && path.exists() {
        let old = out.join("cache.jsonl.old");
        std::fs::rename(&path, &old)
            .with_context(|| format!("moving the old cache {} aside", path.display()))?;
        if !quiet {
            eprintln!(
                "note: {} held an earlier run's evaluations; moved to {} (--resume reuses them instead)",
                path.display(),
                old.display()
            );
        }
    }
    Ok(EvalCache::open(&path)?)
}

/// The progress bar of a study command: `total` simulations, or at most `total` when
/// `at_most` (sequential sampling stops points early, so the bar may end short of its length).
pub fn progress_bar(quiet: bool, total: u64, at_most: bool, label: &str) -> ProgressBar {
    let of = if at_most { "at most " } else { "" };
    let bar = if quiet {
        ProgressBar::hidden()
    } else if !std::io::stderr().is_terminal() {
        // No terminal to draw on (a log file, a pipe): a plain line now and then instead.
        let bar = ProgressBar::hidden();
        bar.set_length(total);
        let label = label.to_owned();
        log_progress(&bar, move |b| {
            format!(
                "{label}: {} of {of}{} simulations",
                b.position(),
                b.length().unwrap_or(0)
            )
        });
        bar
    } else {
        ProgressBar::new(total)
    };
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{spinner}} {label} [{{bar:40}}] {{pos}} of {of}{{len}} simulations {{msg}} ({{elapsed}}, eta {{eta}})"
        ))
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}

/// Seconds between two progress lines when standard error is not a terminal.
pub const LOG_EVERY_S: u64 = 5;

/// Every [`LOG_EVERY_S`] seconds until `bar` is finished (or dropped), the line `line` gives with
/// the elapsed time, on standard error: the progress of a run whose output goes to a log, where
/// the bar does not draw.
pub fn log_progress(bar: &ProgressBar, line: impl Fn(&ProgressBar) -> String + Send + 'static) {
    let weak = bar.downgrade();
    std::thread::spawn(move || {
        let start = std::time::Instant::now();
        let mut next = LOG_EVERY_S;
        loop {
            std::thread::sleep(std::time::Duration::from_millis(200));
            let Some(bar) = weak.upgrade() else {
                return;
            };
            if bar.is_finished() {
                return;
            }
            let elapsed = start.elapsed().as_secs();
            if elapsed >= next {
                next = elapsed + LOG_EVERY_S;
                eprintln!(
                    "{} ({} min {:02} s)",
                    line(&bar),
                    elapsed / 60,
                    elapsed % 60
                );
            }
        }
    });
}

/// The evaluator of a problem, ticking `bar` after every simulation.
pub fn evaluator<'a>(
    problem: &'a Problem,
    cache: Option<&'a EvalCache>,
    bar: &'a ProgressBar,
    quiet: bool,
) -> anyhow::Result<RobustEvaluator<'a>> {
    let ev = RobustEvaluator::new(problem, cache)
        .context("setting up the robust evaluation")?
        .with_progress(move || bar.inc(1));
    // Asked for and left out: every sample's basis goes without the steady-state shapes.
    if let Some(Err(warning)) = super::steady_shapes_line(
        &problem.source,
        ev.steady_shapes,
        crate::units::UnitSystem::Metric,
    ) {
        bar.suspend(|| eprintln!("{warning}"));
    }
    if let Some(c) = cache {
        // A multi-fidelity solve's explore runs share the cache under their own model hash.
        let explore = problem
            .study
            .explore
            .as_ref()
            .map(|e| crate::study::model_hash(&e.apply(problem)));
        let stale = c.other_models_than(&[Some(ev.model_hash), explore]);
        if stale > 0 && !quiet {
            eprintln!(
                "{stale} cached results in {} are of other numerics or another problem: ignored",
                c.path().display()
            );
        }
    }
    // Under mpirun the simulations go to the other ranks.
    #[cfg(feature = "mpi")]
    let ev = if crate::study::mpi::ranks() > 1 {
        ev.with_executor(crate::study::mpi::MpiExecutor::new(problem))
    } else {
        ev
    };
    Ok(ev)
}

/// The explore evaluator of a multi-fidelity solve: `explore` (the problem at
/// `[optimizer.explore]`'s fidelity, [`crate::problem::study::Explore::apply`]) on the same cache
/// and progress bar, its evaluations tagged `explore`. Refused under MPI: the worker ranks
/// rebuild the problem from its file and would simulate at the full fidelity.
pub fn explore_evaluator<'a>(
    explore: &'a Problem,
    cache: Option<&'a EvalCache>,
    bar: &'a ProgressBar,
) -> anyhow::Result<RobustEvaluator<'a>> {
    #[cfg(feature = "mpi")]
    anyhow::ensure!(
        crate::study::mpi::ranks() <= 1,
        "{}: [optimizer.explore] (multi-fidelity) does not run under mpirun yet: the worker ranks would simulate the full fidelity; run it without mpirun, or remove the section",
        explore.source.display()
    );
    Ok(RobustEvaluator::new(explore, cache)
        .context("setting up the explore fidelity's robust evaluation")?
        .with_progress(move || bar.inc(1))
        .with_fidelity(crate::study::Fidelity::Explore))
}

/// How the study's terminal tables show numbers: the unit system, and the unit of the score
/// (that of the study's quantity: m/h or ft/h for ROP, none for efficiency; risk weights convert
/// every penalty into it, so the score converts as the quantity does).
#[derive(Debug, Clone, Copy)]
pub struct TableUnits {
    pub units: UnitSystem,
    /// The score's unit ("" for a pure number) and the factor from the score's metric unit.
    pub score: (&'static str, f64),
}

impl TableUnits {
    /// The table of a study whose score is a statistic of `quantity`, in `units`.
    pub fn new(units: UnitSystem, quantity: crate::problem::study::Quantity) -> Self {
        let metric = crate::report::MetricDisplay::of(quantity.metric()).unit;
        TableUnits {
            units,
            score: units.convert_metric(metric),
        }
    }

    /// `value`, given in the metric unit `unit` ("m/h", "kN"), in this table's unit.
    fn of(&self, unit: &'static str, value: f64) -> f64 {
        self.units.from_metric(unit, value).1
    }

    /// The unit of this table for the metric unit `unit`.
    fn unit(&self, unit: &'static str) -> &'static str {
        self.units.convert_metric(unit).0
    }
}

/// The terminal table of evaluated points.
pub fn print_table(points: &[PointEvaluation], t: &TableUnits) {
    println!("{}", table_header(kind_of(points), t));
    for p in points {
        println!("{}", table_row(p, t));
    }
}

/// The terminal table of a multi-fidelity solve: every row marked with its fidelity.
pub fn print_fidelity_table(points: &[PointEvaluation], t: &TableUnits) {
    println!("fidelity {}", table_header(kind_of(points), t));
    for p in points {
        println!("{:<8} {}", p.fidelity.name(), table_row(p, t));
    }
}

/// `word` as one shell word: as it is when it holds only characters no shell reads specially,
/// else in single quotes (a quote inside written '\\'').
fn shell_word(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "/._-+,:=@%".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

/// `--point OMEGA,SET` of `op` with the digits that reproduce it: the evaluator snaps every
/// point to 12 significant digits in rpm, m/h or kN ([`OperatingPoint::canonical`]), so these
/// digits give the same bits, the same cache entry and the same score (a point printed to one
/// decimal, 111.1 rpm for 111.111111111, is another point: on a depth-of-cut line it was
/// infeasible by round-off, issue 33).
pub fn point_flag(op: &crate::model::OperatingPoint) -> String {
    let c = op.canonical();
    format!(
        "--point {}rpm,{}{}",
        crate::units::round_point(crate::units::to_rpm(c.omega)),
        crate::units::round_point(c.shown_set_point()),
        c.kind().unit()
    )
}

/// The best point's line, or `none` when there is none, and the `compare` command line that
/// evaluates it again (`problem`: the file the study read).
pub fn print_best(
    best: Option<&PointEvaluation>,
    label: &str,
    none: &str,
    t: &TableUnits,
    problem: &std::path::Path,
) {
    let (score_unit, score) = t.score;
    let score_unit = if score_unit.is_empty() {
        String::new()
    } else {
        format!(" {score_unit}")
    };
    match best {
        Some(b) => println!(
            "{label}: Ω = {:.1} rpm, {} = {:.2} {}, score {:.3}{score_unit}{} ({})",
            b.omega_rpm,
            b.op().kind().symbol(),
            t.of(b.op().kind().unit(), b.op().shown_set_point()),
            t.unit(b.op().kind().unit()),
            score * b.objective.unwrap_or(f64::NAN),
            b.score_half_width
                .map_or_else(String::new, |h| format!(" ± {:.3}", score * h)),
            crate::units::count(b.samples_used, "sample")
        ),
        None => println!("{none}"),
    }
    if let Some(b) = best {
        println!(
            "  the same point again: drillopt compare {} {} (the rounded figures above are \
             another point)",
            shell_word(&problem.display().to_string()),
            point_flag(&b.op())
        );
    }
}

/// Below this share of the score over the whole box, a bound at its limit holds the optimum by
/// a tie: the score is flat along it.
pub const TIE_SHARE: f64 = 0.01;

/// A note for a bound at its limit whose slope changes the score by `across` (score units, SI)
/// over the box's whole width, when that is less than [`TIE_SHARE`] of the score `score`: the
/// score is flat along the bound's variable, so the bound holds the optimum by a tie (helper-28:
/// "held by omega.max" on a score that did not depend on Ω). Empty otherwise.
fn tie_note(across: f64, score: Option<f64>, score_factor: f64, score_unit: &str) -> String {
    match score {
        Some(score) if across.abs() < TIE_SHARE * score.abs() => format!(
            "; the score is flat along it ({:+.3}{}{} over the box's whole width, {:.2} % of the score): the bound holds the optimum by a tie, and a point inside scores about the same",
            score_factor * across,
            if score_unit.is_empty() { "" } else { " " },
            score_unit,
            100.0 * across.abs() / score.abs()
        ),
        _ => String::new(),
    }
}

/// What holds `best` (`solve`'s optimum): the study's constraints at their limit
/// ([`crate::solve::activity`]), each with its margin, or that none does; and the rig's limits
/// that commanded an autodriller most of the window (simulator limits, not the study's).
pub fn print_held_by(
    constraints: &crate::problem::study::Constraints,
    best: &PointEvaluation,
    evaluated: &[PointEvaluation],
    t: &TableUnits,
) {
    let units = t.units;
    let activity = crate::solve::activity(constraints, best, evaluated);
    let held: Vec<String> = activity
        .iter()
        .filter(|a| a.at_limit)
        .map(|a| match a.name.strip_prefix("chance.") {
            Some(metric) => {
                let d = crate::report::MetricDisplay::of(metric).in_system(units);
                format!(
                    "{} ({} {} {} against {} {}, margin {:.1} %)",
                    a.name,
                    if best.samples_used > 1 {
                        "its deciding quantile"
                    } else {
                        "at"
                    },
                    crate::units::significant(d.value(a.value)),
                    d.unit,
                    crate::units::significant(d.value(a.limit)),
                    d.unit,
                    100.0 * a.margin
                )
            }
            None => a.name.clone(),
        })
        .collect();
    if held.is_empty() {
        println!("  held by no constraint of the study: an interior optimum of the score");
    } else {
        println!("  held by: {}", held.join("; "));
    }
    // What a binding bound costs: the local slope of the score (a plane through the points
    // evaluated around the optimum), per unit of the bound moved outward.
    let slope = crate::solve::score_slope(constraints, best, evaluated);
    // A bound of the box (Ω, or the set-point V0 or WOB) at its limit.
    let set_point = format!("{}.", constraints.kind.key());
    let bound_held = activity
        .iter()
        .any(|a| a.at_limit && (a.name.starts_with("omega.") || a.name.starts_with(&set_point)));
    if slope.is_none() && bound_held {
        println!(
            "  what moving a bound would change is not estimated: fewer than 3 feasible points \
             were evaluated within {:.0} % of the box around the optimum, or they spread less \
             than {:.0} % of it each way (a finer grid there, or a local method, gives it)",
            100.0 * crate::solve::FIT_RADIUS,
            100.0 * crate::solve::MIN_SPREAD
        );
    }
    if let Some(s) = slope {
        let kind = constraints.kind;
        let (set_unit, set_factor) = units.convert_metric(kind.unit());
        let (score_unit, score_factor) = t.score;
        // With another constraint at its limit too (a line, a chance constraint), moving one
        // bound alone does not move the optimum: the slope is what the score does, not what
        // the bound is worth.
        let bounds = [
            "omega.min",
            "omega.max",
            &format!("{}.min", kind.key()),
            &format!("{}.max", kind.key()),
        ]
        .map(String::from);
        let others = activity
            .iter()
            .filter(|a| a.at_limit && !bounds.contains(&a.name))
            .map(|a| a.name.as_str())
            .collect::<Vec<_>>();
        // The box's width along each variable, in the slope's units (rpm; m/h or kN).
        let omega_width =
            (constraints.omega[1] - constraints.omega[0]) * 60.0 / std::f64::consts::TAU;
        let set_width = (constraints.set_point[1] - constraints.set_point[0])
            * match kind {
                crate::model::SetPoint::Feed => 3600.0,
                crate::model::SetPoint::Wob => 1e-3,
            };
        for a in activity.iter().filter(|a| a.at_limit) {
            let (per, unit, across) = match a.name.rsplit_once('.') {
                Some(("omega", "min")) => (-s.per_rpm, "rpm", s.per_rpm * omega_width),
                Some(("omega", "max")) => (s.per_rpm, "rpm", s.per_rpm * omega_width),
                Some((k, "min")) if k == kind.key() => (
                    -s.per_set_point / set_factor,
                    set_unit,
                    s.per_set_point * set_width,
                ),
                Some((k, "max")) if k == kind.key() => (
                    s.per_set_point / set_factor,
                    set_unit,
                    s.per_set_point * set_width,
                ),
                _ => continue,
            };
            println!(
                "  {}: moving it 1 {unit} outward would change the score by about {:+.3}{}{} (the slope of a plane through {} points evaluated within {:.0} % of the box around the optimum{}){}",
                a.name,
                score_factor * per,
                if score_unit.is_empty() { "" } else { " " },
                score_unit,
                s.points,
                100.0 * s.radius,
                if others.is_empty() {
                    String::new()
                } else {
                    format!(
                        "; {} binds here too, so moving this bound alone does not move the optimum",
                        others.join(", ")
                    )
                },
                tie_note(across, best.objective, score_factor, score_unit)
            );
        }
    }
    let m = |k: &str| best.mean_metrics.get(k).copied().unwrap_or(0.0);
    for (key, what) in [
        ("wob_limit_fraction", "the autodriller's WOB limit"),
        (
            "torque_limit_fraction",
            "the autodriller's torque (or power) limit",
        ),
    ] {
        if m(key) > 0.5 {
            println!(
                "  and by the rig: {what} commands the block {:.0} % of the window",
                100.0 * m(key)
            );
        }
    }
}

/// One line of a terminal table for a point.
pub(super) fn table_row(p: &PointEvaluation, t: &TableUnits) -> String {
    let k = t.score.1;
    let score = p
        .objective
        .map_or_else(|| "   failed".to_string(), |s| format!("{:9.3}", k * s));
    let half_width = p
        .score_half_width
        .map_or_else(|| "       -".to_string(), |h| format!("±{:7.3}", k * h));
    let m = |k: &str| p.mean_metrics.get(k).copied().unwrap_or(f64::NAN);
    // An infeasible or failed point says why (the chance constraint and its estimate, the bound,
    // or the failed sample), as compare.json's `failure` does.
    let feasible = match (&p.failure, p.feasible) {
        (_, true) => "yes".to_string(),
        (Some(why), false) => format!("no: {why}"),
        (None, false) => "no".to_string(),
    };
    // A metric a failed point lacks is a dash, not NaN.
    let cell = |x: f64, width: usize, digits: usize| {
        if x.is_finite() {
            format!("{:>width$}", crate::units::fixed(x, digits))
        } else {
            format!("{:>width$}", "-")
        }
    };
    format!(
        "{:7.1} {:8.2} {} {} {:4} {} {} {} {} {} {feasible}",
        p.omega_rpm,
        t.of(p.op().kind().unit(), p.op().shown_set_point()),
        score,
        half_width,
        p.samples_used,
        cell(t.of("m/h", m("mean_rop_m_per_h")), 8, 3),
        cell(m("stick_slip_severity"), 6, 2),
        cell(100.0 * m("stick_fraction"), 7, 2),
        cell(m("impacts_per_s"), 9, 1),
        cell(t.of("kN", m("mean_wob_n") / 1e3), 8, 1),
    )
}

/// The set-point of a table's points (a study's points share one).
pub(super) fn kind_of(points: &[PointEvaluation]) -> crate::model::SetPoint {
    points
        .first()
        .map_or(crate::model::SetPoint::Feed, |p| p.op().kind())
}

/// `V0`: the feed set-point (the autodriller's, which the bit reaches only below its limits; the
/// ROP column is what it drilled), or under a hook load `Wset`, the WOB set-point (the `WOB kN`
/// column is the bit's mean WOB, the set-point less what the string's axial damping and wall
/// drag take); `±`: the half-width of the score's confidence interval (95 %
/// unless `uncertain.sequential.confidence` says otherwise); `n`: the samples the point used.
/// The score column's header is `score` and its unit.
pub(super) fn table_header(kind: crate::model::SetPoint, t: &TableUnits) -> String {
    let set_point = match kind {
        crate::model::SetPoint::Feed => format!("V0 {}", t.unit("m/h")),
        crate::model::SetPoint::Wob => format!("Wset {}", t.unit("kN")),
    };
    let score = match t.score.0 {
        "" => "score".to_owned(),
        unit => format!("score {unit}"),
    };
    format!(
        "    rpm {set_point:>8} {score:>9}        ±    n {:>8}    SSI stick %  impacts/s {:>7} feasible",
        format!("ROP {}", t.unit("m/h")),
        format!("WOB {}", t.unit("kN")),
    )
}

#[cfg(test)]
mod shell_word_tests {
    #[test]
    fn a_path_is_pasted_as_one_shell_word() {
        assert_eq!(
            super::shell_word("problems/field/well_1km.toml"),
            "problems/field/well_1km.toml"
        );
        assert_eq!(super::shell_word("my well.toml"), "'my well.toml'");
        assert_eq!(super::shell_word("it's.toml"), "'it'\\''s.toml'");
        assert_eq!(super::shell_word(""), "''");
    }
}

#[cfg(test)]
mod tie_note_tests {
    use super::*;

    #[test]
    fn a_bound_along_which_the_score_is_flat_holds_by_a_tie() {
        // A score of 7.62 m/h that changes by 0.004 m/h over the whole Ω box: 0.05 %.
        let note = tie_note(0.004, Some(7.62), 1.0, "m/h");
        assert!(
            note.contains(
                "flat along it (+0.004 m/h over the box's whole width, 0.05 % of the score)"
            ) && note.contains("by a tie"),
            "{note}"
        );
        // 5 % of the score: the bound is worth something; no note.
        assert_eq!(tie_note(0.38, Some(7.62), 1.0, "m/h"), "");
        assert_eq!(tie_note(0.0, None, 1.0, "m/h"), "");
    }
}
