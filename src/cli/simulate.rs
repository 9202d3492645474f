//! `drillopt simulate PROBLEM [--omega V] [--v0 V] [--duration S] [--out DIR] [--quiet]`: one
//! operating point through the nonlinear reduced-order simulator, with its time history, metrics
//! and the paper's Figures 3–5.

use crate::metrics::{self, MetricsConfig};
use crate::model::{OperatingPoint, TopDrive};
use crate::problem::{Dimension, Problem};
use crate::report::{self, ProblemRecord, RunStatus, SummaryJson};
use crate::sim;
use crate::units::{Shown, Shown::*, UnitSystem};
use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

/// The operating point and window of a one-point command (`simulate`, `verify`).
#[derive(Debug, Args)]
pub struct PointArgs {
    // `allow_hyphen_values`: a negative value such as `-1m/h` reaches our parser, which refuses
    // it naming the key and the admissible range, instead of clap reading it as a flag.
    // The help: the words below and the key's admissible range from the key table.
    #[arg(long, allow_hyphen_values = true, help = with_range(
        "Rotation speed with its unit, e.g. `60rpm` (rpm, rad/s, rev/s, Hz); a bare number is \
         refused [default: the problem's]",
        "operating_point.omega",
    ))]
    pub omega: Option<String>,
    // The help: the words below and the key's admissible range from the key table.
    #[arg(long, allow_hyphen_values = true, help = with_range(
        "Imposed axial velocity with its unit, e.g. `5m/h` (m/h, m/s, mm/s, m/min, ft/h); `0` is \
         off-bottom rotation; any other bare number is refused [default: the problem's]",
        "operating_point.v0",
    ))]
    pub v0: Option<String>,
    // The help: the words below and the key's admissible range from the key table.
    #[arg(long, allow_hyphen_values = true, help = with_range(
        "The hook load's WOB set-point with its unit, e.g. `50kN` (N, kN, klbf, lbf); only with \
         `top = \"hook_load\"`, whose set-point it is [default: the problem's]",
        "operating_point.wob",
    ))]
    pub wob: Option<String>,
    // The help: the words below and the key's admissible range from the key table.
    #[arg(long, allow_hyphen_values = true, help = with_range(
        "Simulated duration, e.g. `90` (seconds) or `2s`, `1.5min` [default: \
         simulation.duration]; the analysis window starts after simulation.settling_time (at \
         most half the duration)",
        "simulation.duration",
    ))]
    pub duration: Option<String>,
}

/// `help` followed by the admissible range of `key` from the key table
/// ([`crate::problem::keys::KEYS`]), in the unit a driller types: the help and the refusal
/// quote one range.
fn with_range(help: &str, key: &str) -> String {
    match crate::problem::keys::find(key) {
        Some(row) => {
            let (unit, factor) = crate::problem::keys::display_unit(key, row.spec.dimension);
            format!(
                "{help}; admissible: {}",
                row.spec.range.describe_in(unit, factor)
            )
        }
        None => help.to_string(),
    }
}

#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Problem file (TOML).
    pub problem: PathBuf,
    #[command(flatten)]
    pub point: PointArgs,
    /// Output directory [default: results/<problem>/simulate].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    // The help: the words below and the key's admissible range from the key table.
    #[arg(long, allow_hyphen_values = true, help = with_range(
        "Interval of the written time history (`timeseries.csv`, plots), e.g. `0.5ms`, or `step` \
         for every accepted adaptive step [default: simulation.sample_interval, 0.5 ms]; the \
         metrics read every accepted step whatever it is",
        "simulation.sample_interval",
    ))]
    pub sample_interval: Option<String>,
    /// Run the finite-element model without reduction (every free DOF; a reference for the
    /// reduced basis, for windows of a few seconds: about 100× the reduced model's cost).
    #[arg(long)]
    pub unreduced: bool,
}

/// Refuse a bare number for a rotation speed or an axial velocity on the command line: it would
/// be read in SI (`--omega 60` is 60 rad/s = 573 rpm), never what a driller means. 0 needs no
/// unit. `what` names the flag for the message, `example` shows how to write it.
pub(super) fn require_unit(what: &str, text: &str, dim: Dimension) -> anyhow::Result<()> {
    let t = text.trim();
    let Ok(v) = t.parse::<f64>() else {
        return Ok(());
    };
    if v == 0.0 {
        return Ok(());
    }
    let (example, units, si) = match dim {
        Dimension::AngularVelocity => (
            format!("{t}rpm"),
            "rpm, rad/s, rev/s, Hz",
            format!(
                "{t} rad/s = {} rpm",
                crate::units::short(crate::units::to_rpm(v))
            ),
        ),
        Dimension::Force => (
            format!("{t}kN"),
            "N, kN, MN, lbf, klbf",
            format!("{t} N = {} kN", crate::units::short(v / 1e3)),
        ),
        _ => (
            format!("{t}m/h"),
            "m/h, m/s, mm/s, m/min, ft/h",
            format!(
                "{t} m/s = {} m/h",
                crate::units::short(crate::units::to_m_per_h(v))
            ),
        ),
    };
    anyhow::bail!(
        "{what}: `{t}` has no unit; write it with one, e.g. {example} ({units}); a bare number would be read in SI ({si})"
    )
}

pub(super) fn parse_override(
    text: &Option<String>,
    flag: &str,
    dim: Dimension,
    default: f64,
) -> anyhow::Result<f64> {
    match text {
        None => Ok(default),
        Some(t) => {
            let key = match flag {
                "--omega" => "operating_point.omega",
                "--v0" => "operating_point.v0",
                "--wob" => "operating_point.wob",
                _ => "simulation.duration",
            };
            if flag != "--duration" {
                require_unit(&format!("{flag} (key `{key}`)"), t, dim)?;
            }
            let v = dim
                .parse(t)
                .with_context(|| format!("{flag} (key `{key}`)"))?;
            in_range(flag, key, t, v)?;
            // -0 is 0 (it printed as "V0 = -0.000 m/h").
            Ok(v + 0.0)
        }
    }
}

/// Refuse a command-line quantity outside the admissible range of the problem key it stands
/// for (`--omega`, `--point`: `operating_point.omega`; `--v0`; `--duration`), the range said
/// in the driller's unit of the key, the flag (`what`) and the key named. Every such key has a
/// range ([`crate::problem::keys::range_of`]); each excludes NaN and ±∞.
pub(super) fn in_range(what: &str, key: &str, text: &str, v: f64) -> anyhow::Result<()> {
    let r = crate::problem::keys::range_of(key).expect("a command-line quantity has a range");
    let (unit, factor) = match key {
        "operating_point.omega" => ("rpm", crate::units::from_rpm(1.0)),
        "operating_point.v0" => ("m/h", crate::units::from_m_per_h(1.0)),
        "operating_point.wob" => ("kN", 1e3),
        _ => ("s", 1.0),
    };
    anyhow::ensure!(
        r.contains(v),
        "{what} (key `{key}`) must be {}, got {}",
        r.describe_in(unit, factor),
        text.trim()
    );
    // A nonzero number that underflows to 0 in SI (5e-324 m/h) is not the 0 it became.
    let typed: f64 = text
        .trim()
        .trim_start_matches(['+', '-'])
        .split(|ch: char| !(ch.is_ascii_digit() || ".eE+-".contains(ch)))
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or(0.0);
    anyhow::ensure!(
        v != 0.0 || typed == 0.0,
        "{what} (key `{key}`) must be {}, got {}: so small a value underflows to 0",
        r.describe_in(unit, factor),
        text.trim()
    );
    Ok(())
}

/// The operating point and duration of a one-point command: the problem's, or the overrides
/// `--omega`, `--v0`, `--duration` (each with its unit, within the key's admissible range: V0 may
/// be 0, off-bottom rotation).
pub(super) fn point_and_duration(
    problem: &Problem,
    args: &PointArgs,
) -> anyhow::Result<(OperatingPoint, f64)> {
    let PointArgs {
        omega,
        v0,
        wob,
        duration,
    } = args;
    let base = problem.operating_point;
    let omega = parse_override(omega, "--omega", Dimension::AngularVelocity, base.omega)?;
    // Each top takes its own set-point: the other one's flag would be silently unused.
    let op = match problem.model.top.set_point() {
        crate::model::SetPoint::Feed => {
            anyhow::ensure!(
                wob.is_none(),
                "--wob is the set-point of top = \"hook_load\"; this problem's top takes --v0"
            );
            OperatingPoint::feed(
                omega,
                parse_override(v0, "--v0", Dimension::Velocity, base.v0)?,
            )
        }
        crate::model::SetPoint::Wob => {
            anyhow::ensure!(
                v0.is_none(),
                "--v0 is the feed of the other tops; under top = \"hook_load\" the set-point is --wob \
                 (the rock and the string decide the feed)"
            );
            OperatingPoint::hook_load(
                omega,
                parse_override(wob, "--wob", Dimension::Force, base.wob)?,
            )
        }
    };
    let duration = parse_override(
        duration,
        "--duration",
        Dimension::Time,
        problem.simulation.duration,
    )?;
    let settling = problem.simulation.settling_for(duration);
    if settling < problem.simulation.settling_time {
        // A caution, not an error (short runs are how a file is tried out): printed even with
        // --quiet, since the metrics then include part of what the file discards.
        eprintln!(
            "warning: --duration {} s is shorter than twice simulation.settling_time ({} s): the \
             analysis window starts at {} s, half the run, and holds part of what the file's \
             settling time discards",
            duration, problem.simulation.settling_time, settling
        );
    }
    Ok((op, duration))
}

/// The `--sample-interval` override: `step`, or a time with its unit in the admissible range of
/// `simulation.sample_interval`, no longer than the run.
fn sample_interval(
    text: &Option<String>,
    default: sim::SampleInterval,
    duration: f64,
) -> anyhow::Result<sim::SampleInterval> {
    const KEY: &str = "simulation.sample_interval";
    let Some(t) = text else {
        return Ok(default);
    };
    if t.trim() == "step" {
        return Ok(sim::SampleInterval::EveryStep);
    }
    let dt = Dimension::Time
        .parse(t)
        .with_context(|| format!("--sample-interval (key `{KEY}`; or `step`)"))?;
    let r = crate::problem::keys::range_of(KEY).expect("the key has a range");
    anyhow::ensure!(
        r.contains(dt),
        "--sample-interval (key `{KEY}`) must be {} or `step`, got {t}",
        r.describe_in("s", 1.0)
    );
    anyhow::ensure!(
        dt <= duration,
        "--sample-interval (key `{KEY}`) must be no longer than the run ({duration} s), got {t}"
    );
    Ok(sim::SampleInterval::Fixed(dt))
}

pub fn run(args: &SimulateArgs, units: UnitSystem) -> anyhow::Result<()> {
    let problem = Problem::load(&args.problem)?;
    let (op, duration) = point_and_duration(&problem, &args.point)?;
    let work = crate::study::cost::Work {
        elements: problem.mesh.elements,
        modes: crate::study::cost::basis_size(&problem.mesh.basis),
        simulations: 1,
        seconds_each: duration,
        models_held: 1,
        concurrent: 1,
        holds_results: false,
        unreduced: args.unreduced,
        eigensolves: 0,
    };
    super::study::check_cost(&work, &args.problem, &problem, "simulate", args.quiet)?;
    let interval = sample_interval(
        &args.sample_interval,
        problem.simulation.sample_interval,
        duration,
    )?;
    // The time series is written as it is computed: it must fit on the disk (a day at 0.5 ms is
    // about 60 GB).
    let out_path = args.out.clone().unwrap_or_else(|| {
        std::path::Path::new("results")
            .join(&problem.name)
            .join("simulate")
    });
    // Every accepted step: at least one row per nominal step (a lower bound).
    let rows = interval
        .rows(duration)
        .or_else(|| Some((duration / problem.simulation.time_step).ceil() as usize + 1));
    if let (Some(rows), Some(free)) = (rows, crate::study::cost::available_disk(&out_path)) {
        let bytes =
            rows as f64 * crate::study::cost::csv_bytes_per_row(problem.simulation.probes.len());
        anyhow::ensure!(
            bytes < free,
            "{}: timeseries.csv would take {} {} ({} rows), more than the {} free for {}; raise --sample-interval (key `simulation.sample_interval`, now {}) or shorten --duration",
            args.problem.display(),
            if interval.rows(duration).is_some() {
                "about"
            } else {
                "at least"
            },
            crate::study::cost::bytes_text(bytes),
            rows,
            crate::study::cost::bytes_text(free),
            out_path.display(),
            match interval {
                sim::SampleInterval::Fixed(dt) => format!("{} s", crate::units::sig(dt, 4)),
                sim::SampleInterval::EveryStep => "every step".to_string(),
            }
        );
    }
    let (out, _out_lock) = super::study::out_dir(&args.out, &problem, "simulate")?;
    // An earlier run's summary would read as this run's if this one is killed: it goes now, and
    // this run writes its own at its end (or "not started" when the model cannot be built).
    match std::fs::remove_file(out.join("summary.json")) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            anyhow::bail!(
                "{}: cannot replace it ({e})",
                out.join("summary.json").display()
            )
        }
        _ => {}
    }

    let bar = if args.quiet {
        ProgressBar::hidden()
    } else if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        // No terminal (a log file, a pipe): a plain line now and then instead of the bar.
        let bar = ProgressBar::hidden();
        bar.set_length(1000);
        super::study::log_progress(&bar, |b| format!("simulate: {}", b.message()));
        bar
    } else {
        ProgressBar::new(1000)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} simulate [{bar:40}] {msg} ({elapsed}, eta {eta})")
            .expect("valid template")
            .progress_chars("=> "),
    );
    let kind = if args.unreduced {
        sim::ModelKind::Unreduced
    } else {
        sim::ModelKind::Reduced
    };
    let model = kind
        .build(&problem.model, &problem.mesh, problem.operating_point)
        .map_err(|e| super::basis_error(&args.problem, &problem, e))
        .and_then(|model| {
            super::check_basis(&args.problem, &problem, &model.basis.modes)?;
            Ok(model)
        });
    let model = match model {
        Ok(model) => model,
        Err(e) => {
            // Nothing was simulated: a summary that says so replaces any earlier one.
            bar.finish_and_clear();
            let summary = report::NotStartedJson {
                record: ProblemRecord::of(&problem, &args.problem),
                operating_point: report::PointJson::at(op),
                duration_s: duration,
                elements: problem.mesh.elements,
                status: RunStatus::NotStarted,
                error: format!("{e:#}"),
            };
            report::write_json_atomic(&out.join("summary.json"), &summary)?;
            return Err(e);
        }
    };
    let settling = problem.simulation.settling_for(duration);
    let config = MetricsConfig::for_run(&problem.model, op, settling);
    // Every accepted step goes to the metrics; the written history (streamed to disk) is sampled
    // at `interval`, and the plots keep its extremes per plot interval (bounded memory).
    let probes = &problem.simulation.probes;
    let kept = sim::PlotHistory::new(
        probes,
        duration,
        report::PLOT_BUCKETS,
        interval.rows(duration),
    );
    let csv = report::CsvStream::create(&out.join("timeseries.csv"), probes)?;
    let sink = (
        metrics::OnlineMetrics::new(config.clone(), duration)?,
        sim::Sampler::new(interval, probes.len(), (csv, kept)),
    );
    // Ctrl-C (or SIGTERM) ends the run after the step in progress, and what was computed is
    // written as below (a second Ctrl-C ends the process at once).
    let stop = super::interrupt::install();
    let output = sim::run_model_until(
        &problem.simulation,
        &model,
        op,
        duration,
        sink,
        |t| {
            bar.set_position((1000.0 * t / duration) as u64);
            bar.set_message(format!("t = {t:.2} / {duration} s"));
        },
        stop,
    );
    super::interrupt::uninstall();
    let interrupted = matches!(output.error, Some(sim::SimulationError::Interrupted { .. }));
    let ((online, sampler), output) = output.split();
    let (csv, kept) = sampler.finish();
    let series = kept.into_series();
    bar.set_message("critical speeds");
    // The margin depends on the model and Ω only; a string without a resting state has none. It
    // is taken on the problem's reduced basis even for an unreduced run: a Campbell sweep of every
    // free DOF costs minutes per speed (`drillopt campbell --unreduced` gives the same critical
    // speeds of the seed within 0.3 %, docs/model.md, "Critical speeds").
    let reduced;
    let margin_model = match kind {
        sim::ModelKind::Reduced => &model,
        sim::ModelKind::Unreduced => {
            reduced = sim::ModelKind::Reduced
                .build(&problem.model, &problem.mesh, problem.operating_point)
                .map_err(|e| super::basis_error(&args.problem, &problem, e))?;
            &reduced
        }
    };
    let margin = crate::campbell::critical_speed_margin(
        margin_model,
        problem.campbell.excitation_multiple,
        op.omega,
    );
    bar.finish_and_clear();

    // Cheap beside the run (one more steady state and the eigenvalues of a matrix of twice the
    // basis' size); the model the run used.
    let steady_state = sim::steady_stability(&model, op, sim::Effects::ALL)
        .ok()
        .flatten();
    let (critical_speed_margin, margin_error) = match margin {
        Ok(m) => (m, None),
        Err(e) => (f64::NAN, Some(format!("critical_speed_margin: {e}"))),
    };
    let terms = metrics::ModelTerms {
        critical_speed_margin,
        steady_state,
    };
    let (metrics, mut metrics_error) = match online.metrics() {
        Ok(m) => (
            Some(m.completed(&output.envelope, &problem.model, op, Some(terms))),
            None,
        ),
        Err(e) => (None, Some(e.to_string())),
    };
    if let Some(e) = margin_error {
        metrics_error.get_or_insert(e);
    }
    // A window too short to batch keeps its metrics and goes without intervals.
    let confidence_95 = online.batch_intervals();
    let summary = SummaryJson {
        record: ProblemRecord::of(&problem, &args.problem),
        operating_point: report::PointJson::at(op),
        duration_s: duration,
        settling_time_s: settling,
        start: problem.simulation.start.name(),
        elements: problem.mesh.elements,
        model: kind,
        basis: output.basis,
        steady_shapes: model.steady,
        nominal_step_s: problem.simulation.time_step,
        max_step_s: output.max_step,
        status: match (&output.error, &metrics_error) {
            (None, None) => RunStatus::Completed,
            (None, Some(_)) => RunStatus::NoMetrics,
            (Some(_), _) if interrupted => RunStatus::Interrupted,
            (Some(_), _) => RunStatus::Failed,
        },
        error: output.error.as_ref().map(|e| e.to_string()),
        metrics,
        confidence_95,
        metrics_error,
        steady_state,
        solver: &output.stats,
    };
    report::write_json_atomic(&out.join("summary.json"), &summary)?;
    if !series.is_empty() {
        csv.finish()?;
    }
    // Plots and the stress envelope need a history: a start that fails leaves one row.
    if series.len() >= 2 {
        let s = &series;
        report::plot_bit_axial(s, &op, problem.model.top, units, &out.join("bit_axial.svg"))?;
        report::plot_bit_rotation(s, &op, units, &out.join("bit_rotation.svg"))?;
        // Each probe's wall at its own gap: the hole less its section's outer radius (the
        // smallest gap of the string is a stabiliser's, not the drill pipe's).
        let layout = crate::fem::ElementLayout::of(&problem.model, problem.mesh.elements);
        for (k, x) in s.probe_positions.iter().enumerate() {
            let name = format!("radial_x{}m.svg", report::probe_label(*x));
            let (e, _) = layout.locate(*x);
            let gap = problem.model.borehole_radius - layout.kinds()[layout.kind(e)].outer_radius;
            report::plot_probe_radial(s, k, gap, &op, units, &out.join(name))?;
        }
        let envelope = &output.envelope;
        if envelope.rainflow_overflows > 0 {
            eprintln!(
                "warning: {} rainflow residues filled their {} turning points; the oldest were counted as half cycles, so the fatigue damage is approximate (see fatigue::Rainflow)",
                envelope.rainflow_overflows,
                crate::fatigue::RAINFLOW_CAPACITY
            );
        }
        report::write_envelope_csv(&out.join("stress_envelope.csv"), envelope)?;
        report::plot_stress_envelope(envelope, &op, units, &out.join("stress_envelope.svg"))?;
    }
    print_summary(
        &args.problem,
        &summary,
        &out,
        problem.model.stiffness_damping,
        problem.model.top,
        &section_lines(&problem.model, problem.mesh.elements, units),
        units,
        (problem.campbell).note(problem.model.bit.law().name()),
    );
    if let Some(w) = depth_of_cut_warning(&problem.model) {
        eprintln!("{w}");
    }
    // Only a run that starts on the steady state can read it as the long run.
    let preloaded = problem.simulation.start == crate::model::Start::Preloaded;
    if let Some(w) = steady_state_warning(steady_state, settling, duration).filter(|_| preloaded) {
        eprintln!("{w}");
    }
    if let Some(e) = &output.error {
        // A numerical failure names its stage and the keys that enter it, with their values.
        let keys = super::failed_stage(e).map_or(String::new(), |stage| {
            format!(
                "; {} depends on {}",
                stage.describe(),
                // The point that was run (the file's, or --omega and --v0).
                crate::problem::keys::describe_entering(
                    &crate::problem::Problem {
                        operating_point: op,
                        ..problem.clone()
                    },
                    stage
                )
            )
        });
        anyhow::bail!(
            "{}: simulation stopped early: {e}{keys} (results up to then written to {})",
            args.problem.display(),
            out.display()
        );
    }
    if let Some(e) = &summary.metrics_error {
        anyhow::bail!(
            "the run finished but its metrics could not be computed: {e} (results in {})",
            out.display()
        );
    }
    Ok(())
}

/// The stiffness-proportional damping β with which `verify` found the seed string's stick-slip
/// statistics converged up to bit_damping_ratio 1.98 (docs/model.md, "Converged model"), s; 1 µs was too
/// little.
const CONVERGED_STIFFNESS_DAMPING: f64 = 1e-5;

/// The warning for a depth-of-cut bit (`law = "rgd"`) without the stiffness damping that bounds
/// the reduced basis' spurious high mode (docs/model.md, "A bit that cuts rock"); `None` otherwise.
/// Printed by `simulate` and by the study commands.
pub(super) fn depth_of_cut_warning(string: &crate::model::Drillstring) -> Option<String> {
    (string.bit.blades().is_some()
        && string.stiffness_damping < CONVERGED_STIFFNESS_DAMPING * (1.0 - 1e-9))
        .then(|| {
            format!(
                "warning: a depth-of-cut bit (law = \"rgd\") destabilises every axial mode the model holds, and the reduced basis has a spurious one above its axial modes (near 505 Hz on the seed string, growing faster than the physical first axial mode) that only [model.pipe] stiffness_damping bounds: with stiffness_damping = {:.3} us, below the 10 us with which the reduced model's growth matches the string's characteristic equation (docs/model.md, \"A bit that cuts rock\"), the dynamics may be the basis', not the string's",
                string.stiffness_damping * 1e6
            )
        })
}

/// `stiffness_damping`: the model's β, s; with none (or one below the evidence of
/// [`CONVERGED_STIFFNESS_DAMPING`], to round-off: `"10 us"` reads as 9.999999999999999e-6 s) a
/// bit_damping_ratio above 1 draws a warning.
/// Round-off that an unstable steady state amplifies, relative (the start's own error).
const ROUND_OFF: f64 = 1e-12;

/// The caution for an unstable steady state whose growth out of round-off outlasts the settling
/// time: the window may read the steady state as the long run. `None` when stable, not computed,
/// or grown before the window starts.
pub(super) fn steady_state_warning(
    s: Option<sim::SteadyStability>,
    settling: f64,
    duration: f64,
) -> Option<String> {
    let s = s.filter(|s| s.unstable())?;
    let grown = s.growth_time(1.0 / ROUND_OFF);
    if grown <= settling {
        return None;
    }
    Some(format!(
        "warning: steady drilling is unstable here: the linearised equations' dominant eigenvalue \
         grows at {:.3} 1/s ({:.1} Hz), so a disturbance doubles every {} s and round-off \
         ({ROUND_OFF:e}) reaches the response's own size after about {} s{}; the run starts on \
         the steady state, and a window that ends before the growth reads it as the long run \
         (docs/model.md, \"Linear stability of steady drilling\")",
        s.growth_rate_per_s,
        s.frequency_hz,
        crate::units::sig(s.growth_time(2.0), 3),
        crate::units::sig(grown, 3),
        if grown > duration {
            format!(", later than this {} s run", crate::units::short(duration))
        } else {
            String::new()
        }
    ))
}

/// One line per section of a string of sections, as the model holds it (top drive to bit): its
/// length, outer and inner diameter (mm), steel mass per length (kg/m), buoyed weight per length
/// (N/m) and elements, so that sizes derived from a linear weight are seen; none for a string of
/// one section.
fn section_lines(
    string: &crate::model::Drillstring,
    elements: usize,
    u: UnitSystem,
) -> Vec<String> {
    if string.sections.is_empty() {
        return Vec::new();
    }
    let layout = crate::fem::ElementLayout::of(string, elements);
    let kinds = layout.kinds_of_elements();
    (string.section_strings().iter().enumerate())
        .map(|(k, sub)| {
            let section = crate::model::Section::of(sub);
            let count = kinds.iter().filter(|&&kind| layout.kinds()[kind].section == k).count();
            let weight = u.of(LineLoad, section.weight_mass() * sub.gravity);
            let weight_unit = u.unit(LineLoad);
            // Inches to the thousandth, as the pipe tables give them (4.276 in); mm to 0.01.
            let digits = if u == UnitSystem::Field { 3 } else { 2 };
            format!(
                "  section {k} \"{}\": {:.2} {}, OD {:.digits$} {}, ID {:.digits$} {}, {:.2} {} of steel, buoyed weight {weight:.1} {weight_unit}, {count} elements",
                string.sections[k].name,
                u.of(Position, sub.length),
                u.unit(Position),
                u.of(Size, 2.0 * sub.pipe.outer_radius),
                u.unit(Size),
                u.of(Size, 2.0 * sub.pipe.inner_radius),
                u.unit(Size),
                u.of(LinearDensity, section.pipe_mass),
                u.unit(LinearDensity),
            )
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn print_summary(
    path: &Path,
    s: &SummaryJson,
    out: &Path,
    stiffness_damping: f64,
    top: TopDrive,
    sections: &[String],
    u: UnitSystem,
    campbell_note: Option<String>,
) {
    let st = s.solver;
    // A value in SI shown with its unit: "12.345 ft/h".
    let show = |q: Shown, si: f64, decimals: usize| {
        format!(
            "{} {}",
            crate::units::fixed(u.of(q, si), decimals),
            u.unit(q)
        )
    };
    // A value given in the metric unit `unit` (the keys in m/h or kN), shown so.
    let show_metric = |unit: &'static str, v: f64, decimals: usize| {
        let (unit, v) = u.from_metric(unit, v);
        format!("{} {unit}", crate::units::fixed(v, decimals))
    };
    // A run that stopped early did not simulate its duration: say so (the error follows).
    let done = match s.status {
        RunStatus::Failed => format!("stopped before the end of its {} s", s.duration_s),
        RunStatus::Interrupted => format!("interrupted before the end of its {} s", s.duration_s),
        _ => format!("{} s simulated", s.duration_s),
    };
    println!(
        "{}: Ω = {:.2} rpm, {}, {done} in {:.1} s ({} steps, {} rejected{})",
        s.record.problem,
        s.operating_point.omega_rpm,
        match s.operating_point.set_point {
            crate::model::SetPointValue::Wob { wob_kn, .. } =>
                format!("WOB set-point {}", show_metric("kN", wob_kn, 3)),
            crate::model::SetPointValue::Feed { v0_m_per_h, .. } =>
                format!("V0 = {}", show_metric("m/h", v0_m_per_h, 3)),
        },
        st.wall_time_s,
        st.steps,
        st.rejected_steps,
        // No step taken (a start that failed): no smallest step to give.
        if st.min_dt.is_finite() {
            format!(", min dt {:.2e} s", st.min_dt)
        } else {
            String::new()
        }
    );
    println!(
        "  {} start, {} elements, {}",
        s.start,
        s.elements,
        match s.model {
            sim::ModelKind::Reduced => format!("reduced basis: {}", s.basis),
            sim::ModelKind::Unreduced => format!(
                "unreduced (all {} free DOFs: {} bending, {} torsional, {} axial)",
                s.basis.bending + s.basis.torsional + s.basis.axial + s.basis.static_corrections,
                s.basis.bending,
                s.basis.torsional,
                s.basis.axial
            ),
        }
    );
    match super::steady_shapes_line(path, s.steady_shapes, u) {
        Some(Ok(line)) => println!("{line}"),
        Some(Err(warning)) => eprintln!("{warning}"),
        None => {}
    }
    for line in sections {
        println!("{line}");
    }
    if s.max_step_s < s.nominal_step_s {
        println!(
            "  step at most {:.3} ms (the nominal {:.3} ms capped at 1/20 of the lowest torsional/axial period)",
            1e3 * s.max_step_s,
            1e3 * s.nominal_step_s
        );
    }
    if let Some(m) = &s.metrics {
        println!(
            "  ROP {} | SSI {:.2} | stick {:.1}% | bounce {:.1}% | impacts {:.2}/s | WOB {} | TOB {} | energy residual {:.1e}",
            show_metric("m/h", m.mean_rop_m_per_h, 3),
            m.stick_slip_severity,
            100.0 * m.stick_fraction,
            100.0 * m.bit_bounce_fraction,
            m.impacts_per_s,
            show(Force, m.mean_wob_n, 1),
            show(Torque, m.mean_tob_nm, 2),
            m.energy_balance_residual
        );
        println!(
            "  top drive: torque {} | force {} (surface torque and push: the bit's plus the wall friction and damping along the string)",
            show(Torque, m.mean_top_torque_nm, 2),
            show(Force, m.mean_top_force_n, 1)
        );
        if let TopDrive::Autodriller(ad) = top {
            let torque = match ad.torque_limit_at(s.operating_point.omega_rad_s) {
                Some(l) => format!(
                    "{:.1} % at the torque limit ({}{})",
                    100.0 * m.torque_limit_fraction,
                    show(Torque, l, 2),
                    match ad.power_limit {
                        Some(p) => format!(
                            "; the {} rating gives {} at {:.1} rpm",
                            show(Power, p, 1),
                            show(Torque, p / s.operating_point.omega_rad_s, 2),
                            s.operating_point.omega_rpm
                        ),
                        None => String::new(),
                    }
                ),
                None => "no torque limit".into(),
            };
            println!(
                "  autodriller: ROP / V0 = {} | {:.1} % of the time at the WOB limit ({}) | {torque}",
                crate::units::fixed(m.rop_set_point_ratio, 3),
                100.0 * m.wob_limit_fraction,
                show(Force, ad.wob_limit, 1)
            );
        }
        println!("  {}", integrity_line(m, u));
        if let Some(w) = yield_warning(m, u) {
            eprintln!("{w}");
        }
        // As solve warns at its optimum: a rotation speed near a critical speed.
        if m.critical_speed_margin < crate::solve::CRITICAL_SPEED_WARNING {
            eprintln!(
                "warning: Ω is {:.1} % from a critical speed of the string (critical_speed_margin {:.4}, below {}): `drillopt campbell` lists them{}",
                100.0 * m.critical_speed_margin,
                m.critical_speed_margin,
                crate::solve::CRITICAL_SPEED_WARNING,
                campbell_note.map_or(String::new(), |n| format!(" ({n})"))
            );
        }
        // The ratio is the rate law's slope at the feed the bit drills (V0, or the mean ROP of a
        // free top); an autodriller that holds its WOB limit most of the window fixes the depth of
        // cut, and the law's torque no longer falls with the spin (docs/model.md, "The driller's top"):
        // no warning then.
        let held = matches!(top, TopDrive::Autodriller(_)) && m.wob_limit_fraction > 0.5;
        let negative = m.bit_damping_ratio > 1.0 && !held;
        if negative && stiffness_damping == 0.0 {
            eprintln!(
                "warning: the bit's negative damping is {:.2} times the pipe's torsional impedance (bit_damping_ratio > 1): the bit feeds torsional waves faster than the string carries them away, and without [model.pipe] stiffness_damping the stick-slip statistics depend on the shortest torsional waves the basis holds: expect `drillopt verify` to find them not converged (docs/model.md, \"Converged model\": stiffness_damping = \"10 us\" bounds them)",
                m.bit_damping_ratio
            );
        } else if negative && stiffness_damping < CONVERGED_STIFFNESS_DAMPING * (1.0 - 1e-9) {
            eprintln!(
                "warning: the bit's negative damping is {:.2} times the pipe's torsional impedance (bit_damping_ratio > 1), and stiffness_damping = {:.3} us is below the 10 us with which `drillopt verify` found the stick-slip statistics converged up to a ratio of 1.98 (1 us was too little; docs/model.md, \"Converged model\"): check this point with `drillopt verify`",
                m.bit_damping_ratio,
                stiffness_damping * 1e6
            );
        }
    } else if let Some(e) = &s.metrics_error {
        println!("  metrics unavailable: {e}");
    }
    if let Some(ci) = &s.confidence_95 {
        let (rop, stick, tob, top) = (
            ci["mean_rop_m_per_h"],
            ci["stick_fraction"],
            ci["mean_tob_nm"],
            ci["mean_top_torque_nm"],
        );
        println!(
            "  95 % batch-means intervals: ROP ± {} | stick ± {:.1} % | TOB ± {} | top torque ± {}",
            show_metric("m/h", rop.half_width, 3),
            100.0 * stick.half_width,
            show(Torque, tob.half_width, 3),
            show(Torque, top.half_width, 3)
        );
    }
    match s.steady_state {
        Some(st) if st.unstable() => println!(
            "  steady state: UNSTABLE, grows at {:.3} 1/s ({:.1} Hz; the dominant eigenvalue of the linearised equations)",
            st.growth_rate_per_s, st.frequency_hz
        ),
        Some(st) => println!(
            "  steady state: stable, the slowest decay {:.3} 1/s ({:.1} Hz; the dominant eigenvalue of the linearised equations)",
            -st.growth_rate_per_s, st.frequency_hz
        ),
        None => {}
    }
    println!("  results in {}", out.display());
}

/// The string's integrity in one line: peak von Mises stress, fatigue, buckling, each with where.
fn integrity_line(m: &crate::metrics::Metrics, u: UnitSystem) -> String {
    let at = |x: f64| format!("{:.2} {}", u.of(Position, x), u.unit(Position));
    let fatigue = if m.fatigue_damage_per_h > 0.0 {
        format!(
            "fatigue {:.3e}/h at {} (life {:.3e} h)",
            m.fatigue_damage_per_h,
            at(m.fatigue_worst_at_m),
            m.fatigue_life_h
        )
    } else if m.fatigue_damage_per_h == 0.0 {
        "fatigue: no damage (every range below the endurance limit)".to_string()
    } else {
        "fatigue: not computed".to_string()
    };
    // With a yield strength, the safety factor beside the stress.
    let safety = if m.von_mises_safety_factor.is_finite() {
        format!(" (safety factor {:.2})", m.von_mises_safety_factor)
    } else {
        String::new()
    };
    // Weightless (gravity = 0), a string has no buckling load to compare with.
    let buckling = if m.buckling_utilization.is_finite() {
        format!(
            "compression {:.1} % of sinusoidal buckling at {}",
            100.0 * m.buckling_utilization,
            at(m.buckling_at_m)
        )
    } else {
        "buckling: no figure (a weightless string, gravity = 0, has no sinusoidal buckling load)"
            .to_string()
    };
    format!(
        "von Mises {:.1} {} at {}{safety} | {fatigue} | {buckling}",
        u.of(Stress, m.max_von_mises_pa),
        u.unit(Stress),
        at(m.max_von_mises_at_m),
    )
}

/// A warning when the peak von Mises stress reaches the yield strength (`von_mises_utilization`
/// ≥ 1); none without a yield strength.
fn yield_warning(m: &crate::metrics::Metrics, u: UnitSystem) -> Option<String> {
    (m.von_mises_utilization >= 1.0).then(|| {
        format!(
            "warning: the peak von Mises stress, {:.1} {} at {:.2} {}, reaches the yield strength \
             (model.pipe.yield_strength; von_mises_utilization {:.3}): the string yields there, \
             beyond what this elastic model describes",
            u.of(Stress, m.max_von_mises_pa),
            u.unit(Stress),
            u.of(Position, m.max_von_mises_at_m),
            u.unit(Position),
            m.von_mises_utilization
        )
    })
}
