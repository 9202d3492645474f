//! `drillopt map PROBLEM [--grid 15x15]`: the objective and every risk metric over a grid of the
//! feasible box, as heat maps with the best node marked, and `map.json`; a table of every node.

use super::study;
use crate::problem::Problem;
use crate::report;
use crate::report::{EvaluationJson, MapJson, PointJson, StudyHeader, WorkJson};
use crate::solve::{self, MapOutcome};
use crate::units::UnitSystem;
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Debug, Args)]
pub struct MapArgs {
    /// Problem file (TOML) with a [constraints] section (the box that is mapped).
    pub problem: PathBuf,
    /// Grid size n_Ω x n_V0, e.g. 15x15 (default: the problem's optimizer.grid).
    #[arg(long, allow_hyphen_values = true)]
    pub grid: Option<String>,
    #[command(flatten)]
    pub run: super::study::RunArgs,
}

pub fn parse_grid(text: &str) -> anyhow::Result<[usize; 2]> {
    let parts: Vec<&str> = text.split(['x', 'X']).collect();
    let parse = |s: &str| {
        s.trim()
            .parse::<usize>()
            .ok()
            .filter(|n| (2..=200).contains(n))
    };
    match parts.as_slice() {
        [a, b] => match (parse(a), parse(b)) {
            (Some(a), Some(b)) => Ok([a, b]),
            _ => anyhow::bail!("--grid {text}: each size must be an integer in [2, 200]"),
        },
        _ => anyhow::bail!("--grid {text}: expected n_omega x n_set_point (V0 or WOB), e.g. 15x15"),
    }
}

pub fn run(args: &MapArgs, units: UnitSystem) -> anyhow::Result<()> {
    let mut problem = Problem::load(&args.problem)?;
    if let Some(w) = super::simulate::depth_of_cut_warning(&problem.model) {
        eprintln!("{w}");
    }
    study::apply_overrides(&mut problem, &args.problem, &args.run, None)?;
    study::start_threads(args.run.threads)?;
    let grid = match &args.grid {
        Some(g) => parse_grid(g)?,
        None => problem.study.optimizer.grid(),
    };
    study::check_cost(
        &study::study_work(&problem, grid[0] * grid[1]),
        &args.problem,
        &problem,
        "map",
        args.run.quiet,
    )?;
    let (out, _out_lock) = study::out_dir(&args.run.out, &problem, "map")?;
    let clock = Instant::now();
    let cache = study::open_cache(&out, args.run.resume, args.run.quiet)?;
    let bar = study::progress_bar(
        args.run.quiet,
        (grid[0] * grid[1] * problem.study.samples.max(1)) as u64,
        problem.study.sequential.is_some(),
        "map",
    );
    let ev = study::evaluator(&problem, Some(&cache), &bar, args.run.quiet)?;
    let m = solve::map(&problem, &ev, grid).context("map")?;
    bar.finish_and_clear();
    let json = MapJson {
        header: StudyHeader::of(&problem, &args.problem),
        grid,
        omega_rad_s: &m.omega,
        v0_m_s: (m.kind == crate::model::SetPoint::Feed).then_some(&m.set_point[..]),
        wob_n: (m.kind == crate::model::SetPoint::Wob).then_some(&m.set_point[..]),
        points: m
            .points
            .iter()
            .map(|p| p.as_ref().map(EvaluationJson::of))
            .collect(),
        optimum: m.best.as_ref().map(PointJson::of),
        optimum_objective: m.best.as_ref().and_then(|b| b.objective),
        work: WorkJson::of(&ev, clock.elapsed().as_secs_f64()),
    };
    report::write_json_atomic(&out.join("map.json"), &json)?;
    report::write_evaluations_csv(
        &out,
        &problem,
        &ev.samples,
        m.points.iter().flatten(),
        units,
    )?;
    super::study_plots::map_plots(&problem, &out, &m, units)?;
    // The result is printed even with --quiet, as solve and simulate print theirs.
    let t = study::TableUnits::new(units, problem.study.quantity);
    for line in table(&m, &t) {
        println!("{line}");
    }
    study::print_best(
        m.best.as_ref(),
        "best grid point",
        "no feasible grid point",
        &t,
        &args.problem,
    );
    println!("  results in {}", out.display());
    Ok(())
}

/// The terminal table of a map: a header and one line per grid node (V0 rows, Ω columns, as in
/// `map.json`), a node outside the linear constraints included and said to be so.
fn table(m: &MapOutcome, t: &study::TableUnits) -> Vec<String> {
    let n_omega = m.omega.len();
    let mut lines = vec![study::table_header(m.kind, t)];
    lines.extend(m.points.iter().enumerate().map(|(k, p)| match p {
        Some(p) => study::table_row(p, t),
        None => format!(
            "{:7.1} {:8.2}   outside the linear constraints: not simulated",
            m.omega[k % n_omega] * report::RPM_PER_RAD_S,
            (t.units)
                .from_metric(m.kind.unit(), m.kind.to_unit(m.set_point[k / n_omega]))
                .1
        ),
    }));
    lines
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_table_lists_every_node_of_the_grid() {
        let problem = crate::cli::study_plots::tests::problem();
        let m = crate::cli::study_plots::tests::map_4x4(&problem.study);
        assert_eq!(m.points.iter().filter(|p| p.is_none()).count(), 6);
        let t =
            super::study::TableUnits::new(crate::units::UnitSystem::Metric, problem.study.quantity);
        let lines = super::table(&m, &t);
        assert_eq!(lines.len(), 1 + 16, "{lines:#?}");
        let outside: Vec<&String> = lines.iter().filter(|l| l.contains("outside")).collect();
        assert_eq!(outside.len(), 6);
        // The last node, (120 rpm, 20 m/h), is one of them; the first is simulated.
        assert!(
            lines[16].starts_with("  120.0    20.00   outside"),
            "{}",
            lines[16]
        );
        assert!(lines[1].starts_with("   40.0     2.00 "), "{}", lines[1]);
        // The fixture's nodes are feasible but for (40 rpm, 20 m/h), marked infeasible.
        assert!(lines[1].ends_with("yes"), "{}", lines[1]);
        assert!(
            lines[13].starts_with("   40.0    20.00 ") && lines[13].ends_with("no"),
            "{}",
            lines[13]
        );
    }

    #[test]
    fn grid_sizes_parse_and_bad_ones_are_refused() {
        assert_eq!(super::parse_grid("15x9").unwrap(), [15, 9]);
        assert!(super::parse_grid("15").is_err());
        assert!(super::parse_grid("1x5").is_err());
        assert!(super::parse_grid("ax5").is_err());
    }
}
