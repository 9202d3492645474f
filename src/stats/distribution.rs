//! The law of one uncertain scalar parameter.
//!
//! Every law is given by quantities of the parameter itself (mean, coefficient of variation
//! cov = std/mean, standard deviation or bounds), never by the internal parameters of the
//! sampler, so that a problem file reads in physical terms:
//!
//! | law | parameters | support | sampler parameters |
//! |---|---|---|---|
//! | Gamma | mean > 0, cov ∈ \[1e-6, 1\] | (0, ∞) | shape k = 1/cov², scale θ = mean·cov² |
//! | LogNormal | mean > 0, cov ∈ \[1e-6, 1\] | (0, ∞) | σ² = ln(1 + cov²), μ = ln(mean) − σ²/2 (of ln X) |
//! | Normal | mean, std/\|mean\| ∈ \[1e-6, 1\] (std > 0 if mean = 0) | (−∞, ∞) | as given |
//! | Uniform | low < high, (high − low)/max(\|low\|, \|high\|) ≥ 1e-6 | \[low, high) | as given |
//!
//! The spread has a closed range ([`SPREAD`], issue 34). Its lower end: a parameter known to
//! better than one part in a million is deterministic and is written as a value, without a law;
//! and below it the samplers lose their meaning (the gamma sampler's scale mean·cov² underflows
//! for cov below about 1.5e-162, and `compare`, `solve` and `map` panicked in it). Its upper end:
//! a standard deviation as large as the mean; beyond it the gamma law's shape 1/cov² falls below
//! 1, its density is infinite at 0 and its draws spread over orders of magnitude, a parameter
//! not known at all. Every value a law draws must also be admissible for its parameter: the
//! problem layer checks the draws where the law is loaded.
//!
//! Gamma with k = 1/cov² has mean kθ = mean, variance kθ² = (mean·cov)² and skewness 2/√k = 2·cov.
//! It is the maximum-entropy law on (0, ∞) for a given mean and E\[ln X\] (Soize 2017,
//! *Uncertainty Quantification*, §5.4.8), the choice of Ritto, Soize & Sampaio (2009) and
//! Cunha Jr, Soize & Sampaio (2015) for the bit–rock interaction parameters.

use rand_distr::Distribution as _;
use serde::Serialize;

/// The law of one uncertain parameter, in the parameter's own units.
///
/// Read from problem files by [`crate::problem`] (one schema: `law = "gamma" | "lognormal" |
/// "normal" | "uniform"`); serialised in reports with the same names and keys,
/// e.g. `{"law": "gamma", "mean": 1.0, "cov": 0.1}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "law", rename_all = "lowercase")]
pub enum Distribution {
    /// Gamma law of mean `mean` (> 0) and coefficient of variation `cov` = std/mean (> 0).
    Gamma { mean: f64, cov: f64 },
    /// Uniform law on \[`low`, `high`), `low` < `high`.
    Uniform { low: f64, high: f64 },
    /// Normal law of mean `mean` and standard deviation `std` (> 0).
    Normal { mean: f64, std: f64 },
    /// Log-normal law whose variable (not its log) has mean `mean` (> 0) and coefficient of
    /// variation `cov` (> 0).
    LogNormal { mean: f64, cov: f64 },
}

/// The admissible relative spread of a law (cov, std/|mean|, width over magnitude), see the
/// module doc.
pub const SPREAD: (f64, f64) = (1e-6, 1.0);

/// Why a law was refused: the parameter (`mean`, `cov`, `std`, `low`, `high`) and the message,
/// which names the law, the parameter, its value and what is allowed.
#[derive(Debug, Clone, PartialEq)]
pub struct LawError {
    pub parameter: &'static str,
    pub message: String,
}

impl std::fmt::Display for LawError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// Parameters (μ, σ) of ln X for a log-normal X of mean `mean` and coefficient of variation
/// `cov`: σ² = ln(1 + cov²), μ = ln(mean) − σ²/2. Inverse of E\[X\] = exp(μ + σ²/2),
/// cov² = exp(σ²) − 1.
pub fn lognormal_log_params(mean: f64, cov: f64) -> (f64, f64) {
    // ln_1p keeps σ accurate for small cov, where 1 + cov² rounds.
    let sigma2 = cov.powi(2).ln_1p();
    (mean.ln() - 0.5 * sigma2, sigma2.sqrt())
}

impl Distribution {
    /// Checks the ranges in the table of the module doc. The message names the law, the bad
    /// parameter, its value and what is allowed.
    pub fn validate(&self) -> Result<(), LawError> {
        fn err(parameter: &'static str, message: String) -> Result<(), LawError> {
            Err(LawError { parameter, message })
        }
        fn finite(law: &str, name: &'static str, value: f64) -> Result<(), LawError> {
            if value.is_finite() {
                Ok(())
            } else {
                err(name, format!("{law}: `{name}` = {value} must be finite"))
            }
        }
        fn positive(law: &str, name: &'static str, value: f64) -> Result<(), LawError> {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                err(
                    name,
                    format!("{law}: `{name}` = {value} must be finite and > 0"),
                )
            }
        }
        const WHY: &str = "below 1e-6 the parameter is deterministic: write it as a value, \
                           without a law; above 1 the law spreads over orders of magnitude";
        let (lo, hi) = SPREAD;
        let spread = |law: &str, name: &'static str, what: &str, value: f64, relative: f64| {
            if (lo..=hi).contains(&relative) {
                Ok(())
            } else {
                err(
                    name,
                    format!(
                        "{law}: {what} must be in [{lo:e}, {hi}] ({WHY}), got {}",
                        crate::units::show(value)
                    ),
                )
            }
        };
        match *self {
            Self::Gamma { mean, cov } | Self::LogNormal { mean, cov } => {
                let law = if matches!(self, Self::Gamma { .. }) {
                    "gamma"
                } else {
                    "lognormal"
                };
                positive(law, "mean", mean)?;
                finite(law, "cov", cov)?;
                spread(law, "cov", "`cov` (std/mean)", cov, cov)?;
                // The gamma sampler's scale mean·cov² (and its inverse) must be a normal
                // number: a mean of 5e-324 underflowed it to 0 and the sampler panicked.
                let scale = mean * cov * cov;
                if !(scale.is_normal() && (1.0 / scale).is_normal()) {
                    return err(
                        "mean",
                        format!(
                            "{law}: `mean` = {} is too small to sample with cov = {cov} (mean·cov² must exceed 2.2e-308)",
                            crate::units::show(mean)
                        ),
                    );
                }
                Ok(())
            }
            Self::Normal { mean, std } => {
                finite("normal", "mean", mean)?;
                positive("normal", "std", std)?;
                if mean == 0.0 {
                    return Ok(());
                }
                spread(
                    "normal",
                    "std",
                    "`std` relative to the mean (std/|mean|)",
                    std,
                    std / mean.abs(),
                )
            }
            Self::Uniform { low, high } => {
                finite("uniform", "low", low)?;
                finite("uniform", "high", high)?;
                // high − low must also be finite, or the sampler cannot scale its unit draw.
                if !(low < high && (high - low).is_finite()) {
                    return err(
                        "high",
                        format!(
                            "uniform: needs `low` < `high` (and a finite width), got low = {low}, \
                             high = {high}"
                        ),
                    );
                }
                let relative = (high - low) / low.abs().max(high.abs());
                if relative < lo {
                    return err(
                        "high",
                        format!(
                            "uniform: the width high − low relative to the values must be at least {lo:e} ({WHY}), got low = {}, high = {}",
                            crate::units::show(low),
                            crate::units::show(high)
                        ),
                    );
                }
                Ok(())
            }
        }
    }

    /// Mean of the law, in the parameter's units.
    pub fn mean(&self) -> f64 {
        match *self {
            Self::Gamma { mean, .. } | Self::LogNormal { mean, .. } | Self::Normal { mean, .. } => {
                mean
            }
            Self::Uniform { low, high } => 0.5 * (low + high),
        }
    }

    /// Standard deviation of the law, in the parameter's units.
    pub fn std_dev(&self) -> f64 {
        match *self {
            Self::Gamma { mean, cov } | Self::LogNormal { mean, cov } => mean * cov,
            Self::Normal { std, .. } => std,
            Self::Uniform { low, high } => (high - low) / 12f64.sqrt(),
        }
    }

    /// Lower end of the support: 0 for Gamma and LogNormal, −∞ for Normal, `low` for Uniform.
    pub fn lower_support(&self) -> f64 {
        match *self {
            Self::Gamma { .. } | Self::LogNormal { .. } => 0.0,
            Self::Normal { .. } => f64::NEG_INFINITY,
            Self::Uniform { low, .. } => low,
        }
    }

    /// Upper end of the support: `high` for Uniform, +∞ otherwise.
    pub fn upper_support(&self) -> f64 {
        match *self {
            Self::Uniform { high, .. } => high,
            _ => f64::INFINITY,
        }
    }

    /// Draws one value with `rng` (rand 0.10), through the samplers of `rand_distr` 0.6.
    ///
    /// The stream of values for a given generator state is reproducible for a given version of
    /// `rand_distr`; its Gamma and normal algorithms may change between major versions.
    ///
    /// # Panics
    /// If the law fails [`validate`](Self::validate); validate laws when the problem is loaded.
    pub fn sample<R: rand::Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        if let Err(why) = self.validate() {
            panic!("cannot sample {self:?}: {why}");
        }
        // After validate() the samplers' own checks cannot fail.
        const CHECKED: &str = "parameters checked by validate()";
        match *self {
            Self::Gamma { mean, cov } => {
                let cov2 = cov * cov;
                rand_distr::Gamma::new(1.0 / cov2, mean * cov2)
                    .expect(CHECKED)
                    .sample(rng)
            }
            Self::LogNormal { mean, cov } => {
                let (mu, sigma) = lognormal_log_params(mean, cov);
                rand_distr::LogNormal::new(mu, sigma)
                    .expect(CHECKED)
                    .sample(rng)
            }
            Self::Normal { mean, std } => rand_distr::Normal::new(mean, std)
                .expect(CHECKED)
                .sample(rng),
            Self::Uniform { low, high } => rand_distr::Uniform::new(low, high)
                .expect(CHECKED)
                .sample(rng),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lognormal_parameters_round_trip() {
        for &(mean, cov) in &[(1.0, 0.1), (3.5e-4, 0.5), (250.0, 1e-4), (2.0, 2.0)] {
            let (mu, sigma) = lognormal_log_params(mean, cov);
            let back_mean = (mu + 0.5 * sigma * sigma).exp();
            let back_cov = (sigma * sigma).exp_m1().sqrt();
            assert!((back_mean / mean - 1.0).abs() < 1e-13, "{mean} {back_mean}");
            assert!((back_cov / cov - 1.0).abs() < 1e-10, "{cov} {back_cov}");
        }
    }

    #[test]
    fn closed_form_moments_and_support() {
        let g = Distribution::Gamma {
            mean: 2.0,
            cov: 0.25,
        };
        assert_eq!((g.mean(), g.std_dev(), g.lower_support()), (2.0, 0.5, 0.0));
        let u = Distribution::Uniform {
            low: 1.0,
            high: 4.0,
        };
        assert_eq!(u.mean(), 2.5);
        assert!((u.std_dev() - 3.0 / 12f64.sqrt()).abs() < 1e-15);
        assert_eq!((u.lower_support(), u.upper_support()), (1.0, 4.0));
        let n = Distribution::Normal {
            mean: -1.0,
            std: 0.3,
        };
        assert_eq!(
            (n.mean(), n.std_dev(), n.lower_support()),
            (-1.0, 0.3, f64::NEG_INFINITY)
        );
        let l = Distribution::LogNormal {
            mean: 5.0,
            cov: 0.2,
        };
        assert_eq!((l.mean(), l.std_dev(), l.lower_support()), (5.0, 1.0, 0.0));
    }

    #[test]
    fn validate_rejects_each_bad_case_and_says_what_is_allowed() {
        use Distribution::*;
        let cases: &[(Distribution, &[&str])] = &[
            (
                Gamma {
                    mean: 0.0,
                    cov: 0.1,
                },
                &["gamma", "`mean`", "> 0"],
            ),
            (
                Gamma {
                    mean: -1.0,
                    cov: 0.1,
                },
                &["gamma", "`mean`", "> 0"],
            ),
            (
                Gamma {
                    mean: 1.0,
                    cov: 0.0,
                },
                &["gamma", "`cov`", "[1e-6, 1]"],
            ),
            // Issue 34: the gamma sampler's scale mean·cov² underflowed and it panicked.
            (
                Gamma {
                    mean: 1.0,
                    cov: 1e-163,
                },
                &["gamma", "`cov`", "[1e-6, 1]", "deterministic", "1e-163"],
            ),
            (
                Gamma {
                    mean: 1.0,
                    cov: 1e-160,
                },
                &["gamma", "`cov`", "[1e-6, 1]"],
            ),
            (
                LogNormal {
                    mean: 1.0,
                    cov: 3.0,
                },
                &["lognormal", "`cov`", "[1e-6, 1]"],
            ),
            (
                Gamma {
                    mean: 5e-324,
                    cov: 0.1,
                },
                &["gamma", "`mean`", "too small"],
            ),
            (
                Normal {
                    mean: 250e3,
                    std: 1e-300,
                },
                &["normal", "`std`", "[1e-6, 1]"],
            ),
            (
                Uniform {
                    low: 1.0,
                    high: 1.0 + 1e-12,
                },
                &["uniform", "width", "1e-6"],
            ),
            (
                Gamma {
                    mean: f64::NAN,
                    cov: 0.1,
                },
                &["gamma", "`mean`", "finite"],
            ),
            (
                Gamma {
                    mean: 1.0,
                    cov: f64::INFINITY,
                },
                &["gamma", "`cov`", "finite"],
            ),
            (
                LogNormal {
                    mean: -2.0,
                    cov: 0.1,
                },
                &["lognormal", "`mean`", "> 0"],
            ),
            (
                LogNormal {
                    mean: 2.0,
                    cov: -0.1,
                },
                &["lognormal", "`cov`", "[1e-6, 1]"],
            ),
            (
                Normal {
                    mean: 1.0,
                    std: 0.0,
                },
                &["normal", "`std`", "> 0"],
            ),
            (
                Normal {
                    mean: f64::INFINITY,
                    std: 1.0,
                },
                &["normal", "`mean`", "finite"],
            ),
            (
                Uniform {
                    low: 2.0,
                    high: 1.0,
                },
                &["uniform", "`low` < `high`"],
            ),
            (
                Uniform {
                    low: 1.0,
                    high: 1.0,
                },
                &["uniform", "`low` < `high`"],
            ),
            (
                Uniform {
                    low: f64::NEG_INFINITY,
                    high: 1.0,
                },
                &["uniform", "`low`", "finite"],
            ),
            (
                Uniform {
                    low: -f64::MAX,
                    high: f64::MAX,
                },
                &["uniform", "finite width"],
            ),
        ];
        for (law, words) in cases {
            let msg = law
                .validate()
                .expect_err(&format!("{law:?} must be rejected"))
                .to_string();
            for w in *words {
                assert!(msg.contains(w), "message for {law:?} lacks {w:?}: {msg}");
            }
        }
        for good in [
            Gamma {
                mean: 1.0,
                cov: 0.1,
            },
            LogNormal {
                mean: 1.0,
                cov: 1.0,
            },
            Gamma {
                mean: 1.0,
                cov: 1e-6,
            },
            Normal {
                mean: -4.0,
                std: 0.1,
            },
            Uniform {
                low: -1.0,
                high: 1.0,
            },
        ] {
            assert_eq!(good.validate(), Ok(()));
        }
    }

    #[test]
    fn reports_use_the_problem_file_names() {
        let json = |d: Distribution| serde_json::to_string(&d).unwrap();
        assert_eq!(
            json(Distribution::Gamma {
                mean: 2.0,
                cov: 0.1
            }),
            r#"{"law":"gamma","mean":2.0,"cov":0.1}"#
        );
        assert_eq!(
            json(Distribution::LogNormal {
                mean: 2.0,
                cov: 0.1
            }),
            r#"{"law":"lognormal","mean":2.0,"cov":0.1}"#
        );
    }

    #[test]
    #[should_panic(expected = "cannot sample")]
    fn sampling_an_invalid_law_panics_with_the_reason() {
        let mut rng = super::super::sample_rng(1);
        Distribution::Normal {
            mean: 0.0,
            std: -1.0,
        }
        .sample(&mut rng);
    }
}
