//! Statistics of a metric over Monte Carlo samples: the numbers a robust objective is built from.
//!
//! # Conventions
//! * `values` are the values of one metric, one per sample, all samples weighted equally (the
//!   empirical distribution F̂). For risk terms **larger is worse** (stick-slip severity, MSE,
//!   impact count): [`Statistic::Cvar`], [`Statistic::Quantile`], [`Statistic::ProbExceed`] and
//!   [`Statistic::Max`] look at the upper tail. For a gain where smaller is worse (rate of
//!   penetration) use [`Statistic::LowerCvar`] or [`Statistic::Min`]; the result stays in the
//!   metric's units (nothing is negated).
//! * **Mean**: (1/n) Σ xᵢ.
//! * **StdDev**: the sample standard deviation, √(Σ (xᵢ − x̄)² / (n − 1)); 0 for one sample.
//! * **Quantile** at level α ∈ \[0, 1\]: the empirical value-at-risk
//!   VaR_α = inf{x : F̂(x) ≥ α} = x₍⌈αn⌉₎ (order statistics x₍₁₎ ≤ … ≤ x₍ₙ₎, no interpolation;
//!   α = 0 gives the minimum). It is the VaR that pairs with the CVaR below.
//! * **Cvar** at level α ∈ \[0, 1\] (upper tail; Rockafellar & Uryasev 2000, 2002):
//!   CVaR_α = min_c { c + E\[(X − c)⁺\] / (1 − α) }, the mean of the worst (1 − α) fraction of
//!   the probability mass. For the empirical law with m = (1 − α) n = j + f (j integer,
//!   0 ≤ f < 1) this is exactly (x₍ₙ₎ + … + x₍ₙ₋ⱼ₊₁₎ + f·x₍ₙ₋ⱼ₎) / m: the boundary sample
//!   carries the fractional weight f. CVaR₀ is the mean; CVaR₁ is defined as the maximum (the
//!   limit α → 1). CVaR is continuous in α and in the data, and CVaR_α ≥ VaR_α.
//! * **LowerCvar** at level α: the same for the lower tail, the mean of the smallest (1 − α)
//!   fraction of the mass, = −CVaR_α(−X). LowerCvar₀ is the mean, LowerCvar₁ the minimum.
//! * **ProbExceed** with threshold t: the fraction of samples strictly above t.
//! * **Max** / **Min**: the largest / smallest value.
//!
//! A `(1 − α) n` or `α n` within 10⁻⁹ of an integer is taken as that integer, so that α = 0.9
//! with n = 10 selects exactly one sample despite 0.1·10 = 0.9999999999999998 in binary.
//!
//! Every statistic of an empty slice, or of a slice holding a NaN, is NaN: a failed sample must
//! be dealt with (penalised or dropped) before the statistic, not hidden by it. ±∞ are ordinary
//! values (a CVaR over a tail holding +∞ is +∞).

use serde::Serialize;
use std::fmt;

/// Counts within this distance of an integer are rounded to it (see the module doc).
const COUNT_SNAP: f64 = 1e-9;

/// A statistic of one metric over the samples; see the module doc for the exact definitions.
///
/// Read from problem files by [`crate::problem`] (`statistic = "cvar"`, `level = 0.9`); serialised
/// in reports with the same names: `{"kind": "cvar", "level": 0.9}`, `{"kind": "std_dev"}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Statistic {
    /// Sample mean.
    Mean,
    /// Sample standard deviation (n − 1 denominator; 0 for one sample).
    StdDev,
    /// Mean of the upper (1 − `level`) tail; `level` ∈ \[0, 1\], e.g. 0.9.
    Cvar { level: f64 },
    /// Mean of the lower (1 − `level`) tail, for gains; `level` ∈ \[0, 1\].
    LowerCvar { level: f64 },
    /// Fraction of samples strictly above `threshold` (finite), in the metric's units.
    ProbExceed { threshold: f64 },
    /// Empirical `level`-quantile x₍⌈level·n⌉₎; `level` ∈ \[0, 1\].
    Quantile { level: f64 },
    /// Largest value.
    Max,
    /// Smallest value.
    Min,
}

impl Statistic {
    /// Checks the parameter ranges documented on each variant; the message names the statistic,
    /// the parameter, its value and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        let level = |name: &str, level: f64| {
            if (0.0..=1.0).contains(&level) {
                Ok(())
            } else {
                Err(format!("{name}: `level` = {level} must be in [0, 1]"))
            }
        };
        match *self {
            Self::Cvar { level: a } => level("cvar", a),
            Self::LowerCvar { level: a } => level("lower_cvar", a),
            Self::Quantile { level: a } => level("quantile", a),
            Self::ProbExceed { threshold } if !threshold.is_finite() => Err(format!(
                "prob_exceed: `threshold` = {threshold} must be finite"
            )),
            _ => Ok(()),
        }
    }

    /// The statistic of `values` (one per sample; see the module doc). NaN if `values` is empty
    /// or holds a NaN. An out-of-range level is clamped to \[0, 1\]; call
    /// [`validate`](Self::validate) first to reject it instead.
    pub fn apply(&self, values: &[f64]) -> f64 {
        match *self {
            Self::Mean => mean(values),
            Self::StdDev => std_dev(values),
            Self::Cvar { level } => cvar(values, level),
            Self::LowerCvar { level } => lower_cvar(values, level),
            Self::ProbExceed { threshold } => prob_exceed(values, threshold),
            Self::Quantile { level } => quantile(values, level),
            Self::Max => max(values),
            Self::Min => min(values),
        }
    }
}

impl fmt::Display for Statistic {
    /// A short name for column headers: `mean`, `std_dev`, `cvar_0.9`, `lower_cvar_0.9`,
    /// `prob_exceed_3`, `quantile_0.5`, `max`, `min`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Mean => write!(f, "mean"),
            Self::StdDev => write!(f, "std_dev"),
            Self::Cvar { level } => write!(f, "cvar_{level}"),
            Self::LowerCvar { level } => write!(f, "lower_cvar_{level}"),
            Self::ProbExceed { threshold } => write!(f, "prob_exceed_{threshold}"),
            Self::Quantile { level } => write!(f, "quantile_{level}"),
            Self::Max => write!(f, "max"),
            Self::Min => write!(f, "min"),
        }
    }
}

/// Whether the statistic is undefined: no value, or a NaN among them.
fn undefined(values: &[f64]) -> bool {
    values.is_empty() || values.iter().any(|v| v.is_nan())
}

/// Rounds a count to the nearest integer when it is within [`COUNT_SNAP`] of it.
fn snap(count: f64) -> f64 {
    let r = count.round();
    if (count - r).abs() <= COUNT_SNAP {
        r
    } else {
        count
    }
}

/// Ascending copy of `values` (which hold no NaN).
fn sorted(values: &[f64]) -> Vec<f64> {
    let mut v = values.to_vec();
    v.sort_unstable_by(f64::total_cmp);
    v
}

/// Sample mean; NaN if empty or a NaN is present.
pub fn mean(values: &[f64]) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    values.iter().sum::<f64>() / values.len() as f64
}

/// Sample standard deviation with the n − 1 denominator (two-pass); 0 for one sample.
pub fn std_dev(values: &[f64]) -> f64 {
    let m = mean(values);
    if m.is_nan() {
        return f64::NAN;
    }
    if values.len() == 1 {
        return 0.0;
    }
    let ss: f64 = values.iter().map(|v| (v - m).powi(2)).sum();
    (ss / (values.len() - 1) as f64).sqrt()
}

/// Mean of the first (1 − `level`) fraction of the mass of `worst_first`, `n` values sorted
/// worst first (descending for the upper tail, ascending for the lower). `level` is clamped to
/// \[0, 1\]; level 1 gives the first (most extreme) value.
fn tail_mean(mut worst_first: impl Iterator<Item = f64>, n: usize, level: f64) -> f64 {
    let mass = snap((1.0 - level.clamp(0.0, 1.0)) * n as f64);
    if mass <= 0.0 {
        return worst_first.next().unwrap_or(f64::NAN);
    }
    let whole = mass.floor() as usize; // j samples of weight 1 …
    let frac = mass - whole as f64; // … then the boundary sample with weight f
    let mut sum: f64 = worst_first.by_ref().take(whole).sum();
    if frac > 0.0
        && let Some(x) = worst_first.next()
    {
        sum += frac * x;
    }
    sum / mass
}

/// Upper-tail CVaR at `level` ∈ \[0, 1\] (mean of the largest (1 − level) fraction, exact for the
/// empirical law; see the module doc). `level` is clamped to \[0, 1\].
pub fn cvar(values: &[f64], level: f64) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    tail_mean(sorted(values).into_iter().rev(), values.len(), level)
}

/// Lower-tail CVaR at `level` ∈ \[0, 1\]: mean of the smallest (1 − level) fraction of the mass,
/// = −cvar(−values, level). For gains (ROP) where smaller is worse.
pub fn lower_cvar(values: &[f64], level: f64) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    tail_mean(sorted(values).into_iter(), values.len(), level)
}

/// Empirical quantile x₍⌈level·n⌉₎ (no interpolation; level 0 gives the minimum). `level` is
/// clamped to \[0, 1\].
pub fn quantile(values: &[f64], level: f64) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    let n = values.len();
    let rank = snap(level.clamp(0.0, 1.0) * n as f64).ceil() as usize;
    sorted(values)[rank.clamp(1, n) - 1]
}

/// Fraction of `values` strictly above `threshold`.
pub fn prob_exceed(values: &[f64], threshold: f64) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    values.iter().filter(|&&v| v > threshold).count() as f64 / values.len() as f64
}

/// Largest value.
pub fn max(values: &[f64]) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

/// Smallest value.
pub fn min(values: &[f64]) -> f64 {
    if undefined(values) {
        return f64::NAN;
    }
    values.iter().copied().fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: f64 = 1e-12;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= TOL * (1.0 + b.abs())
    }

    /// 1, 2, …, n in a scrambled order (the statistics must not depend on the order).
    fn one_to(n: usize) -> Vec<f64> {
        (0..n).map(|i| ((i * 7919) % n + 1) as f64).collect()
    }

    /// Closed form of the upper CVaR of {1, …, n}: with m = (1 − α) n = j + f,
    /// (Σ_{k=n−j+1}^{n} k + f (n − j)) / m = (j (2n − j + 1)/2 + f (n − j)) / m.
    fn cvar_one_to(n: usize, level: f64) -> f64 {
        let m = (1.0 - level) * n as f64;
        let j = m.floor();
        let f = m - j;
        let n = n as f64;
        (j * (2.0 * n - j + 1.0) / 2.0 + f * (n - j)) / m
    }

    #[test]
    fn cvar_of_equally_spaced_values() {
        let x = one_to(10);
        // Integer tail sizes.
        assert!(close(cvar(&x, 0.8), 9.5));
        assert!(close(cvar(&x, 0.5), 8.0));
        assert!(close(cvar(&x, 0.9), 10.0));
        // Fractional boundary: m = 2.5 → (10 + 9 + 0.5·8)/2.5 = 9.2; m = 0.5 → 10;
        // m = 3.7 → (10 + 9 + 8 + 0.7·7)/3.7.
        assert!(close(cvar(&x, 0.75), 9.2));
        assert!(close(cvar(&x, 0.95), 10.0));
        assert!(close(cvar(&x, 0.63), (27.0 + 0.7 * 7.0) / 3.7));
        for n in [1, 2, 7, 10, 33, 100] {
            let x = one_to(n);
            for level in [0.0, 0.1, 0.25, 0.5, 0.62, 0.9, 0.95, 0.99, 0.999] {
                let want = cvar_one_to(n, level);
                assert!(
                    close(cvar(&x, level), want),
                    "n {n} α {level}: {} vs {want}",
                    cvar(&x, level)
                );
                // Lower tail of {1..n} mirrors the upper: LowerCVaR = n + 1 − CVaR.
                assert!(close(lower_cvar(&x, level), n as f64 + 1.0 - want));
            }
        }
    }

    #[test]
    fn cvar_of_a_fine_uniform_grid_tends_to_the_continuous_value() {
        // Midpoints of n cells of [0, 1]: the CVaR of U(0, 1) is (1 + α)/2; the empirical one
        // differs by f(1 − f)/(2 n m) ≤ 1/(8 n m) (f the fractional boundary weight).
        let n = 1000;
        let x: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect();
        for level in [0.0, 0.5, 0.9, 0.9234, 0.99] {
            let m = (1.0 - level) * n as f64;
            let bound = 1.0 / (8.0 * n as f64 * m) + 1e-12;
            assert!(
                (cvar(&x, level) - (1.0 + level) / 2.0).abs() <= bound,
                "α {level}"
            );
        }
    }

    #[test]
    fn cvar_limits_mean_and_max() {
        let x = [3.5, -1.0, 8.25, 0.0, 2.0, 2.0, 11.0];
        assert!(close(cvar(&x, 0.0), mean(&x)));
        assert!(close(lower_cvar(&x, 0.0), mean(&x)));
        assert_eq!(cvar(&x, 1.0), 11.0);
        assert_eq!(lower_cvar(&x, 1.0), -1.0);
        // Continuous approach to the max: for m = (1 − α) n ≤ 1 only the max is in the tail.
        for level in [1.0 - 1.0 / 7.0, 0.9, 0.99, 0.999_999] {
            assert!(close(cvar(&x, level), 11.0), "α {level}");
        }
        // And increasing in α.
        let levels: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
        let c: Vec<f64> = levels.iter().map(|&a| cvar(&x, a)).collect();
        assert!(c.windows(2).all(|w| w[1] >= w[0] - TOL));
    }

    #[test]
    fn cvar_is_the_rockafellar_uryasev_minimum_and_dominates_var() {
        // CVaR_α = min_c c + mean((x − c)⁺)/(1 − α); the objective is piecewise linear in c
        // with kinks at the data, so the minimum over the data points is the minimum.
        let mut s: u64 = 12345;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [1, 5, 13, 50] {
            let x: Vec<f64> = (0..n).map(|_| (next() * 10.0).exp()).collect();
            for level in [0.0, 0.3, 0.5, 0.77, 0.9, 0.97] {
                let ru = |c: f64| {
                    c + mean(&x.iter().map(|v| (v - c).max(0.0)).collect::<Vec<_>>())
                        / (1.0 - level)
                };
                let best = x.iter().map(|&c| ru(c)).fold(f64::INFINITY, f64::min);
                let got = cvar(&x, level);
                assert!(
                    (got - best).abs() <= 1e-10 * best.abs(),
                    "n {n} α {level}: {got} vs {best}"
                );
                let var = quantile(&x, level);
                assert!(got >= var - 1e-12 * var.abs());
                assert!(
                    (ru(var) - best).abs() <= 1e-10 * best.abs(),
                    "VaR minimises the RU objective"
                );
            }
        }
    }

    #[test]
    fn quantile_is_the_empirical_inverse_cdf() {
        let x = one_to(10);
        assert_eq!(quantile(&x, 0.0), 1.0);
        assert_eq!(quantile(&x, 0.05), 1.0);
        assert_eq!(quantile(&x, 0.1), 1.0);
        assert_eq!(quantile(&x, 0.11), 2.0);
        assert_eq!(quantile(&x, 0.5), 5.0);
        assert_eq!(quantile(&x, 0.9), 9.0); // 0.9·10 = 9.000000000000002 in binary
        assert_eq!(quantile(&x, 0.91), 10.0);
        assert_eq!(quantile(&x, 1.0), 10.0);
    }

    #[test]
    fn prob_exceed_std_dev_mean_on_hand_sets() {
        let x = [1.0, 2.0, 3.0, 3.0, 4.0];
        assert_eq!(prob_exceed(&x, 3.0), 0.2); // strictly above: only 4
        assert_eq!(prob_exceed(&x, 2.5), 0.6);
        assert_eq!(prob_exceed(&x, 0.0), 1.0);
        assert_eq!(prob_exceed(&x, 4.0), 0.0);
        // The textbook set: mean 5, Σ(x − x̄)² = 32, sample variance 32/7.
        let y = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert_eq!(mean(&y), 5.0);
        assert!(close(std_dev(&y), (32.0f64 / 7.0).sqrt()));
        assert_eq!(std_dev(&[42.0]), 0.0);
        assert_eq!(max(&y), 9.0);
        assert_eq!(min(&y), 2.0);
    }

    #[test]
    fn apply_dispatches_and_handles_degenerate_input() {
        let y = [2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0];
        assert_eq!(Statistic::Mean.apply(&y), 5.0);
        assert_eq!(Statistic::StdDev.apply(&y), std_dev(&y));
        assert_eq!(Statistic::Cvar { level: 0.75 }.apply(&y), 8.0);
        assert_eq!(Statistic::LowerCvar { level: 0.75 }.apply(&y), 3.0);
        assert_eq!(Statistic::ProbExceed { threshold: 4.0 }.apply(&y), 0.5);
        assert_eq!(Statistic::Quantile { level: 0.5 }.apply(&y), 4.0);
        assert_eq!(Statistic::Max.apply(&y), 9.0);
        assert_eq!(Statistic::Min.apply(&y), 2.0);
        let all = [
            Statistic::Mean,
            Statistic::StdDev,
            Statistic::Cvar { level: 0.9 },
            Statistic::LowerCvar { level: 0.9 },
            Statistic::ProbExceed { threshold: 1.0 },
            Statistic::Quantile { level: 0.9 },
            Statistic::Max,
            Statistic::Min,
        ];
        for s in all {
            assert!(s.apply(&[]).is_nan(), "{s} of nothing");
            assert!(s.apply(&[1.0, f64::NAN, 3.0]).is_nan(), "{s} with a NaN");
        }
        assert_eq!(
            Statistic::Cvar { level: 0.5 }.apply(&[1.0, f64::INFINITY]),
            f64::INFINITY
        );
    }

    #[test]
    fn validate_names_the_allowed_range() {
        for (s, words) in [
            (Statistic::Cvar { level: 1.5 }, ["cvar", "[0, 1]"]),
            (Statistic::Cvar { level: f64::NAN }, ["cvar", "[0, 1]"]),
            (
                Statistic::LowerCvar { level: -0.1 },
                ["lower_cvar", "[0, 1]"],
            ),
            (Statistic::Quantile { level: 2.0 }, ["quantile", "[0, 1]"]),
            (
                Statistic::ProbExceed {
                    threshold: f64::INFINITY,
                },
                ["prob_exceed", "finite"],
            ),
        ] {
            let msg = s.validate().expect_err("must be rejected");
            assert!(words.iter().all(|w| msg.contains(w)), "{msg}");
        }
        assert!(Statistic::Cvar { level: 1.0 }.validate().is_ok());
        assert!(Statistic::Quantile { level: 0.0 }.validate().is_ok());
        assert!(Statistic::StdDev.validate().is_ok());
    }

    #[test]
    fn reports_use_the_problem_file_names() {
        let json = |s: Statistic| serde_json::to_string(&s).unwrap();
        assert_eq!(
            json(Statistic::Cvar { level: 0.9 }),
            r#"{"kind":"cvar","level":0.9}"#
        );
        assert_eq!(json(Statistic::StdDev), r#"{"kind":"std_dev"}"#);
        assert_eq!(
            json(Statistic::ProbExceed { threshold: 2.0 }),
            r#"{"kind":"prob_exceed","threshold":2.0}"#
        );
        assert_eq!(Statistic::Cvar { level: 0.9 }.to_string(), "cvar_0.9");
    }
}
