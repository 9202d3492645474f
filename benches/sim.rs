//! The simulator's cost on the seed configuration (105 elements, 51 modes): one time step from a
//! drilling state with stick-slip developing, and a 1 s simulated window from static equilibrium.
//!
//! `cargo bench --bench sim`. The whole 90 s seed run is timed by `drillopt simulate` itself
//! (summary.json, `solver.wall_time_s`).

use criterion::{Criterion, criterion_group, criterion_main};
use drillopt::integrate::{Newmark, NewmarkSettings, StepOutcome};
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Dynamics, Effects, InitialState, RunSettings, simulate, static_equilibrium};
use nalgebra::DVector;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let p = Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/seed_mc2014.toml"
    ))
    .expect("seed problem");
    let model = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).expect("modes");
    let (q_static, _) = static_equilibrium(&model).expect("static equilibrium");
    let n = model.size();

    // A state 0.5 s into the seed run (drilling, on the wall, torsional oscillation growing).
    let settings = RunSettings::new(0.5, p.simulation.time_step);
    let warm = simulate(
        &model,
        p.operating_point,
        Effects::ALL,
        &settings,
        InitialState::Given {
            q: q_static.clone(),
            v: DVector::zeros(n),
        },
        |_| {},
    );
    let (q, v) = warm.final_state;
    let mut sys = Dynamics::new(&model, p.operating_point, Effects::ALL);
    // Full Newton at every attempt (no early rejection), whatever the error of this fixed h.
    let settings = NewmarkSettings {
        early_reject: f64::INFINITY,
        ..Default::default()
    };
    let mut nm = Newmark::new(settings, 0.5, q, v, DVector::zeros(n));
    assert!(nm.consistent_acceleration(&mut sys));
    let h = 2e-4;
    c.bench_function("newmark_step_seed_51_modes", |b| {
        b.iter(|| {
            let outcome = nm.attempt(black_box(&mut sys), h);
            assert!(matches!(outcome, StepOutcome::Converged { .. }));
        })
    });

    let mut group = c.benchmark_group("seed_window");
    group.sample_size(10);
    let one_second = RunSettings::new(1.0, p.simulation.time_step);
    group.bench_function("simulate_1s_from_static_equilibrium", |b| {
        b.iter(|| {
            let out = simulate(
                &model,
                p.operating_point,
                Effects::ALL,
                &one_second,
                InitialState::Given {
                    q: q_static.clone(),
                    v: DVector::zeros(n),
                },
                |_| {},
            );
            assert!(out.error.is_none());
            out.stats.steps
        })
    });
    group.finish();
}

criterion_group!(sim, benches);
criterion_main!(sim);
