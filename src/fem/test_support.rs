//! Helpers shared by the element tests: a deterministic generator, the seed string, and a
//! relative matrix error.

use crate::model::Drillstring;
use nalgebra::SMatrix;

/// A tiny deterministic generator (xorshift) so the tests need no RNG crate.
pub(super) struct Rng(pub(super) u64);

impl Rng {
    pub(super) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// The drillstring of the shipped seed problem.
pub(super) fn seed_string() -> Drillstring {
    crate::problem::Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/seed_mc2014.toml"
    ))
    .unwrap()
    .model
}

/// Largest entry of |a − b| over the largest entry of |b|.
pub(super) fn relative_error<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
) -> f64 {
    (a - b).abs().max() / b.abs().max()
}
