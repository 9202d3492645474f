use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Rust ignores SIGPIPE, so printing into a closed pipe (`drillopt modes … | head -1`) would
    // panic; restore the default action: the process ends quietly, as Unix tools do.
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Under mpirun (`--features mpi`): ranks 1…N−1 simulate what rank 0 sends them; rank 0 runs
    // the command and releases them at the end, whatever its outcome.
    #[cfg(feature = "mpi")]
    let _universe = {
        use drillopt::study::mpi;
        let Some((universe, threading)) =
            ::mpi::initialize_with_threading(::mpi::Threading::Serialized)
        else {
            eprintln!("error: MPI could not be initialised");
            return ExitCode::FAILURE;
        };
        if threading < ::mpi::Threading::Serialized && mpi::ranks() > 1 {
            eprintln!(
                "error: the MPI library gives threading level {threading:?}; drillopt needs Serialized"
            );
            return ExitCode::FAILURE;
        }
        if mpi::rank() > 0 {
            mpi::serve();
            return ExitCode::SUCCESS;
        }
        universe
    };
    // A binary built without MPI, launched by mpirun: every rank would run the whole command.
    #[cfg(not(feature = "mpi"))]
    if let Some(n) = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"]
        .iter()
        .find_map(|v| std::env::var(v).ok())
        .and_then(|n| n.parse::<u32>().ok())
        .filter(|&n| n > 1)
    {
        eprintln!(
            "error: launched on {n} MPI ranks, but this drillopt was built without MPI; rebuild with `cargo build --release --features mpi`"
        );
        return ExitCode::FAILURE;
    }
    let cli = drillopt::cli::Cli::parse();
    let status = match drillopt::cli::run(cli) {
        Ok(drillopt::cli::Outcome::Success) => ExitCode::SUCCESS,
        Ok(drillopt::cli::Outcome::NegativeVerdict) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {}", drillopt::cli::error_text(&e));
            ExitCode::FAILURE
        }
    };
    #[cfg(feature = "mpi")]
    drillopt::study::mpi::stop_workers();
    status
}
