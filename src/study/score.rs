//! The score of an operating point from its Monte Carlo samples: the statistic of the quantity
//! (ROP or efficiency) minus the weighted risk terms, the chance constraints estimated from the
//! samples, and the bounds and linear constraints (conventions in [`crate::problem::study`]).

use crate::model::OperatingPoint;
use crate::problem::study::Study;
use crate::stats::{self, Statistic, sample_seed, splitmix64_mix};
use crate::units::to_rpm;
use serde::Serialize;
use std::collections::BTreeMap;

/// The outcome of one sample at one point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SampleResult {
    pub sample: usize,
    pub seed: u64,
    /// Metric name → value (the keys of `summary.json`), or why the simulation failed.
    #[serde(flatten)]
    pub outcome: SampleOutcome,
    /// Taken from the evaluation cache rather than simulated now.
    pub cached: bool,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleOutcome {
    Metrics(BTreeMap<String, f64>),
    Failed(String),
}

/// One risk term at a point: the statistic of the metric and its weighted share of the score.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RiskValue {
    pub metric: String,
    pub statistic: Statistic,
    pub value: f64,
    pub weight: f64,
    pub penalty: f64,
}

/// One chance constraint at a point: estimated P(metric > threshold) against its limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChanceValue {
    pub metric: String,
    pub threshold: f64,
    pub probability: f64,
    pub max_probability: f64,
    pub satisfied: bool,
}

/// The robust evaluation of one operating point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointEvaluation {
    pub omega_rad_s: f64,
    pub omega_rpm: f64,
    /// The set-point: V0 (`v0_m_s`, `v0_m_per_h`) or a hook load's WOB (`wob_n`, `wob_kn`).
    #[serde(flatten)]
    pub set_point: crate::model::SetPointValue,
    /// The score (maximised); None when a sample failed.
    pub objective: Option<f64>,
    /// Statistic of the quantity (ROP in m/h or efficiency) before the risk penalties.
    pub quantity: Option<f64>,
    pub risk: Vec<RiskValue>,
    pub chance: Vec<ChanceValue>,
    /// No sample failed and every chance constraint holds.
    pub feasible: bool,
    /// Why the point is infeasible or failed, if it is.
    pub failure: Option<String>,
    /// Mean of every metric over the samples (when none failed).
    pub mean_metrics: BTreeMap<String, f64>,
    /// Monte Carlo samples the point was evaluated with (samples 0..n: with sequential sampling,
    /// where the stopping rule stopped).
    pub samples_used: usize,
    /// Half-width of the score's bootstrap confidence interval, in the score's unit, at the
    /// level of [`Study::score_interval`]; None without a score or with one sample.
    pub score_half_width: Option<f64>,
    /// That interval, [low, high] (the percentile interval need not be centred on the score).
    pub score_interval: Option<[f64; 2]>,
    pub samples: Vec<SampleResult>,
    /// The fidelity that produced the evaluation (`explore` only in a multi-fidelity solve).
    pub fidelity: super::Fidelity,
}

impl PointEvaluation {
    pub fn op(&self) -> OperatingPoint {
        self.set_point.at(self.omega_rad_s)
    }
}

/// Metric name → value (the keys of `summary.json`), infinite values kept: an MSE of +∞ (the
/// bit did not advance) is a risk of +∞, not a NaN. Undefined (NaN) metrics are left out.
pub fn metric_map(m: &crate::metrics::Metrics) -> BTreeMap<String, f64> {
    // NaN marks a metric the inputs leave undefined (the safety factor without a yield
    // strength): it is left out rather than carried as a value that equals nothing.
    m.named_values()
        .into_iter()
        .filter(|(_, v)| !v.is_nan())
        .map(|(k, v)| (k.to_string(), v))
        .collect()
}

/// Relative slack allowed on the bounds and linear constraints: an optimizer's point on an
/// active constraint may miss it by round-off.
const CONSTRAINT_SLACK: f64 = 1e-9;

/// `value` and `limit` with the fewest decimals (at least `min`, at most 9) that tell them apart:
/// a point just past a limit (a printed optimum rounded to 111.1 rpm on a depth-of-cut line)
/// read "3.000 mm exceeds 3.000 mm".
fn apart(value: f64, limit: f64, min: usize) -> (String, String) {
    let mut d = min;
    while d < 9 && format!("{value:.d$}") == format!("{limit:.d$}") {
        d += 1;
    }
    (format!("{value:.d$}"), format!("{limit:.d$}"))
}

/// The bounds and linear constraints that `op` violates, each said in driller units.
pub fn deterministic_violations(
    k: &crate::problem::study::Constraints,
    op: OperatingPoint,
) -> Vec<String> {
    let mut out = Vec::new();
    let outside = |x: f64, [lo, hi]: [f64; 2]| {
        x < lo - CONSTRAINT_SLACK * lo.abs() || x > hi + CONSTRAINT_SLACK * hi.abs()
    };
    if outside(op.omega, k.omega) {
        let nearest = if op.omega < k.omega[0] {
            k.omega[0]
        } else {
            k.omega[1]
        };
        let (v, _) = apart(to_rpm(op.omega), to_rpm(nearest), 1);
        out.push(format!(
            "Ω = {v} rpm is outside the bounds [{:.1}, {:.1}] rpm",
            to_rpm(k.omega[0]),
            to_rpm(k.omega[1])
        ));
    }
    let s = op.set_point(k.kind);
    if outside(s, k.set_point) {
        let unit = k.kind.unit();
        let nearest = if s < k.set_point[0] {
            k.set_point[0]
        } else {
            k.set_point[1]
        };
        let (v, _) = apart(k.kind.to_unit(s), k.kind.to_unit(nearest), 2);
        out.push(format!(
            "{} = {v} {unit} is outside the bounds [{:.2}, {:.2}] {unit}",
            k.kind.symbol(),
            k.kind.to_unit(k.set_point[0]),
            k.kind.to_unit(k.set_point[1])
        ));
    }
    for l in &k.linear {
        let value = l.omega * op.omega + l.set_point * s;
        let scale = (l.omega * op.omega).abs() + (l.set_point * s).abs() + l.upper.abs();
        if value > l.upper + CONSTRAINT_SLACK * scale {
            out.push(if l.label == "max_depth_of_cut" {
                // 2π V0 − d Ω ≤ 0: say it as the depth of cut per revolution.
                let (depth, limit) = apart(
                    1e3 * 2.0 * std::f64::consts::PI * op.v0 / op.omega,
                    -1e3 * l.omega,
                    3,
                );
                format!("the depth of cut 2π V0/Ω = {depth} mm exceeds max_depth_of_cut = {limit} mm")
            } else {
                format!(
                    "the linear constraint {:.6e} Ω + {:.6e} {} ≤ {:.6e} (SI) is violated: {value:.6e}",
                    l.omega,
                    l.set_point,
                    k.kind.symbol(),
                    l.upper
                )
            });
        }
    }
    out
}

/// Mixed into the study's seed for the bootstrap's generator, so that it draws apart from the
/// samples' own streams (the bytes of "bootstra").
const BOOTSTRAP_TAG: u64 = 0x626f_6f74_7374_7261;

/// The seed of the bootstrap of a score over `n` samples under the study's `master_seed`: every
/// point with `n` samples resamples the same indices (common random numbers for the interval
/// too), and a run is reproducible from the seed whatever the order of evaluation.
pub fn bootstrap_seed(master_seed: u64, n: usize) -> u64 {
    sample_seed(splitmix64_mix(master_seed ^ BOOTSTRAP_TAG), n)
}

/// The confidence interval of the score over samples whose quantity column is `quantity` and
/// risk columns `risk` (one per [`Study::risk`] term, in order): the bootstrap percentile
/// interval of statistic(quantity) − Σ weight·statistic(metric), the whole score resampled at
/// once so that the terms' correlation over the samples is kept. None for fewer than 2 samples.
pub fn score_interval(
    study: &Study,
    quantity: &[f64],
    risk: &[Vec<f64>],
) -> Option<stats::Interval> {
    let n = quantity.len();
    if n < 2 {
        return None;
    }
    let settings = study.score_interval();
    let pick =
        |column: &[f64], idx: &[usize]| -> Vec<f64> { idx.iter().map(|&i| column[i]).collect() };
    stats::percentile_interval(
        n,
        settings.resamples,
        settings.confidence,
        bootstrap_seed(study.seed, n),
        |idx| {
            let mut score = study.statistic.apply(&pick(quantity, idx));
            for (r, column) in study.risk.iter().zip(risk) {
                score -= r.weight * r.statistic.apply(&pick(column, idx));
            }
            score
        },
    )
}

/// The score of a point from its samples (see [`crate::problem::study`] for the conventions).
/// A point is feasible when it meets the bounds, the linear constraints and the chance
/// constraints; an infeasible point keeps its score and says why in `failure`.
pub fn score(study: &Study, op: OperatingPoint, samples: Vec<SampleResult>) -> PointEvaluation {
    let mut eval = PointEvaluation {
        omega_rad_s: op.omega,
        omega_rpm: to_rpm(op.omega),
        set_point: crate::model::SetPointValue::of(&op),
        objective: None,
        quantity: None,
        risk: Vec::new(),
        chance: Vec::new(),
        feasible: false,
        failure: None,
        mean_metrics: BTreeMap::new(),
        samples_used: samples.len(),
        score_half_width: None,
        score_interval: None,
        samples: Vec::new(),
        fidelity: super::Fidelity::Full,
    };
    let maps: Vec<&BTreeMap<String, f64>> = samples
        .iter()
        .filter_map(|s| match &s.outcome {
            SampleOutcome::Metrics(m) => Some(m),
            SampleOutcome::Failed(_) => None,
        })
        .collect();
    if maps.len() < samples.len() {
        let (i, why) = samples
            .iter()
            .find_map(|s| match &s.outcome {
                SampleOutcome::Failed(w) => Some((s.sample, w.clone())),
                _ => None,
            })
            .expect("a failed sample");
        eval.failure = Some(format!(
            "{} of {} simulations failed (sample {i}: {why})",
            samples.len() - maps.len(),
            samples.len()
        ));
        eval.samples = samples;
        return eval;
    }
    let column = |name: &str| -> Vec<f64> {
        maps.iter()
            .map(|m| m.get(name).copied().unwrap_or(f64::NAN))
            .collect()
    };
    if let Some(first) = maps.first() {
        for k in first.keys() {
            eval.mean_metrics.insert(k.clone(), stats::mean(&column(k)));
        }
    }
    let quantity_column = column(study.quantity.metric());
    let risk_columns: Vec<Vec<f64>> = study.risk.iter().map(|r| column(&r.metric)).collect();
    let quantity = study.statistic.apply(&quantity_column);
    let mut score = quantity;
    for (r, values) in study.risk.iter().zip(&risk_columns) {
        let value = r.statistic.apply(values);
        let penalty = r.weight * value;
        score -= penalty;
        eval.risk.push(RiskValue {
            metric: r.metric.clone(),
            statistic: r.statistic,
            value,
            weight: r.weight,
            penalty,
        });
    }
    let mut feasible = true;
    if let Some(k) = &study.constraints {
        for c in &k.chance {
            let probability = stats::prob_exceed(&column(&c.metric), c.threshold);
            let satisfied = probability <= c.max_probability;
            feasible &= satisfied;
            eval.chance.push(ChanceValue {
                metric: c.metric.clone(),
                threshold: c.threshold,
                probability,
                max_probability: c.max_probability,
                satisfied,
            });
        }
    }
    // Each violated chance constraint by name: "P(fatigue_damage_per_h > 0.05) = 1 > 0.1".
    let mut reasons: Vec<String> = eval
        .chance
        .iter()
        .filter(|c| !c.satisfied)
        .map(|c| {
            format!(
                "chance constraint P({} > {}) = {} > {}",
                c.metric, c.threshold, c.probability, c.max_probability
            )
        })
        .collect();
    if let Some(k) = &study.constraints {
        let violated = deterministic_violations(k, op);
        feasible &= violated.is_empty();
        reasons.extend(violated);
    }
    if !score.is_finite() {
        // A score of −∞ (a run that did not drill: ROP 0, MSE +∞) is no reason to hide why the
        // point is infeasible too (off bottom, V0 = 0, is below every v0 bound).
        let why = if score == f64::NEG_INFINITY {
            "no score: the point does not drill (a zero rate of penetration, or an infinite \
             mechanical specific energy)"
        } else {
            "no score: a metric it is made of is undefined"
        };
        reasons.insert(0, why.to_string());
        eval.failure = Some(reasons.join("; "));
        eval.samples = samples;
        return eval;
    }
    if !reasons.is_empty() {
        eval.failure = Some(reasons.join("; "));
    }
    if let Some(i) = score_interval(study, &quantity_column, &risk_columns) {
        eval.score_half_width = Some(i.half_width());
        eval.score_interval = Some([i.low, i.high]);
    }
    eval.quantity = Some(quantity);
    eval.objective = Some(score);
    eval.feasible = feasible;
    eval.samples = samples;
    eval
}

#[cfg(test)]
mod constraint_tests {
    use super::*;
    use crate::problem::study::{Constraints, LinearConstraint};
    use std::f64::consts::PI;

    fn tiny_constraints() -> Constraints {
        let rpm = PI / 30.0;
        Constraints {
            omega: [30.0 * rpm, 150.0 * rpm],
            kind: crate::model::SetPoint::Feed,
            set_point: [2.0 / 3600.0, 20.0 / 3600.0],
            linear: vec![LinearConstraint {
                omega: -3e-3,
                set_point: 2.0 * PI,
                upper: 0.0,
                label: "max_depth_of_cut",
            }],
            chance: Vec::new(),
        }
    }

    fn at(rpm: f64, m_per_h: f64) -> OperatingPoint {
        OperatingPoint {
            omega: rpm * PI / 30.0,
            v0: m_per_h / 3600.0,
            wob: 0.0,
        }
    }

    #[test]
    fn bounds_and_linear_constraints_decide_feasibility() {
        let k = tiny_constraints();
        let v = deterministic_violations(&k, at(200.0, 30.0));
        assert_eq!(v.len(), 2, "{v:?}");
        assert!(
            v[0].contains("200.0 rpm") && v[1].contains("30.00 m/h"),
            "{v:?}"
        );
        // 30 rpm at 20 m/h cuts 2π V0/Ω = 11.1 mm per revolution.
        let v = deterministic_violations(&k, at(30.0, 20.0));
        assert_eq!(v.len(), 1);
        assert!(v[0].contains("11.111 mm"), "{v:?}");
        // The vertex Ω = 2π V0 / 3 mm = 111.1 rpm is feasible; 0.1 % below it is not.
        let vertex = 2.0 * PI * (20.0 / 3600.0) / 3e-3 * 30.0 / PI;
        assert!(deterministic_violations(&k, at(vertex, 20.0)).is_empty());
        assert_eq!(
            deterministic_violations(&k, at(0.999 * vertex, 20.0)).len(),
            1
        );
        // The vertex printed to one decimal, 111.1 rpm, is 0.01 % past the line: said with the
        // digits that show it, not "3.000 mm exceeds 3.000 mm".
        let v = deterministic_violations(&k, at(111.1, 20.0));
        assert!(
            v[0].contains("3.0003 mm exceeds max_depth_of_cut = 3.0000 mm"),
            "{v:?}"
        );
        assert!(deterministic_violations(&k, at(60.0, 5.0)).is_empty());
    }
}
