//! Why `integrate::DenseLu` is hand-written (issue 12: keep our own code only where a benchmark
//! says why): the Newton matrix of the reduced model is small and dense (46 vectors for the
//! default basis, 51 for the paper's, 69 for the ×1.5 refinement of `verify`) and is factorised
//! hundreds of thousands of times per run. This bench times factor + one solve of such a matrix
//! with DenseLu and with faer's partial-pivoting LU used in place (preallocated permutations and
//! scratch: no allocation, as the time-step loop requires) and through its allocating
//! high-level API.
//!
//! `cargo bench -p drillopt-benches --bench lu`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use drillopt::integrate::DenseLu;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::{Conj, Mat, Par};
use nalgebra::{DMatrix, DVector};
use std::hint::black_box;

/// A well-conditioned nonsymmetric matrix like a Newton matrix I + c_v D + c_q K_t: diagonal
/// dominant with a random part (xorshift, seeded).
fn newton_like(n: usize) -> DMatrix<f64> {
    let mut state = 0x9E37_79B9_7F4A_7C15_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    DMatrix::from_fn(n, n, |i, j| if i == j { 2.0 + n as f64 } else { next() })
}

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("lu_factor_solve");
    for n in [46, 51, 69] {
        let a = newton_like(n);
        let b = DVector::from_fn(n, |i, _| 1.0 + i as f64);

        let mut ours = DenseLu::new(n);
        let mut x = b.clone();
        group.bench_with_input(BenchmarkId::new("dense_lu", n), &n, |bench, _| {
            bench.iter(|| {
                ours.factor(black_box(&a)).expect("regular");
                x.copy_from(&b);
                ours.solve_in_place(&mut x);
                black_box(x[0])
            })
        });

        let mut lu = Mat::<f64>::zeros(n, n);
        let mut rhs = Mat::<f64>::zeros(n, 1);
        let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default())
            .or(solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq));
        let mut buffer = MemBuffer::new(req);
        group.bench_with_input(BenchmarkId::new("faer_in_place", n), &n, |bench, _| {
            bench.iter(|| {
                for j in 0..n {
                    for i in 0..n {
                        lu[(i, j)] = a[(i, j)];
                    }
                    rhs[(j, 0)] = b[j];
                }
                let stack = MemStack::new(&mut buffer);
                let (_, p) = factor::lu_in_place(
                    lu.as_mut(),
                    &mut perm,
                    &mut perm_inv,
                    Par::Seq,
                    stack,
                    Default::default(),
                );
                solve::solve_in_place_with_conj(
                    lu.as_ref(),
                    lu.as_ref(),
                    p,
                    Conj::No,
                    rhs.as_mut(),
                    Par::Seq,
                    MemStack::new(&mut buffer),
                );
                black_box(rhs[(0, 0)])
            })
        });

        // Both factorisations solve the same system (checked once, outside the timing).
        let diff = (0..n)
            .map(|i| (x[i] - rhs[(i, 0)]).abs())
            .fold(0.0, f64::max);
        assert!(
            diff < 1e-12 * x.amax(),
            "DenseLu and faer disagree by {diff}"
        );

        let af = Mat::<f64>::from_fn(n, n, |i, j| a[(i, j)]);
        let bf = Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
        group.bench_with_input(BenchmarkId::new("faer_allocating", n), &n, |bench, _| {
            use faer::linalg::solvers::Solve;
            bench.iter(|| {
                let lu = black_box(&af).partial_piv_lu();
                black_box(lu.solve(&bf)[(0, 0)])
            })
        });
    }
    group.finish();
}

criterion_group!(lu, benches);
criterion_main!(lu);
