//! `drillopt campbell PROBLEM [--omega-range 20rpm..200rpm] [--points N] [--multiple K]
//! [--out DIR] [--json] [--quiet]`: the natural frequencies of the string linearised about its
//! resting state against the rotation speed (the Campbell diagram), forward and backward whirl,
//! and the critical speeds where a mode meets 1× or K× the rotation frequency
//! ([`crate::campbell`]): `campbell.json`, `campbell.svg` and a table.

use crate::campbell::{
    CampbellDiagram, LinearSystem, Linearisation, MarginTable, ModeFamily, crossings, margin_window,
};
use crate::problem::{Dimension, Problem};
use crate::report::{self, CampbellJson, CampbellModeJson, CampbellPlot, CampbellPointJson};
use crate::sim::ModelKind;
use crate::units::{from_rpm, to_rpm};
use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

/// Highest rotation speed of `--omega-range`, rpm (that of `operating_point.omega`).
const MAX_RPM: f64 = 1000.0;
/// Most rotation speeds of `--points`.
const MAX_POINTS: usize = 2000;

#[derive(Debug, Args)]
pub struct CampbellArgs {
    /// Problem file (TOML).
    pub problem: PathBuf,
    /// Rotation speeds LOW..HIGH, each with a unit (rpm, rad/s, rev/s, Hz; a bare number other
    /// than 0 is refused, as for `--omega`), 0 ≤ LOW < HIGH ≤ 1000 rpm.
    #[arg(long, default_value = "20rpm..200rpm", allow_hyphen_values = true)]
    pub omega_range: String,
    /// Number of evenly spaced rotation speeds, in [2, 2000].
    #[arg(long, default_value_t = 91, value_parser = super::whole_number, allow_hyphen_values = true)]
    pub points: usize,
    /// The bit's excitation multiple K: critical speeds are sought on 1× and K× the rotation
    /// frequency, K in [1, 50] [default: campbell.excitation_multiple of the problem, else 3, a
    /// tri-cone bit].
    #[arg(long, allow_hyphen_values = true)]
    pub multiple: Option<String>,
    /// Output directory [default: results/<problem>/campbell].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print campbell.json on standard output instead of the table.
    #[arg(long)]
    pub json: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Without the wall: linearise about the straight unloaded string (at Ω = 0 the frequencies
    /// of `drillopt modes`).
    #[arg(long)]
    pub no_contact: bool,
    /// With the structural damping c M_pipe + β K (`damping`, `stiffness_damping`; damped
    /// frequencies and damping ratios).
    #[arg(long)]
    pub damping: bool,
    /// The finite-element model without reduction (every free DOF) instead of the problem's
    /// basis: a reference for the basis, much slower.
    #[arg(long)]
    pub unreduced: bool,
}

/// `LOW..HIGH` in rad/s, refused naming the flag and what is allowed.
pub(crate) fn parse_omega_range(text: &str) -> anyhow::Result<[f64; 2]> {
    let allowed = format!(
        "LOW..HIGH with a unit on each (rpm, rad/s, rev/s, Hz; a bare number other than 0 is refused) and 0 <= LOW < HIGH <= {MAX_RPM} rpm with HIGH at least 1 rpm (the lowest rotation speed of an operating point), e.g. 20rpm..200rpm"
    );
    let Some((lo, hi)) = text.split_once("..") else {
        anyhow::bail!("--omega-range must be {allowed}, got {text:?}");
    };
    let parse = |side: &str| {
        super::simulate::require_unit("--omega-range", side, Dimension::AngularVelocity)?;
        Dimension::AngularVelocity
            .parse(side)
            .map_err(|e| anyhow::anyhow!("--omega-range: {e}; the range must be {allowed}"))
    };
    let (lo, hi) = (parse(lo)?, parse(hi)?);
    anyhow::ensure!(
        lo >= 0.0 && lo < hi && hi >= from_rpm(1.0) && hi <= from_rpm(MAX_RPM) * (1.0 + 1e-12),
        "--omega-range must be {allowed}, got {text:?} ({} to {} rpm)",
        crate::units::short(to_rpm(lo)),
        crate::units::short(to_rpm(hi))
    );
    Ok([lo, hi])
}

/// The excitation multiple: `--multiple`, else the problem's.
fn multiple(args: &CampbellArgs, problem: &Problem) -> anyhow::Result<f64> {
    let Some(text) = &args.multiple else {
        return Ok(problem.campbell.excitation_multiple);
    };
    let range = crate::problem::keys::range_of("campbell.excitation_multiple")
        .expect("the key has a range");
    let k = Dimension::Dimensionless
        .parse(text)
        .with_context(|| "--multiple (key `campbell.excitation_multiple`)")?;
    anyhow::ensure!(
        range.contains(k),
        "--multiple (key `campbell.excitation_multiple`) must be a number in [{}, {}] ({}), got {text}",
        range.lo,
        range.hi,
        range.why
    );
    Ok(k)
}

pub fn run(args: &CampbellArgs) -> anyhow::Result<()> {
    let problem = Problem::load(&args.problem)?;
    let [lo, hi] = parse_omega_range(&args.omega_range)?;
    anyhow::ensure!(
        (2..=MAX_POINTS).contains(&args.points),
        "--points must be an integer in [2, {MAX_POINTS}], got {}",
        args.points
    );
    let k = multiple(args, &problem)?;
    let work = crate::study::cost::Work {
        elements: problem.mesh.elements,
        modes: crate::study::cost::basis_size(&problem.mesh.basis),
        simulations: 0,
        seconds_each: 0.0,
        models_held: 1,
        concurrent: 1,
        holds_results: false,
        unreduced: args.unreduced,
        eigensolves: args.points as u64 + crate::study::cost::CAMPBELL_REFINEMENT_SOLVES,
    };
    super::study::check_cost(&work, &args.problem, &problem, "campbell", args.quiet)?;
    let (out, _out_lock) = super::study::out_dir(&args.out, &problem, "campbell")?;
    let kind = if args.unreduced {
        ModelKind::Unreduced
    } else {
        ModelKind::Reduced
    };
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(args.points as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} campbell [{bar:40}] {pos}/{len} rotation speeds: {msg} ({elapsed})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message("modes and the resting state");
    let model = kind
        .build(&problem.model, &problem.mesh, problem.operating_point)
        .map_err(|e| super::basis_error(&args.problem, &problem, e))?;
    super::check_basis(&args.problem, &problem, &model.basis.modes)?;
    // Asked for and left out: the diagram is of the basis without the steady-state shapes.
    if let Some(Err(warning)) = super::steady_shapes_line(
        &args.problem,
        model.steady,
        crate::units::UnitSystem::Metric,
    ) {
        bar.suspend(|| eprintln!("{warning}"));
    }
    let options = Linearisation {
        contact: !args.no_contact,
        damping: args.damping,
    };
    let sys = LinearSystem::about_rest(&model, options)
        .with_context(|| format!("linearising {}", args.problem.display()))?;
    let omegas: Vec<f64> = (0..args.points)
        .map(|i| lo + (hi - lo) * i as f64 / (args.points - 1) as f64)
        .collect();
    bar.set_message("eigenvalues");
    let diagram = CampbellDiagram::sweep(&sys, &omegas, |_| bar.inc(1))
        .with_context(|| format!("Campbell diagram of {}", args.problem.display()))?;
    bar.set_message("critical speeds");
    let speeds = crossings(&sys, &diagram, k)?;
    // The margin of the operating point: from the diagram's critical speeds when its range
    // holds [Ω/1.5, 2Ω], else by the metric's own search (`critical_speed_margin`).
    let op = problem.operating_point.omega;
    let [w_lo, w_hi] = margin_window(op);
    let table = if lo <= w_lo && w_hi <= hi {
        MarginTable {
            range: [op, op],
            speeds: speeds.clone(),
        }
    } else {
        bar.set_message("critical speeds about the operating point");
        MarginTable::search(&sys, k, [op, op])?
    };
    bar.finish_and_clear();
    let nearest = table
        .speeds
        .iter()
        .filter(|c| (w_lo..=w_hi).contains(&c.omega_rad_s))
        .min_by(|a, b| {
            let d =
                |c: &&crate::campbell::CriticalSpeed| (op - c.omega_rad_s).abs() / c.omega_rad_s;
            d(a).total_cmp(&d(b))
        });
    let modes = CampbellModeJson::all(&diagram, options.damping);
    let omega_rpm: Vec<f64> = omegas.iter().map(|&w| to_rpm(w)).collect();
    let report = CampbellJson {
        record: report::ProblemRecord::of(&problem, &args.problem),
        model: kind,
        elements: problem.mesh.elements,
        basis: model.basis.counts(),
        coordinates: sys.size(),
        linearisation: report::LinearisationJson::of(options, sys.resting.clone()),
        excitation_multiple: k,
        omega_rpm: omega_rpm.clone(),
        modes,
        critical_speeds: &speeds,
        operating_point: CampbellPointJson {
            omega_rpm: to_rpm(op),
            critical_speed_margin: table.margin(op).unwrap_or(crate::campbell::MARGIN_CAP),
            nearest_critical_rpm: nearest.map(|c| c.omega_rpm),
        },
        non_oscillatory: diagram.spectra.iter().map(|s| s.non_oscillatory).sum(),
    };
    report::write_json_atomic(&out.join("campbell.json"), &report)?;
    let title = format!(
        "{}: Campbell diagram ({}, {})",
        problem.name,
        if options.contact {
            "resting on the wall"
        } else {
            "no wall"
        },
        match kind {
            ModelKind::Reduced => "reduced basis",
            ModelKind::Unreduced => "unreduced",
        }
    );
    report::plot_campbell(
        &out.join("campbell.svg"),
        &CampbellPlot {
            title: &title,
            omega_rpm: &omega_rpm,
            modes: &report.modes,
            multiple: k,
            critical_speeds: &speeds,
            operating_rpm: Some(to_rpm(op)),
        },
    )?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_table(&report, &out);
        if args.multiple.is_none() {
            let k = &problem.campbell;
            if k.source == crate::model::MultipleSource::Blades {
                println!(
                    "K = {}: the bit's blade count (model.bit.blades)",
                    crate::units::short(k.excitation_multiple)
                );
            }
            if let Some(note) = k.note(problem.model.bit.law().name()) {
                println!("note: {note} (or --multiple)");
            }
        }
    }
    Ok(())
}

fn print_table(r: &CampbellJson, out: &Path) {
    let lin = &r.linearisation;
    println!(
        "{}: {} coordinates ({}), linearised about the {}{}",
        r.record.problem,
        r.coordinates,
        match r.model {
            ModelKind::Reduced => format!("reduced basis: {}", r.basis),
            ModelKind::Unreduced => "every free DOF".into(),
        },
        lin.about,
        if lin.options.damping {
            ", with damping"
        } else {
            ", undamped"
        }
    );
    if let Some(rest) = &lin.resting {
        println!(
            "  at rest {} nodes touch the wall{} carrying {:.1} kN",
            rest.contact_nodes,
            rest.contact_span_m
                .map_or(String::new(), |[a, b]| format!(" (x = {a:.1} to {b:.1} m)")),
            rest.wall_force_n / 1e3
        );
    }
    let (first, last) = (r.omega_rpm[0], r.omega_rpm[r.omega_rpm.len() - 1]);
    let top = 1.15 * r.excitation_multiple.max(1.0) * last / 60.0;
    println!(
        "  modes below {:.2} Hz (1.15 × {}× at {} rpm); κ: +1 circular forward, −1 circular backward, 0 planar (whirl \"planar\" for |κ| ≤ 1e-3)",
        top,
        crate::units::short(r.excitation_multiple),
        crate::units::short(last)
    );
    println!(
        "{:>5}  {:<10} {:<9} {:>12} {:>12} {:>9}",
        "mode",
        "family",
        "whirl",
        format!("{} rpm", crate::units::short(first)),
        format!("{} rpm", crate::units::short(last)),
        "κ (last)"
    );
    let show = |v: Option<f64>| v.map_or("-".to_string(), |f| format!("{f:.4} Hz"));
    for m in r
        .modes
        .iter()
        .filter(|m| m.freq_hz.iter().flatten().any(|&f| f <= top))
    {
        println!(
            "{:>5}  {:<10} {:<9} {:>12} {:>12} {:>9}",
            m.mode,
            m.family.name(),
            if m.family == ModeFamily::Bending {
                m.whirl.name()
            } else {
                "-"
            },
            show(m.freq_hz[0]),
            show(*m.freq_hz.last().expect("two points at least")),
            m.circularity
                .last()
                .copied()
                .flatten()
                .map_or("-".into(), |c| format!("{c:+.1e}"))
        );
    }
    if r.critical_speeds.is_empty() {
        println!(
            "  no critical speed between {} and {} rpm",
            crate::units::short(first),
            crate::units::short(last)
        );
    } else {
        println!("critical speeds:");
        println!(
            "{:>10}  {:>5}  {:>10}  {:>5}  {:<10} whirl",
            "rpm", "line", "freq [Hz]", "mode", "family"
        );
        for c in r.critical_speeds {
            println!(
                "{:>10.2}  {:>4}×  {:>10.4}  {:>5}  {:<10} {}",
                c.omega_rpm,
                crate::units::short(c.multiple),
                c.freq_hz,
                c.mode,
                c.family.name(),
                if c.family == ModeFamily::Bending {
                    c.whirl.name()
                } else {
                    "-"
                }
            );
        }
    }
    let p = &r.operating_point;
    println!(
        "  operating point {} rpm: critical_speed_margin {:.3}{}",
        crate::units::short(p.omega_rpm),
        p.critical_speed_margin,
        p.nearest_critical_rpm.map_or(
            " (no critical speed within [Ω/1.5, 2Ω]: at least 50 % away)".to_string(),
            |c| format!(" (nearest critical speed {c:.1} rpm)")
        )
    );
    println!("  results in {}", out.display());
}
