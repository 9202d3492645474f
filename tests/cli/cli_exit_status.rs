//! A command never exits 0 with a missing result, and an absurd override is refused before
//! anything runs.

use crate::common;

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

/// A 1 ns window took one step and had no analysis window, so the run exited 1 with "no
/// metrics"; it is now refused before anything runs, naming the flag, the key and the range
/// (issue 34: `--duration 1e-300` failed naming no flag). The shortest admissible window, one
/// microsecond, runs to its metrics. (The "no metrics" status itself is tested in the metrics'
/// unit tests: `WindowTooShort`.)
#[test]
fn a_window_too_short_for_metrics_is_refused_before_it_runs() {
    let dir = tempfile::tempdir().unwrap();
    for short in ["1e-9s", "1e-300"] {
        let out = simulate(&["--duration", short], dir.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains("--duration")
                && stderr.contains("simulation.duration")
                && stderr.contains("[1e-6, 86400] s"),
            "{stderr}"
        );
        assert!(!dir.path().join("summary.json").exists());
    }
    let out = simulate(&["--duration", "1us"], dir.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    assert!(summary["metrics"].is_object(), "{summary}");
}
