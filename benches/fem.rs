//! Assembly and modal solve of the seed configuration (105 elements, 636 DOF), and the element
//! kernels of the time-step loop (strain and inertial forces of one element).
//!
//! `cargo bench -p drillopt-benches --bench fem`. `-- modes_` benches the basis of a 2000-element
//! mesh (sparse assembly and Lanczos) and one 799-DOF bending block dense against Lanczos. The
//! modal solve is benched both as drillopt does it (four decoupled family blocks) and as one dense
//! generalized eigenproblem on all 628 free DOFs, for comparison. The element kernels (`cargo bench
//! -p drillopt-benches --bench fem -- element_`) are benched next to the dense path they replaced:
//! G d, Gᵀ ∂W/∂g, Gᵀ H G and the inertia rows through nalgebra's generic products on the dense
//! operators, rebuilt here from the public interpolation, Gauss point by point.

use criterion::{Criterion, criterion_group, criterion_main};
use drillopt::fem::Dof;
use drillopt::fem::{
    BeamElement, BoundaryConditions, ElementInertia, ElementMatrix, ElementStrains, ElementVector,
    STRAIN_VARS, StrainEnergy, assemble, gauss_legendre_4,
};
use drillopt::problem::Problem;
use drillopt::rom::{ModalBasis, generalized_symmetric_eigen, sparse_generalized_eigen};
use faer::Par;
use nalgebra::{SMatrix, Vector3};
use std::hint::black_box;

fn seed() -> Problem {
    Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../problems/seed_mc2014.toml"
    ))
    .expect("seed problem")
}

/// A drilling-like element state: elastic displacements ~1 cm, rotations ~1e-2 rad and a twist of
/// a few radians (the simulator passes the elastic state); absolute velocities with the spin
/// Ω ≈ 10 rad/s; accelerations ~10.
fn element_state() -> [ElementVector; 3] {
    let wave = |k: f64, amp: f64| ElementVector::from_fn(|i, _| amp * ((i as f64 + 1.0) * k).sin());
    let mut d = wave(0.7, 1e-2);
    let mut v = wave(1.3, 0.2);
    let a = wave(2.1, 10.0);
    (d[3], d[9]) = (2.5, 2.52);
    (v[3], v[9]) = (10.3, 9.8);
    [d, v, a]
}

/// The dense 8 × 12 strain operators at the Gauss points, with the weights.
fn dense_strain_operators(e: &BeamElement) -> ([SMatrix<f64, STRAIN_VARS, 12>; 4], [f64; 4]) {
    let (xs, ws) = gauss_legendre_4(e.length);
    let ops = xs.map(|x| {
        let n = e.interpolation(x);
        let mut g = SMatrix::<f64, STRAIN_VARS, 12>::zeros();
        for k in 0..6 {
            g.set_row(k, &n.derivative.row(k));
        }
        g.set_row(6, &n.value.row(4));
        g.set_row(7, &n.value.row(5));
        g
    });
    (ops, ws)
}

fn dense_strain_force_and_energy(
    ops: &[SMatrix<f64, STRAIN_VARS, 12>; 4],
    ws: &[f64; 4],
    law: &StrainEnergy,
    d: &ElementVector,
) -> (ElementVector, f64) {
    let mut f = ElementVector::zeros();
    let mut u = 0.0;
    for (g, &w) in ops.iter().zip(ws) {
        let (wd, dw) = law.gradient(&(g * d));
        f.gemv_tr(w, g, &dw, 1.0);
        u += w * wd;
    }
    (f, u)
}

fn dense_tangent_fast(
    ops: &[SMatrix<f64, STRAIN_VARS, 12>; 4],
    ws: &[f64; 4],
    law: &StrainEnergy,
    d: &ElementVector,
) -> ElementMatrix {
    let mut k = ElementMatrix::zeros();
    for (g, &w) in ops.iter().zip(ws) {
        let h = law.hessian_fd(&(g * d));
        k += g.transpose() * (h * w) * g;
    }
    k
}

/// The dense 3 × 12 rotation rows (θx, θy, θz) at the Gauss points.
fn dense_rotation_rows(e: &BeamElement) -> [SMatrix<f64, 3, 12>; 4] {
    gauss_legendre_4(e.length)
        .0
        .map(|x| e.interpolation(x).value.fixed_rows::<3>(3).into_owned())
}

/// The nonlinear inertial force and T_nl through the dense rows (the formulas of `ElementInertia`).
fn dense_inertia_force_and_energy(
    rot: &[SMatrix<f64, 3, 12>; 4],
    ws: &[f64; 4],
    rho_i: f64,
    d: &ElementVector,
    v: &ElementVector,
    a: &ElementVector,
) -> (ElementVector, f64) {
    let k = 2.0 * rho_i;
    let mut f = ElementVector::zeros();
    let mut t = 0.0;
    for (n, &w) in rot.iter().zip(ws) {
        let (th, rate, acc) = (n * d, n * v, n * a);
        let (ty, wx, wy, wz) = (th[1], rate[0], rate[1], rate[2]);
        let p = Vector3::new(
            -k * (wy * wz + ty * acc[2]),
            k * (wx * wz - ty * wz * wz),
            k * (-wx * wy - ty * acc[0] + 2.0 * ty * wy * wz + ty * ty * acc[2]),
        );
        f.gemv_tr(w, n, &p, 1.0);
        t += w * rho_i * (-2.0 * ty * wx * wz + ty * ty * wz * wz);
    }
    (f, t)
}

fn kernels(c: &mut Criterion) {
    let p = seed();
    let element = *assemble(&p.model, p.mesh.elements).layout.element(0);
    let law = StrainEnergy::of(&p.model);
    let strains = ElementStrains::new(&element);
    let inertia = ElementInertia::new(&element);
    let [d, v, a] = element_state();
    let (ops, ws) = dense_strain_operators(&element);
    let rot = dense_rotation_rows(&element);
    let rho_i = element.section.rotary_inertia;

    let mut g = c.benchmark_group("element_strain");
    g.bench_function("dense_reference_force_energy", |b| {
        b.iter(|| dense_strain_force_and_energy(&ops, &ws, &law, black_box(&d)))
    });
    g.bench_function("internal_force_and_energy", |b| {
        b.iter(|| strains.internal_force_and_energy(&law, black_box(&d)))
    });
    g.bench_function("internal_force", |b| {
        b.iter(|| strains.internal_force(&law, black_box(&d)))
    });
    g.bench_function("energy", |b| b.iter(|| strains.energy(&law, black_box(&d))));
    g.bench_function("dense_reference_tangent_fast", |b| {
        b.iter(|| dense_tangent_fast(&ops, &ws, &law, black_box(&d)))
    });
    g.bench_function("tangent_fast", |b| {
        b.iter(|| strains.tangent_fast(&law, black_box(&d)))
    });
    g.finish();

    let mut g = c.benchmark_group("element_inertia");
    g.bench_function("dense_reference_force_energy", |b| {
        b.iter(|| dense_inertia_force_and_energy(&rot, &ws, rho_i, black_box(&d), &v, &a))
    });
    g.bench_function("force_and_energy", |b| {
        b.iter(|| inertia.force_and_energy(black_box(&d), black_box(&v), black_box(&a)))
    });
    g.bench_function("force", |b| {
        b.iter(|| inertia.force(black_box(&d), black_box(&v), black_box(&a)))
    });
    g.bench_function("energy", |b| {
        b.iter(|| inertia.energy(black_box(&d), black_box(&v)))
    });
    g.finish();
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
        b.iter(|| ModalBasis::lowest(black_box(&global), &bc, 51, Par::Seq).unwrap())
    });

    // Long meshes (issue 13 item 6): the basis of the problem by sparse assembly and Lanczos, and
    // one bending block of 799 DOFs (400 elements, just under LANCZOS_MIN_BLOCK) dense and by
    // Lanczos, which sets the threshold.
    c.bench_function("modes_long_2000_elements_default_basis", |b| {
        b.iter(|| ModalBasis::compute(black_box(&p.model), 2000, &p.mesh.basis).unwrap())
    });
    let long = drillopt::fem::assemble_sparse(&p.model, 400);
    let bending: Vec<usize> = BoundaryConditions::drillstring(400)
        .free_dofs()
        .into_iter()
        .filter(|&i| matches!(Dof::of_index(i), Dof::V | Dof::ThetaZ))
        .collect();
    let (kb, mb) = (
        long.stiffness.submatrix(&bending),
        long.mass.submatrix(&bending),
    );
    let (kd, md) = (kb.to_dense(), mb.to_dense());
    c.bench_function("modes_block_799_dense_16", |b| {
        b.iter(|| generalized_symmetric_eigen(black_box(kd.as_ref()), md.as_ref(), 16, Par::Seq))
    });
    c.bench_function("modes_block_799_lanczos_16", |b| {
        b.iter(|| sparse_generalized_eigen(black_box(&kb), &mb, 16, Par::Seq))
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
criterion_group! {
    name = element;
    config = Criterion::default();
    targets = kernels
}
criterion_main!(fem, element);
