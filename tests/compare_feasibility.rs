//! `drillopt compare` reports a point outside the bounds or beyond the depth-of-cut limit as
//! infeasible, saying why, and refuses points written without units.

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
    let out = run(&["200rpm,30m/h", "30rpm,20m/h", "60rpm,5m/h"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("compare.json")).unwrap())
            .unwrap();
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

    let out = run(&["60,5"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no unit"));
}
