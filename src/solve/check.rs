//! The numerical check of an optimum: the basis refinement of `verify` run at the optimum with
//! nominal parameters, set beside the statistical spread of each decision metric over the samples,
//! so a report says whether the numbers that decided the optimum are converged.

use crate::problem::Problem;
use crate::study::PointEvaluation;
use serde::Serialize;
use std::collections::BTreeMap;

/// One decision metric at the optimum: the numerical change under basis refinement (nominal
/// parameters) against the statistical spread over the Monte Carlo samples.
#[derive(Debug, Clone, Serialize)]
pub struct CheckedMetric {
    /// The nominal model's value with the problem's basis.
    pub value: f64,
    /// The same with every family of the basis enriched 1.5×.
    pub refined_basis: f64,
    /// |refined − value| / max(|value|, floor), as in `verify`.
    pub rel_change: f64,
    pub limit: f64,
    pub converged: bool,
    /// Standard deviation of the metric over the samples at the optimum (none with one sample).
    pub sample_std_dev: Option<f64>,
}

/// The basis check at an optimum.
#[derive(Debug, Clone, Serialize)]
pub struct NumericalCheck {
    pub basis: crate::rom::BasisCounts,
    pub refined_basis: crate::rom::BasisCounts,
    pub converged: bool,
    pub metrics: BTreeMap<&'static str, CheckedMetric>,
}

/// Run the basis check of `verify` at the optimum and set it beside the sample spread.
pub fn numerical_check(
    problem: &Problem,
    best: &PointEvaluation,
) -> Result<NumericalCheck, crate::verify::VerifyError> {
    use crate::verify::{Refinement, VerifySettings, verify_with};
    let settings = VerifySettings {
        op: crate::model::OperatingPoint {
            omega: best.omega_rad_s,
            v0: best.v0_m_s,
        },
        duration: problem.simulation.duration,
        settling: problem.simulation.settling_time,
    };
    let report = verify_with(problem, settings, &[Refinement::Basis], |_| {})?;
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
    let metrics = report
        .metrics
        .iter()
        .map(|(&key, v)| {
            (
                key,
                CheckedMetric {
                    value: v.value,
                    refined_basis: v.refined[Refinement::Basis.name()],
                    rel_change: v.max_rel_change,
                    limit: v.limit,
                    converged: v.converged,
                    sample_std_dev: spread(key),
                },
            )
        })
        .collect();
    Ok(NumericalCheck {
        basis: report.basis,
        refined_basis: report.refined_basis,
        converged: report.converged,
        metrics,
    })
}
