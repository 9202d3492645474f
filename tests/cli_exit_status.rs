//! A command never exits 0 with a missing result: `simulate` at an absurd V0 (1e308 m/h) cannot
//! find its starting state and says so, with exit status 1 and a summary that says "failed".

use std::process::Command;

#[test]
fn simulate_without_a_result_exits_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args([
            "simulate",
            "problems/regression/tiny_string.toml",
            "--v0",
            "1e308m/h",
            "--quiet",
            "--out",
            dir.path().to_str().unwrap(),
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("drillopt runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("starting equilibrium"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["status"], "failed");
    assert!(summary["metrics"].is_null());
}
