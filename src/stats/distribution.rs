//! The law of one uncertain scalar parameter.
//!
//! Every law is given by quantities of the parameter itself (mean, coefficient of variation
//! cov = std/mean, standard deviation or bounds), never by the internal parameters of the
//! sampler, so that a problem file reads in physical terms:
//!
//! | law | parameters | support | sampler parameters |
//! |---|---|---|---|
//! | Gamma | mean > 0, cov > 0 | (0, ∞) | shape k = 1/cov², scale θ = mean·cov² |
//! | LogNormal | mean > 0, cov > 0 | (0, ∞) | σ² = ln(1 + cov²), μ = ln(mean) − σ²/2 (of ln X) |
//! | Normal | mean, std > 0 | (−∞, ∞) | as given |
//! | Uniform | low < high | \[low, high) | as given |
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
    pub fn validate(&self) -> Result<(), String> {
        fn finite(law: &str, name: &str, value: f64) -> Result<(), String> {
            if value.is_finite() {
                Ok(())
            } else {
                Err(format!("{law}: `{name}` = {value} must be finite"))
            }
        }
        fn positive(law: &str, name: &str, value: f64) -> Result<(), String> {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(format!("{law}: `{name}` = {value} must be finite and > 0"))
            }
        }
        match *self {
            Self::Gamma { mean, cov } => {
                positive("gamma", "mean", mean)?;
                positive("gamma", "cov", cov)
            }
            Self::LogNormal { mean, cov } => {
                positive("lognormal", "mean", mean)?;
                positive("lognormal", "cov", cov)
            }
            Self::Normal { mean, std } => {
                finite("normal", "mean", mean)?;
                positive("normal", "std", std)
            }
            Self::Uniform { low, high } => {
                finite("uniform", "low", low)?;
                finite("uniform", "high", high)?;
                // high − low must also be finite, or the sampler cannot scale its unit draw.
                if low < high && (high - low).is_finite() {
                    Ok(())
                } else {
                    Err(format!(
                        "uniform: needs `low` < `high` (and a finite width), got low = {low}, \
                         high = {high}"
                    ))
                }
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
                &["gamma", "`cov`", "> 0"],
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
                &["lognormal", "`cov`", "> 0"],
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
                .expect_err(&format!("{law:?} must be rejected"));
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
                cov: 3.0,
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
