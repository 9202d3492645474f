//! `evaluations.csv` of `solve`, `map` and `compare`: every evaluation as a table a drilling
//! engineer opens in a spreadsheet, one row per (operating point, Monte Carlo sample).
//!
//! Every column header carries its unit in brackets, in the driller's units the terminal uses
//! (rpm, m/h, kN, kN·m, MPa; `[1]` for a pure number). Columns, in order: `omega [rpm]`,
//! `v0 [m/h]`, `sample` (index from 0), one column per uncertain parameter named by its key
//! (`model.bit.limit_force [kN]`: the sample's value), one column per metric of `summary.json`
//! (its key with the SI suffix taken off, e.g. `mse [MPa]`, `stick_fraction [1]`; see
//! [`metric_column`]), then the point's `score` (the robust objective, the same on every row of a
//! point; empty when a sample failed; `[m/h]` for a score of ROP, `[1]` for efficiency),
//! `feasible` (`true`/`false`), `failure` (why the sample or the point failed, else empty) and
//! `fidelity` (`full`, or `explore` for the cheap evaluations of a multi-fidelity solve).
//!
//! Numbers are written with 10 significant digits, as the shortest text that reads back to the
//! rounded value (`55.3`, not `55.300000000000004` from the conversion of 55300 N to kN): enough
//! to reproduce a point or a value, no round-off noise. A failed sample's metric cells are empty;
//! +∞ (the MSE of a bit that did not advance) is written `inf`. The sample values are the
//! evaluator's own draw (`RobustEvaluator::samples`), each checked against the sample's seed.

use crate::metrics::METRICS;
use crate::problem::Problem;
use crate::problem::study::Quantity;
use crate::stats::SampleSet;
use crate::study::{PointEvaluation, SampleOutcome};
use crate::units::UnitSystem;
use std::fmt::Write as _;
use std::path::Path;

/// The header of a metric's column and the factor from the metric's value (`summary.json`) to
/// the column's unit: the key without its SI suffix, and the unit of its dimension in `units`
/// (`mean_wob_n` → `mean_wob [kN]`, 1e-3, or `mean_wob [klbf]`), or the unit the key names when
/// it is not SI (`mean_rop_m_per_h` → `mean_rop [m/h]`, 1, or `mean_rop [ft/h]`; from the metric
/// catalogue). `mean_rop_m_s` keeps its key (`mean_rop_m_s [m/s]`): the same ROP as `mean_rop`,
/// in SI.
pub fn metric_column(key: &str, units: UnitSystem) -> (String, f64) {
    if key == "mean_rop_m_s" {
        return ("mean_rop_m_s [m/s]".into(), 1.0);
    }
    let (unit, scale) = match crate::metrics::catalogue::find(key) {
        Some(spec) => match spec.own_unit {
            Some(own) => units.convert_metric(own),
            None => units.for_dimension(spec.dimension),
        },
        None => ("1", 1.0),
    };
    let base = ["_m_per_h", "_per_h", "_nm", "_ns", "_pa", "_n", "_m", "_h"]
        .iter()
        .find_map(|suffix| key.strip_suffix(suffix))
        .unwrap_or(key);
    (format!("{base} [{unit}]"), scale)
}

/// The CSV text of `points` (see the module documentation).
pub fn evaluations_csv<'a>(
    problem: &Problem,
    samples: &SampleSet,
    points: impl IntoIterator<Item = &'a PointEvaluation>,
    units: UnitSystem,
) -> String {
    let study = &problem.study;
    let params: Vec<(String, f64)> = study
        .uncertain
        .iter()
        .map(|u| {
            let (unit, scale) = units.for_dimension(u.key.spec().dimension);
            (format!("{} [{unit}]", u.key.name()), scale)
        })
        .collect();
    let metrics: Vec<(String, f64)> = (METRICS.iter())
        .map(|s| metric_column(s.key, units))
        .collect();

    // The second column is the problem's set-point: V0, or a hook load's WOB.
    let kind = problem.model.top.set_point();
    let (set_point_unit, set_point_scale) = units.convert_metric(kind.unit());
    let mut out = format!("omega [rpm],{} [{set_point_unit}],sample", kind.key());
    for (header, _) in params.iter().chain(&metrics) {
        out.push(',');
        out.push_str(header);
    }
    let (score_unit, score_scale) = match study.quantity {
        Quantity::Rop => units.convert_metric("m/h"),
        Quantity::Efficiency => ("1", 1.0),
    };
    let _ = writeln!(out, ",score [{score_unit}],feasible,failure,fidelity");
    for p in points {
        let score = (p.objective)
            .map(|s| number(score_scale * s))
            .unwrap_or_default();
        for s in &p.samples {
            let _ = write!(
                out,
                "{},{},{}",
                number(p.omega_rpm),
                number(
                    set_point_scale
                        * match p.set_point {
                            crate::model::SetPointValue::Feed { v0_m_per_h, .. } => v0_m_per_h,
                            crate::model::SetPointValue::Wob { wob_kn, .. } => wob_kn,
                        }
                ),
                s.sample
            );
            // The values this sample was evaluated with (its seed says it is the same draw).
            let drawn = samples
                .samples
                .get(s.sample)
                .filter(|d| d.seed == s.seed)
                .map(|d| d.values.as_slice());
            for (i, (_, scale)) in params.iter().enumerate() {
                out.push(',');
                if let Some(v) = drawn.and_then(|v| v.get(i)) {
                    out.push_str(&number(scale * v));
                }
            }
            let (values, failure) = match &s.outcome {
                SampleOutcome::Metrics(m) => (Some(m), p.failure.as_deref()),
                SampleOutcome::Failed(why) => (None, Some(why.as_str())),
            };
            for (spec, (_, scale)) in METRICS.iter().zip(&metrics) {
                out.push(',');
                if let Some(v) = values.and_then(|m| m.get(spec.key)) {
                    out.push_str(&number(scale * v));
                }
            }
            let _ = writeln!(
                out,
                ",{score},{},{},{}",
                p.feasible,
                quoted(failure.unwrap_or("")),
                p.fidelity.name()
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
    units: UnitSystem,
) -> std::io::Result<()> {
    let text = evaluations_csv(problem, samples, points, units);
    super::write_atomic(&dir.join("evaluations.csv"), text.as_bytes())
}

/// `x` to 10 significant digits, as the shortest text that reads back to that rounding (`90`,
/// `55.3`, `1.234567891e-7`; `inf`, `-inf`, `NaN` for the non-finite): the round-off of a unit
/// conversion (59.99999999999999 rpm) is not written.
fn number(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let r: f64 = format!("{x:.9e}").parse().unwrap_or(x);
    format!("{r}")
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
density = "7900 kg/m^3"
youngs_modulus = "203 GPa"
poisson_ratio = 0.3
inner_radius = "40 mm"
outer_radius = "60 mm"
damping = "0.03 1/s"
[model.fluid]
density = "1200 kg/m^3"
[model.borehole]
radius = "70 mm"
[model.wall]
stiffness = "1e10 N/m"
cubic_stiffness = "1e16 N/m^3"
damping = 1e-9
friction = 1e-5
[model.bit]
limit_force = "250 kN"
rate = "180 s/m"
friction = "0.04 m"
[mesh]
elements = 12
[operating_point]
omega = "60 rpm"
v0 = "5 m/h"
[simulation]
duration = "1 s"
time_step = "10 ms"
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
            METRICS.iter().map(|s| (s.key.to_string(), 0.5)).collect();
        metrics.insert("mse_pa".into(), f64::INFINITY);
        metrics.insert("mean_rop_m_per_h".into(), 12.25);
        PointEvaluation {
            omega_rad_s: crate::units::from_rpm(90.0),
            omega_rpm: 89.99999999999999,
            set_point: crate::model::SetPointValue::Feed {
                v0_m_s: crate::units::from_m_per_h(12.0),
                v0_m_per_h: 12.000000000000002,
            },
            objective: None,
            quantity: None,
            risk: Vec::new(),
            chance: Vec::new(),
            feasible: false,
            failure: Some("sample 1 failed".into()),
            mean_metrics: BTreeMap::new(),
            samples_used: 2,
            score_half_width: None,
            score_interval: None,
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
            fidelity: crate::study::Fidelity::Explore,
        }
    }

    #[test]
    fn header_and_rows_of_a_point() {
        let problem = Problem::from_toml(TOML, Path::new("p.toml")).unwrap();
        // The evaluator's draw: the problem's law, 2 samples, seed 7.
        let drawn = SampleSet::draw_or_nominal(&[problem.study.uncertain[0].law], 2, 7);
        let p = point(&drawn);
        let text = evaluations_csv(&problem, &drawn, [&p], UnitSystem::Metric);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");

        let header: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(
            header[..4],
            [
                "omega [rpm]",
                "v0 [m/h]",
                "sample",
                "model.bit.limit_force [kN]"
            ]
        );
        // Every metric column says its unit, and no two share a header.
        for h in &header[4..4 + METRICS.len()] {
            assert!(h.ends_with(']') && h.contains(" ["), "{h}");
        }
        let unique: std::collections::BTreeSet<&&str> = header.iter().collect();
        assert_eq!(unique.len(), header.len());
        assert_eq!(
            header[4 + METRICS.len()..],
            ["score [m/h]", "feasible", "failure", "fidelity"]
        );

        // Sample 0: its drawn Γ_BR in kN to 10 digits, every metric, +∞ as `inf`.
        let row: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(row.len(), header.len());
        assert_eq!(row[..3], ["90", "12", "0"]);
        let gamma_kn: f64 = row[3].parse().unwrap();
        assert!((gamma_kn - 1e-3 * drawn.samples[0].values[0]).abs() <= 1e-9 * gamma_kn);
        assert!(
            row[3].len() <= 12,
            "10 significant digits at most: {}",
            row[3]
        );
        let cell = |key: &str| row[header.iter().position(|h| *h == key).unwrap()];
        assert_eq!(cell("mean_rop [m/h]"), "12.25");
        assert_eq!(cell("mse [MPa]"), "inf");
        assert_eq!(cell("stick_fraction [1]"), "0.5");
        // 0.5 N is 0.0005 kN, 0.5 N·m 0.0005 kN·m, 0.5 Pa 5e-7 MPa: the driller's units.
        assert_eq!(cell("mean_wob [kN]"), "0.0005");
        assert_eq!(cell("mean_tob [kN·m]"), "0.0005");
        assert_eq!(cell("max_von_mises [MPa]"), "0.0000005");
        assert_eq!(cell("max_von_mises_at [m]"), "0.5");
        assert_eq!(cell("fatigue_life [h]"), "0.5");
        assert_eq!(
            row[row.len() - 4..],
            ["", "false", "sample 1 failed", "explore"]
        );

        // Sample 1 failed: no metrics, its reason quoted (it holds a comma).
        let (cells, reason) = lines[2].split_once('"').unwrap();
        let row: Vec<&str> = cells.split(',').collect();
        assert_eq!(row[..3], ["90", "12", "1"]);
        let gamma_kn: f64 = row[3].parse().unwrap();
        assert!((gamma_kn - 1e-3 * drawn.samples[1].values[0]).abs() <= 1e-9 * gamma_kn);
        assert!(row[4..4 + METRICS.len()].iter().all(|c| c.is_empty()));
        assert_eq!(row[4 + METRICS.len()..], ["", "false", ""]);
        assert_eq!(reason, "step collapsed, at t = 0.5 s\",explore");
    }

    #[test]
    fn field_units_convert_every_column_with_a_unit() {
        let problem = Problem::from_toml(TOML, Path::new("p.toml")).unwrap();
        let drawn = SampleSet::draw_or_nominal(&[problem.study.uncertain[0].law], 2, 7);
        let p = point(&drawn);
        let text = evaluations_csv(&problem, &drawn, [&p], UnitSystem::Field);
        let lines: Vec<&str> = text.lines().collect();
        let header: Vec<&str> = lines[0].split(',').collect();
        assert_eq!(
            header[..4],
            [
                "omega [rpm]",
                "v0 [ft/h]",
                "sample",
                "model.bit.limit_force [klbf]"
            ]
        );
        assert!(
            !lines[0].contains("[m/h]") && !lines[0].contains("[kN") && !lines[0].contains("MPa")
        );
        let row: Vec<&str> = lines[1].split(',').collect();
        let cell = |key: &str| row[header.iter().position(|h| *h == key).unwrap()];
        // 12 m/h = 39.37007874 ft/h (0.3048 m per ft, exact); 12.25 m/h = 40.19028871 ft/h.
        assert_eq!(row[..3], ["90", "39.37007874", "0"]);
        assert_eq!(cell("mean_rop [ft/h]"), "40.19028871");
        // 0.5 N = 0.0001124044715 klbf; 0.5 Pa = 7.251886887e-5 psi; 0.5 m = 1.640419948 ft.
        assert_eq!(cell("mean_wob [klbf]"), "0.0001124044715");
        assert_eq!(cell("max_von_mises [psi]"), "0.00007251886887");
        assert_eq!(cell("max_von_mises_at [ft]"), "1.640419948");
        // Shares and hours as they are; the SI twin of the ROP stays SI.
        assert_eq!(cell("stick_fraction [1]"), "0.5");
        assert_eq!(cell("fatigue_life [h]"), "0.5");
        assert!(header.contains(&"mean_rop_m_s [m/s]"));
        let gamma_klbf: f64 = row[3].parse().unwrap();
        let expected = drawn.samples[0].values[0] / 4_448.221_615_260_5;
        assert!((gamma_klbf - expected).abs() <= 1e-9 * expected);
    }
}
