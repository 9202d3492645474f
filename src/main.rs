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
    stdout_errors_end_the_process();
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

/// `println!` panics when standard output cannot be written (`drillopt modes … > /dev/full`: "failed
/// printing to stdout: No space left on device", exit status 101 with a backtrace). That is an I/O
/// error, not a bug: said in one line, exit status 1. Other panics keep the default report.
fn stdout_errors_end_the_process() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied());
        if let Some(why) = message.and_then(|m| m.strip_prefix("failed printing to stdout: ")) {
            eprintln!("error: cannot write to standard output: {why}");
            std::process::exit(1);
        }
        default(info);
    }));
}
