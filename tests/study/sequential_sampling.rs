//! Sequential sampling end to end (issue 16 item 3): `drillopt map --grid 4x4` of the tiny
//! regression string (0.6 s windows) with three uncertain bit parameters, at a fixed 16 samples
//! per point and with `[uncertain.sequential]` (4 → 16 samples, ± 1.5 m/h at 95 %).
//!
//! - The sequential map runs fewer simulations than the fixed one and finds the same best node.
//! - Each point reports the samples it used and the half-width of its score; points that stop
//!   early meet the target, the others used the maximum.
//! - Common random numbers: the fixed map's cache answers every simulation of the sequential
//!   map (sample k is the same draw at every point and in both modes), which then gives exactly
//!   the evaluations of a fresh sequential run.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const UNCERTAIN: &str = r#"
[uncertain]
samples = 16
seed = 2014
[[uncertain.parameter]]
key = "model.bit.limit_force"
law = "gamma"
mean = "250 kN"
cov = 0.1
[[uncertain.parameter]]
key = "model.bit.rate"
law = "gamma"
mean = "180 s/m"
cov = 0.1
[[uncertain.parameter]]
key = "model.bit.friction"
law = "gamma"
mean = "0.04 m"
cov = 0.1
"#;

const SEQUENTIAL: &str = "[uncertain.sequential]\nmin_samples = 4\nscore_half_width = 1.5\n";

/// The tiny string with the uncertain section (and the sequential rule if `sequential`), in
/// `dir`.
fn problem(dir: &Path, sequential: bool) -> PathBuf {
    let tiny = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    let mut text = tiny
        .replace("duration = \"1.5 s\"", "duration = \"0.6 s\"")
        .replace("settling_time = \"0.5 s\"", "settling_time = \"0.2 s\"")
        + UNCERTAIN;
    assert!(text.contains("0.6 s") && text.contains("0.2 s"));
    if sequential {
        // A sub-table of [uncertain] may come after its array of tables.
        text += SEQUENTIAL;
    }
    let path = dir.join(if sequential { "seq.toml" } else { "fixed.toml" });
    std::fs::write(&path, text).unwrap();
    path
}

/// `drillopt map FILE --grid 4x4 --out OUT --threads 1 --quiet [--resume]`: map.json and stdout.
fn map(file: &Path, out: &Path, resume: bool) -> (Value, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_drillopt"));
    cmd.arg("map")
        .arg(file)
        .args(["--grid", "4x4", "--threads", "1", "--quiet", "--out"])
        .arg(out);
    if resume {
        cmd.arg("--resume");
    }
    let o = cmd.output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let json = std::fs::read_to_string(out.join("map.json")).unwrap();
    (serde_json::from_str(&json).unwrap(), stdout)
}

fn points(j: &Value) -> Vec<&Value> {
    j["points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| !p.is_null())
        .collect()
}

#[test]
fn sequential_map_runs_fewer_simulations_and_finds_the_same_best_node() {
    let dir = tempfile::tempdir().unwrap();
    let (fixed_file, seq_file) = (problem(dir.path(), false), problem(dir.path(), true));
    let fixed_out = dir.path().join("fixed");
    let (fixed, _) = map(&fixed_file, &fixed_out, false);
    let (seq, stdout) = map(&seq_file, &dir.path().join("seq"), false);
    let run = |j: &Value| j["work"]["simulations_run"].as_u64().unwrap();
    let nodes = points(&fixed).len() as u64;
    println!(
        "fixed: {} simulations, best {} rpm {} m/h score {}; sequential: {} simulations, best {} rpm {} m/h score {}",
        run(&fixed),
        fixed["optimum"]["omega_rpm"],
        fixed["optimum"]["v0_m_per_h"],
        fixed["optimum_objective"],
        run(&seq),
        seq["optimum"]["omega_rpm"],
        seq["optimum"]["v0_m_per_h"],
        seq["optimum_objective"]
    );
    assert_eq!(run(&fixed), 16 * nodes);
    assert!(
        run(&seq) < run(&fixed) && run(&seq) >= 4 * nodes,
        "{} vs {}",
        run(&seq),
        run(&fixed)
    );
    assert_eq!(fixed["optimum"], seq["optimum"], "the same best node");
    // The report: the rule in the header, samples and half-width at every node.
    assert_eq!(seq["sequential"]["min_samples"], 4);
    assert_eq!(seq["samples"], 16);
    assert!(fixed["sequential"].is_null());
    let mut used = Vec::new();
    for p in points(&seq) {
        let n = p["samples_used"].as_u64().unwrap();
        let h = p["score_half_width"].as_f64().unwrap();
        assert!([4, 8, 16].contains(&n), "{p}");
        assert!(n == 16 || h <= 1.5, "stopped early above the target: {p}");
        used.push(n);
    }
    assert_eq!(
        used.iter().sum::<u64>(),
        run(&seq),
        "work = the samples used"
    );
    assert!(
        used.contains(&4),
        "some node stops at min_samples: {used:?}"
    );
    // Fixed nodes report their half-width too, over all 16 samples.
    for p in points(&fixed) {
        assert_eq!(p["samples_used"], 16);
        assert!(p["score_half_width"].as_f64().unwrap() >= 0.0);
    }
    // The terminal table shows ± and n beside the score.
    assert!(
        stdout
            .lines()
            .next()
            .unwrap()
            .contains("score m/h        ±    n"),
        "{stdout}"
    );
    assert!(
        stdout.contains("best grid point") && stdout.contains(" ± "),
        "{stdout}"
    );

    // The fixed map's cache answers the whole sequential map: the same samples, the same keys.
    let (resumed, _) = map(&seq_file, &fixed_out, true);
    assert_eq!(run(&resumed), 0);
    assert_eq!(
        resumed["work"]["simulations_from_cache"].as_u64().unwrap(),
        run(&seq)
    );
    assert_eq!(
        resumed["points"], seq["points"],
        "the same decisions and scores"
    );
}
