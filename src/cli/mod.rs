//! The command line: argument parsing and the commands that drive the library. This is the
//! binary's edge, where errors become `anyhow` reports and exit codes.

mod batch;
mod compare;
mod map;
mod modes;
mod simulate;
mod solve;
mod study;
mod study_plots;

use clap::{Parser, Subcommand};

/// Robust operating-point optimisation of horizontal drillstrings.
#[derive(Debug, Parser)]
#[command(name = "drillopt", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// The lowest natural modes of the linear drillstring (constrained FE model).
    Modes(modes::ModesArgs),
    /// One operating point through the nonlinear reduced-order simulator.
    Simulate(simulate::SimulateArgs),
    /// The robust optimum (Ω, V0) of a problem: solution.json and plots.
    Solve(solve::SolveArgs),
    /// Robust statistics of given operating points side by side.
    Compare(compare::CompareArgs),
    /// The objective and risk metrics over a grid of the feasible box (heat maps).
    Map(map::MapArgs),
    /// Solve every problem with an [expect] section in a directory; fail on any regression.
    Batch(batch::BatchArgs),
}

/// Run a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Modes(args) => modes::run(&args),
        Command::Simulate(args) => simulate::run(&args),
        Command::Solve(args) => solve::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Map(args) => map::run(&args),
        Command::Batch(args) => batch::run(&args),
    }
}
