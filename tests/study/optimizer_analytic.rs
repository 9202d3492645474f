//! End-to-end tests of `drillopt::optimize` on analytic problems with known constrained optima:
//! the trust-region method (TR) beside Nelder–Mead (NM) on the same problems and starts.
//!
//! Each test states its tolerance and evaluation budget in its doc comment and prints the
//! evaluation counts and errors (`cargo test --release --test study -- optimizer_analytic::
//! --nocapture`).
//! Every test also checks that every evaluated point satisfies the linear constraints (the
//! optimisers never evaluate outside them).

use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use drillopt::optimize::{
    BlackBox, Evaluation, FEASIBILITY_TOL, FeasibleSet, NelderMeadOptions, OptimizeError,
    OptimizeResult, SwarmOptions, TrustRegionOptions, grid_search, minimize_nelder_mead,
    minimize_particle_swarm, minimize_trust_region,
};

/// A 2-D black box from closures, counting calls to `evaluate_batch`.
struct Problem2 {
    m: usize,
    f: fn(&[f64]) -> Evaluation,
    batches: AtomicUsize,
}

impl Problem2 {
    fn new(m: usize, f: fn(&[f64]) -> Evaluation) -> Self {
        Problem2 {
            m,
            f,
            batches: AtomicUsize::new(0),
        }
    }
}

impl BlackBox for Problem2 {
    fn dim(&self) -> usize {
        2
    }
    fn n_constraints(&self) -> usize {
        self.m
    }
    fn evaluate(&self, x: &[f64]) -> Evaluation {
        (self.f)(x)
    }
    fn evaluate_batch(&self, xs: &[Vec<f64>]) -> Vec<Evaluation> {
        self.batches.fetch_add(1, Ordering::Relaxed);
        xs.iter().map(|x| self.evaluate(x)).collect()
    }
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn report(name: &str, method: &str, r: &OptimizeResult, x_ref: &[f64], f_ref: f64) -> (f64, f64) {
    let ex = dist(&r.x, x_ref);
    let ef = r.evaluation.objective - f_ref;
    println!(
        "{name:<28} {method:<3} evals {:>3}  |x − x*| = {ex:.2e}  f − f* = {ef:.2e}  ({})",
        r.evaluations, r.termination
    );
    (ex, ef)
}

fn assert_all_in_set(set: &FeasibleSet, r: &OptimizeResult) {
    for (x, _) in &r.history {
        assert!(
            set.contains(x, FEASIBILITY_TOL),
            "evaluated point {x:?} violates the linear constraints by {:.2e}",
            set.violation(x)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// (a) Convex quadratic, linear constraint active at the optimum.

const Q: [[f64; 2]; 2] = [[3.0, 1.0], [1.0, 2.0]];
const P: [f64; 2] = [0.8, 0.7];

fn quadratic(x: &[f64]) -> f64 {
    let d = [x[0] - P[0], x[1] - P[1]];
    0.5 * (Q[0][0] * d[0] * d[0] + 2.0 * Q[0][1] * d[0] * d[1] + Q[1][1] * d[1] * d[1])
}

fn unit_triangle() -> FeasibleSet {
    // Unit box cut by x + y ≤ 1.
    FeasibleSet::new(
        vec![0.0, 0.0],
        vec![1.0, 1.0],
        vec![vec![1.0, 1.0]],
        vec![1.0],
    )
    .unwrap()
}

/// KKT of min ½(x−p)ᵀQ(x−p) s.t. x + y = 1: `Q x + λ(1, 1) = Q p`, `x + y = 1`, solved by
/// eliminating y = 1 − x. Returns (x*, λ).
fn quadratic_kkt() -> ([f64; 2], f64) {
    // Stationarity along the line: d/dx f(x, 1−x) = 0 with f quadratic.
    // Row 1 − Row 2 of Q x − Q p = −λ(1, 1) gives (Q₁₁ − Q₂₁) x + (Q₁₂ − Q₂₂) y = (Q p)₁ − (Q p)₂.
    let qp = [
        Q[0][0] * P[0] + Q[0][1] * P[1],
        Q[1][0] * P[0] + Q[1][1] * P[1],
    ];
    let (a, b) = (Q[0][0] - Q[1][0], Q[0][1] - Q[1][1]);
    // a x + b (1 − x) = qp₀ − qp₁.
    let x = (qp[0] - qp[1] - b) / (a - b);
    let y = 1.0 - x;
    let lambda = qp[0] - (Q[0][0] * x + Q[0][1] * y);
    ([x, y], lambda)
}

/// (a) min ½(x−p)ᵀQ(x−p), Q = [[3,1],[1,2]], p = (0.8, 0.7) on the unit box with x + y ≤ 1
/// (active: p violates it), from (0.1, 0.1). Reference: KKT in closed form, x* = (19/30, 11/30).
/// Tolerances: TR |x − x*| ≤ 1e-4 within 30 evaluations (min_radius 1e-4: the final radius
/// bounds the error); NM |x − x*| ≤ 1e-3 within its 200-evaluation budget.
#[test]
fn a_quadratic_with_active_linear_constraint() {
    let (x_ref, lambda) = quadratic_kkt();
    assert!(lambda > 0.1, "constraint must be active, λ = {lambda}");
    assert!((x_ref[0] - 19.0 / 30.0).abs() < 1e-12);
    let f_ref = quadratic(&x_ref);
    let bb = Problem2::new(0, |x| Evaluation::new(quadratic(x), vec![]));
    let set = unit_triangle();
    let opts = TrustRegionOptions {
        min_radius: 1e-4,
        ..Default::default()
    };
    let tr = minimize_trust_region(&bb, &set, &[0.1, 0.1], &opts, None).unwrap();
    let (ex, _) = report("(a) quadratic + linear", "TR", &tr, &x_ref, f_ref);
    assert!(ex <= 1e-4, "TR error {ex}");
    assert!(
        tr.evaluations <= 30,
        "TR used {} evaluations",
        tr.evaluations
    );
    assert_all_in_set(&set, &tr);
    // The 2n+1 initial design went through one evaluate_batch call.
    assert!(bb.batches.load(Ordering::Relaxed) >= 1);

    let nm =
        minimize_nelder_mead(&bb, &set, &[0.1, 0.1], &NelderMeadOptions::default(), None).unwrap();
    let (ex, _) = report("(a) quadratic + linear", "NM", &nm, &x_ref, f_ref);
    assert!(ex <= 1e-3, "NM error {ex}");
    assert!(nm.evaluations <= 200);
    assert_all_in_set(&set, &nm);
}

// ---------------------------------------------------------------------------------------------
// (b) Rosenbrock with x + y ≤ 1.5.

fn rosenbrock(x: &[f64]) -> f64 {
    (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2)
}

/// Minimiser of t ↦ rosenbrock(t, 1.5 − t) on [0, 1.5] (the part of the line x + y = 1.5 in the
/// box): a scan on 15 001 points, then golden-section refinement to 1e-12.
fn rosenbrock_on_line() -> [f64; 2] {
    let g = |t: f64| rosenbrock(&[t, 1.5 - t]);
    let n = 15_000;
    let h = 1.5 / n as f64;
    let k = (0..=n)
        .min_by(|&i, &j| g(i as f64 * h).total_cmp(&g(j as f64 * h)))
        .unwrap();
    let (mut a, mut b) = ((k as f64 - 1.0) * h, (k as f64 + 1.0) * h);
    let r = (5f64.sqrt() - 1.0) / 2.0;
    while b - a > 1e-12 {
        let (c, d) = (b - r * (b - a), a + r * (b - a));
        if g(c) < g(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let t = 0.5 * (a + b);
    [t, 1.5 - t]
}

/// (b) Rosenbrock on [−1.5, 1.5]² with x + y ≤ 1.5, from (−1.2, 1.0) (the classic start).
/// Rosenbrock's only stationary point (1, 1) violates the constraint, so the minimiser lies on
/// the boundary; the reference is a 1-D search along x + y = 1.5, and the test checks on a
/// 301×301 grid that no feasible point beats it (the box edges are far worse).
/// Tolerances: TR |x − x*| ≤ 1e-4 within 150 evaluations (min_radius 1e-5); NM |x − x*| ≤ 1e-2
/// within 400 evaluations.
#[test]
fn b_rosenbrock_with_active_linear_constraint() {
    let x_ref = rosenbrock_on_line();
    let f_ref = rosenbrock(&x_ref);
    let set = FeasibleSet::new(
        vec![-1.5, -1.5],
        vec![1.5, 1.5],
        vec![vec![1.0, 1.0]],
        vec![1.5],
    )
    .unwrap();
    for i in 0..=300 {
        for j in 0..=300 {
            let x = [-1.5 + 0.01 * i as f64, -1.5 + 0.01 * j as f64];
            if set.contains(&x, 0.0) {
                assert!(
                    rosenbrock(&x) >= f_ref - 1e-12,
                    "grid point {x:?} beats the reference"
                );
            }
        }
    }
    let bb = Problem2::new(0, |x| Evaluation::new(rosenbrock(x), vec![]));
    let opts = TrustRegionOptions {
        min_radius: 1e-5,
        max_evaluations: 150,
        ..Default::default()
    };
    let tr = minimize_trust_region(&bb, &set, &[-1.2, 1.0], &opts, None).unwrap();
    let (ex, _) = report("(b) Rosenbrock + linear", "TR", &tr, &x_ref, f_ref);
    assert!(ex <= 1e-4, "TR error {ex}");
    assert!(tr.evaluations <= 150);
    assert_all_in_set(&set, &tr);

    let nm_opts = NelderMeadOptions {
        max_evaluations: 400,
        max_iterations: 400,
        ..Default::default()
    };
    let nm = minimize_nelder_mead(&bb, &set, &[-1.2, 1.0], &nm_opts, None).unwrap();
    let (ex, _) = report("(b) Rosenbrock + linear", "NM", &nm, &x_ref, f_ref);
    assert!(ex <= 1e-2, "NM error {ex}");
    assert_all_in_set(&set, &nm);
}

// ---------------------------------------------------------------------------------------------
// (c) Noisy objective.

/// Deterministic pseudo-noise in [−1, 1) from a hash (SplitMix64 steps) of the bits of x and a
/// seed.
fn hash_noise(x: &[f64], seed: u64) -> f64 {
    let mut h: u64 = 0x9E37_79B9_7F4A_7C15 ^ seed.wrapping_mul(0xD1B5_4A32_D192_ED03);
    for v in x {
        h ^= v.to_bits();
        h = h.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h = z ^ (z >> 31);
    }
    (h >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Amplitude of the pseudo-noise: 1e-3 of the objective scale (f(x0) ≈ 1.5, f* ≈ 0.21).
const NOISE: f64 = 1e-3;

/// Problem (a) plus pseudo-noise of amplitude `NOISE` with a given seed.
struct NoisyQuadratic {
    seed: u64,
}

impl BlackBox for NoisyQuadratic {
    fn dim(&self) -> usize {
        2
    }
    fn n_constraints(&self) -> usize {
        0
    }
    fn evaluate(&self, x: &[f64]) -> Evaluation {
        Evaluation::new(quadratic(x) + NOISE * hash_noise(x, self.seed), vec![])
    }
}

/// (c) Problem (a) plus pseudo-noise of amplitude 1e-3, for 5 noise seeds × 3 starts. The
/// curvature along the active constraint is 1.5, so noise ±1e-3 makes points within
/// √(4·1e-3/1.5) ≈ 0.05 of x* indistinguishable by single evaluations. Stated tolerance: TR
/// |x − x*| ≤ 0.03 (and true f − f* ≤ 1e-3) in every run, within 40 evaluations each
/// (min_radius 0.01, above the noise-dominated scale; the TR stops after 11–16 evaluations
/// with errors 5e-4–2e-2); NM |x − x*| ≤ 0.05 within 200.
#[test]
fn c_noisy_quadratic() {
    let (x_ref, _) = quadratic_kkt();
    let f_ref = quadratic(&x_ref);
    let set = unit_triangle();
    let opts = TrustRegionOptions {
        min_radius: 1e-2,
        max_evaluations: 40,
        ..Default::default()
    };
    let (mut worst_tr, mut worst_nm, mut max_evals) = (0.0_f64, 0.0_f64, 0);
    for seed in 0..5 {
        let bb = NoisyQuadratic { seed };
        for x0 in [[0.1, 0.1], [0.9, 0.05], [0.0, 1.0]] {
            let tr = minimize_trust_region(&bb, &set, &x0, &opts, None).unwrap();
            let ex = dist(&tr.x, &x_ref);
            let true_gap = quadratic(&tr.x) - f_ref;
            assert!(ex <= 0.03, "TR error {ex} (seed {seed}, x0 {x0:?})");
            assert!(true_gap <= 1e-3, "TR true gap {true_gap}");
            assert!(tr.evaluations <= 40);
            assert_all_in_set(&set, &tr);
            worst_tr = worst_tr.max(ex);
            max_evals = max_evals.max(tr.evaluations);
            let nm =
                minimize_nelder_mead(&bb, &set, &x0, &NelderMeadOptions::default(), None).unwrap();
            let ex_nm = dist(&nm.x, &x_ref);
            assert!(ex_nm <= 0.05, "NM error {ex_nm} (seed {seed}, x0 {x0:?})");
            worst_nm = worst_nm.max(ex_nm);
            if seed == 0 && x0 == [0.1, 0.1] {
                report("(c) noisy quadratic", "TR", &tr, &x_ref, f_ref);
                report("(c) noisy quadratic", "NM", &nm, &x_ref, f_ref);
            }
        }
    }
    println!(
        "(c) over 15 runs: TR worst |x − x*| = {worst_tr:.2e} (≤ {max_evals} evals), \
         NM worst {worst_nm:.2e}"
    );
}

// ---------------------------------------------------------------------------------------------
// (d) Nonlinear black-box constraint.

/// (d) min (x−2)² + (y−1)² s.t. x² + y² ≤ 1 given only as a black-box constraint value, on
/// [−1.5, 1.5]², from (−0.5, −0.5). Optimum (2, 1)/√5 (projection of (2, 1) onto the disc),
/// multiplier √5 − 1. Tolerances: TR |x − x*| ≤ 1e-4 and constraint violation ≤ 1e-6 at the
/// result (the exact ℓ1 merit accepts violations of the order of the final radius squared)
/// within 40 evaluations (min_radius 1e-4); NM |x − x*| ≤ 1e-2 within 300 evaluations.
#[test]
fn d_black_box_disc_constraint() {
    let s5 = 5f64.sqrt();
    let x_ref = [2.0 / s5, 1.0 / s5];
    let f = |x: &[f64]| (x[0] - 2.0).powi(2) + (x[1] - 1.0).powi(2);
    let f_ref = f(&x_ref);
    let bb = Problem2::new(1, |x| {
        Evaluation::new(
            (x[0] - 2.0).powi(2) + (x[1] - 1.0).powi(2),
            vec![x[0] * x[0] + x[1] * x[1] - 1.0],
        )
    });
    let set = FeasibleSet::from_box(vec![-1.5, -1.5], vec![1.5, 1.5]).unwrap();
    let opts = TrustRegionOptions {
        min_radius: 1e-4,
        ..Default::default()
    };
    let tr = minimize_trust_region(&bb, &set, &[-0.5, -0.5], &opts, None).unwrap();
    let (ex, _) = report("(d) black-box disc", "TR", &tr, &x_ref, f_ref);
    println!(
        "    TR constraint value {:.2e}",
        tr.evaluation.constraints[0]
    );
    assert!(ex <= 1e-4, "TR error {ex}");
    assert!(tr.evaluation.constraints[0] <= 1e-6);
    assert!(tr.evaluations <= 40);
    assert_all_in_set(&set, &tr);

    let nm_opts = NelderMeadOptions {
        max_evaluations: 300,
        ..Default::default()
    };
    let nm = minimize_nelder_mead(&bb, &set, &[-0.5, -0.5], &nm_opts, None).unwrap();
    let (ex, _) = report("(d) black-box disc", "NM", &nm, &x_ref, f_ref);
    assert!(ex <= 1e-2, "NM error {ex}");
    assert!(nm.is_feasible(0.0));
}

// ---------------------------------------------------------------------------------------------
// (e) A region where evaluations fail.

fn fails_in_disc(x: &[f64]) -> Evaluation {
    if (x[0] - 0.4).powi(2) + (x[1] - 0.6).powi(2) < 0.15 * 0.15 {
        return Evaluation {
            objective: f64::NAN,
            constraints: vec![],
            failed: true,
        };
    }
    Evaluation::new((x[0] - 0.7).powi(2) + 2.0 * (x[1] - 0.3).powi(2), vec![])
}

/// (e) min (x−0.7)² + 2(y−0.3)² on the unit box, but evaluations fail in the disc of radius 0.15
/// about (0.4, 0.6), which lies on the straight path from the start (0.1, 0.9) to the optimum
/// (0.7, 0.3). Checks that the trust region did hit the failing region, nothing crashed, and:
/// TR |x − x*| ≤ 1e-4 within 40 evaluations; NM |x − x*| ≤ 1e-3 within 200.
#[test]
fn e_failing_region() {
    let x_ref = [0.7, 0.3];
    let bb = Problem2::new(0, fails_in_disc);
    let set = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
    let opts = TrustRegionOptions {
        min_radius: 1e-4,
        ..Default::default()
    };
    let tr = minimize_trust_region(&bb, &set, &[0.1, 0.9], &opts, None).unwrap();
    let (ex, _) = report("(e) failing region", "TR", &tr, &x_ref, 0.0);
    let failures = tr.history.iter().filter(|(_, e)| e.failed).count();
    println!("    TR failed evaluations: {failures}");
    assert!(
        failures > 0,
        "the failing region was never hit: the test would not test failures"
    );
    assert!(!tr.evaluation.failed);
    assert!(ex <= 1e-4, "TR error {ex}");
    assert!(tr.evaluations <= 40);
    assert_all_in_set(&set, &tr);

    let nm =
        minimize_nelder_mead(&bb, &set, &[0.1, 0.9], &NelderMeadOptions::default(), None).unwrap();
    let (ex, _) = report("(e) failing region", "NM", &nm, &x_ref, 0.0);
    let nm_failures = nm.history.iter().filter(|(_, e)| e.failed).count();
    println!("    NM failed evaluations: {nm_failures}");
    assert!(ex <= 1e-3, "NM error {ex}");
}

// ---------------------------------------------------------------------------------------------
// Robustness and plumbing.

/// A black box that always fails: every method returns a result saying so, none panics.
#[test]
fn everything_fails() {
    let bb = Problem2::new(1, |_| Evaluation::failure(1));
    let set = unit_triangle();
    let tr = minimize_trust_region(&bb, &set, &[0.2, 0.2], &TrustRegionOptions::default(), None)
        .unwrap();
    assert!(tr.evaluation.failed);
    assert_eq!(tr.termination, "every evaluation failed");
    assert!(tr.evaluations <= 60);
    let nm =
        minimize_nelder_mead(&bb, &set, &[0.2, 0.2], &NelderMeadOptions::default(), None).unwrap();
    assert!(nm.evaluation.failed);
    assert!(nm.evaluations <= 200);
}

/// An empty feasible set is refused with `Infeasible` before any evaluation.
#[test]
fn empty_feasible_set_is_refused() {
    let bb = Problem2::new(0, |x| Evaluation::new(quadratic(x), vec![]));
    let set = FeasibleSet::new(
        vec![0.0, 0.0],
        vec![1.0, 1.0],
        vec![vec![-1.0, -1.0]],
        vec![-2.5],
    )
    .unwrap();
    let r = minimize_trust_region(&bb, &set, &[0.5, 0.5], &TrustRegionOptions::default(), None);
    assert!(matches!(r, Err(OptimizeError::Infeasible { .. })), "{r:?}");
    let msg = r.unwrap_err().to_string();
    assert!(msg.contains("feasible set is empty"), "{msg}");
    assert_eq!(bb.batches.load(Ordering::Relaxed), 0);
}

/// The callback sees every iterate of the path, whose evaluation counts never decrease; a start
/// outside the linear constraints is projected.
#[test]
fn callback_and_path() {
    let bb = Problem2::new(0, |x| Evaluation::new(quadratic(x), vec![]));
    let set = unit_triangle();
    let seen = Arc::new(Mutex::new(0usize));
    let seen2 = Arc::clone(&seen);
    let tr = minimize_trust_region(
        &bb,
        &set,
        &[0.9, 0.9],
        &TrustRegionOptions::default(),
        Some(Box::new(move |_| *seen2.lock().unwrap() += 1)),
    )
    .unwrap();
    assert_eq!(*seen.lock().unwrap(), tr.path.len());
    assert!(
        tr.path
            .windows(2)
            .all(|w| w[0].evaluations <= w[1].evaluations)
    );
    assert!(tr.path.iter().all(|it| it.radius.is_some()));
    assert!(
        dist(&tr.history[0].0, &[0.5, 0.5]) < 1e-9,
        "{:?}",
        tr.history[0].0
    );
    assert_eq!(tr.path.last().unwrap().x, tr.x);
}

/// Particle swarm and grid on (a): reproducible for a seed, and near the optimum.
/// Tolerances: swarm |x − x*| ≤ 0.02 within 250 evaluations; grid (41×41, spacing 0.025) within
/// half a diagonal spacing plus the constraint cut, |x − x*| ≤ 0.03.
#[test]
fn swarm_and_grid_on_quadratic() {
    let (x_ref, _) = quadratic_kkt();
    let f_ref = quadratic(&x_ref);
    let bb = Problem2::new(0, |x| Evaluation::new(quadratic(x), vec![]));
    let set = unit_triangle();
    let opts = SwarmOptions::default();
    let a = minimize_particle_swarm(&bb, &set, &opts, None).unwrap();
    let b = minimize_particle_swarm(&bb, &set, &opts, None).unwrap();
    assert_eq!(a.x, b.x, "same seed, same result");
    let (ex, _) = report("(a) quadratic + linear", "PSO", &a, &x_ref, f_ref);
    assert!(ex <= 0.02, "swarm error {ex}");
    assert!(a.evaluations <= 250);
    assert_all_in_set(&set, &a);
    let g = grid_search(&bb, &set, 41, 0.0).unwrap();
    let (ex, _) = report("(a) quadratic + linear", "grid", &g, &x_ref, f_ref);
    assert!(ex <= 0.03, "grid error {ex}");
}
