//! Multi-fidelity `solve` (`[optimizer.explore]`, issue 16 item 2), end to end on the tiny
//! regression string (1.5 s windows, basis 4 / 2 / 2), one thread:
//!
//! - the method explores on the cheap fidelity (0.8 s windows, basis 2 / 1 / 1) and the best
//!   distinct candidates are re-run at full fidelity: the optimum's metrics are those of
//!   `drillopt simulate` at that point with the full settings, bit for bit, and its explore
//!   evaluation's are those of `simulate` with the explore settings (and differ);
//! - the optimum is the best of the confirmed full-fidelity points, and says so;
//! - every evaluation carries its fidelity in `solution.json` and `evaluations.csv`;
//! - the cache keys the explore runs apart when the window or the basis differs, and shares
//!   the simulations when only the samples differ (sample i is the same draw).

use crate::common;
use common::drillopt;

use drillopt::problem::Problem;
use drillopt::study::{Fidelity, RobustEvaluator, model_hash};
use serde_json::Value;
use std::path::Path;

const TINY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/regression/tiny_string.toml"
);

/// The tiny string without `[expect]`, with `replace` applied and `extra` appended, written to
/// `dir/name.toml`.
fn problem_file(dir: &Path, name: &str, replace: &[(&str, &str)], extra: &str) -> String {
    let text = std::fs::read_to_string(TINY).unwrap();
    let mut text = text[..text.find("[expect]").unwrap()].to_string();
    for (from, to) in replace {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    text.push_str(extra);
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

const EXPLORE: &str = r#"
[optimizer.explore]
duration = "0.8 s"
settling_time = "0.3 s"
confirm = 3
[optimizer.explore.basis]
bending = 2
torsional = 1
axial = 1
"#;

/// The explore fidelity written as a problem of its own: `simulate` runs it.
const EXPLORE_AS_FULL: [(&str, &str); 5] = [
    ("duration = \"1.5 s\"", "duration = \"0.8 s\""),
    ("settling_time = \"0.5 s\"", "settling_time = \"0.3 s\""),
    ("bending = 4 ", "bending = 2 "),
    ("torsional = 2\n", "torsional = 1\n"),
    ("axial = 2\n", "axial = 1\n"),
];

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn run(args: &[&str]) {
    let out = drillopt(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `summary.json`'s metrics of `drillopt simulate file` at (ω rad/s, v m/s), exactly that point.
/// `drillopt solve FILE` on one thread into `dir/solve`: that folder and its `solution.json`.
fn solve(dir: &Path, file: &str) -> (std::path::PathBuf, Value) {
    let out = dir.join("solve");
    run(&[
        "solve",
        file,
        "--threads",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let s = json(&out.join("solution.json"));
    (out, s)
}

fn simulate(file: &str, omega: f64, v0: f64, out: &Path) -> Value {
    let (w, v) = (format!("{omega:?} rad/s"), format!("{v0:?} m/s"));
    let out_s = out.to_str().unwrap();
    run(&[
        "simulate", file, "--omega", &w, "--v0", &v, "--quiet", "--out", out_s,
    ]);
    json(&out.join("summary.json"))["metrics"].clone()
}

/// The metrics of the dynamics (the critical-speed margin comes from a table in a study and is
/// searched directly by `simulate`, so it is left out).
const DYNAMICS: [&str; 6] = [
    "mean_rop_m_per_h",
    "mean_wob_n",
    "mean_tob_nm",
    "stick_slip_severity",
    "mse_pa",
    "max_bit_speed_ratio",
];

#[test]
fn candidates_are_confirmed_at_full_fidelity_and_the_optimum_is_the_best_of_them() {
    let dir = tempfile::tempdir().unwrap();
    let file = problem_file(dir.path(), "mf", &[], EXPLORE);
    let (out, s) = solve(dir.path(), &file);
    let evals = s["evaluations"].as_array().unwrap();
    let of = |f: &str| -> Vec<&Value> { evals.iter().filter(|e| e["fidelity"] == f).collect() };
    let (explore, full) = (of("explore"), of("full"));
    assert_eq!(explore.len() + full.len(), evals.len(), "every one tagged");
    assert_eq!(full.len(), 3, "confirm = 3");
    assert!(explore.len() >= 4);
    // The explore evaluations come first, then the confirmations.
    assert!(
        evals[..explore.len()]
            .iter()
            .all(|e| e["fidelity"] == "explore")
    );

    // The confirmed points are the three best distinct feasible explore points…
    let key = |e: &Value| {
        (
            e["omega_rad_s"].as_f64().unwrap(),
            e["v0_m_s"].as_f64().unwrap(),
        )
    };
    let mut ranked: Vec<&Value> = Vec::new();
    for e in explore.iter().filter(|e| e["feasible"] == true) {
        if !ranked.iter().any(|r| key(r) == key(e)) {
            ranked.push(e);
        }
    }
    ranked.sort_by(|a, b| {
        b["objective"]
            .as_f64()
            .partial_cmp(&a["objective"].as_f64())
            .unwrap()
    });
    // Then at least 5 % of the box apart (the default separation; Ω 30–150 rpm, V0 2–20 m/h),
    // points passed over filling the count in rank order.
    let unit = |e: &Value| {
        (
            (e["omega_rpm"].as_f64().unwrap() - 30.0) / 120.0,
            (e["v0_m_per_h"].as_f64().unwrap() - 2.0) / 18.0,
        )
    };
    let (mut apart, mut close): (Vec<&Value>, Vec<&Value>) = (Vec::new(), Vec::new());
    for e in &ranked {
        let (x, y) = unit(e);
        if apart.iter().any(|a| {
            let (ax, ay) = unit(a);
            (x - ax).hypot(y - ay) < 0.05
        }) {
            close.push(e);
        } else {
            apart.push(e);
        }
    }
    let picked: Vec<_> = apart.iter().chain(&close).take(3).map(|e| key(e)).collect();
    assert_eq!(full.iter().map(|e| key(e)).collect::<Vec<_>>(), picked);

    // The optimum is the best full-fidelity point, not the best explore one.
    let best_full = full
        .iter()
        .max_by(|a, b| {
            a["objective"]
                .as_f64()
                .partial_cmp(&b["objective"].as_f64())
                .unwrap()
        })
        .unwrap();
    let opt = &s["optimum"];
    assert_eq!(
        (
            opt["omega_rad_s"].as_f64().unwrap(),
            opt["v0_m_s"].as_f64().unwrap()
        ),
        key(best_full)
    );
    let objective = &s["objective"];
    assert_eq!(objective["fidelity"], "full");
    assert_eq!(objective["score"], best_full["objective"]);
    let explore_here = explore.iter().find(|e| key(e) == key(best_full)).unwrap();
    assert_eq!(objective["explore_score"], explore_here["objective"]);
    assert_ne!(objective["explore_score"], objective["score"]);
    // The header records the overrides; the confirmation lists the candidates.
    assert_eq!(s["explore"]["duration_s"], 0.8);
    assert_eq!(s["explore"]["settling_time_s"], 0.3);
    assert_eq!(s["explore"]["confirm"], 3);
    assert_eq!(s["explore"]["max_confirm"], 6);
    assert_eq!(s["explore"]["separation"], 0.05);
    assert_eq!(
        s["confirmation"]["rounds"], 1,
        "a feasible candidate in the first round"
    );
    assert!(
        s["explore"]["basis"]
            .as_str()
            .unwrap()
            .contains("bending 2")
    );
    let candidates = s["confirmation"]["candidates"].as_array().unwrap();
    assert_eq!(candidates.len(), 3);
    assert_eq!(candidates[0]["explore_score"], ranked[0]["objective"]);
    let work = &s["work"]["by_fidelity"];
    assert_eq!(work["explore"]["simulations_run"], explore.len());
    assert_eq!(work["full"]["simulations_run"], 3);

    // The optimum's metrics are `simulate`'s at that point with the full settings, exactly; its
    // explore evaluation's are `simulate`'s with the explore settings, and they differ.
    let (omega, v0) = key(best_full);
    let at_full = simulate(&file, omega, v0, &dir.path().join("sim_full"));
    let cheap = problem_file(dir.path(), "cheap", &EXPLORE_AS_FULL, "");
    let at_explore = simulate(&cheap, omega, v0, &dir.path().join("sim_explore"));
    for k in DYNAMICS {
        assert_eq!(s["metrics"][k], at_full[k], "{k}: full fidelity");
        assert_eq!(best_full["mean_metrics"][k], at_full[k], "{k}");
        assert_eq!(
            explore_here["mean_metrics"][k], at_explore[k],
            "{k}: explore"
        );
    }
    assert_ne!(
        at_full["stick_slip_severity"], at_explore["stick_slip_severity"],
        "the explore fidelity is another model"
    );

    // evaluations.csv: the last column says the fidelity of every row.
    let csv = std::fs::read_to_string(out.join("evaluations.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().ends_with(",fidelity"));
    let tags: Vec<&str> = lines.map(|l| l.rsplit(',').next().unwrap()).collect();
    assert_eq!(
        tags.iter().filter(|t| **t == "explore").count(),
        explore.len()
    );
    assert_eq!(tags.iter().filter(|t| **t == "full").count(), 3);
}

/// `refine = 6`: after the confirmation, the trust region at full fidelity from the best
/// confirmed point; the optimum is the best full-fidelity point of both, and every refinement
/// point is a full-fidelity evaluation.
#[test]
fn a_refinement_continues_at_full_fidelity_from_the_best_confirmed_point() {
    let dir = tempfile::tempdir().unwrap();
    let file = problem_file(
        dir.path(),
        "refine",
        &[],
        &EXPLORE.replace("confirm = 3\n", "confirm = 3\nrefine = 6\n"),
    );
    let (_, s) = solve(dir.path(), &file);
    let evals = s["evaluations"].as_array().unwrap();
    let full: Vec<&Value> = evals.iter().filter(|e| e["fidelity"] == "full").collect();
    let refinement = &s["confirmation"]["refinement"];
    let n = refinement["evaluations"].as_u64().unwrap() as usize;
    assert!((1..=6).contains(&n), "{refinement}");
    assert_eq!(full.len(), 3 + n);
    assert_eq!(s["status"], refinement["status"]);
    assert_eq!(s["explore"]["refine"], 6);
    assert_eq!(s["work"]["by_fidelity"]["full"]["simulations_run"], 3 + n);
    // The optimum is the best full-fidelity point of the confirmation and the refinement, at
    // least as good as the best confirmed one.
    let score = |e: &Value| e["objective"].as_f64().unwrap();
    let best = full.iter().map(|e| score(e)).fold(f64::MIN, f64::max);
    let confirmed = full[..3].iter().map(|e| score(e)).fold(f64::MIN, f64::max);
    assert_eq!(s["objective"]["score"].as_f64().unwrap(), best);
    assert!(best >= confirmed);
    assert_eq!(s["objective"]["fidelity"], "full");
}

const UNCERTAIN: &str = "\n[uncertain]\nsamples = 4\nseed = 11\n[[uncertain.parameter]]\nkey = \"model.bit.limit_force\"\nlaw = \"gamma\"\nmean = \"250 kN\"\ncov = 0.1\n";

/// Fewer samples only: the explore runs are the full fidelity's samples 0..2, so the
/// confirmation simulates samples 2 and 3 alone and reads 0 and 1 from the cache; the scores
/// differ (2 samples against 4).
#[test]
fn explore_with_fewer_samples_shares_the_full_fidelitys_simulations() {
    let dir = tempfile::tempdir().unwrap();
    let file = problem_file(
        dir.path(),
        "samples",
        &[(
            "method = \"trust_region\"\nmax_evaluations = 30\ngrid = [9, 9]",
            "method = \"grid\"\ngrid = [3, 3]",
        )],
        &(UNCERTAIN.to_string() + "[optimizer.explore]\nsamples = 2\nconfirm = 2\n"),
    );
    // `start` is a key the grid does not read.
    let text = std::fs::read_to_string(&file).unwrap();
    let text: String = text
        .lines()
        .filter(|l| !l.starts_with("start = "))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&file, text).unwrap();
    let (out, s) = solve(dir.path(), &file);
    let evals = s["evaluations"].as_array().unwrap();
    let explore = evals.iter().filter(|e| e["fidelity"] == "explore").count();
    let work = &s["work"]["by_fidelity"];
    assert_eq!(work["explore"]["samples_per_point"], 2);
    assert_eq!(work["explore"]["simulations_run"], 2 * explore);
    assert_eq!(work["full"]["samples_per_point"], 4);
    assert_eq!(work["full"]["simulations_run"], 2 * 2, "samples 2 and 3");
    assert_eq!(
        work["full"]["simulations_from_cache"],
        2 * 2,
        "samples 0, 1"
    );
    assert_eq!(s["objective"]["samples_used"], 4);
    assert_ne!(s["objective"]["explore_score"], s["objective"]["score"]);
    // evaluations.csv: 2 rows per explore point, 4 per confirmed point.
    let csv = std::fs::read_to_string(out.join("evaluations.csv")).unwrap();
    let rows = |f: &str| {
        csv.lines()
            .filter(|l| l.ends_with(&format!(",{f}")))
            .count()
    };
    assert_eq!(rows("explore"), 2 * explore);
    assert_eq!(rows("full"), 2 * 4);
}

fn tiny_with(extra: &str) -> Problem {
    let text = std::fs::read_to_string(TINY).unwrap();
    let text = text[..text.find("[expect]").unwrap()].to_string() + extra;
    Problem::from_toml(&text, Path::new("mf.toml")).unwrap()
}

#[test]
fn explore_runs_have_their_own_cache_key_when_the_window_or_the_basis_differs() {
    let full = tiny_with(UNCERTAIN);
    let hash = |extra: &str| {
        let p = tiny_with(&(UNCERTAIN.to_string() + extra));
        assert_eq!(
            model_hash(&p),
            model_hash(&full),
            "the section is no part of it"
        );
        model_hash(&p.study.explore.as_ref().unwrap().apply(&p))
    };
    let window = hash("[optimizer.explore]\nduration = \"1 s\"\n");
    let settling = hash("[optimizer.explore]\nduration = \"1 s\"\nsettling_time = \"0.2 s\"\n");
    let basis = hash("[optimizer.explore.basis]\nbending = 2\ntorsional = 2\naxial = 2\n");
    let samples = hash("[optimizer.explore]\nsamples = 2\n");
    let keys = [model_hash(&full), window, settling, basis];
    for (i, a) in keys.iter().enumerate() {
        for b in &keys[i + 1..] {
            assert_ne!(a, b);
        }
    }
    // Fewer samples: the same simulations (sample i is the same draw, its seed in the key).
    assert_eq!(samples, model_hash(&full));
    let p = tiny_with(&(UNCERTAIN.to_string() + "[optimizer.explore]\nsamples = 2\n"));
    let cheap = p.study.explore.as_ref().unwrap().apply(&p);
    let (a, b) = (
        RobustEvaluator::new(&p, None).unwrap(),
        RobustEvaluator::new(&cheap, None).unwrap(),
    );
    assert_eq!(b.samples.len(), 2);
    assert_eq!(a.samples.samples[..2], b.samples.samples[..]);
}

#[test]
fn an_explore_basis_that_is_not_smaller_is_refused_before_anything_runs() {
    // 10 000 Hz keeps every bending mode of the 12 elements: more than the full basis's 4.
    let p =
        tiny_with("[optimizer.explore.basis]\nbending = \"10000 Hz\"\ntorsional = 1\naxial = 1\n");
    let cheap = p.study.explore.as_ref().unwrap().apply(&p);
    let full = RobustEvaluator::new(&p, None).unwrap();
    let explore = RobustEvaluator::new(&cheap, None)
        .unwrap()
        .with_fidelity(Fidelity::Explore);
    let e = drillopt::solve::solve_multi_fidelity(&p, &full, &explore, None).unwrap_err();
    let msg = e.to_string();
    for part in [
        "mf.toml",
        "optimizer.explore.basis",
        "smaller reduced model",
    ] {
        assert!(msg.contains(part), "{msg}");
    }
    assert_eq!(
        full.counters
            .simulated
            .load(std::sync::atomic::Ordering::Relaxed),
        0
    );
}

/// Without `[optimizer.explore]`: one fidelity, every evaluation `full`, no explore record.
#[test]
fn without_an_explore_section_every_evaluation_is_full_fidelity() {
    let mut p = tiny_with("");
    p.study.override_budget(4).unwrap();
    let ev = RobustEvaluator::new(&p, None).unwrap();
    let outcome = drillopt::solve::solve(&p, &ev, None).unwrap();
    assert!(outcome.confirmation.is_none());
    let work = drillopt::report::WorkJson::of_fidelities(&ev, None, 0.0);
    let json = drillopt::report::SolutionJson::of(&p, Path::new("mf.toml"), &outcome, work, None);
    let s = serde_json::to_value(&json).unwrap();
    assert_eq!(s["explore"], Value::Null);
    assert_eq!(s["confirmation"], Value::Null);
    assert!(s["work"].get("by_fidelity").is_none());
    assert_eq!(s["objective"]["fidelity"], "full");
    assert_eq!(s["objective"]["explore_score"], Value::Null);
    let evals = s["evaluations"].as_array().unwrap();
    assert_eq!(evals.len(), 4);
    assert!(evals.iter().all(|e| e["fidelity"] == "full"));
}
