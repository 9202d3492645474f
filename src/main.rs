use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = drillopt::cli::Cli::parse();
    match drillopt::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
