//! The plots of `solve`, `map` and `compare`: study results turned into the plain inputs of
//! [`crate::report`]'s study plots (Ω in rpm and V0 in m/h on the axes).

use crate::problem::Problem;
use crate::problem::study::Constraints;
use crate::report::{self, ConstraintLine, EvaluatedPoint, Region};
use crate::sim::RunOutput;
use crate::solve::{MapOutcome, SolveOutcome};
use crate::study::PointEvaluation;
use std::f64::consts::PI;
use std::path::Path;

const RPM: f64 = 30.0 / PI;
const MPH: f64 = 3600.0;

/// The bounds box and linear constraints in plot units: a_Ω Ω + a_V V0 ≤ b with Ω = rpm/RPM and
/// V0 = m/h / MPH gives (a_Ω/RPM) rpm + (a_V/MPH) m/h ≤ b.
fn region(c: &Constraints) -> Region {
    Region {
        omega_rpm: [c.omega[0] * RPM, c.omega[1] * RPM],
        v0_m_per_h: [c.v0[0] * MPH, c.v0[1] * MPH],
        lines: c
            .linear
            .iter()
            .map(|l| ConstraintLine {
                label: l.label.replace('_', " "),
                omega_coef: l.omega / RPM,
                v0_coef: l.v0 / MPH,
                upper: l.upper,
            })
            .collect(),
    }
}

fn evaluated(points: &[PointEvaluation]) -> Vec<EvaluatedPoint> {
    points
        .iter()
        .map(|p| EvaluatedPoint {
            omega_rpm: p.omega_rpm,
            v0_m_per_h: p.v0_m_per_h,
            score: p.objective,
            feasible: p.feasible,
        })
        .collect()
}

/// The metrics that matter at a point: the quantity, each risk metric and each chance metric, with
/// every sample's value.
fn metric_samples(problem: &Problem, p: &PointEvaluation) -> Vec<(String, Vec<f64>)> {
    let mut names = vec!["mean_rop_m_per_h".to_string()];
    for r in &problem.study.risk {
        names.push(r.metric.clone());
    }
    if let Some(c) = &problem.study.constraints {
        names.extend(c.chance.iter().map(|c| c.metric.clone()));
    }
    for extra in ["stick_slip_severity", "impacts_per_s", "mean_wob_n"] {
        names.push(extra.to_string());
    }
    let mut seen = std::collections::BTreeSet::new();
    names.retain(|n| seen.insert(n.clone()));
    names
        .into_iter()
        .map(|n| {
            let values = p
                .samples
                .iter()
                .filter_map(|s| match &s.outcome {
                    crate::study::SampleOutcome::Metrics(m) => m.get(&n).copied(),
                    crate::study::SampleOutcome::Failed(_) => None,
                })
                .collect();
            (n, values)
        })
        .collect()
}

pub fn solve_plots(problem: &Problem, out: &Path, o: &SolveOutcome) -> anyhow::Result<()> {
    let c = problem
        .study
        .constraints
        .as_ref()
        .expect("solve checked constraints");
    let path: Vec<(f64, f64)> = o
        .path
        .iter()
        .map(|p| (p.omega_rad_s * RPM, p.v0_m_s * MPH))
        .collect();
    let optimum = o.best.as_ref().map(|b| (b.omega_rpm, b.v0_m_per_h));
    report::plot_optimizer_path(
        &region(c),
        &evaluated(&o.evaluations),
        &path,
        optimum,
        &format!("{}: {} path", problem.name, o.method.name()),
        &out.join("optimizer_path.svg"),
    )?;
    if let Some(b) = &o.best {
        report::plot_metric_samples(
            &format!(
                "{}: metrics at the optimum ({:.1} rpm, {:.2} m/h), {} samples",
                problem.name,
                b.omega_rpm,
                b.v0_m_per_h,
                b.samples.len()
            ),
            &metric_samples(problem, b),
            &out.join("optimum_metrics.svg"),
        )?;
    }
    Ok(())
}

pub fn map_plots(problem: &Problem, out: &Path, m: &MapOutcome) -> anyhow::Result<()> {
    let omega: Vec<f64> = m.omega.iter().map(|w| w * RPM).collect();
    let v0: Vec<f64> = m.v0.iter().map(|v| v * MPH).collect();
    let optimum = m.best.as_ref().map(|b| (b.omega_rpm, b.v0_m_per_h));
    let scores: Vec<Option<f64>> = m
        .points
        .iter()
        .map(|p| p.as_ref().and_then(|p| p.objective))
        .collect();
    report::plot_heatmap(
        &format!("{}: robust score", problem.name),
        "score",
        &omega,
        &v0,
        &scores,
        optimum,
        &out.join("map_objective.svg"),
    )?;
    let mut metrics: Vec<String> = problem
        .study
        .risk
        .iter()
        .map(|r| r.metric.clone())
        .collect();
    if let Some(c) = &problem.study.constraints {
        metrics.extend(c.chance.iter().map(|c| c.metric.clone()));
    }
    for extra in ["mean_rop_m_per_h", "stick_slip_severity", "impacts_per_s"] {
        metrics.push(extra.to_string());
    }
    let mut seen = std::collections::BTreeSet::new();
    metrics.retain(|n| seen.insert(n.clone()));
    for name in metrics {
        let values: Vec<Option<f64>> = m
            .points
            .iter()
            .map(|p| p.as_ref().and_then(|p| p.mean_metrics.get(&name).copied()))
            .collect();
        report::plot_heatmap(
            &format!("{}: {name} (sample mean)", problem.name),
            &name,
            &omega,
            &v0,
            &values,
            optimum,
            &out.join(format!("map_{name}.svg")),
        )?;
    }
    Ok(())
}

pub fn compare_plots(out: &Path, runs: &[(String, RunOutput)]) -> anyhow::Result<()> {
    let series: Vec<(String, &crate::sim::TimeSeries)> =
        runs.iter().map(|(l, r)| (l.clone(), &r.series)).collect();
    report::plot_bit_speed_overlay(&series, &out.join("compare_bit_speed.svg"))?;
    Ok(())
}
