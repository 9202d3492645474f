//! Fixtures (a robust study, evaluated points, a 4 × 4 map) and tests of the study plots.

use super::*;
use crate::problem::study::ChanceConstraint;
use crate::report::M_PER_H_PER_M_PER_S as MPH;
use crate::study::SampleResult;
use crate::study::{ChanceValue, RiskValue};
use std::collections::BTreeMap;

/// The seed robust study (mean ROP less a CVaR 75 % of SSI and the mean MSE) with a chance
/// constraint P(impacts > 50 /s) ≤ 10 %.
pub(in crate::cli) fn problem() -> Problem {
    let mut p = Problem::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/seed_robust.toml"
    ))
    .unwrap();
    p.study
        .constraints
        .as_mut()
        .unwrap()
        .chance
        .push(ChanceConstraint {
            metric: "impacts_per_s".into(),
            threshold: 50.0,
            max_probability: 0.1,
        });
    p
}

/// A point evaluated over four samples, consistent with `study`: SSI 0.5, 0.6, 0.7, 2.0
/// (mean 0.95, CVaR 75 % 2.0), impacts 10, 20, 80, 30 /s (P(> 50) = 25 %), MSE 700 MPa,
/// WOB 55 kN, no wall force at all, ROP `v0_m_per_h`.
pub(in crate::cli) fn point(study: &Study, omega_rpm: f64, v0_m_per_h: f64) -> PointEvaluation {
    let ssi = [0.5, 0.6, 0.7, 2.0];
    let impacts = [10.0, 20.0, 80.0, 30.0];
    let samples: Vec<BTreeMap<String, f64>> = (0..4)
        .map(|k| {
            BTreeMap::from([
                ("mean_rop_m_per_h".to_owned(), v0_m_per_h),
                ("stick_slip_severity".to_owned(), ssi[k]),
                ("impacts_per_s".to_owned(), impacts[k]),
                ("mse_pa".to_owned(), 7e8),
                ("mean_wob_n".to_owned(), 55e3),
                ("peak_wall_force_n".to_owned(), 0.0),
            ])
        })
        .collect();
    let column = |key: &str| -> Vec<f64> { samples.iter().map(|m| m[key]).collect::<Vec<_>>() };
    let mean = |key: &str| Statistic::Mean.apply(&column(key));
    let quantity = study.statistic.apply(&column(study.quantity.metric()));
    let risk: Vec<RiskValue> = study
        .risk
        .iter()
        .map(|r| {
            let value = r.statistic.apply(&column(&r.metric));
            RiskValue {
                metric: r.metric.clone(),
                statistic: r.statistic,
                value,
                weight: r.weight,
                penalty: r.weight * value,
            }
        })
        .collect();
    let chance: Vec<ChanceValue> = study
        .constraints
        .iter()
        .flat_map(|c| &c.chance)
        .map(|c| {
            let probability = Statistic::ProbExceed {
                threshold: c.threshold,
            }
            .apply(&column(&c.metric));
            ChanceValue {
                metric: c.metric.clone(),
                threshold: c.threshold,
                probability,
                max_probability: c.max_probability,
                satisfied: probability <= c.max_probability,
            }
        })
        .collect();
    let feasible = chance.iter().all(|c| c.satisfied);
    PointEvaluation {
        omega_rad_s: omega_rpm / RPM,
        omega_rpm,
        set_point: crate::model::SetPointValue::Feed {
            v0_m_s: v0_m_per_h / MPH,
            v0_m_per_h,
        },
        objective: Some(quantity - risk.iter().map(|r| r.penalty).sum::<f64>()),
        quantity: Some(quantity),
        risk,
        chance,
        feasible,
        failure: None,
        mean_metrics: samples[0].keys().map(|k| (k.clone(), mean(k))).collect(),
        samples_used: samples.len(),
        score_half_width: None,
        score_interval: None,
        samples: samples
            .into_iter()
            .enumerate()
            .map(|(k, m)| SampleResult {
                sample: k,
                seed: k as u64,
                outcome: SampleOutcome::Metrics(m),
                cached: false,
            })
            .collect(),
        fidelity: crate::study::Fidelity::Full,
    }
}

/// A 4 × 4 map over 40–120 rpm × 2–20 m/h whose six nodes of highest Ω + V0 lie outside
/// the linear constraints; the best node is (66.67 rpm, 8 m/h).
pub(in crate::cli) fn map_4x4(study: &Study) -> MapOutcome {
    let omega: Vec<f64> = (0..4)
        .map(|i| (40.0 + 80.0 * i as f64 / 3.0) / RPM)
        .collect();
    let v0: Vec<f64> = (0..4).map(|j| (2.0 + 6.0 * j as f64) / MPH).collect();
    let mut points = Vec::new();
    for (j, v) in v0.iter().enumerate() {
        for (i, w) in omega.iter().enumerate() {
            points.push((i + j < 4).then(|| point(study, w * RPM, v * MPH)));
        }
    }
    // The fixture's chance constraint fails at every node (P(impacts > 50) = 25 %); the map
    // shows nodes feasible but for the one at 40 rpm, 20 m/h, the highest score.
    for (k, p) in points.iter_mut().enumerate() {
        if let Some(p) = p {
            p.feasible = k != 12;
        }
    }
    let best = points[4 + 1].clone();
    MapOutcome {
        grid: [4, 4],
        kind: crate::model::SetPoint::Feed,
        omega,
        set_point: v0,
        points,
        best,
    }
}

/// The texts of every `<text>` element.
fn texts(svg: &str) -> Vec<&str> {
    svg.split("<text ")
        .skip(1)
        .map(|s| s[s.find('>').unwrap() + 1..s.find("</text>").unwrap()].trim())
        .collect()
}

#[test]
fn optimum_metrics_mark_the_objective_statistic_and_the_chance_limits() {
    let problem = problem();
    let p = point(&problem.study, 60.0, 5.0);
    let rows = metric_rows(&problem.study, &p, UnitSystem::Metric);
    let labels: Vec<&str> = rows.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "mean ROP [m/h]",
            "stick-slip severity (10 ms average)",
            "mechanical specific energy [MPa]",
            "wall impacts [1/s]",
            "mean WOB [kN]"
        ]
    );
    let ssi = &rows[1];
    // The objective takes the CVaR 75 % of SSI (the worst of four samples), not the mean.
    assert_eq!(ssi.marks.len(), 1);
    assert_eq!(ssi.marks[0].name, "CVaR 75 % (objective)");
    assert_eq!(ssi.marks[0].value, 2.0);
    assert_eq!(ssi.marks[0].kind, MarkKind::Statistic);
    assert_eq!(rows[2].marks[0].name, "mean (objective)");
    assert!((rows[2].marks[0].value - 700.0).abs() < 1e-9);
    assert_eq!(rows[2].samples, [700.0; 4]);
    // The chance constraint: a dashed limit at 50 /s, violated at 25 % > 10 %.
    let limit = &rows[3].marks[0];
    assert_eq!((limit.value, limit.kind), (50.0, MarkKind::Limit));
    assert_eq!(
        limit.note,
        "P(above) = 25 %, at most 10 % allowed: violated"
    );
    // Outside the objective: the mean, in kN.
    assert_eq!(rows[4].marks[0].name, "mean");
    assert_eq!(rows[4].marks[0].value, 55.0);

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("optimum_metrics.svg");
    report::plot_metric_samples("at the optimum", &rows, &out).unwrap();
    let svg = std::fs::read_to_string(&out).unwrap();
    for text in [
        "stick-slip severity (10 ms average): CVaR 75 % (objective) = 2.000 (red); 4 samples",
        "wall impacts [1/s]: chance limit = 50.00 (dashed), P(above) = 25 %, at most 10 % \
         allowed: violated; 4 samples",
        "mean WOB [kN]: mean = 55.00 (red); 4 samples",
    ] {
        assert!(texts(&svg).contains(&text), "{text:?} in {:?}", texts(&svg));
    }
    for key in [
        "stick_slip_severity",
        "mse_pa",
        "mean_wob_n",
        "impacts_per_s",
    ] {
        assert!(!svg.contains(key), "{key}");
    }
}

#[test]
fn statistics_are_named_for_a_reader_and_spreads_mark_the_mean() {
    assert_eq!(statistic_name(&Statistic::Cvar { level: 0.9 }), "CVaR 90 %");
    assert_eq!(
        statistic_name(&Statistic::Quantile { level: 0.5 }),
        "50 % quantile"
    );
    assert_eq!(
        statistic_name(&Statistic::ProbExceed { threshold: 1.5 }),
        "P(> 1.500)"
    );
    let wob = MetricDisplay::of("mean_wob_n");
    let sd = objective_mark(&Statistic::StdDev, 2000.0, &wob, 55.0);
    assert_eq!((sd.name.as_str(), sd.value), ("mean", 55.0));
    assert_eq!(sd.note, "objective: std dev = 2.000");
    let p = objective_mark(&Statistic::ProbExceed { threshold: 60e3 }, 0.25, &wob, 55.0);
    assert_eq!((p.value, p.kind), (60.0, MarkKind::Limit));
    assert_eq!(p.note, "P(above) = 25 %");
}

#[test]
fn map_plots_name_metrics_with_units_show_constants_and_star_the_best_node() {
    let problem = problem();
    let m = map_4x4(&problem.study);
    let dir = tempfile::tempdir().unwrap();
    map_plots(&problem, dir.path(), &m, UnitSystem::Metric).unwrap();
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap();

    let objective = read("map_objective.svg");
    let caption = "best map node (highest score): \u{3a9} = 66.67 rpm, V0 = 8.000 m/h";
    for text in ["robust score [m/h]", BEST_NODE, caption] {
        assert!(texts(&objective).contains(&text), "{text:?}");
    }
    assert!(!objective.contains("optimum"));
    // The infeasible node (40 rpm, 20 m/h) is grey: the colour bar's top is the best feasible
    // score (14 m/h less the same penalties), not its score.
    let score = |k: usize| m.points[k].as_ref().unwrap().objective.unwrap();
    let top = texts(&objective)
        .into_iter()
        .find_map(|t| t.strip_prefix("max ").map(|x| x.parse::<f64>().unwrap()))
        .unwrap();
    assert!(
        (top - score(8)).abs() < 1e-2 * score(8).abs(),
        "{top} vs {}",
        score(8)
    );
    assert!(score(12) > score(8) + 1.0);
    assert!(texts(&objective).contains(&"no value (infeasible/failed)"));

    // Mapped metrics are named for a reader, in driller units, never by their code key.
    let mse = read("map_mse_pa.svg");
    assert!(texts(&mse).contains(&"mechanical specific energy [MPa]"));
    assert!(texts(&mse).contains(&"seed_robust: mechanical specific energy (sample mean)"));
    for (file, key) in [
        ("map_mse_pa.svg", "mse_pa"),
        ("map_mean_rop_m_per_h.svg", "mean_rop_m_per_h"),
        ("map_stick_slip_severity.svg", "stick_slip_severity"),
        ("map_impacts_per_s.svg", "impacts_per_s"),
    ] {
        assert!(!read(file).contains(key), "{file}");
    }

    // MSE is the same at every node: its value, said to be constant; no invented range.
    let t = texts(&mse);
    assert!(t.contains(&"constant: 700.0"), "{t:?}");
    assert!(t.contains(&"the same at every point"));
    assert!(
        !t.iter()
            .any(|t| t.starts_with("max ") || t.starts_with("min "))
    );
    // ROP varies with V0: a colour bar with its range.
    let rop = read("map_mean_rop_m_per_h.svg");
    assert!(texts(&rop).contains(&"max 20.00") && texts(&rop).contains(&"min 2.000"));
    assert!(!texts(&rop).iter().any(|t| t.starts_with("constant")));
}

#[test]
fn map_plots_in_field_units_put_feet_per_hour_and_psi_on_every_axis_and_scale() {
    let problem = problem();
    let m = map_4x4(&problem.study);
    let dir = tempfile::tempdir().unwrap();
    map_plots(&problem, dir.path(), &m, UnitSystem::Field).unwrap();
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap();
    let objective = read("map_objective.svg");
    // 8 m/h = 26.25 ft/h.
    let caption = "best map node (highest score): \u{3a9} = 66.67 rpm, V0 = 26.25 ft/h";
    for text in ["robust score [ft/h]", "V0 [ft/h]", caption] {
        assert!(texts(&objective).contains(&text), "{text:?}");
    }
    // The colour bar's top is the best feasible score in ft/h.
    let score = m.points[8].as_ref().unwrap().objective.unwrap() / 0.3048;
    let top = texts(&objective)
        .into_iter()
        .find_map(|t| t.strip_prefix("max ").map(|x| x.parse::<f64>().unwrap()))
        .unwrap();
    assert!((top - score).abs() < 1e-2 * score.abs(), "{top} vs {score}");
    // 700 MPa = 101 526 psi; 20 m/h = 65.62 ft/h.
    let mse = texts(&read("map_mse_pa.svg")).join("|");
    assert!(mse.contains("mechanical specific energy [psi]"), "{mse}");
    assert!(mse.contains("constant: 1.015e5"), "{mse}");
    let rop = read("map_mean_rop_m_per_h.svg");
    assert!(texts(&rop).contains(&"max 65.62") && texts(&rop).contains(&"min 6.562"));
    assert!(!objective.contains("m/h") && !rop.contains("m/h"));
}
