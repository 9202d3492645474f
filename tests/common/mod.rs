//! Shared test helpers: the seed problem and closed-form references computed independently of the
//! crate (from the raw Table 1 numbers, not from `Section`).
#![allow(dead_code)]

use std::f64::consts::PI;

pub const SEED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed_mc2014.toml");
/// The paper's own seed problem: the same pipe and mesh without the bit inertia (and with the
/// paper's 51 lowest modes and unloaded start).
pub const SEED_PAPER: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/seed_mc2014_paper.toml"
);

/// The keys of the metrics `drillopt verify` checks for `p` (`verify::decision_metrics`).
pub fn decision_keys(p: &drillopt::problem::Problem) -> Vec<&'static str> {
    drillopt::verify::decision_metrics(p)
        .iter()
        .map(|d| d.key)
        .collect()
}

/// The seed problem with the paper's string: the bit inertia that the shipped file adds (not in
/// the paper's Table 1) is taken out, so that the closed forms of the bare pipe apply.
pub fn seed() -> drillopt::problem::Problem {
    let mut p = drillopt::problem::Problem::load(SEED).expect("the seed problem loads");
    p.model.bit_inertia = 0.0;
    p
}

/// Table 1 of the seed paper, SI.
pub struct Table1;
impl Table1 {
    pub const L: f64 = 35.0;
    pub const RHO: f64 = 7900.0;
    pub const RHO_F: f64 = 1200.0;
    pub const E: f64 = 203e9;
    pub const NU: f64 = 0.3;
    pub const R_INT: f64 = 0.040;
    pub const R_EXT: f64 = 0.060;

    pub fn area() -> f64 {
        PI * (Self::R_EXT.powi(2) - Self::R_INT.powi(2))
    }
    pub fn inertia() -> f64 {
        PI / 4.0 * (Self::R_EXT.powi(4) - Self::R_INT.powi(4))
    }
    pub fn fluid_area() -> f64 {
        PI * Self::R_INT.powi(2)
    }
    pub fn shear_modulus() -> f64 {
        Self::E / (2.0 * (1.0 + Self::NU))
    }
    /// Cowper's factor for the hollow circle, MODEL.md §1.
    pub fn cowper() -> f64 {
        let m2 = (Self::R_INT / Self::R_EXT).powi(2);
        let a = (1.0 + m2).powi(2);
        6.0 * (1.0 + Self::NU) * a / ((7.0 + 6.0 * Self::NU) * a + (20.0 + 12.0 * Self::NU) * m2)
    }
    pub fn lateral_mass() -> f64 {
        Self::RHO * Self::area() + Self::RHO_F * Self::fluid_area()
    }
}

/// Fixed–free rod: f_n = (2n − 1) c / (4L), c the wave speed.
pub fn fixed_free_rod_hz(n: usize, wave_speed: f64, length: f64) -> f64 {
    (2 * n - 1) as f64 * wave_speed / (4.0 * length)
}

/// Roots of tan x = tanh x (clamped–pinned Euler–Bernoulli beam), by bisection on
/// ((4n+1)π/4 ± 0.3).
pub fn clamped_pinned_root(n: usize) -> f64 {
    let f = |x: f64| x.sin() * x.cosh() - x.cos() * x.sinh();
    let centre = (4 * n + 1) as f64 * PI / 4.0;
    let (mut a, mut b) = (centre - 0.3, centre + 0.3);
    assert!(f(a) * f(b) < 0.0);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if f(a) * f(m) <= 0.0 { b = m } else { a = m }
    }
    0.5 * (a + b)
}

/// Clamped–pinned Euler–Bernoulli beam: f_n = (β_n L)² / (2π L²) √(EI/m).
pub fn clamped_pinned_hz(n: usize, ei: f64, mass_per_length: f64, length: f64) -> f64 {
    let bl = clamped_pinned_root(n);
    bl * bl / (2.0 * PI * length * length) * (ei / mass_per_length).sqrt()
}

/// Pinned–pinned Timoshenko beam with rotatory inertia, exact: the lower root ω² of
/// m ρI ω⁴ − ω² [m(EI k² + κGA) + ρI κGA k²] + κGA EI k⁴ = 0, k = nπ/L.
pub fn pinned_pinned_timoshenko_hz(
    n: usize,
    ei: f64,
    kga: f64,
    m: f64,
    rho_i: f64,
    length: f64,
) -> f64 {
    let k = n as f64 * PI / length;
    let a = m * rho_i;
    let b = m * (ei * k * k + kga) + rho_i * kga * k * k;
    let c = kga * ei * k.powi(4);
    let omega2 = (b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    omega2.sqrt() / (2.0 * PI)
}

/// A small basis with every family and the bit's static corrections (10 bending modes per
/// plane, 2 torsional, 2 axial): cheap, and it exercises every kind of basis vector.
pub fn small_basis() -> drillopt::model::BasisSpec {
    use drillopt::model::{BasisSpec, FamilySize};
    BasisSpec::PerFamily {
        bending: FamilySize::Count(10),
        torsional: FamilySize::Count(2),
        axial: FamilySize::Count(2),
        static_corrections: true,
        steady_shapes: false,
    }
}

/// `drillopt simulate problems/regression/tiny_string.toml --quiet --out OUT EXTRA…`, run from the
/// crate root.
pub fn simulate_tiny(extra: &[&str], out: &std::path::Path) -> std::process::Output {
    let mut args = vec![
        "simulate",
        "problems/regression/tiny_string.toml",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(&args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("drillopt runs")
}

/// Metrics (`named_values`) of the golden short run of a tiny-string problem `p`: 0.6 s at
/// 8 rad/s and 10 m/h from the pre-loaded state, analysis window from 0.2 s.
pub fn tiny_run_metrics(p: &drillopt::problem::Problem) -> Vec<(&'static str, f64)> {
    use drillopt::model::OperatingPoint;
    use drillopt::sim::{Effects, InitialState, RunSettings, simulate};
    let model = drillopt::rom::ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
    let op = OperatingPoint {
        omega: 8.0,
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &RunSettings::new(0.6, p.simulation.time_step),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    drillopt::metrics::of_run(&out, &p.model, op, 0.2, None)
        .unwrap()
        .named_values()
        .to_vec()
}

/// Runs the built `drillopt` binary with `args` from the crate root and returns its output.
pub fn drillopt(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("drillopt runs")
}

/// The matrices of a simply supported (pinned–pinned) spinning beam of `string` on `elements`
/// elements, restricted to its free DOFs: the top end holds u, θx, v, w, the bit end v, w, and
/// no rotation is held (the string's own supports clamp the top's θy, θz, so its modes are
/// clamped–pinned). Mass, stiffness, the gyroscopic matrix per unit spin, each free DOF's family,
/// and the selectors of the lateral v and w of every node (rows: nodes).
pub struct SimplySupported {
    pub mass: nalgebra::DMatrix<f64>,
    pub stiffness: nalgebra::DMatrix<f64>,
    pub gyroscopic: nalgebra::DMatrix<f64>,
    pub families: Vec<drillopt::rom::Family>,
    pub lateral: [nalgebra::DMatrix<f64>; 2],
}

pub fn simply_supported(string: &drillopt::model::Drillstring, elements: usize) -> SimplySupported {
    use drillopt::fem::{BoundaryConditions, Dof, ElementInertia, assemble};
    use nalgebra::DMatrix;
    let n = elements;
    let global = assemble(string, n);
    let bc = BoundaryConditions::free(n)
        .fix(0, &[Dof::U, Dof::ThetaX, Dof::V, Dof::W])
        .fix(n, &[Dof::V, Dof::W]);
    let free = bc.free_dofs();
    let dof = global.dof();
    let mut g_full = DMatrix::zeros(dof, dof);
    for e in 0..n {
        let g_e = ElementInertia::new(global.layout.element(e)).gyroscopic();
        for i in 0..12 {
            for j in 0..12 {
                g_full[(6 * e + i, 6 * e + j)] += g_e[(i, j)];
            }
        }
    }
    let restrict = |f: &dyn Fn(usize, usize) -> f64| {
        DMatrix::from_fn(free.len(), free.len(), |i, j| f(free[i], free[j]))
    };
    let lateral = |d: Dof| {
        DMatrix::from_fn(n + 1, free.len(), |node, j| {
            f64::from(u8::from(free[j] == d.at(node)))
        })
    };
    SimplySupported {
        mass: restrict(&|i, j| global.mass[(i, j)]),
        stiffness: restrict(&|i, j| global.stiffness[(i, j)]),
        gyroscopic: restrict(&|i, j| g_full[(i, j)]),
        families: free
            .iter()
            .map(|&i| drillopt::rom::Family::of(Dof::of_index(i)))
            .collect(),
        lateral: [lateral(Dof::V), lateral(Dof::W)],
    }
}

/// The growth rate and frequency of an oscillation `y(t)` (a deviation from a steady value):
/// the least-squares slope of the log of its peaks |y| at the samples `take` selects, 1/s, and the
/// frequency from its zero crossings between the first and last of those peaks, Hz. Panics with
/// fewer than 21 peaks.
pub fn growth_and_frequency(t: &[f64], y: &[f64], take: impl Fn(usize) -> bool) -> (f64, f64) {
    let mut peaks = Vec::new();
    for k in 1..y.len() - 1 {
        let a = y[k].abs();
        if a >= y[k - 1].abs() && a >= y[k + 1].abs() && take(k) {
            peaks.push((t[k], a.ln()));
        }
    }
    assert!(peaks.len() > 20, "{} peaks", peaks.len());
    let (from, to) = (peaks[0].0, peaks[peaks.len() - 1].0);
    let crossings: Vec<f64> = (1..y.len())
        .filter(|&k| t[k] >= from && t[k] <= to && y[k] * y[k - 1] < 0.0)
        .map(|k| t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]))
        .collect();
    let n = peaks.len() as f64;
    let (mt, ml) = (
        peaks.iter().map(|p| p.0).sum::<f64>() / n,
        peaks.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = peaks.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum::<f64>()
        / peaks.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    let span = crossings[crossings.len() - 1] - crossings[0];
    (slope, (crossings.len() - 1) as f64 / (2.0 * span))
}
