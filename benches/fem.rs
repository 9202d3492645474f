//! Assembly and modal solve of the seed configuration (105 elements, 636 DOF).
//!
//! `cargo bench --bench fem`. The modal solve is benched both as drillopt does it (four decoupled
//! family blocks) and as one dense generalized eigenproblem on all 628 free DOFs, for comparison.

use criterion::{Criterion, criterion_group, criterion_main};
use drillopt::fem::{BoundaryConditions, assemble};
use drillopt::problem::Problem;
use drillopt::rom::{ModalBasis, generalized_symmetric_eigen};
use faer::Par;
use std::hint::black_box;

fn seed() -> Problem {
    Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/seed_mc2014.toml"
    ))
    .expect("seed problem")
}

fn benches(c: &mut Criterion) {
    let p = seed();
    let n = p.mesh.elements;
    c.bench_function("assemble_seed_636dof", |b| {
        b.iter(|| assemble(black_box(&p.model), n))
    });

    let global = assemble(&p.model, n);
    let bc = BoundaryConditions::drillstring(n);
    c.bench_function("modes_seed_51_of_636dof", |b| {
        b.iter(|| ModalBasis::of(black_box(&global), &bc, p.mesh.reduced_modes, Par::Seq).unwrap())
    });

    let (k, m) = (bc.reduce(&global.stiffness), bc.reduce(&global.mass));
    c.bench_function("dense_generalized_eigen_628", |b| {
        b.iter(|| {
            generalized_symmetric_eigen(black_box(k.as_ref()), m.as_ref(), 51, Par::Seq).unwrap()
        })
    });
}

criterion_group! {
    name = fem;
    config = Criterion::default().sample_size(20);
    targets = benches
}
criterion_main!(fem);
