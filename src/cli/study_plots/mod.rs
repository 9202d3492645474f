//! The plots of `solve`, `map` and `compare`: study results turned into the plain inputs of
//! [`crate::report`]'s study plots, in the units a driller reads (Ω in rpm and V0 in m/h on the
//! axes, each metric in its display unit, [`MetricDisplay`]).
//!
//! `optimum_metrics.svg` marks on each metric the statistic the objective takes of it (a CVaR,
//! not the mean, when the objective uses a CVaR) and the threshold of each chance constraint;
//! a metric the objective does not use shows its mean. The map's star is its best node, and says
//! so: a map does not solve for the optimum.

use crate::model::OperatingPoint;
use crate::problem::Problem;
use crate::problem::study::{Constraints, Quantity, Study};
use crate::report::{
    self, ConstraintLine, EvaluatedPoint, Mark, MarkKind, MetricDisplay, MetricRow, OverlayRun,
    RPM_PER_RAD_S as RPM, Region, SetPointAxis, StarredPoint, fmt_sig, short,
};
use crate::sim::TimeSeries;
use crate::solve::{MapOutcome, SolveOutcome};
use crate::stats::Statistic;
use crate::study::{PointEvaluation, SampleOutcome};
use crate::units::UnitSystem;
use std::collections::BTreeSet;
use std::path::Path;

/// Metrics shown besides those of the objective and the constraints, in `optimum_metrics.svg`.
const EXTRA_SAMPLE_METRICS: [&str; 3] = ["stick_slip_severity", "impacts_per_s", "mean_wob_n"];
/// Metrics mapped besides those of the objective and the constraints.
const EXTRA_MAP_METRICS: [&str; 3] = ["mean_rop_m_per_h", "stick_slip_severity", "impacts_per_s"];
/// Legend and caption of the map's star.
const BEST_NODE: &str = "best map node (highest score)";

/// The bounds box and linear constraints in plot units: a_Ω Ω + a_V V0 ≤ b with Ω = rpm/RPM and
/// V0 = m/h / MPH gives (a_Ω/RPM) rpm + (a_V/MPH) m/h ≤ b (the same in ft/h or klbf).
fn region(c: &Constraints, units: UnitSystem) -> Region {
    let axis = SetPointAxis {
        kind: c.kind,
        units,
    };
    Region {
        omega_rpm: [c.omega[0] * RPM, c.omega[1] * RPM],
        set_point: c.set_point.map(|s| axis.of_si(s)),
        kind: axis,
        lines: c
            .linear
            .iter()
            .map(|l| ConstraintLine {
                label: l.label.replace('_', " "),
                omega_coef: l.omega / RPM,
                // a_s s = (a_s / (unit/SI)) s_unit.
                set_point_coef: l.set_point / axis.of_si(1.0),
                upper: l.upper,
            })
            .collect(),
    }
}

/// The points in plot units; the score in the unit of [`score_label`] (`score`: the factor from
/// the score's metric unit).
fn evaluated(points: &[PointEvaluation], units: UnitSystem, score: f64) -> Vec<EvaluatedPoint> {
    points
        .iter()
        .map(|p| EvaluatedPoint {
            omega_rpm: p.omega_rpm,
            set_point: units
                .from_metric(p.op().kind().unit(), p.op().shown_set_point())
                .1,
            score: p.objective.map(|s| score * s),
            feasible: p.feasible,
        })
        .collect()
}

/// The unit of the score: that of the quantity (risk weights convert into it).
fn score_label(q: Quantity, units: UnitSystem) -> String {
    let d = MetricDisplay::of_in(q.metric(), units);
    if d.unit.is_empty() {
        "robust score".to_owned()
    } else {
        format!("robust score [{}]", d.unit)
    }
}

/// The factor from the score's metric unit (m/h for ROP) to its unit in `units`.
fn score_factor(q: Quantity, units: UnitSystem) -> f64 {
    units.convert_metric(MetricDisplay::of(q.metric()).unit).1
}

/// `level` ∈ [0, 1] as a percentage, "90 %".
fn percent(level: f64) -> String {
    format!("{} %", short(100.0 * level))
}

/// A statistic as a reader names it: "mean", "CVaR 90 %", "P(> 1.5)".
fn statistic_name(s: &Statistic) -> String {
    match *s {
        Statistic::Mean => "mean".to_owned(),
        Statistic::StdDev => "std dev".to_owned(),
        Statistic::Cvar { level } => format!("CVaR {}", percent(level)),
        Statistic::LowerCvar { level } => format!("lower CVaR {}", percent(level)),
        Statistic::ProbExceed { threshold } => format!("P(> {})", fmt_sig(threshold)),
        Statistic::Quantile { level } => format!("{} quantile", percent(level)),
        Statistic::Max => "max".to_owned(),
        Statistic::Min => "min".to_owned(),
    }
}

/// The mark of the objective's statistic `s` of a metric, whose value is `value` (in the
/// metric's SI unit; a probability for `ProbExceed`) and whose samples have mean `mean`
/// (display unit). A location (mean, CVaR, quantile, max, min) is drawn where it is; a spread
/// marks the mean and states itself; an exceedance probability marks its threshold.
fn objective_mark(s: &Statistic, value: f64, d: &MetricDisplay, mean: f64) -> Mark {
    let name = format!("{} (objective)", statistic_name(s));
    match *s {
        Statistic::StdDev => Mark {
            name: "mean".to_owned(),
            value: mean,
            kind: MarkKind::Statistic,
            note: format!("objective: std dev = {}", fmt_sig(d.value(value))),
        },
        Statistic::ProbExceed { threshold } => Mark {
            name: format!("threshold of {name}"),
            value: d.value(threshold),
            kind: MarkKind::Limit,
            note: format!("P(above) = {}", percent(value)),
        },
        _ => Mark {
            name,
            value: d.value(value),
            kind: MarkKind::Statistic,
            note: String::new(),
        },
    }
}

/// One row per metric that matters at `p`: the objective's quantity and risk metrics, the chance
/// metrics, then a few more; samples and marks in the metric's display unit.
fn metric_rows(study: &Study, p: &PointEvaluation, units: UnitSystem) -> Vec<MetricRow> {
    let quantity = study.quantity.metric();
    let chance = study
        .constraints
        .as_ref()
        .map_or(&[][..], |c| &c.chance[..]);
    let mut keys: Vec<&str> = vec![quantity];
    keys.extend(study.risk.iter().map(|r| r.metric.as_str()));
    keys.extend(chance.iter().map(|c| c.metric.as_str()));
    keys.extend(EXTRA_SAMPLE_METRICS);
    let mut seen = BTreeSet::new();
    keys.retain(|k| seen.insert(*k));
    keys.into_iter()
        .map(|key| {
            let d = MetricDisplay::of_in(key, units);
            let samples: Vec<f64> = p
                .samples
                .iter()
                .filter_map(|s| match &s.outcome {
                    SampleOutcome::Metrics(m) => m.get(key).map(|&v| d.value(v)),
                    SampleOutcome::Failed(_) => None,
                })
                .collect();
            let plain = MetricRow::with_mean(d.label(), samples);
            let mean = plain.marks.first().map_or(f64::NAN, |m| m.value);
            let mut marks = Vec::new();
            if key == quantity
                && let Some(q) = p.quantity
            {
                marks.push(objective_mark(&study.statistic, q, &d, mean));
            }
            for r in p.risk.iter().filter(|r| r.metric == key) {
                marks.push(objective_mark(&r.statistic, r.value, &d, mean));
            }
            for c in p.chance.iter().filter(|c| c.metric == key) {
                marks.push(Mark {
                    name: "chance limit".to_owned(),
                    value: d.value(c.threshold),
                    kind: MarkKind::Limit,
                    note: format!(
                        "P(above) = {}, at most {} allowed{}",
                        percent(c.probability),
                        percent(c.max_probability),
                        if c.satisfied { "" } else { ": violated" }
                    ),
                });
            }
            if marks.is_empty() {
                plain
            } else {
                MetricRow { marks, ..plain }
            }
        })
        .collect()
}

pub fn solve_plots(
    problem: &Problem,
    out: &Path,
    o: &SolveOutcome,
    units: UnitSystem,
) -> anyhow::Result<()> {
    let c = problem
        .study
        .constraints
        .as_ref()
        .expect("solve checked constraints");
    let region = region(c, units);
    let axis = region.kind;
    let path: Vec<(f64, f64)> = o
        .path
        .iter()
        .map(|p| (p.omega_rad_s * RPM, axis.of_si(p.op().set_point(c.kind))))
        .collect();
    let optimum = o
        .best
        .as_ref()
        .map(|b| (b.omega_rpm, axis.of_si(b.op().set_point(c.kind))));
    let score = score_factor(problem.study.quantity, units);
    // What holds the optimum, in the title as on the terminal ([`crate::solve::activity`]).
    let held = o.best.as_ref().map_or(String::new(), |b| {
        let names: Vec<String> = crate::solve::activity(c, b, &o.evaluations)
            .into_iter()
            .filter(|a| a.at_limit)
            .map(|a| a.name)
            .collect();
        if names.is_empty() {
            "; optimum held by no constraint".to_string()
        } else {
            format!("; optimum held by {}", names.join(", "))
        }
    });
    report::plot_optimizer_path(
        &region,
        &evaluated(&o.evaluations, units, score),
        &path,
        optimum,
        &match o.confirmation {
            // The path is the exploration's; the optimum is the best confirmed point.
            Some(_) => format!(
                "{}: {} path (explore fidelity), optimum at full fidelity{held}",
                problem.name,
                o.method.name()
            ),
            None => format!("{}: {} path{held}", problem.name, o.method.name()),
        },
        &out.join("optimizer_path.svg"),
    )?;
    if let Some(b) = &o.best {
        report::plot_metric_samples(
            &format!(
                "{}: metrics at the optimum ({}), {}",
                problem.name,
                report::operating_point_text(&b.op(), units),
                crate::units::count(b.samples.len(), "sample")
            ),
            &metric_rows(&problem.study, b, units),
            &out.join("optimum_metrics.svg"),
        )?;
    }
    Ok(())
}

/// The metrics a map shows: those of the objective and the constraints, then a few more.
fn map_metrics(study: &Study) -> Vec<String> {
    let mut metrics: Vec<String> = study.risk.iter().map(|r| r.metric.clone()).collect();
    if let Some(c) = &study.constraints {
        metrics.extend(c.chance.iter().map(|c| c.metric.clone()));
    }
    metrics.extend(EXTRA_MAP_METRICS.map(String::from));
    let mut seen = BTreeSet::new();
    metrics.retain(|n| seen.insert(n.clone()));
    metrics
}

pub fn map_plots(
    problem: &Problem,
    out: &Path,
    m: &MapOutcome,
    units: UnitSystem,
) -> anyhow::Result<()> {
    let axis = SetPointAxis {
        kind: m.kind,
        units,
    };
    let omega: Vec<f64> = m.omega.iter().map(|w| w * RPM).collect();
    let set_point: Vec<f64> = m.set_point.iter().map(|&v| axis.of_si(v)).collect();
    let best = m.best.as_ref().map(|b| StarredPoint {
        omega_rpm: b.omega_rpm,
        set_point: axis.of_si(b.op().set_point(m.kind)),
        label: BEST_NODE.to_owned(),
    });
    let score = score_factor(problem.study.quantity, units);
    // An infeasible node has a score but is not a candidate: grey, as a failed one (the table
    // and map.json say why).
    let scores: Vec<Option<f64>> = m
        .points
        .iter()
        .map(|p| p.as_ref().filter(|p| p.feasible).and_then(|p| p.objective))
        .map(|s| s.map(|s| score * s))
        .collect();
    report::plot_heatmap(
        &format!("{}: robust score (higher is better)", problem.name),
        &score_label(problem.study.quantity, units),
        &omega,
        &set_point,
        &scores,
        best.as_ref(),
        axis,
        &out.join("map_objective.svg"),
    )?;
    for name in map_metrics(&problem.study) {
        let d = MetricDisplay::of_in(&name, units);
        let values: Vec<Option<f64>> = m
            .points
            .iter()
            .map(|p| {
                p.as_ref()
                    .and_then(|p| p.mean_metrics.get(&name))
                    .map(|&v| d.value(v))
            })
            .collect();
        report::plot_heatmap(
            &format!("{}: {} (sample mean)", problem.name, d.name),
            &d.label(),
            &omega,
            &set_point,
            &values,
            best.as_ref(),
            axis,
            &out.join(format!("map_{name}.svg")),
        )?;
    }
    Ok(())
}

/// `runs[k]` was simulated at `ops[k]`.
pub fn compare_plots(
    out: &Path,
    runs: &[(String, TimeSeries)],
    ops: &[OperatingPoint],
) -> anyhow::Result<()> {
    let overlay: Vec<OverlayRun<'_>> = runs
        .iter()
        .zip(ops)
        .map(|((label, r), op)| OverlayRun {
            label,
            series: r,
            omega_rad_s: op.omega,
        })
        .collect();
    report::plot_bit_speed_overlay(&overlay, &out.join("compare_bit_speed.svg"))?;
    Ok(())
}

#[cfg(test)]
pub(super) mod tests;
