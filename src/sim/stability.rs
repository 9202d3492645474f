//! Linear stability of steady drilling: the dominant eigenvalue of the equations of motion
//! linearised about the pre-loaded steady state.
//!
//! A run starts on the steady state of its operating point (MODEL.md §4). When that state is
//! unstable, a disturbance grows out of round-off at the rate σ of the dominant eigenvalue, and a
//! window that ends before it has grown reads the unstable state as if it were the long run
//! (`problems/regression/seed_power_limit.toml`: steady for about 25 s, then a limit cycle that
//! drills 24 % less). The linearisation says so at once. With the residual
//! r(q, q̇, q̈) = 0 of the run (the string under the imposed feed, or with the free block of a
//! hook load or an autodriller), its exact Newton matrix ∂r/∂q̈ ca + ∂r/∂q̇ cv + ∂r/∂q cq
//! gives M, C and K at the steady state (q̇ = q̈ = 0 relative to the rigid motion), and the
//! eigenvalues λ of M q̈ + C q̇ + K q = 0 are those of the companion matrix
//! [[0, I], [−M⁻¹K, −M⁻¹C]] (Tisseur & Meerbergen, SIAM Review 43(2), 2001, §3.4). The bit law's
//! tangents (its negative damping), the wall contacts', the gyroscopic coupling and the top's are
//! all in it. A neutral eigenvalue (|λ| below [`NEUTRAL`]: the block position of a rate-law bit,
//! which nothing holds) is no growth and is left out.
//!
//! Not for a depth-of-cut bit (`law = "rgd"`): its blades' delay makes the linearisation a delay
//! equation, whose spectrum `tests/model/bit_rgd/delay.rs` computes apart.

use super::SimulationError;
use super::run::Driven;
use crate::integrate::{ImplicitSystem, JacobianCoefficients};
use crate::model::OperatingPoint;
use crate::rom::ReducedModel;
use nalgebra::{DMatrix, DVector};

/// Eigenvalues of modulus below this (1/s) are neutral, not growth.
pub const NEUTRAL: f64 = 1e-6;

/// The largest number of unknowns whose stability is computed: the dense companion matrix has
/// twice as many rows and its eigenvalues cost O(rows³) (measured, one core: 622 unknowns 3 s,
/// 978 17 s, 1246 40 s; a reduced basis has 50–200). Large enough for the unreduced model of a
/// field well on a mesh twice its default (`simulate --unreduced`: the reference a reduced
/// basis' growth rate is checked against, docs/model.md "Linear stability of steady
/// drilling"); a longer mesh is left out (`None`).
pub const MAX_UNKNOWNS: usize = 1300;

/// The dominant eigenvalue of steady drilling at an operating point.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SteadyStability {
    /// Largest real part of the eigenvalues, 1/s: > 0 unstable (a disturbance grows as
    /// e^(σt)), < 0 stable (the slowest decay).
    pub growth_rate_per_s: f64,
    /// The frequency of that eigenvalue, |Im λ|/2π, Hz.
    pub frequency_hz: f64,
}

impl SteadyStability {
    /// Whether a disturbance grows.
    pub fn unstable(&self) -> bool {
        self.growth_rate_per_s > 0.0
    }

    /// The time for a disturbance to grow by `factor` (∞ when stable), s.
    pub fn growth_time(&self, factor: f64) -> f64 {
        if self.unstable() {
            factor.ln() / self.growth_rate_per_s
        } else {
            f64::INFINITY
        }
    }
}

/// The dominant eigenvalue of the run's equations linearised about the pre-loaded steady state
/// of `op` (module doc). `None` for a depth-of-cut bit (a delay equation), for more than
/// [`MAX_UNKNOWNS`] unknowns, or when the mass matrix is singular. Errors: the steady state's
/// own ([`super::preloaded_equilibrium`], [`super::free_top_start`]).
pub fn steady_stability(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: super::Effects,
) -> Result<Option<SteadyStability>, SimulationError> {
    if model.string.bit.blades().is_some() || model.size() + 1 > MAX_UNKNOWNS {
        return Ok(None);
    }
    let n = model.size();
    let (q, v) = if model.string.top.is_free() {
        let (q, speed, _) = super::free_top_start(model, op, effects)?;
        (q.push(0.0), DVector::zeros(n).push(speed))
    } else {
        let (q, _) = super::preloaded_equilibrium(model, op, effects)?;
        (q, DVector::zeros(n))
    };
    let size = q.len();
    let a = DVector::zeros(size);
    let mut sys = Driven::new(model, op, effects);
    let mut r = DVector::zeros(size);
    // The residual sets the contacts and the bit's state the Newton matrix reads.
    sys.residual(0.0, &q, &v, &a, &mut r);
    let mut matrix = |ca: f64, cv: f64, cq: f64| {
        let mut out = DMatrix::zeros(size, size);
        let c = JacobianCoefficients { ca, cv, cq };
        sys.jacobian(0.0, &q, &v, &a, c, true, &mut out);
        out
    };
    let (mass, damping, stiffness) = (
        matrix(1.0, 0.0, 0.0),
        matrix(0.0, 1.0, 0.0),
        matrix(0.0, 0.0, 1.0),
    );
    let Some(lu) = Some(mass.lu()).filter(|lu| lu.is_invertible()) else {
        return Ok(None);
    };
    let (mk, mc) = (
        lu.solve(&stiffness).expect("invertible"),
        lu.solve(&damping).expect("invertible"),
    );
    // The state (q, q̇/w), w a typical frequency sqrt(max |(M⁻¹K)_ii|): the similarity balances the
    // blocks (as the Campbell diagram's first-order form, whose solver looped on a stiff wall
    // without it), and the Schur iteration is capped (30 sweeps per eigenvalue, LAPACK's rule): a
    // matrix it cannot reduce gives no verdict rather than a run without end.
    let w = (0..size)
        .map(|i| mk[(i, i)].abs())
        .fold(0.0, f64::max)
        .sqrt()
        .max(1.0);
    let mut companion = DMatrix::zeros(2 * size, 2 * size);
    for i in 0..size {
        companion[(i, size + i)] = w;
        for j in 0..size {
            companion[(size + i, j)] = -mk[(i, j)] / w;
            companion[(size + i, size + j)] = -mc[(i, j)];
        }
    }
    let Some(schur) = nalgebra::linalg::Schur::try_new(companion, f64::EPSILON, 30 * 2 * size)
    else {
        return Ok(None);
    };
    let dominant = schur
        .complex_eigenvalues()
        .iter()
        .copied()
        .filter(|l| l.norm() > NEUTRAL)
        .max_by(|x, y| x.re.total_cmp(&y.re));
    Ok(dominant.map(|l| SteadyStability {
        growth_rate_per_s: l.re,
        frequency_hz: l.im.abs() / (2.0 * std::f64::consts::PI),
    }))
}
