//! `drillopt modes PROBLEM [--count n] [--json]`.

use crate::fem::{BoundaryConditions, assemble};
use crate::problem::Problem;
use crate::rom::{ModalBasis, Mode};
use anyhow::Context;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct ModesArgs {
    /// Problem file (TOML).
    pub problem: PathBuf,
    /// How many of the lowest modes to list [default: mesh.reduced_modes of the problem].
    #[arg(long)]
    pub count: Option<usize>,
    /// Print JSON {"dof", "modes": [{"index", "freq_hz", "family"}]} instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct ModesReport<'a> {
    problem: &'a str,
    dof: usize,
    free_dof: usize,
    modes: &'a [Mode],
}

pub fn run(args: &ModesArgs) -> anyhow::Result<()> {
    let problem = Problem::load(&args.problem)?;
    let elements = problem.mesh.elements;
    let bc = BoundaryConditions::drillstring(elements);
    let count = args.count.unwrap_or(problem.mesh.reduced_modes);
    anyhow::ensure!(
        (1..=bc.free_count()).contains(&count),
        "--count must be in [1, {}] (the free DOFs of this mesh), got {count}",
        bc.free_count()
    );
    let global = assemble(&problem.model, elements);
    let basis = ModalBasis::of(&global, &bc, count, faer::Par::Seq)
        .with_context(|| format!("modal analysis of {}", args.problem.display()))?;
    let report = ModesReport {
        problem: &problem.name,
        dof: bc.dof(),
        free_dof: bc.free_count(),
        modes: &basis.modes,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{}: {} elements, {} DOF ({} free); lowest {} modes",
            problem.name,
            elements,
            report.dof,
            report.free_dof,
            basis.len()
        );
        println!(
            "{:>5}  {:>12}  {:>14}  {:<10}  {:>6}",
            "mode", "freq [Hz]", "omega [rad/s]", "family", "share"
        );
        for m in &basis.modes {
            let share = m.energy_share.iter().cloned().fold(0.0, f64::max);
            println!(
                "{:>5}  {:>12.5}  {:>14.4}  {:<10}  {:>5.1}%",
                m.index,
                m.freq_hz,
                m.omega,
                m.family,
                100.0 * share
            );
        }
    }
    Ok(())
}
