//! The finite-element model without reduction (issue 11: the reference of the reduced bases).
//!
//! Its equations are those of a complete modal basis written in other coordinates (nodal instead
//! of mass-normalised modal ones), and the two are computed by different code paths: identity
//! selection with sparse mass, stiffness and damping, a sparse LU and the energy norm √(qᵀKq),
//! against dense modal operators, the dense LU and ω-weights. The same trajectory from both is
//! the check that the unreduced path solves the model it claims to.

use drillopt::model::{BasisSpec, OperatingPoint};
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunOutput, RunSettings, simulate};

fn tiny() -> Problem {
    Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap()
}

fn run(model: &ReducedModel, op: OperatingPoint, duration: f64, divisor: f64) -> RunOutput {
    let mut settings = RunSettings::new(duration, 1e-3);
    settings.newmark.atol /= divisor;
    settings.newmark.rtol /= divisor;
    settings.newmark.newton_tol /= divisor;
    let out = simulate(
        model,
        op,
        Effects::ALL,
        &settings,
        InitialState::StaticEquilibrium,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    out
}

/// The bit speed at time t, interpolated linearly in the recorded history.
fn at(series: &[f64], times: &[f64], t: f64) -> f64 {
    let k = times.partition_point(|&s| s < t).clamp(1, times.len() - 1);
    let f = (t - times[k - 1]) / (times[k] - times[k - 1]);
    (1.0 - f) * series[k - 1] + f * series[k]
}

#[test]
fn the_unreduced_model_follows_the_trajectory_of_its_complete_modal_basis() {
    let p = tiny();
    let elements = p.mesh.elements;
    let nodal = ReducedModel::unreduced(&p.model, elements).unwrap();
    let n = nodal.size();
    assert!(nodal.is_unreduced());
    assert_eq!(n, nodal.bc.free_dofs().len());
    let complete = ReducedModel::new(&p.model, elements, &BasisSpec::Lowest(n)).unwrap();
    // Every mode of the mesh, counted by family the same way in both.
    assert_eq!(nodal.basis.counts(), complete.basis.counts());
    // Seed materials on an 8 m string at 40 rpm and 10 m/h, from rest: the bit sticks and slips
    // within 0.05 s. The comparison stops at 0.07 s: from there on stick-slip amplifies any
    // difference of round-off (or of tolerance) into a different phase, for both models alike
    // (measured: both agree to 6 digits up to 0.07 s with the default tolerances and with
    // tolerances ÷10 and ÷100, while each moves with its tolerance).
    let op = OperatingPoint {
        omega: drillopt::units::from_rpm(40.0),
        v0: drillopt::units::from_m_per_h(10.0),
        wob: 0.0,
    };
    let (a, b) = (run(&nodal, op, 0.07, 1.0), run(&complete, op, 0.07, 1.0));
    let (sa, sb) = (&a.series, &b.series);
    let spread = sb
        .bit_angular_velocity
        .iter()
        .fold(0.0_f64, |m, w| m.max((w - op.omega).abs()));
    assert!(
        spread > 0.05 * op.omega,
        "the bit speed must move for the check to mean something: {spread}"
    );
    let mut worst = 0.0_f64;
    for k in 0..=35 {
        let t = 0.002 * k as f64;
        let wa = at(&sa.bit_angular_velocity, &sa.t, t);
        let wb = at(&sb.bit_angular_velocity, &sb.t, t);
        worst = worst.max((wa - wb).abs());
    }
    println!(
        "bit speed: largest difference {worst:.3e} rad/s of a swing {spread:.3e} rad/s; steps {} / {}",
        a.stats.steps, b.stats.steps
    );
    // Two integrations of the same equations with the same step sequence up to round-off.
    assert!(worst < 1e-4 * spread, "{worst} against {spread}");
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let (wob_a, wob_b) = (mean(&sa.weight_on_bit), mean(&sb.weight_on_bit));
    assert!((wob_a - wob_b).abs() < 1e-3 * wob_b, "{wob_a} {wob_b}");
}

/// The unreduced model at rest: the static sag under gravity is the modal one, and the lowest
/// torsional and axial frequencies (which set the step) are those of `drillopt modes`.
#[test]
fn the_unreduced_model_has_the_frequencies_of_the_mesh() {
    let p = tiny();
    let nodal = ReducedModel::unreduced(&p.model, p.mesh.elements).unwrap();
    let reduced = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
    for family in [
        drillopt::rom::Family::Torsional,
        drillopt::rom::Family::Axial,
    ] {
        let lowest = |m: &ReducedModel| {
            m.basis
                .family(family)
                .filter(|m| m.kind == drillopt::rom::ModeKind::Normal)
                .map(|m| m.freq_hz)
                .fold(f64::INFINITY, f64::min)
        };
        let (a, b) = (lowest(&nodal), lowest(&reduced));
        assert!((a - b).abs() < 1e-9 * b, "{family}: {a} against {b}");
    }
    assert_eq!(
        drillopt::sim::resolving_step(&nodal),
        drillopt::sim::resolving_step(&reduced)
    );
}
