//! Issue 13 item 13: off-bottom rotation (V0 = 0) runs through `simulate` with defined metrics,
//! and a negative `--v0` reaches drillopt's parser (not clap's flag reader) and is refused naming
//! the key and the admissible range.

use crate::common;

use common::simulate_tiny as simulate;

#[test]
fn off_bottom_rotation_simulates_with_defined_metrics() {
    let dir = tempfile::tempdir().unwrap();
    let out = simulate(&["--v0", "0", "--duration", "0.6s"], dir.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["operating_point"]["v0_m_s"], 0.0);
    let m = &summary["metrics"];
    let num = |k: &str| m[k].as_f64().unwrap_or_else(|| panic!("{k}: {}", m[k]));
    assert!(num("mean_rop_m_per_h").abs() < 1e-6, "no feed, no ROP");
    // +∞ by definition (serde_json writes it as null): no rock is cut, no feed to compare with.
    assert!(m["mse_pa"].is_null() && m["axial_velocity_fluctuation"].is_null());
    assert_eq!(num("bit_bounce_fraction"), 1.0);
    // Stick-slip statistics relative to Ω: a bit without load turns with the top.
    assert!(num("stick_slip_severity") < 1e-3);
    assert_eq!(num("stick_fraction"), 0.0);
    assert!((num("max_bit_speed_ratio") - 1.0).abs() < 1e-3);
    assert!(num("mean_wob_n").abs() < 1.0 && num("efficiency").abs() < 1e-3);
}

#[test]
fn a_negative_v0_on_the_command_line_is_refused_naming_the_key_and_range() {
    let dir = tempfile::tempdir().unwrap();
    for v0 in ["-1m/h", "-1e-3m/s"] {
        let out = simulate(&["--v0", v0], dir.path());
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains("--v0")
                && stderr.contains("operating_point.v0")
                && stderr.contains("0 or in [0.1, 1000] m/h")
                && stderr.contains("off-bottom"),
            "{stderr}"
        );
        assert!(!stderr.contains("unexpected argument"), "{stderr}");
        assert!(!dir.path().join("summary.json").exists());
    }
    // A bare number (other than 0) is refused for its missing unit, saying how to write it.
    let out = simulate(&["--v0", "-1e-3"], dir.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("--v0") && stderr.contains("has no unit") && stderr.contains("-1e-3m/h"),
        "{stderr}"
    );
    // The same for a negative rotation speed: the range of operating_point.omega.
    let out = simulate(&["--omega", "-60rpm"], dir.path());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("operating_point.omega") && stderr.contains("1 to 1000 rpm"),
        "{stderr}"
    );
}

/// Issue 13: `--omega 60` would be 60 rad/s (573 rpm), never what a driller means: simulate,
/// verify and compare refuse a bare rotation speed or feed the same way, saying how to write it.
#[test]
fn a_bare_number_for_omega_or_v0_is_refused_by_every_one_point_command() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = "problems/regression/tiny_string.toml";
    let out = dir.path().to_str().unwrap();
    for args in [
        vec!["simulate", tiny, "--quiet", "--out", out, "--omega", "60"],
        vec!["verify", tiny, "--quiet", "--omega", "60"],
        vec![
            "compare", tiny, "--quiet", "--out", out, "--point", "60,5m/h",
        ],
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
            .args(&args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("`60` has no unit")
                && stderr.contains("e.g. 60rpm")
                && stderr.contains("572.9578 rpm"),
            "{args:?}: {stderr}"
        );
    }
    assert!(!dir.path().join("summary.json").exists());
}
