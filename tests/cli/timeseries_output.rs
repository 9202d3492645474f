//! Issue 16 item 5, time-series output that scales: `simulation.sample_interval` and
//! `--sample-interval` are read or refused naming the file (or flag) and the key; `simulate`
//! writes ⌊duration/Δ⌋ + 1 rows at t = kΔ, or one row per accepted step with `step`, and the
//! metrics do not depend on the written interval (they read every accepted step).

use crate::common;

use common::simulate_tiny as simulate;
use drillopt::problem::{Problem, ProblemError};
use drillopt::sim::SampleInterval;
use std::path::Path;

const FILE: &str = "problems/seed_mc2014.toml";
const SEED: &str = include_str!("../../problems/seed_mc2014.toml");

/// The seed with `key = value` added under `[simulation]`.
fn with_interval(value: &str) -> Result<Problem, ProblemError> {
    let text = SEED.replacen(
        "[simulation]\n",
        &format!("[simulation]\nsample_interval = {value}\n"),
        1,
    );
    Problem::from_toml(&text, Path::new(FILE))
}

#[test]
fn the_key_reads_a_time_or_step_and_defaults_to_half_a_millisecond() {
    let seed = Problem::from_toml(SEED, Path::new(FILE)).unwrap();
    assert_eq!(seed.simulation.sample_interval, SampleInterval::Fixed(5e-4));
    let p = with_interval("\"0.25 ms\"").unwrap();
    assert_eq!(p.simulation.sample_interval, SampleInterval::Fixed(2.5e-4));
    let p = with_interval("\"step\"").unwrap();
    assert_eq!(p.simulation.sample_interval, SampleInterval::EveryStep);
}

#[test]
fn the_key_refuses_zero_negative_wrong_units_and_out_of_range() {
    for (value, words) in [
        ("0", &["must be in [1e-6, 1] s"][..]),
        ("\"-1 ms\"", &["must be in [1e-6, 1] s"][..]),
        ("\"2 m\"", &["unit"][..]),
        ("\"2 s\"", &["1 µs and 1 s"][..]),
        ("\"0.5 us\"", &["1 µs and 1 s"][..]),
        ("\"steps\"", &[][..]),
    ] {
        let e = with_interval(value).expect_err(value);
        let msg = e.to_string();
        assert!(msg.contains(FILE), "{value}: {msg}");
        assert!(
            msg.contains("`simulation.sample_interval`"),
            "{value}: {msg}"
        );
        for w in words {
            assert!(msg.contains(w), "{value}: lacks {w:?}: {msg}");
        }
    }
}

fn rows(dir: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with("t_s,"));
    lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn simulate_writes_duration_over_interval_rows_and_the_same_metrics() {
    let (fixed, every) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let out = simulate(
        &["--duration", "0.6s", "--sample-interval", "2ms"],
        fixed.path(),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r = rows(fixed.path());
    assert_eq!(r.len(), 301, "0.6 s / 2 ms + 1 rows");
    for (k, row) in r.iter().enumerate() {
        assert_eq!(row[0], k as f64 * 2e-3, "row {k} at t = k Δ");
    }
    let out = simulate(
        &["--duration", "0.6s", "--sample-interval", "step"],
        every.path(),
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let all = rows(every.path());
    let (a, b) = (summary(fixed.path()), summary(every.path()));
    assert_eq!(all.len() as u64, b["solver"]["steps"].as_u64().unwrap() + 1);
    assert_eq!(a["metrics"], b["metrics"], "metrics read every step");
    assert_eq!(a["confidence_95"], b["confidence_95"]);
    // The first and last rows are the first and last accepted steps.
    assert_eq!(r[0], all[0]);
    assert_eq!(r[300], all[all.len() - 1]);
    // A row inside the run lies on the straight line between the steps around it.
    let s = r[150][0];
    let j = all.iter().position(|row| row[0] >= s).unwrap();
    let (p, q) = (&all[j - 1], &all[j]);
    let w = (s - p[0]) / (q[0] - p[0]);
    let got = &r[150];
    for c in 1..got.len() {
        if c == 9 || c == 10 {
            continue; // the counts are held from the step before
        }
        let want = p[c] + w * (q[c] - p[c]);
        assert!(
            (got[c] - want).abs() <= 1e-12 * want.abs().max(1e-300),
            "column {c}"
        );
    }
}

#[test]
fn the_flag_refuses_a_bad_interval_naming_the_flag_and_key() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["0ms", "-1ms", "3kg", "5s"] {
        let out = simulate(
            &["--duration", "0.6s", "--sample-interval", bad],
            dir.path(),
        );
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_ne!(out.status.code(), Some(0), "{bad}");
        assert!(stderr.contains("--sample-interval"), "{bad}: {stderr}");
        assert!(
            stderr.contains("simulation.sample_interval"),
            "{bad}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{bad}: {stderr}");
    }
}

/// Ctrl-C during `simulate` (SIGINT; SIGTERM alike): the run stops after the step in progress and
/// writes what it had: the time series renamed into place (no hidden temporary file left), a
/// summary with status `interrupted` and the time it stopped, and an exit status that is not 0.
/// While it runs, a second `simulate` on the same `--out` is refused.
#[cfg(unix)]
#[test]
fn an_interrupted_simulate_writes_what_it_had_and_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["simulate", FILE, "--duration", "60", "--quiet", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The time series' temporary file appears just before the run starts; a second later the
    // run is stepping (the seed's 60 s take about a minute).
    let hidden = |out: &Path| -> Vec<String> {
        std::fs::read_dir(out).map_or(Vec::new(), |d| {
            d.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with('.') && n != ".drillopt.lock")
                .collect()
        })
    };
    let start = std::time::Instant::now();
    while hidden(&out).is_empty() {
        assert!(start.elapsed().as_secs() < 60, "the run never started");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(1500));
    // A second run on the same folder is refused while the first holds it (it replaced the
    // first one's results before), and leaves the first running.
    let second = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["simulate", FILE, "--duration", "0.01", "--quiet", "--out"])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let refusal = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success(), "{refusal}");
    assert!(
        refusal.contains("in use by another drillopt run") && refusal.contains("--out"),
        "{refusal}"
    );
    // SAFETY: a plain kill(2) of our own child.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{stderr}");
    assert!(stderr.contains("interrupted at t ="), "{stderr}");
    assert_eq!(hidden(&out), Vec::<String>::new());
    let s = summary(&out);
    assert_eq!(s["status"], "interrupted", "{s}");
    let stopped: f64 = s["error"].as_str().unwrap()["interrupted at t = ".len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(stopped > 0.0 && stopped < 60.0, "{stopped}");
    // The rows reach the time it stopped, every 0.5 ms.
    let rows = rows(&out);
    let last = rows.last().unwrap()[0];
    assert!(last <= stopped && last > stopped - 1e-3, "{last} {stopped}");
    assert!(out.join("bit_axial.svg").exists());
}

/// A run killed outright (kill -9) left the earlier run's summary.json ("completed", another
/// operating point) beside its own half-written time series, and its hidden temporary files: the
/// next run on the folder removes the temporaries, and a run removes the earlier summary when it
/// starts, so a killed run leaves none rather than a stale one.
#[test]
fn a_killed_simulate_leaves_no_stale_summary_and_the_next_run_clears_its_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let run = |duration: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
            .args(["simulate", FILE, "--duration", duration, "--quiet", "--out"])
            .arg(&out)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    assert!(run("0.01").wait().unwrap().success());
    assert_eq!(summary(&out)["status"], "completed");
    let mut child = run("60");
    // Running once its time series' temporary file is there.
    let temporaries = |out: &Path| -> usize {
        std::fs::read_dir(out).map_or(0, |d| {
            d.flatten()
                .filter(|e| e.file_name().to_string_lossy().starts_with(".tmp"))
                .count()
        })
    };
    let start = std::time::Instant::now();
    while temporaries(&out) == 0 {
        assert!(start.elapsed().as_secs() < 60, "the run never started");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        !out.join("summary.json").exists(),
        "the earlier run's summary is still there"
    );
    assert!(temporaries(&out) > 0, "kill -9 leaves the temporary file");
    assert!(run("0.01").wait().unwrap().success());
    assert_eq!(temporaries(&out), 0);
    assert_eq!(summary(&out)["status"], "completed");
}
