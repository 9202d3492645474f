//! `evaluations.csv` of `solve`, `map` and `compare`: every evaluation as a table a drilling
//! engineer opens in a spreadsheet, one row per (operating point, Monte Carlo sample).
//!
//! Columns, in order: `omega_rpm`, `v0_m_per_h`, `sample` (index from 0), one column per
//! uncertain parameter named by its key (`model.bit.limit_force`; the sample's value, SI), one
//! column per metric of `summary.json` (its key, which carries the unit, e.g. `mse_pa`), then the
//! point's `score` (the robust objective, the same on every row of a point; empty when a sample
//! failed), `feasible` (`true`/`false`) and `failure` (why the sample or the point failed, else
//! empty). A failed sample's metric cells are empty; +∞ (the MSE of a bit that did not advance)
//! is written `inf`. The sample values are the evaluator's own draw (`RobustEvaluator::samples`),
//! each checked against the sample's seed.

use crate::problem::Problem;
use crate::problem::study::METRICS;
use crate::stats::SampleSet;
use crate::study::{PointEvaluation, SampleOutcome};
use std::fmt::Write as _;
use std::path::Path;

/// The CSV text of `points` (see the module documentation).
pub fn evaluations_csv<'a>(
    problem: &Problem,
    samples: &SampleSet,
    points: impl IntoIterator<Item = &'a PointEvaluation>,
) -> String {
    let study = &problem.study;
    let keys: Vec<&str> = study.uncertain.iter().map(|u| u.key.name()).collect();

    let mut out = String::from("omega_rpm,v0_m_per_h,sample");
    for k in keys.iter().chain(METRICS.iter()) {
        out.push(',');
        out.push_str(k);
    }
    out.push_str(",score,feasible,failure\n");
    for p in points {
        let score = p.objective.map(number).unwrap_or_default();
        for s in &p.samples {
            let _ = write!(
                out,
                "{},{},{}",
                driller(p.omega_rpm),
                driller(p.v0_m_per_h),
                s.sample
            );
            // The values this sample was evaluated with (its seed says it is the same draw).
            let drawn = samples
                .samples
                .get(s.sample)
                .filter(|d| d.seed == s.seed)
                .map(|d| d.values.as_slice());
            for i in 0..keys.len() {
                out.push(',');
                if let Some(v) = drawn.and_then(|v| v.get(i)) {
                    out.push_str(&number(*v));
                }
            }
            let (metrics, failure) = match &s.outcome {
                SampleOutcome::Metrics(m) => (Some(m), p.failure.as_deref()),
                SampleOutcome::Failed(why) => (None, Some(why.as_str())),
            };
            for key in METRICS {
                out.push(',');
                if let Some(v) = metrics.and_then(|m| m.get(key)) {
                    out.push_str(&number(*v));
                }
            }
            let _ = writeln!(
                out,
                ",{score},{},{}",
                p.feasible,
                quoted(failure.unwrap_or(""))
            );
        }
    }
    out
}

/// Write [`evaluations_csv`] to `dir/evaluations.csv` atomically; the error names the path.
pub fn write_evaluations_csv<'a>(
    dir: &Path,
    problem: &Problem,
    samples: &SampleSet,
    points: impl IntoIterator<Item = &'a PointEvaluation>,
) -> std::io::Result<()> {
    let text = evaluations_csv(problem, samples, points);
    super::write_atomic(&dir.join("evaluations.csv"), text.as_bytes())
}

/// The shortest text that reads back to `x` (`inf`, `-inf`, `NaN` for the non-finite).
fn number(x: f64) -> String {
    format!("{x}")
}

/// Ω in rpm or V0 in m/h to 10 significant digits: the round-off of the conversion from SI
/// (59.99999999999999 rpm) is not what the user asked for.
fn driller(x: f64) -> String {
    let r: f64 = format!("{x:.9e}").parse().unwrap_or(x);
    number(r)
}

/// A text cell: quoted when it holds a comma, a quote or a line break (RFC 4180).
fn quoted(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::SampleResult;
    use std::collections::BTreeMap;

    const TOML: &str = r#"
[model]
length = "8 m"
[model.pipe]
density = 7900.0
youngs_modulus = 203e9
poisson_ratio = 0.3
inner_radius = 0.04
outer_radius = 0.06
damping = 0.03
[model.fluid]
density = 1200.0
[model.borehole]
radius = 0.07
[model.wall]
stiffness = 1e10
cubic_stiffness = 1e16
damping = 1e-9
friction = 1e-5
[model.bit]
limit_force = 250e3
rate = 180.0
friction = 0.04
[mesh]
elements = 12
[operating_point]
omega = "60 rpm"
v0 = "5 m/h"
[simulation]
duration = 1.0
time_step = 0.01
[uncertain]
samples = 2
seed = 7
[[uncertain.parameter]]
key = "model.bit.limit_force"
law = "gamma"
mean = "250 kN"
cov = 0.1
"#;

    /// A point at 90 rpm, 12 m/h: sample 0 with metrics (MSE +∞), sample 1 failed.
    fn point(draws: &SampleSet) -> PointEvaluation {
        let mut metrics: BTreeMap<String, f64> =
            METRICS.iter().map(|k| (k.to_string(), 0.5)).collect();
        metrics.insert("mse_pa".into(), f64::INFINITY);
        metrics.insert("mean_rop_m_per_h".into(), 12.25);
        PointEvaluation {
            omega_rad_s: crate::units::from_rpm(90.0),
            v0_m_s: crate::units::from_m_per_h(12.0),
            omega_rpm: 89.99999999999999,
            v0_m_per_h: 12.000000000000002,
            objective: None,
            quantity: None,
            risk: Vec::new(),
            chance: Vec::new(),
            feasible: false,
            failure: Some("sample 1 failed".into()),
            mean_metrics: BTreeMap::new(),
            samples: vec![
                SampleResult {
                    sample: 0,
                    seed: draws.samples[0].seed,
                    outcome: SampleOutcome::Metrics(metrics),
                    cached: false,
                },
                SampleResult {
                    sample: 1,
                    seed: draws.samples[1].seed,
                    outcome: SampleOutcome::Failed("step collapsed, at t = 0.5 s".into()),
                    cached: true,
                },
            ],
        }
    }

    #[test]
    fn header_and_rows_of_a_point() {
        let problem = Problem::from_toml(TOML, Path::new("p.toml")).unwrap();
        // The evaluator's draw: the problem's law, 2 samples, seed 7.
        let drawn = SampleSet::draw_or_nominal(&[problem.study.uncertain[0].law], 2, 7);
        let p = point(&drawn);
        let text = evaluations_csv(&problem, &drawn, [&p]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");

        let header: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(
            header[..4],
            ["omega_rpm", "v0_m_per_h", "sample", "model.bit.limit_force"]
        );
        assert_eq!(header[4..4 + METRICS.len()], METRICS);
        assert_eq!(
            header[4 + METRICS.len()..],
            ["score", "feasible", "failure"]
        );

        // Sample 0: its drawn Γ_BR, every metric, +∞ as `inf`.
        let row: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(row.len(), header.len());
        assert_eq!(row[..3], ["90", "12", "0"]);
        assert_eq!(row[3].parse::<f64>().unwrap(), drawn.samples[0].values[0]);
        let cell = |key: &str| row[header.iter().position(|h| *h == key).unwrap()];
        assert_eq!(cell("mean_rop_m_per_h"), "12.25");
        assert_eq!(cell("mse_pa"), "inf");
        assert_eq!(cell("stick_fraction"), "0.5");
        assert_eq!(row[row.len() - 3..], ["", "false", "sample 1 failed"]);

        // Sample 1 failed: no metrics, its reason quoted (it holds a comma).
        let (cells, reason) = lines[2].split_once('"').unwrap();
        let row: Vec<&str> = cells.split(',').collect();
        assert_eq!(row[..3], ["90", "12", "1"]);
        assert_eq!(row[3].parse::<f64>().unwrap(), drawn.samples[1].values[0]);
        assert!(row[4..4 + METRICS.len()].iter().all(|c| c.is_empty()));
        assert_eq!(row[4 + METRICS.len()..], ["", "false", ""]);
        assert_eq!(reason, "step collapsed, at t = 0.5 s\"");
    }
}
