//! `drillopt modes PROBLEM [--count n] [--json]`.

use crate::fem::BoundaryConditions;
use crate::problem::Problem;
use crate::rom::{BasisCounts, ModalBasis, Mode, ModeKind};
use anyhow::Context;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct ModesArgs {
    /// Problem file (TOML).
    pub problem: PathBuf,
    /// List this many lowest modes instead of the problem's basis.
    #[arg(long, value_parser = super::whole_number, allow_hyphen_values = true)]
    pub count: Option<usize>,
    /// Print JSON {"problem", "dof", "free_dof", "basis": {"bending", "torsional", "axial",
    /// "static_corrections", "resting_shapes", "steady_shapes"}, "steady_shapes": {"status", …},
    /// "modes": [{"index", "freq_hz", "family", "kind"}]}
    /// instead of a table (kind: "mode", "static_correction", "resting_shape" or
    /// "steady_shape").
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct ModesReport<'a> {
    problem: &'a str,
    dof: usize,
    free_dof: usize,
    basis: BasisCounts,
    /// What became of the steady drilling state's shapes (`not_asked` with `--count`).
    steady_shapes: crate::rom::SteadyStatus,
    modes: &'a [Mode],
}

pub fn run(args: &ModesArgs, units: crate::units::UnitSystem) -> anyhow::Result<()> {
    let problem = Problem::load(&args.problem)?;
    let elements = problem.mesh.elements;
    let bc = BoundaryConditions::drillstring(elements);
    // Long meshes are assembled sparse and solved by Lanczos (ModalBasis::sparse_mesh).
    let mut steady = crate::rom::SteadyStatus::NotAsked;
    let basis = match args.count {
        Some(count) => {
            anyhow::ensure!(
                (1..=bc.free_count()).contains(&count),
                "--count must be in [1, {}] (the free DOFs of this mesh), got {count}",
                bc.free_count()
            );
            ModalBasis::compute_lowest(&problem.model, elements, count)
                .with_context(|| format!("modal analysis of {}", args.problem.display()))?
        }
        // The simulator's basis, with the steady state's shapes when it takes them (up to the
        // finite-element steady solve's size; longer meshes keep the sparse modal solve).
        None if problem.mesh.basis.steady_shapes()
            && bc.free_count() <= crate::sim::STEADY_SHAPES_MAX_UNKNOWNS =>
        {
            let model =
                crate::sim::reduced_model(&problem.model, &problem.mesh, problem.operating_point)
                    .map_err(|e| super::basis_error(&args.problem, &problem, e))?;
            steady = model.steady;
            model.basis
        }
        None => {
            if problem.mesh.basis.steady_shapes() {
                // Above the finite-element steady solve's size, as in `simulate`.
                steady = crate::rom::SteadyStatus::MeshTooLarge {
                    unknowns: bc.free_count(),
                    limit: crate::sim::STEADY_SHAPES_MAX_UNKNOWNS,
                };
            }
            ModalBasis::compute(&problem.model, elements, &problem.mesh.basis)
                .map_err(|e| super::basis_error(&args.problem, &problem, e))?
        }
    };
    super::check_basis(&args.problem, &problem, &basis.modes)?;
    let report = ModesReport {
        problem: &problem.name,
        dof: bc.dof(),
        free_dof: bc.free_count(),
        basis: basis.counts(),
        steady_shapes: steady,
        modes: &basis.modes,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{}: {} elements, {} DOF ({} free); {} of {} vectors: {}",
            problem.name,
            elements,
            report.dof,
            report.free_dof,
            if args.count.is_some() {
                "the lowest modes (--count, not the problem's basis)"
            } else {
                "the problem's basis"
            },
            basis.len(),
            report.basis
        );
        match super::steady_shapes_line(&args.problem, steady, units) {
            Some(Ok(line)) => println!("{line}"),
            Some(Err(warning)) => eprintln!("{warning}"),
            None => {}
        }
        println!(
            "  the modes of the string without the wall (held at the top drive and the bit only: the bending modes of a long span are at mHz); on the wall, its lateral frequencies are those of `drillopt campbell` (linearised about the string at rest on the wall)"
        );
        if basis.modes.iter().any(|m| m.kind != ModeKind::Normal) {
            println!(
                "  the frequency of a static correction, resting shape or steady-state shape is its Rayleigh quotient √(ψᵀKψ)/2π (a Ritz vector's), not a natural frequency"
            );
        }
        println!(
            "{:>5}  {:>12}  {:>14}  {:<10}  {:>6}  kind",
            "mode", "freq [Hz]", "omega [rad/s]", "family", "share"
        );
        for m in &basis.modes {
            let share = m.energy_share.iter().cloned().fold(0.0, f64::max);
            println!(
                "{:>5}  {:>12.5}  {:>14.4}  {:<10}  {:>5.1}%  {}",
                m.index,
                m.freq_hz,
                m.omega,
                m.family,
                100.0 * share,
                match m.kind {
                    ModeKind::Normal => "mode",
                    ModeKind::StaticCorrection => "static correction",
                    ModeKind::RestingShape => "resting shape",
                    ModeKind::SteadyShape => "steady-state shape",
                }
            );
        }
    }
    Ok(())
}
