//! The command line: argument parsing and the commands that drive the library. This is the
//! binary's edge, where errors become `anyhow` reports and exit codes.

mod modes;
mod simulate;

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
}

/// Run a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Modes(args) => modes::run(&args),
        Command::Simulate(args) => simulate::run(&args),
    }
}
