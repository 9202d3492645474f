//! The command line: argument parsing and the commands that drive the library. This is the
//! binary's edge, where errors become `anyhow` reports and exit codes.

mod batch;
mod campbell;
mod compare;
pub use compare::parse_point;
mod interrupt;
mod keys;
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
    /// Units of the terminal, the CSV tables (evaluations.csv) and the plots: `metric` (rpm, m/h,
    /// kN, kN·m, MPa, m, mm, kW) or `field` (oilfield units: rpm, ft/h, klbf, kft·lbf, psi, ft,
    /// in, hp; also `oilfield`). The JSON results, timeseries.csv and stress_envelope.csv stay in
    /// SI, with the unit in each key or column
    #[arg(long, global = true, value_enum, default_value = "metric")]
    pub units: Units,
}

/// `--units`: the [`UnitSystem`](crate::units::UnitSystem) of the human-readable outputs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Units {
    /// rpm, m/h, kN, kN·m, MPa, m, mm, kW.
    #[default]
    Metric,
    /// rpm, ft/h, klbf, kft·lbf, psi, ft, in, hp.
    #[value(alias = "oilfield")]
    Field,
}

impl From<Units> for crate::units::UnitSystem {
    fn from(u: Units) -> Self {
        match u {
            Units::Metric => crate::units::UnitSystem::Metric,
            Units::Field => crate::units::UnitSystem::Field,
        }
    }
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
    /// The problem-file keys: unit, admissible range, default and meaning of every scalar key
    /// and law parameter (Markdown; docs/keys.md is this output).
    Keys(keys::KeysArgs),
}

/// A basis error as the user should read it: file, key, what went wrong. A numerical failure of
/// the eigen-solve comes from the physical inputs, not from the basis: it names the keys that set
/// the matrix that failed.
pub(crate) fn basis_error(
    path: &std::path::Path,
    problem: &crate::problem::Problem,
    e: crate::rom::BasisError,
) -> anyhow::Error {
    use crate::rom::{BasisError, EigenError};
    let basis_key = match problem.mesh.basis {
        crate::model::BasisSpec::Lowest(_) => "mesh.reduced_modes",
        crate::model::BasisSpec::PerFamily { .. } => "mesh.basis",
    };
    use crate::problem::keys::Stage;
    let stage = match &e {
        BasisError::Eigen(EigenError::MassNotPositiveDefinite { .. }) => Stage::MassMatrix,
        BasisError::Eigen(EigenError::StiffnessNotPositive { .. }) => Stage::StiffnessMatrix,
        // The eigen-solve itself (Lanczos, then the dense solver up to 4000 DOFs per family)
        // did not reach the count: the count or the mesh, not the physical inputs.
        BasisError::Eigen(EigenError::NoConvergence { converged, asked }) => {
            return anyhow::anyhow!(
                "{}: key `{basis_key}`: the eigen-solve found {converged} of the {asked} lowest modes of a family to the accuracy the basis needs (the sparse Lanczos solver, then the dense one for a family of up to 4000 degrees of freedom); ask for at most {converged} modes per family (or a cutoff frequency), or use fewer elements (`mesh.elements`)",
                path.display()
            );
        }
        BasisError::Eigen(EigenError::TooMany { .. }) | BasisError::EmptyFamily { .. } => {
            return anyhow::anyhow!("{}: key `{basis_key}`: {e}", path.display());
        }
        BasisError::RestingShape { .. } => Stage::RestingShape,
    };
    anyhow::anyhow!(
        "{}: {e}; {} depends on {} (and `{basis_key}`): check their values and units",
        path.display(),
        stage.describe(),
        crate::problem::keys::describe_entering(problem, stage)
    )
}

/// Why a basis that asked for the steady-state shapes has none (`None`: it has them, or did not
/// ask).
pub(crate) fn steady_shapes_missing(status: crate::rom::SteadyStatus) -> Option<String> {
    use crate::rom::SteadyStatus;
    Some(match status {
        SteadyStatus::NotAsked | SteadyStatus::Added { .. } => return None,
        SteadyStatus::MeshTooLarge { unknowns, limit } => format!(
            "the finite-element steady state is solved for at most {limit} free DOFs and this mesh has {unknowns}"
        ),
        SteadyStatus::NoReducedStart => {
            "the basis without them has no steady drilling state at the file's operating point"
                .into()
        }
        SteadyStatus::NotConverged { iterations, update } => format!(
            "Newton on the finite-element model's steady state did not converge ({iterations} iterations, last lateral update {:.3} mm)",
            1e3 * update
        ),
        SteadyStatus::FrictionContinuation {
            reached,
            iterations,
        } => format!(
            "the finite-element model's continuation in the wall friction stopped at {:.1} % of it after {iterations} Newton iterations",
            100.0 * reached
        ),
        SteadyStatus::NoFiniteElementStart => {
            "the finite-element model's steady state could not be found (a non-finite state)".into()
        }
    })
}

/// What the basis' steady-state shapes are, for the line below the basis counts: where they come
/// from when they are in (`Ok`), a warning naming `path` that says why not when they were asked
/// for and left out (`Err`), nothing when not asked for.
pub(crate) fn steady_shapes_line(
    path: &std::path::Path,
    status: crate::rom::SteadyStatus,
    units: crate::units::UnitSystem,
) -> Option<Result<String, String>> {
    if let crate::rom::SteadyStatus::Added { omega, v0, .. } = status {
        let (unit, v) = units.from_metric("m/h", crate::units::to_m_per_h(v0));
        return Some(Ok(format!(
            "  steady-state shapes: the finite-element model's steady drilling state at {:.1} rpm, {} {unit} (the file's operating point; for a free top, the block speed the basis without them finds there), in the basis",
            crate::units::to_rpm(omega),
            crate::units::fixed(v, 2)
        )));
    }
    let why = steady_shapes_missing(status)?;
    Some(Err(format!(
        "warning: {}: the basis has no steady-state shapes ({why}): its steady wall forces and torque can differ from the finite-element model's (`drillopt verify` compares them); `[mesh.basis] steady_shapes = false` leaves them out without this warning",
        path.display()
    )))
}

/// The stage a run's failure comes from, and so the keys that can cause it
/// ([`crate::problem::keys`]); none for a failure that is not numerical (an interrupted run, a
/// failed output).
pub(crate) fn failed_stage(e: &crate::sim::SimulationError) -> Option<crate::problem::keys::Stage> {
    use crate::problem::keys::Stage;
    use crate::sim::SimulationError as E;
    match e {
        E::StaticEquilibrium { .. }
        | E::FrictionContinuation { .. }
        | E::NonPhysicalStart { .. }
        | E::NoSteadyDrilling { .. }
        | E::NoHookLoad { .. } => Some(Stage::Start),
        E::StepTooSmall { .. }
        | E::TooManySteps { .. }
        | E::NonFinite { .. }
        | E::Diverged { .. }
        | E::NonPhysicalStress { .. } => Some(Stage::Step),
        E::RecordingStopped { .. } | E::Interrupted { .. } => None,
    }
}

/// Refuses a basis with a frequency that is not positive and finite: a 0 Hz (or NaN) mode means
/// the eigen-solve did not resolve the inputs, and a run or a table on it would be meaningless.
pub(crate) fn check_basis(
    path: &std::path::Path,
    problem: &crate::problem::Problem,
    modes: &[crate::rom::Mode],
) -> anyhow::Result<()> {
    match modes
        .iter()
        .find(|m| !(m.freq_hz > 0.0 && m.freq_hz.is_finite()))
    {
        None => Ok(()),
        Some(m) => Err(anyhow::anyhow!(
            "{}: the eigen-solve gave basis vector {} ({}) a frequency of {} Hz, which is not \
             positive and finite; {} depends on {}: check their values and units",
            path.display(),
            m.index,
            m.family.name(),
            crate::units::show(m.freq_hz),
            crate::problem::keys::Stage::StiffnessMatrix.describe(),
            crate::problem::keys::describe_entering(
                problem,
                crate::problem::keys::Stage::StiffnessMatrix
            )
        )),
    }
}

/// An error and its causes on one line, `a: b: c`, without repeating a cause that a message
/// already quotes (an error that prints its source would otherwise show it twice).
pub fn error_text(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let cause = cause.to_string();
        if text.contains(&cause) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&cause);
    }
    text
}

/// A count flag (`--samples`, `--budget`, `--threads`, `--count`, `--points`): digits only.
/// Clap's own words for `many` or `1e3` were "invalid digit found in string".
pub(crate) fn whole_number(s: &str) -> Result<usize, String> {
    s.trim().parse::<usize>().map_err(|_| {
        "not a whole number; write digits only, such as 20 (no sign, decimal point, exponent \
         or unit)"
            .to_string()
    })
}

/// The name of the lock file a run holds in its output directory (hidden; left in place, since
/// deleting a lock file races with the next run that opens it).
pub(crate) const OUT_LOCK: &str = ".drillopt.lock";

/// An output directory held by this run: an exclusive advisory lock on `<dir>/.drillopt.lock`
/// (`File::try_lock`), released when dropped, so that two runs never write one folder at once
/// (a second `simulate` on the same `--out` silently replaced the first's results). On
/// filesystems without locks the run goes on without one.
#[must_use = "the output directory is locked only while this is held"]
#[derive(Debug)]
pub struct OutDirLock {
    _file: std::fs::File,
}

/// Creates an output directory (`--out`, or the command's default) and locks it for this run,
/// saying which and why when it cannot: a file of that name, a file on the way, no permission,
/// another drillopt run writing there now.
pub(crate) fn create_out_dir(dir: &std::path::Path) -> anyhow::Result<OutDirLock> {
    make_out_dir(dir)?;
    let path = dir.join(OUT_LOCK);
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(|e| {
            anyhow::anyhow!(
                "output directory {}: cannot create its lock file {OUT_LOCK} ({e}); --out takes a directory you may write to",
                dir.display()
            )
        })?;
    match file.try_lock() {
        Ok(()) => {
            remove_stale_temporaries(dir);
            Ok(OutDirLock { _file: file })
        }
        Err(std::fs::TryLockError::Error(_)) => Ok(OutDirLock { _file: file }),
        Err(std::fs::TryLockError::WouldBlock) => anyhow::bail!(
            "output directory {} is in use by another drillopt run (it holds {OUT_LOCK}); wait for it to finish or choose another --out",
            dir.display()
        ),
    }
}

/// Remove the hidden temporary files (`.tmpXXXXXX`) that runs killed in mid-write left in `dir`:
/// under the folder's lock no other drillopt run writes there, so every one is stale. Best
/// effort (a file that cannot be removed stays).
fn remove_stale_temporaries(dir: &std::path::Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let stale = entry
            .file_name()
            .to_str()
            .is_some_and(|n| n.starts_with(".tmp"))
            && entry.file_type().is_ok_and(|t| t.is_file());
        if stale {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

fn make_out_dir(dir: &std::path::Path) -> anyhow::Result<()> {
    if dir.exists() && !dir.is_dir() {
        anyhow::bail!(
            "output directory {}: a file of that name exists; --out takes a directory (created if missing)",
            dir.display()
        );
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        anyhow::anyhow!(
            "output directory {}: cannot be created ({e}); --out takes a directory you may write to",
            dir.display()
        )
    })
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
    let units = crate::units::UnitSystem::from(cli.units);
    match cli.command {
        Command::Modes(args) => done(modes::run(&args, units)),
        Command::Campbell(args) => done(campbell::run(&args)),
        Command::Simulate(args) => done(simulate::run(&args, units)),
        Command::Solve(args) => done(solve::run(&args, units)),
        Command::Compare(args) => done(compare::run(&args, units)),
        Command::Map(args) => done(map::run(&args, units)),
        Command::Batch(args) => done(batch::run(&args, units)),
        Command::Verify(args) => verify::run(&args, units),
        Command::Keys(args) => done(keys::run(&args)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn tiny() -> crate::problem::Problem {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/regression/tiny_string.toml"
        );
        crate::problem::Problem::load(Path::new(path)).unwrap()
    }

    #[test]
    fn a_singular_mass_matrix_names_the_keys_that_set_the_mass() {
        let e = crate::rom::BasisError::Eigen(crate::rom::EigenError::MassNotPositiveDefinite {
            pivot: 0,
        });
        let text = basis_error(Path::new("p.toml"), &tiny(), e).to_string();
        for key in [
            "model.pipe.density",
            "model.pipe.outer_radius",
            "model.length",
        ] {
            assert!(text.contains(&format!("`{key}`")), "{text}");
        }
        assert!(text.starts_with("p.toml: "), "{text}");
    }

    #[test]
    fn a_basis_with_a_zero_or_nan_frequency_is_refused() {
        let problem = tiny();
        let basis = crate::rom::ModalBasis::compute(
            &problem.model,
            problem.mesh.elements,
            &problem.mesh.basis,
        )
        .unwrap();
        assert!(check_basis(Path::new("p.toml"), &problem, &basis.modes).is_ok());
        for bad in [0.0, f64::NAN, f64::INFINITY, -1.0] {
            let mut modes = basis.modes.clone();
            modes[2].freq_hz = bad;
            let text = check_basis(Path::new("p.toml"), &problem, &modes)
                .unwrap_err()
                .to_string();
            assert!(
                text.contains("p.toml")
                    && text.contains("basis vector 3")
                    && text.contains("`model.pipe.youngs_modulus`"),
                "{text}"
            );
        }
    }

    #[test]
    fn a_cause_quoted_by_its_error_is_printed_once() {
        #[derive(Debug, thiserror::Error)]
        #[error("evaluation cache x/cache.jsonl: {source}")]
        struct Quoting {
            source: std::io::Error,
        }
        let io = std::io::Error::from_raw_os_error(20);
        let once = io.to_string();
        let e = anyhow::Error::new(Quoting { source: io }).context("solve p.toml");
        let text = error_text(&e);
        assert_eq!(text.matches(&once).count(), 1, "{text}");
        assert!(text.starts_with("solve p.toml: evaluation cache"), "{text}");
    }

    #[test]
    fn count_flags_say_what_they_take() {
        assert_eq!(whole_number("20"), Ok(20));
        for bad in ["many", "1e3", "-1", "2.5", ""] {
            assert!(
                whole_number(bad).unwrap_err().contains("whole number"),
                "{bad}"
            );
        }
    }

    #[test]
    fn an_output_path_held_by_a_file_is_called_so() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("afile");
        std::fs::write(&file, "x").unwrap();
        let text = create_out_dir(&file).unwrap_err().to_string();
        assert!(
            text.contains("afile") && text.contains("a file of that name"),
            "{text}"
        );
        let text = create_out_dir(&file.join("sub")).unwrap_err().to_string();
        assert!(
            text.contains("afile/sub") && text.contains("cannot be created"),
            "{text}"
        );
        let _held = create_out_dir(&dir.path().join("new/deeper")).unwrap();
    }

    #[test]
    fn an_output_directory_is_held_by_one_run_at_a_time() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let held = create_out_dir(&out).unwrap();
        let text = create_out_dir(&out).unwrap_err().to_string();
        assert!(
            text.contains("in use by another drillopt run") && text.contains("--out"),
            "{text}"
        );
        drop(held);
        let _again = create_out_dir(&out).unwrap();
    }
}
