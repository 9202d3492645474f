//! `drillopt compare PROBLEM --point 60rpm,5m/h --point 50rpm,25m/h …`: the robust statistics of
//! given operating points side by side, `compare.json`, and one plot overlaying their bit speeds
//! (nominal sample).

use super::study;
use crate::model::{OperatingPoint, SetPoint};
use crate::problem::{Dimension, Problem};
use crate::report;
use crate::report::{CompareJson, StudyHeader, WorkJson};
use crate::sim;
use crate::units::UnitSystem;
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Problem file (TOML); its [uncertain] samples, [objective] and [constraints] apply.
    pub problem: PathBuf,
    /// An operating point "OMEGA,V0", each with its unit, e.g. 60rpm,5m/h, or "OMEGA,WOB" under
    /// top = "hook_load", e.g. 60rpm,50kN (repeat the flag); points outside the problem's
    /// constraints are evaluated and reported infeasible.
    #[arg(long = "point", required = true, allow_hyphen_values = true)]
    pub points: Vec<String>,
    #[command(flatten)]
    pub run: super::study::RunArgs,
}

/// `--point OMEGA,S` with the set-point S of `kind`: V0 (`60rpm,5m/h`) or the WOB (`60rpm,50kN`).
pub fn parse_point(text: &str, kind: SetPoint) -> anyhow::Result<OperatingPoint> {
    let example = match kind {
        SetPoint::Feed => "OMEGA,V0 such as 60rpm,5m/h",
        SetPoint::Wob => "OMEGA,WOB such as 60rpm,50kN (this problem's top is a hook load)",
    };
    let (w, v) = text
        .split_once(',')
        .with_context(|| format!("--point {text}: expected {example}"))?;
    let what = match kind {
        SetPoint::Feed => "axial velocity",
        SetPoint::Wob => "WOB set-point",
    };
    // The same rule as simulate's --omega and --v0: a bare number is refused (0 needs no unit).
    super::simulate::require_unit(
        &format!("--point {text}: rotation speed"),
        w,
        Dimension::AngularVelocity,
    )?;
    super::simulate::require_unit(&format!("--point {text}: {what}"), v, kind.dimension())?;
    let omega = Dimension::AngularVelocity
        .parse(w.trim())
        .with_context(|| format!("--point {text}: rotation speed"))?;
    let s = kind
        .dimension()
        .parse(v.trim())
        .with_context(|| format!("--point {text}: {what}"))?;
    // The ranges of the problem keys, as for `--omega` and `--v0` (`1e-300rpm` printed
    // 280-digit scores, `1e308rpm` an "inf" row).
    super::simulate::in_range(
        &format!("--point {text}: rotation speed"),
        "operating_point.omega",
        w,
        omega,
    )?;
    super::simulate::in_range(
        &format!("--point {text}: {what}"),
        &format!("operating_point.{}", kind.key()),
        v,
        s,
    )?;
    // -0 is 0.
    Ok(OperatingPoint::of(kind, omega, s + 0.0))
}

pub fn run(args: &CompareArgs, units: UnitSystem) -> anyhow::Result<()> {
    let mut problem = Problem::load(&args.problem)?;
    if let Some(w) = super::simulate::depth_of_cut_warning(&problem.model) {
        eprintln!("{w}");
    }
    study::apply_overrides(&mut problem, &args.problem, &args.run, None)?;
    study::start_threads(args.run.threads)?;
    let ops = args
        .points
        .iter()
        .map(|p| parse_point(p, problem.model.top.set_point()))
        .collect::<anyhow::Result<Vec<_>>>()?;
    // The study, and one more run per point for the overlay plot.
    let mut work = study::study_work(&problem, ops.len());
    work.simulations += ops.len() as u64;
    study::check_cost(&work, &args.problem, &problem, "compare", args.run.quiet)?;
    let (out, _out_lock) = study::out_dir(&args.run.out, &problem, "compare")?;
    let clock = Instant::now();
    let cache = study::open_cache(&out, args.run.resume, args.run.quiet)?;
    let bar = study::progress_bar(
        args.run.quiet,
        (ops.len() * problem.study.samples.max(1)) as u64,
        problem.study.sequential.is_some(),
        "compare",
    );
    let ev = study::evaluator(&problem, Some(&cache), &bar, args.run.quiet)?;
    let points = ev.evaluate(&ops);
    bar.finish_and_clear();
    // Bit-speed histories of the nominal model, for the overlay plot.
    let nominal =
        sim::ModelKind::Reduced.build(&problem.model, &problem.mesh, problem.operating_point);
    let runs: Vec<(String, sim::TimeSeries)> = ops
        .iter()
        .map(|op| {
            let (unit, set_point) = units.from_metric(op.kind().unit(), op.shown_set_point());
            let label = format!(
                "{:.0} rpm, {set_point:.1} {unit}",
                crate::units::to_rpm(op.omega),
            );
            // The extremes per plot interval only: memory bounded in the duration.
            let duration = problem.simulation.duration;
            nominal.as_ref().map_err(Clone::clone).map(|model| {
                let kept = sim::PlotHistory::new(
                    &problem.simulation.probes,
                    duration,
                    report::PLOT_BUCKETS,
                    None,
                );
                let (kept, _) = sim::run_model_until(
                    &problem.simulation,
                    model,
                    *op,
                    duration,
                    kept,
                    |_| {},
                    sim::StopFlag::default(),
                )
                .split();
                (label, kept.into_series())
            })
        })
        .collect::<Result<_, _>>()
        .context("modal analysis")?;
    let json = CompareJson {
        header: StudyHeader::of(&problem, &args.problem),
        points: &points,
        work: WorkJson::of(&ev, clock.elapsed().as_secs_f64()),
    };
    report::write_json_atomic(&out.join("compare.json"), &json)?;
    report::write_evaluations_csv(&out, &problem, &ev.samples, &points, units)?;
    super::study_plots::compare_plots(&out, &runs, &ops)?;
    // The result is printed even with --quiet, as solve and simulate print theirs.
    study::print_table(
        &points,
        &study::TableUnits::new(units, problem.study.quantity),
    );
    println!("  results in {}", out.display());
    // A point whose simulations failed is a missing result: not a success (the table says
    // why). A point that ran but does not drill (off bottom: a score of −∞) is a result.
    let missing = points
        .iter()
        .filter(|p| {
            p.samples
                .iter()
                .any(|s| matches!(s.outcome, crate::study::SampleOutcome::Failed(_)))
        })
        .count();
    anyhow::ensure!(
        missing == 0,
        "{missing} of {} points have no result: a simulation failed (the table's last column says why; compare.json has each sample)",
        points.len()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::model::SetPoint;
    #[test]
    fn points_parse_with_units_and_bad_ones_are_refused() {
        let p = super::parse_point("60rpm, 5m/h", SetPoint::Feed).unwrap();
        assert!((p.omega - 2.0 * std::f64::consts::PI).abs() < 1e-12);
        assert!((p.v0 - 5.0 / 3600.0).abs() < 1e-15);
        assert!(super::parse_point("60rpm", SetPoint::Feed).is_err());
        assert!(super::parse_point("60rpm,-5m/h", SetPoint::Feed).is_err());
        assert!(super::parse_point("60 furlongs,5m/h", SetPoint::Feed).is_err());
        // Bare numbers would be rad/s and m/s (60 → 573 rpm, 5 → 18 000 m/h): refused.
        let err = super::parse_point("60,5", SetPoint::Feed)
            .unwrap_err()
            .to_string();
        assert!(err.contains("no unit"), "{err}");
        assert!(super::parse_point("60rpm,5", SetPoint::Feed).is_err());
        // A hook load's point is (Ω, WOB): its bare number is refused with a force's units, and
        // a velocity is the wrong dimension.
        let err = super::parse_point("60rpm,12", SetPoint::Wob)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("12kN") && err.contains("klbf") && !err.contains("m/h"),
            "{err}"
        );
        let p = super::parse_point("60rpm,12klbf", SetPoint::Wob).unwrap();
        assert_eq!((p.v0, p.kind()), (0.0, SetPoint::Wob));
        assert!((p.wob - 12e3 * 4.4482216152605).abs() < 1e-6, "{}", p.wob);
        assert!(super::parse_point("60rpm,5m/h", SetPoint::Wob).is_err());
        // 0 is 0 in every unit: off bottom needs none.
        assert_eq!(
            super::parse_point("60rpm,0", SetPoint::Feed).unwrap().v0,
            0.0
        );
        // The point is converted by the one conversion of the driller's units: the same bits as
        // units::from_rpm / from_m_per_h (the cache key of a solved point, issue 13).
        let p = super::parse_point("80rpm,12m/h", SetPoint::Feed).unwrap();
        assert_eq!(p.omega.to_bits(), crate::units::from_rpm(80.0).to_bits());
        assert_eq!(p.v0.to_bits(), crate::units::from_m_per_h(12.0).to_bits());
        // Off bottom (V0 = 0) is a drilling state like any other; a negative V0 is not.
        assert_eq!(
            super::parse_point("60rpm,0m/h", SetPoint::Feed).unwrap().v0,
            0.0
        );
        assert!(super::parse_point("60rpm,-1m/h", SetPoint::Feed).is_err());
        assert!(super::parse_point("0rpm,5m/h", SetPoint::Feed).is_err());
        // Issue 34: the ranges of operating_point.omega and .v0, said in the driller's units.
        for (bad, key, range) in [
            ("1e-300rpm,5m/h", "operating_point.omega", "[1, 1000] rpm"),
            ("1e308rpm,5m/h", "operating_point.omega", "[1, 1000] rpm"),
            (
                "60rpm,1e-300m/h",
                "operating_point.v0",
                "0 or in [0.1, 1000] m/h",
            ),
            (
                "60rpm,2e8m/h",
                "operating_point.v0",
                "0 or in [0.1, 1000] m/h",
            ),
        ] {
            let err = super::parse_point(bad, SetPoint::Feed)
                .unwrap_err()
                .to_string();
            assert!(
                err.contains(&format!("--point {bad}"))
                    && err.contains(&format!("`{key}`"))
                    && err.contains(range),
                "{err}"
            );
        }
    }
}
