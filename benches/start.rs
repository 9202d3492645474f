//! The cost of the pre-loaded start (the steady drilling state, MODEL.md §11.6) and of 1 s of
//! simulation from it, at field wall friction: the seed (35 m, 105 elements, default basis) and a
//! 1 km collar string (`problems/long_collars.toml`, a field problem, lengthened to 1000 m, 300
//! elements), both at μ = 0.3 with the Coulomb friction on the slip.
//!
//! `cargo bench -p drillopt-benches --bench start`. Before the friction continuation (revision 8)
//! neither start converged at μ = 0.3 ("did not converge in 300 Newton iterations"), so there is no
//! "before" time to compare: the before figure is a failure.

use criterion::{Criterion, criterion_group, criterion_main};
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunSettings, preloaded_equilibrium, simulate};
use nalgebra::DVector;
use std::hint::black_box;

/// A shipped problem file with the wall friction set to 0.3 (long_collars.toml has it already)
/// and other edits `(from, to)`.
fn field(text: &str, edits: &[(&str, &str)]) -> Problem {
    let mut text = text.replace("friction = 1e-5                 # mu_FS", "friction = 0.3");
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    Problem::from_toml(&text, std::path::Path::new("bench_field.toml")).expect("problem")
}

fn benches(c: &mut Criterion) {
    let cases = [
        (
            "seed",
            field(include_str!("../problems/seed_mc2014.toml"), &[]),
        ),
        (
            "collars_1km",
            field(
                include_str!("../problems/long_collars.toml"),
                &[
                    ("length = \"466 m\"", "length = \"1000 m\""),
                    ("elements = 150 ", "elements = 300 "),
                    ("probes = [\"233 m\"]", "probes = [\"500 m\"]"),
                ],
            ),
        ),
    ];
    for (name, p) in cases {
        let model = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).expect("modes");
        let op = p.operating_point;
        let mut group = c.benchmark_group("field_friction");
        group.sample_size(10);
        group.bench_function(format!("preloaded_start_{name}"), |b| {
            b.iter(|| {
                let (q, iterations) =
                    preloaded_equilibrium(black_box(&model), op, Effects::ALL).expect("start");
                (q.len(), iterations)
            })
        });
        let (q0, _) = preloaded_equilibrium(&model, op, Effects::ALL).expect("start");
        let start = InitialState::Given {
            v: DVector::zeros(q0.len()),
            q: q0,
        };
        let one_second = RunSettings::new(1.0, p.simulation.time_step);
        group.bench_function(format!("simulate_1s_{name}"), |b| {
            b.iter(|| {
                let out = simulate(&model, op, Effects::ALL, &one_second, start.clone(), |_| {});
                assert!(out.error.is_none(), "{:?}", out.error);
                out.stats.steps
            })
        });
        group.finish();
    }
}

criterion_group!(start, benches);
criterion_main!(start);
