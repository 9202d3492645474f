//! Statistics low in the house: the laws of uncertain parameters, seeded Monte Carlo samples, and
//! the statistics of a metric over samples. The problem layer reads laws and statistics from
//! problem files; the study layer draws samples and scores points with them.
//!
//! * [`Distribution`]: the law of one uncertain parameter — Gamma (the maximum-entropy law for a
//!   positive parameter of given mean and E\[ln X\], used for bit–rock parameters by Ritto, Soize
//!   & Sampaio 2009 and Cunha Jr, Soize & Sampaio 2015), log-normal, normal or uniform, each
//!   given by its own mean and spread rather than by the parameters of the sampler.
//! * [`SampleSet`]: `n` samples drawn from a master seed so that sample `i` is a pure function of
//!   (master seed, `i`, the laws) — the same whatever `n`, the thread count or the evaluation
//!   order. See [`sample_seed`] for the seed derivation and [`sample_rng`] for the generator.
//! * [`Statistic`]: mean, standard deviation, quantile, CVaR (upper and lower), probability of
//!   exceedance, max and min of one metric over the samples.
//! * [`percentile_interval`]: the bootstrap percentile interval of any statistic of the samples
//!   (Efron & Tibshirani 1993), the confidence of a robust score.
//!
//! Values are in the units of the parameter or metric they describe; this module does not know them.

mod bootstrap;
mod distribution;
mod sampling;
mod statistic;

#[cfg(test)]
mod tests;

pub use bootstrap::{Interval, percentile_interval};
pub use distribution::{Distribution, LawError, SPREAD, lognormal_log_params};
pub use sampling::{Sample, SampleRng, SampleSet, sample_rng, sample_seed, splitmix64_mix};
pub use statistic::{Statistic, cvar, lower_cvar, max, mean, min, prob_exceed, quantile, std_dev};
