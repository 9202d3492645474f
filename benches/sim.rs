//! The simulator's cost on the seed configuration (105 elements) with the paper's basis (51 lowest
//! modes, unloaded start) and with drillopt's default basis (16 / 8 / 4 per family + 2 static
//! corrections, pre-loaded start): one time step from a drilling state with stick-slip developing,
//! and a 1 s simulated window; 1 s of the seed string with Detournay's rate law and with the
//! delayed depth-of-cut law `rgd` (`bit_law/…`).
//!
//! `cargo bench -p drillopt-benches --bench sim`. The whole 90 s seed run is timed by `drillopt
//! simulate` itself (summary.json, `solver.wall_time_s`).

use criterion::{Criterion, criterion_group, criterion_main};
use drillopt::integrate::{Newmark, NewmarkSettings, StepOutcome};
use drillopt::model::BasisSpec;
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{
    Dynamics, Effects, InitialState, RunSettings, preloaded_equilibrium, simulate,
    static_equilibrium,
};
use nalgebra::DVector;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let p = Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../problems/seed_mc2014.toml"
    ))
    .expect("seed problem");
    let op = p.operating_point;
    for (name, basis, preloaded) in [
        ("paper", BasisSpec::Lowest(51), false),
        ("default", BasisSpec::DEFAULT, true),
    ] {
        let model = ReducedModel::new(&p.model, p.mesh.elements, &basis).expect("modes");
        let (q0, _) = if preloaded {
            preloaded_equilibrium(&model, op, Effects::ALL)
        } else {
            static_equilibrium(&model)
        }
        .expect("equilibrium");
        let n = model.size();
        let start = InitialState::Given {
            q: q0.clone(),
            v: DVector::zeros(n),
        };

        // A state 0.5 s into the seed run (drilling, on the wall, torsional oscillation growing).
        let settings = RunSettings::new(0.5, p.simulation.time_step);
        let warm = simulate(&model, op, Effects::ALL, &settings, start.clone(), |_| {});
        let (q, v) = warm.final_state;
        let mut sys = Dynamics::new(&model, op, Effects::ALL);
        // Full Newton at every attempt (no early rejection), whatever the error of this fixed h.
        let settings = NewmarkSettings {
            early_reject: f64::INFINITY,
            ..Default::default()
        };
        let mut nm = Newmark::new(settings, 0.5, q, v, DVector::zeros(n));
        assert!(nm.consistent_acceleration(&mut sys));
        let h = 2e-4;
        c.bench_function(&format!("newmark_step_seed_{name}"), |b| {
            b.iter(|| {
                let outcome = nm.attempt(black_box(&mut sys), h);
                assert!(matches!(outcome, StepOutcome::Converged { .. }));
            })
        });

        let mut group = c.benchmark_group("seed_window");
        group.sample_size(10);
        let one_second = RunSettings::new(1.0, p.simulation.time_step);
        group.bench_function(format!("simulate_1s_{name}"), |b| {
            b.iter(|| {
                let out = simulate(&model, op, Effects::ALL, &one_second, start.clone(), |_| {});
                assert!(out.error.is_none());
                out.stats.steps
            })
        });
        group.finish();
    }
    bit_laws(c);
}

/// 1 s of `problems/seed_detournay.toml` (60 rpm, 5 m/h, imposed feed, default basis, pre-loaded
/// start) with Detournay's rate law and with the delayed depth-of-cut law `rgd` (4 blades, the
/// same rock): the cost of the delay (the rock surface's read and cut, and the axial
/// instability it lets grow; issue 29).
fn bit_laws(c: &mut Criterion) {
    let text = include_str!("../problems/seed_detournay.toml");
    let mut group = c.benchmark_group("bit_law");
    group.sample_size(10);
    for law in ["detournay", "rgd"] {
        let toml = if law == "rgd" {
            text.replace("law = \"detournay\"", "law = \"rgd\"\nblades = 4")
        } else {
            text.to_string()
        };
        let p = Problem::from_toml(&toml, std::path::Path::new("seed_detournay.toml"))
            .expect("seed_detournay");
        let model =
            ReducedModel::new(&p.model, p.mesh.elements, &BasisSpec::DEFAULT).expect("modes");
        let one_second = RunSettings::new(1.0, p.simulation.time_step);
        group.bench_function(format!("simulate_1s_{law}"), |b| {
            b.iter(|| {
                let out = simulate(
                    &model,
                    p.operating_point,
                    Effects::ALL,
                    &one_second,
                    InitialState::Preloaded,
                    |_| {},
                );
                assert!(out.error.is_none());
                out.stats.steps
            })
        });
    }
    group.finish();
}

criterion_group!(sim, benches);
criterion_main!(sim);
