//! `drillopt campbell` end to end, its refusals, and the metric `critical_speed_margin` where
//! metrics are reported (summary.json) and where studies read them (problem validation).

use crate::common;
use common::drillopt;

use std::path::Path;

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn campbell_of_the_seed_writes_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let run = drillopt(&[
        "campbell",
        "problems/seed_mc2014.toml",
        "--out",
        out,
        "--quiet",
        "--points",
        "19",
    ]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(stdout.contains("critical speeds"), "{stdout}");
    let c = json(&dir.path().join("campbell.json"));
    assert_eq!(c["problem"], "seed_mc2014");
    assert!(c["problem_hash"].is_string() && c["problem_toml"].is_string());
    assert_eq!(c["excitation_multiple"], 3.0);
    assert_eq!(c["omega_rpm"].as_array().unwrap().len(), 19);
    assert!((c["omega_rpm"][0].as_f64().unwrap() - 20.0).abs() < 1e-9);
    assert!((c["omega_rpm"][18].as_f64().unwrap() - 200.0).abs() < 1e-9);
    let modes = c["modes"].as_array().unwrap();
    assert_eq!(
        modes.len(),
        50,
        "the default basis: 32 + 8 + 4 modes, 2 + 4 Ritz vectors"
    );
    assert_eq!(modes[0]["freq_hz"].as_array().unwrap().len(), 19);
    assert_eq!(c["linearisation"]["contact"], true);
    let speeds = c["critical_speeds"].as_array().unwrap();
    assert!(!speeds.is_empty());
    for s in speeds {
        let (w, f, k) = (
            s["omega_rpm"].as_f64().unwrap(),
            s["freq_hz"].as_f64().unwrap(),
            s["multiple"].as_f64().unwrap(),
        );
        assert!((20.0..=200.0).contains(&w));
        assert!((f - k * w / 60.0).abs() < 1e-9 * f);
        assert!(s["mode"].as_u64().unwrap() >= 1);
    }
    let margin = c["operating_point"]["critical_speed_margin"]
        .as_f64()
        .unwrap();
    assert!((0.0..=0.5).contains(&margin));
    let svg = std::fs::read_to_string(dir.path().join("campbell.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("rotation speed"));
}

#[test]
fn bad_ranges_and_multiples_are_refused_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    for (flag, value, says) in [
        ("--omega-range", "200rpm..20rpm", "0 <= LOW < HIGH"),
        ("--omega-range", "20kg..200rpm", "unknown unit"),
        ("--omega-range", "20rpm-200rpm", "LOW..HIGH"),
        ("--omega-range", "20rpm..5000rpm", "<= 1000 rpm"),
        ("--omega-range", "-5rpm..20rpm", "0 <= LOW"),
        ("--omega-range", "2..20", "`2` has no unit"),
        ("--multiple", "0.5", "in [1, 50]"),
        ("--points", "1", "[2, 2000]"),
    ] {
        let run = drillopt(&[
            "campbell",
            "problems/seed_mc2014.toml",
            "--out",
            out,
            flag,
            value,
        ]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{flag} {value}: {stderr}");
        assert!(
            stderr.contains(flag) && stderr.contains(says),
            "{flag} {value}: {stderr}"
        );
    }
    assert!(
        !dir.path().join("campbell.json").exists(),
        "nothing written"
    );
}

#[test]
fn the_excitation_multiple_is_read_and_checked_in_the_problem_file() {
    let text = std::fs::read_to_string(common::SEED).unwrap();
    let load = |extra: &str| {
        drillopt::problem::Problem::from_toml(&format!("{text}\n{extra}"), Path::new(common::SEED))
    };
    assert_eq!(load("").unwrap().campbell.excitation_multiple, 3.0);
    let p = load("[campbell]\nexcitation_multiple = 5").unwrap();
    assert_eq!(p.campbell.excitation_multiple, 5.0);
    for bad in [
        "[campbell]\nexcitation_multiple = 0.5",
        "[campbell]\nexcitation_multiple = \"3 rpm\"",
        "[campbell]\nmultiple = 3",
    ] {
        let err = load(bad).unwrap_err().to_string();
        assert!(
            err.contains("seed_mc2014.toml") && err.contains("campbell"),
            "{bad}: {err}"
        );
    }
    let err = load("[campbell]\nexcitation_multiple = 60")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("campbell.excitation_multiple") && err.contains("[1, 50]"),
        "{err}"
    );
}

/// Without `[campbell] excitation_multiple`: a depth-of-cut bit's blade count (n blades excite
/// n×), else the tri-cone's 3, which a PDC bit's rate law (detournay) says is a default.
#[test]
fn the_excitation_multiple_defaults_to_the_blades_of_a_bit_that_has_them() {
    use drillopt::model::MultipleSource;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let load = |file: &str, extra: &str| {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        drillopt::problem::Problem::from_toml(
            &format!(
                "{text}
{extra}"
            ),
            &dir.join(file),
        )
        .unwrap()
    };
    // seed_rgd.toml: 4 blades.
    let rgd = load("seed_rgd.toml", "");
    assert_eq!(rgd.campbell.excitation_multiple, 4.0);
    assert_eq!(rgd.campbell.source, MultipleSource::Blades);
    assert_eq!(rgd.campbell.note(rgd.model.bit.law().name()), None);
    let given = load("seed_rgd.toml", "[campbell]\nexcitation_multiple = 5");
    assert_eq!(given.campbell.excitation_multiple, 5.0);
    assert_eq!(given.campbell.source, MultipleSource::File);
    // seed_detournay.toml: a PDC bit's rate law, no blades: 3, and a note saying why.
    let pdc = load("seed_detournay.toml", "");
    assert_eq!(pdc.campbell.excitation_multiple, 3.0);
    let note = pdc.campbell.note(pdc.model.bit.law().name()).unwrap();
    assert!(
        note.contains("excitation_multiple") && note.contains("blade count"),
        "{note}"
    );
    let given = load("seed_detournay.toml", "[campbell]\nexcitation_multiple = 6");
    assert_eq!(given.campbell.note(given.model.bit.law().name()), None);
    // The seed's exponential law (no bit type): 3, no note.
    let seed = load("seed_mc2014.toml", "");
    assert_eq!(seed.campbell.source, MultipleSource::Default);
    assert_eq!(seed.campbell.note(seed.model.bit.law().name()), None);
}

#[test]
fn risks_use_the_proximity_not_the_margin() {
    let text = std::fs::read_to_string(common::SEED).unwrap();
    let load = |extra: String| {
        drillopt::problem::Problem::from_toml(&format!("{text}\n{extra}"), Path::new(common::SEED))
    };
    let risk =
        |m: &str| format!("[objective]\n[[objective.risk]]\nmetric = \"{m}\"\nweight = 1.0\n");
    let err = load(risk("critical_speed_margin")).unwrap_err().to_string();
    assert!(err.contains("objective.risk[0].metric"), "{err}");
    assert!(err.contains("critical_speed_proximity"), "{err}");
    load(risk("critical_speed_proximity")).unwrap();
    let chance = "[constraints]\nomega = [\"40 rpm\", \"120 rpm\"]\nv0 = [\"2 m/h\", \"10 m/h\"]\n[[constraints.chance]]\nmetric = \"critical_speed_margin\"\nthreshold = 0.1\nmax_probability = 0.1\n";
    let err = load(chance.into()).unwrap_err().to_string();
    assert!(err.contains("constraints.chance[0].metric"), "{err}");
}

/// simulate and a study (compare, its evaluations.csv) report the margin of their Ω from the
/// critical speeds that `drillopt campbell` lists.
#[test]
fn simulate_and_studies_report_the_margin_of_the_critical_speeds_campbell_finds() {
    let dir = tempfile::tempdir().unwrap();
    let sim = common::simulate_tiny(&["--duration", "0.6s", "--omega", "110rpm"], dir.path());
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    let summary = json(&dir.path().join("summary.json"));
    let margin = summary["metrics"]["critical_speed_margin"]
        .as_f64()
        .unwrap();
    let proximity = summary["metrics"]["critical_speed_proximity"].as_f64();
    assert!((0.0..=0.5).contains(&margin), "{margin}");
    match proximity {
        Some(p) => assert!((p * margin - 1.0).abs() < 1e-12),
        None => assert_eq!(margin, 0.0, "+inf is written null"),
    }
    let out = dir.path().join("c");
    let run = drillopt(&[
        "campbell",
        "problems/regression/tiny_string.toml",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--omega-range",
        "1rpm..1000rpm",
        "--points",
        "200",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let c = json(&out.join("campbell.json"));
    let nearest = |rpm: f64| {
        c["critical_speeds"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["omega_rpm"].as_f64().unwrap())
            .map(|w| (rpm - w).abs() / w)
            .fold(0.5, f64::min)
    };
    let expected = nearest(110.0);
    assert!(
        expected < 0.5,
        "a critical speed within [Ω/1.5, 2Ω] of 110 rpm"
    );
    assert!(
        (expected - margin).abs() < 1e-6,
        "campbell {expected} vs simulate {margin}"
    );
    assert_eq!(
        c["operating_point"]["critical_speed_margin"]
            .as_f64()
            .unwrap(),
        nearest(60.0)
    );
    // A study's evaluations.csv carries the column, for every sample.
    let study = dir.path().join("compare");
    let run = drillopt(&[
        "compare",
        "problems/regression/tiny_string.toml",
        "--quiet",
        "--out",
        study.to_str().unwrap(),
        "--point",
        "110rpm,5m/h",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let csv = std::fs::read_to_string(study.join("evaluations.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|h| *h == "critical_speed_margin [1]")
        .unwrap();
    let rows: Vec<&str> = lines.collect();
    assert!(!rows.is_empty());
    for row in rows {
        let value: f64 = row.split(',').nth(column).unwrap().parse().unwrap();
        assert!((value - expected).abs() < 1e-6, "{value} vs {expected}");
    }
}

/// Critical speeds per family (issue 33 item 3): on the 466 m collar string the first torsional
/// mode (1.687 Hz) and an axial one (2.720 Hz) lie low enough to meet the 1× line inside 20-200
/// rpm (at 101.2 and 163.2 rpm), where nothing in a drillstring drives them; only the bit's 3×
/// does (at 33.7 and 54.4 rpm). Bending modes keep both lines.
#[test]
fn axial_and_torsional_modes_meet_the_bits_multiple_only() {
    let dir = tempfile::tempdir().unwrap();
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["campbell", "problems/long_collars.toml", "--quiet", "--out"])
        .arg(dir.path())
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let c = json(&dir.path().join("campbell.json"));
    let speeds = c["critical_speeds"].as_array().unwrap();
    let of = |family: &str| -> Vec<(f64, f64)> {
        speeds
            .iter()
            .filter(|s| s["family"] == family)
            .map(|s| {
                (
                    s["omega_rpm"].as_f64().unwrap(),
                    s["multiple"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    for family in ["torsional", "axial"] {
        let found = of(family);
        assert!(!found.is_empty(), "{family}: {speeds:?}");
        assert!(found.iter().all(|&(_, k)| k == 3.0), "{family}: {found:?}");
    }
    // The first torsional mode at 3×: f = 3 Ω / 60 at 33.73 rpm, f = 1.6866 Hz.
    let first = of("torsional")[0].0;
    assert!((first - 33.73).abs() < 0.05, "{first}");
    assert!(of("bending").iter().any(|&(_, k)| k == 1.0), "{speeds:?}");
}

/// The fourth fuzz campaign's one unbounded run: `campbell` on the collar string with a wall
/// 1000× stiffer (3.2e12 N/m per metre) never ended: faer's Schur reordering looped on the
/// badly scaled first-order matrix (M⁻¹K to 1e10 beside the identity). The balanced form ends in
/// about a second; the test gives it two minutes before it counts as the hang.
#[test]
fn a_stiff_wall_does_not_hang_the_eigen_solve() {
    let text = std::fs::read_to_string("problems/long_collars_rgd_stick.toml")
        .unwrap()
        .replacen(
            "stiffness = \"3.2189e9 N/m\"",
            "stiffness = \"3.2189e12 N/m\"",
            1,
        );
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("stiff_wall.toml");
    std::fs::write(&file, text).unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .arg("campbell")
        .arg(&file)
        .args(["--quiet", "--out"])
        .arg(dir.path().join("out"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > std::time::Duration::from_secs(120) {
            child.kill().unwrap();
            panic!("campbell did not end within 120 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    assert!(status.success(), "{status}");
    let c = json(&dir.path().join("out/campbell.json"));
    assert!(!c["modes"].as_array().unwrap().is_empty());
}
