//! The numerical check of an optimum: what `drillopt verify` runs (the basis, mesh, integrator
//! tolerance and window refinements, the smoothing one where a law smooths a set-valued contact,
//! and the 1e-4 perturbation of Ω) at the optimum with nominal parameters, set beside the
//! statistical spread of each decision metric over the samples, so a report says whether the
//! numbers that decided the optimum are converged, and under which refinement they are not.

use crate::problem::Problem;
use crate::study::PointEvaluation;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};

/// One decision metric at the optimum: the numerical change under `verify`'s refinements
/// (nominal parameters) against the statistical spread over the Monte Carlo samples.
#[derive(Debug, Clone, Serialize)]
pub struct CheckedMetric {
    /// The nominal model's value with the problem's basis.
    pub value: f64,
    /// The same with every family of the basis enriched 1.5×.
    pub refined_basis: f64,
    /// The value of each refined run, by refinement (`basis`, `mesh`, `tolerance`, `window`,
    /// `smoothing`).
    pub refined: BTreeMap<&'static str, f64>,
    /// The value at Ω·(1 + 1e-4).
    pub perturbed: Option<f64>,
    /// Largest |refined − value| / max(|value|, floor) over the refinements, as in `verify`.
    pub rel_change: f64,
    pub limit: f64,
    /// `verify`'s verdict: converged, not converged (a refinement beyond the limit) or
    /// sensitive (the perturbation alone beyond it).
    pub verdict: crate::verify::Verdict,
    /// The refinements that moved it beyond its limit.
    pub beyond_limit: Vec<&'static str>,
    pub converged: bool,
    /// Whether the problem's score or constraints use the metric ([`metrics_used`]).
    pub used: bool,
    /// Standard deviation of the metric over the samples at the optimum (none with one sample).
    pub sample_std_dev: Option<f64>,
}

/// The numerical check at an optimum.
#[derive(Debug, Clone, Serialize)]
pub struct NumericalCheck {
    pub basis: crate::rom::BasisCounts,
    pub refined_basis: crate::rom::BasisCounts,
    /// The refinements run (those of `verify` for this problem), then `perturbed`.
    pub runs: Vec<&'static str>,
    /// Every metric the problem uses ([`CheckedMetric::used`]) is converged: the optimum rests
    /// on converged numbers.
    pub converged: bool,
    /// Every decision metric is converged, used or not.
    pub all_converged: bool,
    pub metrics: BTreeMap<&'static str, CheckedMetric>,
}

/// The metric keys the problem's score and constraints depend on: the objective's quantity
/// (`mean_rop_m_per_h` or `efficiency`), every risk term's and every chance constraint's metric,
/// and the compared metrics each is checked through (its row of the metric catalogue,
/// [`crate::metrics::catalogue::checked_through`]): MSE = WOB/A + 2π N·TOB/(A·ROP) (Teale 1965)
/// and the efficiency bring the WOB, TOB and ROP; `von_mises_utilization` (peak von Mises stress
/// / yield strength) brings `max_von_mises_pa`, which the basis check compares.
pub fn metrics_used(problem: &Problem) -> BTreeSet<String> {
    let mut used = BTreeSet::new();
    for m in problem.study.metrics_named() {
        used.insert(m.to_string());
        used.extend(
            crate::metrics::catalogue::checked_through(m)
                .into_iter()
                .map(String::from),
        );
    }
    used
}

/// Run `verify`'s refinements and perturbation at the optimum (nominal parameters, the
/// problem's window) and set them beside the sample spread. `progress` is told the name of each
/// run as it finishes.
pub fn numerical_check(
    problem: &Problem,
    best: &PointEvaluation,
    progress: impl Fn(&str) + Sync,
) -> Result<NumericalCheck, crate::verify::VerifyError> {
    use crate::verify::{Refinement, VerifySettings, refinements, verify_with};
    let settings = VerifySettings {
        op: best.op(),
        duration: problem.simulation.duration,
        settling: problem.simulation.settling_time,
        stability_reference: false,
    };
    let mut runs = refinements(problem);
    runs.push(Refinement::Perturbed);
    let report = verify_with(problem, settings, &runs, progress)?;
    let spread = |key: &str| {
        let values: Vec<f64> = best
            .samples
            .iter()
            .filter_map(|s| match &s.outcome {
                crate::study::SampleOutcome::Metrics(m) => m.get(key).copied(),
                _ => None,
            })
            .collect();
        let n = values.len() as f64;
        if n < 2.0 {
            return None;
        }
        let mean = values.iter().sum::<f64>() / n;
        Some((values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt())
    };
    let used = metrics_used(problem);
    let metrics: BTreeMap<&'static str, CheckedMetric> = report
        .metrics
        .iter()
        .map(|(&key, v)| {
            (
                key,
                CheckedMetric {
                    value: v.value,
                    refined_basis: v.refined[Refinement::Basis.name()],
                    refined: v.refined.clone(),
                    perturbed: v.perturbed,
                    rel_change: v.max_rel_change,
                    limit: v.limit,
                    verdict: v.verdict,
                    beyond_limit: v.beyond_limit.clone(),
                    converged: v.converged,
                    used: used.contains(key),
                    sample_std_dev: spread(key),
                },
            )
        })
        .collect();
    Ok(NumericalCheck {
        basis: report.basis,
        refined_basis: report.refined_basis,
        runs: runs.iter().map(|r| r.name()).collect(),
        converged: metrics.values().all(|m| m.converged || !m.used),
        all_converged: report.converged,
        metrics,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn used(file: &str) -> BTreeSet<String> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
        metrics_used(&Problem::load(&path).unwrap())
    }

    #[test]
    fn the_metrics_used_are_those_of_the_score_and_the_constraints() {
        // ROP − 5·SSI − 1e-8·MSE: the SSI, and the WOB, TOB and ROP the MSE is made of.
        let tiny = used("problems/regression/tiny_string.toml");
        for key in [
            "mean_rop_m_per_h",
            "stick_slip_severity",
            "mse_pa",
            "mean_wob_n",
            "mean_tob_nm",
        ] {
            assert!(tiny.contains(key), "{key}: {tiny:?}");
        }
        for key in [
            "stick_fraction",
            "max_bit_speed_ratio",
            "fatigue_damage_per_h",
        ] {
            assert!(!tiny.contains(key), "{key}: {tiny:?}");
        }
        // ROP − 1e-8·MSE with fatigue and buckling chance constraints: no stick-slip statistic.
        let fatigue = used("problems/regression/slim_pipe_fatigue.toml");
        for key in ["fatigue_damage_per_h", "buckling_utilization", "mse_pa"] {
            assert!(fatigue.contains(key), "{key}: {fatigue:?}");
        }
        assert!(!fatigue.contains("stick_slip_severity"), "{fatigue:?}");
        // A chance constraint on the von Mises utilization: the peak stress it is computed from.
        let study = used("problems/bench/seed_study.toml");
        for key in [
            "von_mises_utilization",
            "max_von_mises_pa",
            "stick_slip_severity",
        ] {
            assert!(study.contains(key), "{key}: {study:?}");
        }
        assert!(!study.contains("mean_wob_n"), "{study:?}");
        // No constraint on it since the benchmark carries the stiffness damping.
        assert!(!study.contains("bit_damping_ratio"), "{study:?}");
        assert!(!fatigue.contains("max_von_mises_pa"), "{fatigue:?}");
    }

    /// Every metric a problem may decide on (the objective's quantities, and every metric that
    /// risk terms and chance constraints accept) is compared by the numerical check, itself or
    /// through the metrics it is computed from, and is marked used there.
    #[test]
    fn every_metric_a_problem_may_use_is_in_the_numerical_check() {
        use crate::metrics::{METRICS, catalogue};
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("problems/regression/tiny_string.toml");
        let tiny = std::fs::read_to_string(&path)
            .unwrap()
            .replace("[model.pipe]", "[model.pipe]\nyield_strength = \"S-135\"");
        let with = |extra: String| Problem::from_toml(&(tiny.clone() + &extra), &path).unwrap();
        let efficiency = tiny.replace("quantity = \"rop\"", "quantity = \"efficiency\"");
        let mut problems = vec![(
            "efficiency".to_string(),
            Problem::from_toml(&efficiency, &path).unwrap(),
        )];
        for spec in METRICS.iter().filter(|s| s.penalisable()) {
            let key = spec.key;
            let chance = format!(
                "\n[[constraints.chance]]\nmetric = \"{key}\"\nthreshold = 1.0\nmax_probability = 0.1\n"
            );
            let risk = format!("\n[[objective.risk]]\nmetric = \"{key}\"\nweight = 1.0\n");
            problems.push((key.to_string(), with(chance)));
            problems.push((key.to_string(), with(risk)));
        }
        for (key, problem) in &problems {
            let compared: Vec<&str> = crate::verify::decision_metrics(problem)
                .iter()
                .map(|d| d.key)
                .collect();
            let used = metrics_used(problem);
            let through = catalogue::checked_through(key);
            assert!(!through.is_empty(), "{key}");
            for k in through {
                assert!(
                    compared.contains(&k),
                    "{key}: {k} not compared: {compared:?}"
                );
                assert!(used.contains(k), "{key}: {k} not marked used: {used:?}");
            }
        }
        // The one the issue found missing, and the ones computed from a compared metric.
        let radial = &problems
            .iter()
            .find(|(k, _)| k == "max_radial_over_gap")
            .unwrap()
            .1;
        assert!(metrics_used(radial).contains("max_radial_over_gap"));
        let compression = catalogue::checked_through("max_compression_n");
        assert_eq!(compression, ["max_von_mises_pa"]);
    }
}
