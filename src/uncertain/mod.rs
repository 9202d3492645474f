//! Uncertain parameters: probability laws and seeded Monte Carlo samples (issue 4).
//!
//! A robust objective averages (or takes a risk measure of) a metric over samples of the
//! uncertain parameters. This module owns the two halves of that:
//!
//! * [`Distribution`]: the law of one uncertain parameter — Gamma (the maximum-entropy law for a
//!   positive parameter of given mean and E\[ln X\], used for bit–rock parameters by Ritto, Soize
//!   & Sampaio 2009 and Cunha Jr, Soize & Sampaio 2015), log-normal, normal or uniform, each
//!   given by its own mean and spread rather than by the parameters of the sampler.
//! * [`SampleSet`]: `n` samples drawn from a master seed so that sample `i` is a pure function of
//!   (master seed, `i`, the laws) — the same whatever `n`, the thread count or the evaluation
//!   order. See [`sample_seed`] for the seed derivation and [`sample_rng`] for the generator.
//!
//! Values are in the units of the parameter they describe; this module does not know them.

mod distribution;
mod sampling;

#[cfg(test)]
mod tests;

pub use distribution::{Distribution, lognormal_log_params};
pub use sampling::{Sample, SampleRng, SampleSet, sample_rng, sample_seed, splitmix64_mix};
