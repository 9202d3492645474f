//! End-to-end checks of issue 11 through the real binary: the pre-loaded start removes the
//! start-up bias, a long string keeps every family and shows stick-slip, and `verify` reports a
//! verdict that follows from the numbers it prints.

use serde_json::Value;
use std::path::Path;
use std::process::Command;

fn drillopt(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("drillopt runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// From the unloaded static state WOB takes about a second to build (a 2 s seed window drilled at
/// 2.8 m/h for V0 = 5 m/h); from the steady drilling state the bit advances at V0 at once.
#[test]
fn a_two_second_seed_window_drills_at_v0_from_the_preloaded_start() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let (ok, stdout, stderr) = drillopt(&[
        "simulate",
        "problems/seed_mc2014.toml",
        "--duration",
        "2",
        "--quiet",
        "--out",
        out,
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains(
            "basis: 32 bending (both planes), 8 torsional, 4 axial, 2 static corrections, 4 resting shapes"
        )
    );
    let s = summary(dir.path());
    let rop = s["metrics"]["mean_rop_m_per_h"].as_f64().unwrap();
    assert!(
        (rop / 5.0 - 1.0).abs() < 0.05,
        "ROP {rop} m/h for V0 = 5 m/h"
    );
    assert_eq!(s["basis"]["torsional"], 8);
    // The paper's unloaded start, same window: the start-up bias the pre-loaded start removes.
    let (ok, _, stderr) = drillopt(&[
        "simulate",
        "problems/seed_mc2014_paper.toml",
        "--duration",
        "2",
        "--quiet",
        "--out",
        out,
    ]);
    assert!(ok, "{stderr}");
    let rop = summary(dir.path())["metrics"]["mean_rop_m_per_h"]
        .as_f64()
        .unwrap();
    assert!(rop < 0.8 * 5.0, "unloaded start: ROP {rop} m/h");
}

/// 466 m of collars: the 51 lowest modes are all bending; the default basis holds every family,
/// and the string sticks and slips at 40 rpm.
#[test]
fn the_long_collar_string_keeps_every_family_and_sticks_and_slips() {
    let (ok, stdout, stderr) = drillopt(&["modes", "problems/long_collars.toml", "--count", "51"]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("51 bending (both planes), 0 torsional, 0 axial"),
        "{stdout}"
    );
    // They are the string's without the wall: the terminal says so, and where the wall's are.
    assert!(
        stdout.contains("the modes of the string without the wall")
            && stdout.contains("`drillopt campbell`"),
        "{stdout}"
    );
    let (ok, stdout, _) = drillopt(&["modes", "problems/long_collars.toml", "--json"]);
    assert!(ok);
    let modes: Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(modes["basis"]["torsional"], 8);
    assert_eq!(modes["basis"]["axial"], 4);
    assert_eq!(modes["basis"]["static_corrections"], 2);
    assert_eq!(modes["basis"]["resting_shapes"], 4);
    let dir = tempfile::tempdir().unwrap();
    let (ok, _, stderr) = drillopt(&[
        "simulate",
        "problems/long_collars.toml",
        "--duration",
        "10",
        "--quiet",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let m = &summary(dir.path())["metrics"];
    let stick = m["stick_fraction"].as_f64().unwrap();
    let ssi = m["stick_slip_severity"].as_f64().unwrap();
    // The field string (κ_t = 1, μ = 0.3 on the slip, mud) sticks about 5 % of the time (the
    // paper's κ_t = κ_s, μ = 1e-5 string stuck 16 %): it sticks and slips, SSI well above 1.
    assert!(stick > 0.01 && ssi > 1.0, "stick {stick}, SSI {ssi}");
}

/// `verify --json` on the tiny string: every refinement ran, the refined basis is at least 1.5×
/// the base in every family, and each verdict is what its own numbers say.
#[test]
fn verify_reports_verdicts_that_follow_from_its_numbers() {
    let (ok, stdout, stderr) = drillopt(&[
        "verify",
        "problems/regression/tiny_string.toml",
        "--duration",
        "1",
        "--json",
        "--quiet",
    ]);
    let r: Value = serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"));
    let converged = r["converged"].as_bool().unwrap();
    assert_eq!(ok, converged, "exit status follows the verdict: {stderr}");
    for family in ["bending", "torsional", "axial"] {
        let (base, refined) = (
            r["basis"][family].as_f64().unwrap(),
            r["refined_basis"][family].as_f64().unwrap(),
        );
        assert!(refined >= 1.5 * base, "{family}: {base} → {refined}");
    }
    let window = r["window_s"].as_f64().unwrap();
    assert!(
        (window - 0.5).abs() < 1e-12,
        "1 s less the 0.5 s settling: {window}"
    );
    // Ω = 60 rpm: one revolution per second.
    let revolutions = r["window_revolutions"].as_f64().unwrap();
    assert!((revolutions - 0.5).abs() < 1e-12, "{revolutions}");
    assert_eq!(
        r["smoothing_keys"],
        serde_json::json!(["model.wall.slip_smoothing"])
    );
    // The base model's steady state: the tiny string's bit node, with its small inertia, is
    // unstable (docs/model.md, "Linear stability"): the linearisation grows at about 271 1/s,
    // 578 Hz (613 1/s, 687 Hz without the inertia, up to revision 12).
    let growth = r["steady_state"]["growth_rate_per_s"].as_f64().unwrap();
    assert!(growth > 100.0, "{growth}");
    let metrics = r["metrics"].as_object().unwrap();
    // The tiny string decides on no stress metric: the core decision metrics only.
    let always = drillopt::metrics::METRICS
        .iter()
        .filter(|s| matches!(s.verification, drillopt::metrics::Verification::Always(..)));
    assert_eq!(metrics.len(), always.count());
    assert!(!metrics.contains_key("max_von_mises_pa"));
    let mut all = true;
    for (key, v) in metrics {
        let value = v["value"].as_f64().unwrap();
        let floor = v["floor"].as_f64().unwrap();
        let refined = v["refined"].as_object().unwrap();
        // The tiny string's wall has the seed's friction (1e-5) on the Coulomb law: its slip
        // smoothing is refined too.
        assert_eq!(
            refined.keys().collect::<Vec<_>>(),
            ["basis", "mesh", "smoothing", "tolerance", "window"],
            "{key}"
        );
        let max = refined
            .values()
            .map(|r| (r.as_f64().unwrap() - value).abs() / value.abs().max(floor))
            .fold(0.0, f64::max);
        let reported = v["max_rel_change"].as_f64().unwrap();
        assert!((reported - max).abs() <= 1e-12 * max.max(1.0), "{key}");
        // The perturbed run (Ω·(1 + 1e-4)) is apart from the refinements: its change is the
        // sensitivity, which alone makes a metric "sensitive".
        let limit = v["limit"].as_f64().unwrap();
        let perturbed = v["perturbed"].as_f64().unwrap();
        let sensitivity = (perturbed - value).abs() / value.abs().max(floor);
        let reported = v["sensitivity"].as_f64().unwrap();
        assert!(
            (reported - sensitivity).abs() <= 1e-12 * sensitivity.max(1.0),
            "{key}"
        );
        let expected = if sensitivity > limit {
            "sensitive"
        } else if max > limit {
            "not_converged"
        } else {
            "converged"
        };
        assert_eq!(v["verdict"].as_str().unwrap(), expected, "{key}");
        let verdict = v["converged"].as_bool().unwrap();
        assert_eq!(verdict, expected == "converged", "{key}");
        all &= verdict;
    }
    assert_eq!(all, converged);
}

/// Issue 13: `verify`'s table is in the terminal's units, and its end is a verdict, not an error:
/// the last line says converged or NOT converged (with the metric, its change and its limit),
/// the exit status follows it, and stderr carries no `error:` line.
#[test]
fn verify_ends_with_a_verdict_in_the_terminal_units() {
    let (ok, stdout, stderr) = drillopt(&[
        "verify",
        "problems/regression/tiny_string.toml",
        "--duration",
        "1",
        "--quiet",
    ]);
    assert!(!stderr.contains("error"), "{stderr}");
    // 0.5 s of window at 60 rpm: half a revolution, which the user is warned of.
    assert!(
        stderr.contains("warning: the analysis window (0.500 s) holds 0.500 revolutions"),
        "{stderr}"
    );
    assert!(stdout.contains("0.50 revolutions"), "{stdout}");
    let last = stdout.lines().last().unwrap();
    if ok {
        assert!(last.starts_with("verdict: converged"), "{stdout}");
    } else {
        // Truncation first; a verdict that only the 1e-4 perturbation moved says "sensitive".
        if last.starts_with("verdict: NOT converged (") {
            assert!(
                last.contains(" % > ") && last.contains("refinement"),
                "{last}"
            );
        } else {
            assert!(
                last.starts_with("verdict: sensitive (sensitive: "),
                "{stdout}"
            );
            assert!(!last.contains("refinement"), "{last}");
        }
    }
    let row = |key: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("{key}: {stdout}"))
            .split_whitespace()
            .collect::<Vec<_>>()
    };
    // WOB in kN (the tiny string's is about 55 kN), TOB in kN·m, MSE in MPa, stick time in %.
    let wob = row("mean_wob_n");
    assert_eq!(wob[1], "kN");
    let kn: f64 = wob[2].parse().unwrap();
    assert!((10.0..200.0).contains(&kn), "{kn}");
    assert_eq!(row("mean_tob_nm")[1], "kN·m");
    assert_eq!(row("mse_pa")[1], "MPa");
    assert_eq!(row("stick_fraction")[1], "%");
}

/// `bit_damping_ratio` in `summary.json` is the bit law's negative damping over the pipe's
/// torsional impedance, computed here from the tiny string's data by hand (its pipe is the seed's:
/// R 60/40 mm, E 203 GPa, ν 0.3, ρ 7900 kg/m³, κ_t = Cowper's κ_s; Γ 250 kN, α 180 s/m,
/// μ 0.04 m); `simulate` warns above 1 and not below.
#[test]
fn simulate_reports_the_bit_damping_ratio_and_warns_above_one() {
    use std::f64::consts::PI;
    let (ro, ri, e, nu, rho) = (0.06_f64, 0.04_f64, 203e9, 0.3, 7900.0);
    // tiny_string.toml has St Venant torsion, κ_t = 1: Z = √(G J · ρ J).
    let kappa_t = 1.0;
    let j = PI / 2.0 * (ro.powi(4) - ri.powi(4));
    let z = (kappa_t * e / (2.0 * (1.0 + nu)) * j * rho * j).sqrt();
    for (rpm, m_per_h, above) in [(60.0, 5.0, false), (40.0, 20.0, true)] {
        let dir = tempfile::tempdir().unwrap();
        let (omega, v0) = (format!("{rpm}rpm"), format!("{m_per_h}m/h"));
        let (ok, _, stderr) = drillopt(&[
            "simulate",
            "problems/regression/tiny_string.toml",
            "--omega",
            &omega,
            "--v0",
            &v0,
            "--duration",
            "0.2",
            "--quiet",
            "--out",
            dir.path().to_str().unwrap(),
        ]);
        assert!(ok, "{stderr}");
        let w = rpm * PI / 30.0;
        let wob = 250e3 * (1.0 - (-180.0 * m_per_h / 3600.0_f64).exp());
        let dxi = 1.0 - w.tanh().powi(2) + 2.0 * (1.0 - w * w) / (1.0 + w * w).powi(2);
        let expected = -0.04 * wob * dxi / z;
        let ratio = summary(dir.path())["metrics"]["bit_damping_ratio"]
            .as_f64()
            .unwrap();
        assert!(
            (ratio / expected - 1.0).abs() < 1e-9,
            "{ratio} vs {expected}"
        );
        assert_eq!(ratio > 1.0, above, "{rpm} rpm, {m_per_h} m/h: {ratio}");
        assert_eq!(stderr.contains("bit_damping_ratio > 1"), above, "{stderr}");
    }
}

#[test]
fn an_unreduced_field_well_reports_its_own_steady_state_eigenvalue() {
    // 622 unknowns, above the old 600 limit: the finite-element model's growth rate is the
    // reference a reduced basis is checked against (docs/model.md, "Linear stability").
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("unreduced");
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/field/well_1km.toml");
    let (ok, _, stderr) = drillopt(&[
        "simulate",
        file,
        "--unreduced",
        "--duration",
        "0.002",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    let s = summary(&out);
    assert_eq!(s["model"], "unreduced");
    let steady = &s["steady_state"];
    let (growth, hz) = (
        steady["growth_rate_per_s"].as_f64().expect("a growth rate"),
        steady["frequency_hz"].as_f64().expect("a frequency"),
    );
    assert!(growth.is_finite() && hz > 0.0, "{steady}");
}
