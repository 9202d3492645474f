//! `drillopt compare` reports a point outside the bounds or beyond the depth-of-cut limit as
//! infeasible, saying why, and refuses points written without units; `evaluations.csv` has a row
//! per (point, sample).

use serde_json::Value;
use std::process::Command;

#[test]
fn compare_calls_points_outside_the_constraints_infeasible() {
    let dir = tempfile::tempdir().unwrap();
    let run = |points: &[&str]| {
        let mut args = vec![
            "compare",
            "problems/regression/tiny_string.toml",
            "--quiet",
            "--out",
            dir.path().to_str().unwrap(),
        ];
        for p in points {
            args.extend(["--point", p]);
        }
        Command::new(env!("CARGO_BIN_EXE_drillopt"))
            .args(&args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("drillopt runs")
    };
    // compare.json of a run that must succeed.
    let report = |points: &[&str]| -> Value {
        let out = run(points);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(dir.path().join("compare.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    };
    let json = report(&["200rpm,30m/h", "30rpm,20m/h", "60rpm,5m/h"]);
    // The terminal table says why too, at the end of each infeasible row (`--quiet` keeps the
    // results on stdout).
    let stdout =
        String::from_utf8_lossy(&run(&["200rpm,30m/h", "30rpm,20m/h", "60rpm,5m/h"]).stdout)
            .into_owned();
    let row = |rpm: &str| {
        stdout
            .lines()
            .find(|l| l.trim_start().starts_with(rpm))
            .unwrap_or_else(|| panic!("{rpm}: {stdout}"))
            .to_string()
    };
    assert!(
        row("200.0").contains("no: ") && row("200.0").contains("outside the bounds"),
        "{stdout}"
    );
    assert!(
        row("30.0").contains("no: ") && row("30.0").contains("depth of cut"),
        "{stdout}"
    );
    assert!(row("60.0").trim_end().ends_with("yes"), "{stdout}");
    let points = json["points"].as_array().unwrap();
    let verdict = |i: usize| {
        (
            points[i]["feasible"].as_bool().unwrap(),
            points[i]["failure"].as_str().unwrap_or("").to_string(),
        )
    };
    let (ok, why) = verdict(0);
    assert!(!ok && why.contains("outside the bounds"), "{why}");
    let (ok, why) = verdict(1);
    assert!(!ok && why.contains("depth of cut"), "{why}");
    assert_eq!(verdict(2), (true, String::new()));

    // Issue 13 item 15: evaluations.csv beside compare.json, one row per (point, sample), the
    // verdicts as in the JSON.
    let csv = std::fs::read_to_string(dir.path().join("evaluations.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 1 + 3, "{csv}");
    assert_eq!(rows[0][..3], ["omega [rpm]", "v0 [m/h]", "sample"]);
    let feasible = rows[0].iter().position(|h| *h == "feasible").unwrap();
    let first = |r: &[&str]| (r[0].to_string(), r[1].to_string(), r[feasible].to_string());
    assert_eq!(first(&rows[1]), ("200".into(), "30".into(), "false".into()));
    assert_eq!(first(&rows[3]), ("60".into(), "5".into(), "true".into()));

    // Issue 13 item 3: off bottom (V0 = 0) the run does not drill: MSE +∞ gives the score −∞
    // (not NaN), and the point is also said to be outside the V0 bounds.
    let json = report(&["60rpm,0"]);
    let point = &json["points"][0];
    let why = point["failure"].as_str().unwrap();
    assert_eq!(point["feasible"], false);
    assert!(
        why.contains("no score: the point does not drill") && why.contains("outside the bounds"),
        "{why}"
    );

    let out = run(&["60,5"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no unit"));
}

/// A point that violates a chance constraint says which one, with its probability.
#[test]
fn compare_names_the_violated_chance_constraint() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    // A buckling utilization above 1 % at any WOB of tens of kN: violated everywhere.
    let text = tiny.replace(
        "[optimizer]",
        "[[constraints.chance]]\nmetric = \"buckling_utilization\"\nthreshold = 0.01\nmax_probability = 0.1\n\n[optimizer]",
    );
    let file = dir.path().join("chance.toml");
    std::fs::write(&file, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args([
            "compare",
            file.to_str().unwrap(),
            "--quiet",
            "--point",
            "60rpm,5m/h",
            "--out",
        ])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("no: chance constraint P(buckling_utilization > 0.01) = 1 > 0.1"),
        "{stdout}"
    );
    let json: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/compare.json")).unwrap(),
    )
    .unwrap();
    let why = json["points"][0]["failure"].as_str().unwrap();
    assert!(
        why.contains("P(buckling_utilization > 0.01) = 1 > 0.1"),
        "{why}"
    );
}
