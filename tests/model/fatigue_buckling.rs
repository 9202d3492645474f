//! Fatigue and buckling of the string (issue 14, items 2, 3 and 5): the metrics of a run against
//! hand values, the `[model.pipe.fatigue]` keys, thresholds of risk terms and chance constraints
//! written with units, and what `simulate` writes.

use crate::common;

use drillopt::metrics;
use drillopt::model::OperatingPoint;
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunSettings, simulate};
use std::path::Path;

/// The seed problem with `extra_pipe` lines in `[model.pipe]` and `extra` appended.
fn seed_with(extra_pipe: &str, extra: &str) -> Result<Problem, drillopt::problem::ProblemError> {
    let text = std::fs::read_to_string(common::SEED)
        .unwrap()
        .replace("[model.pipe]", &format!("[model.pipe]\n{extra_pipe}"))
        + extra;
    Problem::from_toml(&text, Path::new("fatigue.toml"))
}

/// The seed problem with a `[model.pipe.fatigue]` table of `lines`.
fn with_fatigue(lines: &str) -> Result<Problem, drillopt::problem::ProblemError> {
    let text = std::fs::read_to_string(common::SEED).unwrap().replace(
        "[model.fluid]",
        &format!("[model.pipe.fatigue]\n{lines}\n\n[model.fluid]"),
    );
    Problem::from_toml(&text, Path::new("fatigue.toml"))
}

/// The seed string (30 elements, small basis) drilling for `duration` s at 120 rpm, 10 m/h.
fn run(p: &Problem, duration: f64) -> drillopt::metrics::Metrics {
    let model = ReducedModel::new(&p.model, 30, &common::small_basis()).unwrap();
    let op = OperatingPoint {
        omega: 4.0 * std::f64::consts::PI,
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &RunSettings::new(duration, p.simulation.time_step),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    metrics::of_run(&out, &p.model, op, 0.0, None).unwrap()
}

/// Dawson & Paslay's sinusoidal load and Chen, Lin & Cheatham's helical load of the seed pipe from
/// the raw Table 1 numbers: F_sin = 2 √(E I w / r), F_hel = 2√2 √(E I w / r), w = (ρA + ρ_f A_f) g
/// (no buoyancy in the model), r = 10 mm. By hand: 601 839.8 N and 851 130.0 N.
#[test]
fn buckling_metrics_compare_the_largest_compression_with_the_hand_loads() {
    use common::Table1;
    let w = Table1::lateral_mass() * 9.81;
    let root = (Table1::E * Table1::inertia() * w / 0.01).sqrt();
    let (f_sin, f_hel) = (2.0 * root, 2.0 * std::f64::consts::SQRT_2 * root);
    assert!((f_sin / 601_839.8 - 1.0).abs() < 1e-6 && (f_hel / 851_130.0 - 1.0).abs() < 1e-6);
    let p = seed_with("", "").unwrap();
    let m = run(&p, 0.3);
    assert!(m.max_compression_n > 10e3, "the bit compresses the string");
    assert!((m.buckling_utilization / (m.max_compression_n / f_sin) - 1.0).abs() < 1e-9);
    assert!((m.helical_buckling_utilization / (m.max_compression_n / f_hel) - 1.0).abs() < 1e-9);
    assert!((m.buckling_margin - (1.0 - m.buckling_utilization)).abs() < 1e-15);
    assert!((0.0..=35.0).contains(&m.buckling_at_m));
}

#[test]
fn fatigue_metrics_of_a_run_follow_the_curve_and_its_endurance_limit() {
    // Without a cut-off every cycle counts (DNV's variable-amplitude reading of the B1 curve).
    let open = with_fatigue("endurance_limit = 0").unwrap();
    assert_eq!(open.model.pipe.fatigue.endurance_limit, 0.0);
    assert_eq!(open.model.pipe.fatigue.name, "DNV-B1");
    let m = run(&open, 0.5);
    assert!(m.fatigue_damage_per_h > 0.0 && m.fatigue_damage_per_h.is_finite());
    assert!((m.fatigue_life_h * m.fatigue_damage_per_h - 1.0).abs() < 1e-12);
    assert!((0.0..=35.0).contains(&m.fatigue_worst_at_m));
    // A stress concentration of 2 multiplies every range by 2: the damage of the cycles on the
    // m = 5 branch by 2⁵ and on the m = 4 branch by 2⁴ (between the two here).
    let notched = with_fatigue("endurance_limit = 0\nstress_concentration = 2").unwrap();
    let ratio = run(&notched, 0.5).fatigue_damage_per_h / m.fatigue_damage_per_h;
    assert!((16.0 * 0.999..=32.0 * 1.001).contains(&ratio), "{ratio}");
    // The default cut-off (B1's 106.97 MPa fatigue limit) is far above these ranges: no damage.
    let m = run(&seed_with("", "").unwrap(), 0.5);
    assert_eq!(m.fatigue_damage_per_h, 0.0);
    assert_eq!(m.fatigue_life_h, f64::INFINITY);
}

#[test]
fn the_fatigue_table_takes_a_named_curve_or_its_parameters() {
    let p = seed_with("", "").unwrap();
    let c = &p.model.pipe.fatigue;
    assert_eq!((c.name, c.m1, c.log_a1), ("DNV-B1", 4.0, 15.117));
    assert_eq!(c.second, Some((17.146, 5.0)));
    assert!((c.endurance_limit - 106.97e6).abs() < 1.0);
    let p = with_fatigue("sn_curve = \"dnv-d\"\nendurance_limit = \"40 MPa\"").unwrap();
    let c = &p.model.pipe.fatigue;
    assert_eq!(
        (c.name, c.m1, c.log_a1, c.endurance_limit),
        ("DNV-D", 3.0, 12.164, 40e6)
    );
    // By its parameters: one slope, the endurance limit defaults to the range at 10⁷ cycles.
    let p = with_fatigue("log_a1 = 12.0\nm1 = 3").unwrap();
    let c = &p.model.pipe.fatigue;
    assert_eq!((c.name, c.second), ("custom", None));
    assert!((c.endurance_limit / 10f64.powf(5.0 / 3.0 + 6.0) - 1.0).abs() < 1e-12);
}

#[test]
fn bad_fatigue_keys_are_refused_naming_the_file_the_key_and_what_is_allowed() {
    let refuse = |lines: &str, key: &str, says: &[&str]| {
        let err = with_fatigue(lines).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("fatigue.toml"), "{text}");
        assert!(text.contains(key), "{text} lacks {key}");
        for s in says {
            assert!(text.contains(s), "{text} lacks {s}");
        }
    };
    refuse(
        "sn_curve = \"API-X\"",
        "model.pipe.fatigue.sn_curve",
        &["DNV-B1", "DNV-W3", "log_a1"],
    );
    refuse(
        "sn_curve = \"DNV-C\"\nm1 = 3",
        "model.pipe.fatigue.m1",
        &["not both"],
    );
    refuse("log_a1 = 12", "model.pipe.fatigue.m1", &["required"]);
    refuse(
        "log_a1 = 12\nm1 = 3\nlog_a2 = 15\nm2 = 3",
        "model.pipe.fatigue.m2",
        &["greater than m1"],
    );
    refuse(
        "log_a1 = 50\nm1 = 3",
        "model.pipe.fatigue.log_a1",
        &["[5, 40]"],
    );
    refuse(
        "endurance_limit = \"-5 MPa\"",
        "model.pipe.fatigue.endurance_limit",
        &["in [0, 2e9] Pa", "no cut-off"],
    );
    refuse(
        "endurance_limit = \"5 kN\"",
        "model.pipe.fatigue.endurance_limit",
        &["unit `kN` of a force, the wrong dimension", "MPa"],
    );
    refuse(
        "stress_concentration = 0.5",
        "model.pipe.fatigue.stress_concentration",
        &["[1, 20]"],
    );
    refuse("slope = 3", "model.pipe.fatigue", &["slope"]);
}

/// A chance constraint on `metric` with `threshold` as written.
fn chance(metric: &str, threshold: &str) -> String {
    format!(
        "\n[constraints]\nomega = [\"40 rpm\", \"120 rpm\"]\nv0 = [\"2 m/h\", \"20 m/h\"]\n[[constraints.chance]]\nmetric = \"{metric}\"\nthreshold = {threshold}\nmax_probability = 0.1\n"
    )
}

#[test]
fn thresholds_are_read_with_the_units_of_their_metric() {
    let threshold = |metric: &str, written: &str| {
        let p = seed_with("yield_strength = \"S-135\"", &chance(metric, written)).unwrap();
        p.study.constraints.unwrap().chance[0].threshold
    };
    let close = |a: f64, b: f64| assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} != {b}");
    close(threshold("max_von_mises_pa", "\"500 MPa\""), 500e6);
    close(
        threshold("max_von_mises_pa", "\"72.5 ksi\""),
        72.5e3 * 6894.757293168,
    );
    close(threshold("max_compression_n", "\"20 kN\""), 20e3);
    close(
        threshold("mean_wob_n", "\"10 klbf\""),
        10e3 * 4.4482216152605,
    );
    close(threshold("max_torque_nm", "\"5 kN·m\""), 5e3);
    close(
        threshold("mean_tob_nm", "\"1000 ft·lbf\""),
        1000.0 * 0.3048 * 4.4482216152605,
    );
    close(threshold("contact_impulse_ns", "\"2 kN·s\""), 2e3);
    close(threshold("impacts_per_s", "\"120 1/min\""), 2.0);
    close(threshold("max_von_mises_at_m", "\"30 ft\""), 9.144);
    // Metrics whose key names a unit other than SI are compared in it.
    close(threshold("mean_rop_m_per_h", "\"10 m/h\""), 10.0);
    close(threshold("mean_rop_m_per_h", "\"1 mm/s\""), 3.6);
    close(threshold("fatigue_damage_per_h", "\"1e-3 1/h\""), 1e-3);
    close(threshold("fatigue_damage_per_h", "\"1e-6 1/s\""), 3.6e-3);
    // Bare numbers as before: the metric's own value (SI but for those keys).
    close(threshold("max_von_mises_pa", "5e8"), 5e8);
    close(threshold("mean_rop_m_per_h", "12"), 12.0);
    close(threshold("von_mises_utilization", "0.5"), 0.5);
    // A risk term's prob_exceed threshold too.
    let risk = "\n[objective]\n[[objective.risk]]\nmetric = \"max_compression_n\"\nstatistic = \"prob_exceed\"\nthreshold = \"50 kN\"\nweight = 1.0\n";
    let p = seed_with("", risk).unwrap();
    assert_eq!(
        p.study.risk[0].statistic,
        drillopt::stats::Statistic::ProbExceed { threshold: 50e3 }
    );
}

#[test]
fn a_threshold_of_the_wrong_dimension_is_refused_with_the_allowed_units() {
    let err = |metric: &str, written: &str| {
        seed_with("yield_strength = \"S-135\"", &chance(metric, written))
            .unwrap_err()
            .to_string()
    };
    let e = err("max_von_mises_pa", "\"20 kN\"");
    for part in [
        "fatigue.toml",
        "constraints.chance[0].threshold",
        "the unit `kN` of a force, the wrong dimension",
        "max_von_mises_pa is a stress",
        "in Pa",
        "MPa",
    ] {
        assert!(e.contains(part), "{e} lacks {part}");
    }
    let e = err("stick_fraction", "\"20 %\"");
    assert!(
        e.contains("stick_fraction is dimensionless: a plain number"),
        "{e}"
    );
    let e = err("mean_rop_m_per_h", "\"5 kN\"");
    assert!(e.contains("a number in m/h"), "{e}");
    let e = err("max_compression_n", "\"lots\"");
    assert!(e.contains("does not start with a number"), "{e}");
}

#[test]
fn risks_use_damage_and_utilization_not_life_and_margin() {
    for (metric, instead) in [
        ("fatigue_life_h", "fatigue_damage_per_h"),
        ("buckling_margin", "buckling_utilization"),
    ] {
        let risk =
            format!("\n[objective]\n[[objective.risk]]\nmetric = \"{metric}\"\nweight = 1.0\n");
        let e = seed_with("", &risk).unwrap_err();
        assert_eq!(e.key(), Some("objective.risk[0].metric"));
        assert!(e.to_string().contains(instead), "{e}");
        let e = seed_with("", &chance(metric, "1.0")).unwrap_err();
        assert_eq!(e.key(), Some("constraints.chance[0].metric"));
    }
    // The ones to use are accepted, and verify then checks them.
    let keys = common::decision_keys;
    let p = seed_with("", &chance("fatigue_damage_per_h", "\"1e-3 1/h\"")).unwrap();
    assert!(keys(&p).contains(&"fatigue_damage_per_h"));
    assert!(!keys(&p).contains(&"max_von_mises_pa"));
    let p = seed_with("", &chance("buckling_utilization", "0.5")).unwrap();
    assert!(keys(&p).contains(&"buckling_utilization"));
    assert!(!keys(&common::seed()).contains(&"fatigue_damage_per_h"));
}

/// `simulate` reports the new metrics in summary.json and the envelope along the string.
#[test]
fn simulate_writes_fatigue_and_buckling_with_the_envelope() {
    let dir = tempfile::tempdir().unwrap();
    let out = common::simulate_tiny(&["--duration", "0.6"], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("sinusoidal buckling"), "{stdout}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    let m = &summary["metrics"];
    for key in [
        "fatigue_damage_per_h",
        "fatigue_life_h",
        "fatigue_worst_at_m",
        "buckling_utilization",
        "helical_buckling_utilization",
        "buckling_margin",
        "buckling_at_m",
    ] {
        assert!(m.get(key).is_some(), "{key} missing");
    }
    assert!(m["buckling_utilization"].as_f64().unwrap() > 0.0);
    let csv = std::fs::read_to_string(dir.path().join("stress_envelope.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains("fatigue_damage_per_h"));
    assert_eq!(csv.lines().count(), 13, "a header and the 12 elements");
    assert!(dir.path().join("stress_envelope.svg").exists());
}
