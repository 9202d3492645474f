//! The command line: argument parsing and the commands that drive the library. This is the
//! binary's edge, where errors become `anyhow` reports and exit codes.

mod batch;
mod campbell;
mod compare;
mod map;
mod modes;
mod simulate;
mod solve;
mod study;
mod study_plots;
mod verify;

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
    /// Natural frequencies against the rotation speed (Campbell diagram), whirl, critical speeds.
    Campbell(campbell::CampbellArgs),
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
    /// Solution verification at one operating point: are the decision metrics converged in the
    /// basis, the mesh, the integrator tolerances and the window? Exit status 1 when not.
    Verify(verify::VerifyArgs),
}

/// A basis error as the user should read it: file, key, what went wrong.
pub(crate) fn basis_error(
    path: &std::path::Path,
    problem: &crate::problem::Problem,
    e: crate::rom::BasisError,
) -> anyhow::Error {
    let key = match problem.mesh.basis {
        crate::model::BasisSpec::Lowest(_) => "mesh.reduced_modes",
        crate::model::BasisSpec::PerFamily { .. } => "mesh.basis",
    };
    anyhow::anyhow!("{}: key `{key}`: {e}", path.display())
}

/// How a command that ran to its end came out: a verdict is data, not an error (`verify` judging
/// a model not converged printed its verdict; the process exits with status 1, without an
/// `error:` line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Exit status 0.
    Success,
    /// The command's verdict is negative (printed); exit status 1.
    NegativeVerdict,
}

/// Run a parsed command line; `Err` for a command that could not run (bad input, I/O, …).
pub fn run(cli: Cli) -> anyhow::Result<Outcome> {
    let done = |r: anyhow::Result<()>| r.map(|()| Outcome::Success);
    match cli.command {
        Command::Modes(args) => done(modes::run(&args)),
        Command::Campbell(args) => done(campbell::run(&args)),
        Command::Simulate(args) => done(simulate::run(&args)),
        Command::Solve(args) => done(solve::run(&args)),
        Command::Compare(args) => done(compare::run(&args)),
        Command::Map(args) => done(map::run(&args)),
        Command::Batch(args) => done(batch::run(&args)),
        Command::Verify(args) => verify::run(&args),
    }
}
