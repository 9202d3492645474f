//! A command never exits 0 with a missing result, and an absurd override is refused before
//! anything runs.

mod common;

use common::simulate_tiny as simulate;

/// V0 = 1e308 m/h is outside the admissible range of operating_point.v0: refused, naming the flag
/// and the range.
#[test]
fn an_absurd_override_is_refused_with_its_range() {
    let dir = tempfile::tempdir().unwrap();
    let out = simulate(&["--v0", "1e308m/h"], dir.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("--v0") && stderr.contains("at most 1000 m/h"),
        "{stderr}"
    );
}

/// A 1 ns window has one step and no analysis window: the run completes but has no metrics, so
/// the command exits 1 and the summary says "no metrics" with the reason.
#[test]
fn simulate_without_metrics_exits_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let out = simulate(&["--duration", "1e-9s"], dir.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("metrics could not be computed"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["status"], "no metrics");
    assert!(summary["metrics"].is_null());
    assert!(summary["metrics_error"].is_string());
}
