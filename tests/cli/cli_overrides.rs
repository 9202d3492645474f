//! Issue 13: the study commands' overrides (`--samples`, `--budget`, `--threads`) are checked
//! under their keys' rules and recorded in the report; a compare at a point a solve evaluated
//! finds it in the evaluation cache (the same bits through one conversion of rpm and m/h).

use crate::common;
use common::drillopt;

use serde_json::Value;
use std::path::Path;
use std::process::Output;

const TINY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/regression/tiny_string.toml"
);

/// The tiny string with `replace` applied and `extra` appended, written to `dir/name.toml`.
fn problem(dir: &Path, name: &str, replace: &[(&str, &str)], extra: &str) -> String {
    // The `[expect] active` list names the constraints the file's optimum holds; the edited
    // copies here move the constraints, so it is dropped.
    let mut text: String = std::fs::read_to_string(TINY)
        .unwrap()
        .lines()
        .filter(|l| !l.trim_start().starts_with("active") && !l.starts_with("start = "))
        .map(|l| format!("{l}\n"))
        .collect();
    for (from, to) in replace {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    text.push_str(extra);
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

const UNCERTAIN: &str = "\n[uncertain]\nsamples = 4\nseed = 11\n[[uncertain.parameter]]\nkey = \"model.bit.limit_force\"\nlaw = \"gamma\"\nmean = \"250 kN\"\ncov = 0.05\n";

#[test]
fn samples_and_threads_overrides_run_and_are_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let file = problem(
        dir.path(),
        "mc",
        &[
            ("duration = \"1.5 s\"", "duration = \"0.8 s\""),
            ("settling_time = \"0.5 s\"", "settling_time = \"0.3 s\""),
        ],
        UNCERTAIN,
    );
    let out = dir.path().join("out");
    let compare = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            file.as_str(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
            "--point",
            "60rpm,5m/h",
        ];
        args.extend(extra);
        drillopt(&args)
    };
    ok(&compare(&["--samples", "2", "--threads", "1"]));
    let j = json(&out.join("compare.json"));
    assert_eq!(
        j["samples"], 2,
        "the header says what ran, not the file's 4"
    );
    assert_eq!(j["overrides"]["samples"], 2);
    assert_eq!(j["overrides"]["threads"], 1);
    assert_eq!(j["overrides"]["budget"], Value::Null);
    assert_eq!(j["work"]["executor"], "1 thread");
    assert_eq!(j["work"]["simulations_run"], 2);
    assert_eq!(j["points"][0]["samples"].as_array().unwrap().len(), 2);
    // Sample i is the same draw whatever the number of samples: 3 samples reuse the 2 cached.
    ok(&compare(&["--samples", "3", "--resume"]));
    let j = json(&out.join("compare.json"));
    assert_eq!(j["samples"], 3);
    assert_eq!(j["overrides"]["threads"], Value::Null);
    assert_eq!(j["work"]["simulations_from_cache"], 2);
    assert_eq!(j["work"]["simulations_run"], 1);
}

#[test]
fn bad_overrides_are_refused_naming_the_flag_the_key_and_what_is_allowed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    let refused = |args: &[&str], parts: &[&str]| {
        let o = drillopt(args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for p in parts {
            assert!(stderr.contains(p), "{args:?}: {stderr:?} lacks {p:?}");
        }
    };
    let point = ["--point", "60rpm,5m/h"];
    let compare = |extra: &[&str]| {
        let mut a = vec!["compare", TINY, "--quiet", "--out", out];
        a.extend(point);
        a.extend(extra);
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let a = compare(&["--samples", "0"]);
    refused(
        &strs(&a),
        &[
            "--samples",
            "uncertain.samples",
            "tiny_string.toml",
            "[1, 10000]",
            "got 0",
        ],
    );
    // The tiny string has no uncertain parameter: 3 identical samples are refused.
    let a = compare(&["--samples", "3"]);
    refused(
        &strs(&a),
        &[
            "--samples",
            "uncertain.samples",
            "no [[uncertain.parameter]]",
        ],
    );
    let a = compare(&["--threads", "0"]);
    refused(&strs(&a), &["--threads", "[1, 1024]", "got 0"]);
    // Not a number: clap's usage error (exit status 2), naming the flag and the value.
    let a = compare(&["--samples", "many"]);
    let o = drillopt(&strs(&a));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--samples") && stderr.contains("many"),
        "{stderr}"
    );
    refused(
        &["solve", TINY, "--quiet", "--out", out, "--budget", "2"],
        &[
            "--budget",
            "optimizer.max_evaluations",
            "[3, 100000]",
            "got 2",
        ],
    );
    let dir2 = tempfile::tempdir().unwrap();
    let grid = problem(
        dir2.path(),
        "grid",
        &[(
            "method = \"trust_region\"\nmax_evaluations = 30\n",
            "method = \"grid\"\n",
        )],
        "",
    );
    refused(
        &["solve", &grid, "--quiet", "--out", out, "--budget", "20"],
        &[
            "--budget",
            "optimizer.max_evaluations",
            "has no budget",
            "optimizer.grid",
        ],
    );
    // Nothing was written by a refused command.
    assert!(!Path::new(out).join("compare.json").exists());
    assert!(!Path::new(out).join("solution.json").exists());
}

#[test]
fn a_budget_override_bounds_the_solve_and_is_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let file = problem(
        dir.path(),
        "budget",
        &[
            ("duration = \"1.5 s\"", "duration = \"0.8 s\""),
            ("settling_time = \"0.5 s\"", "settling_time = \"0.3 s\""),
        ],
        "",
    );
    let out = dir.path().join("out");
    ok(&drillopt(&[
        "solve",
        &file,
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--budget",
        "4",
    ]));
    let j = json(&out.join("solution.json"));
    assert_eq!(j["overrides"]["budget"], 4);
    let n = j["evaluations"].as_array().unwrap().len();
    assert!(n <= 4, "{n} design points for a budget of 4");
}

#[test]
fn a_compare_at_the_points_a_solve_evaluated_hits_the_cache() {
    let dir = tempfile::tempdir().unwrap();
    // A 3×3 grid on [40, 120] rpm × [2, 20] m/h: the middle node, 80 rpm, is 40 rpm + ½(80 rpm)
    // by the optimizer's scaling, one ulp away from the parse of "80rpm" (the cache missed).
    let file = problem(
        dir.path(),
        "grid",
        &[
            (
                "omega = [\"30 rpm\", \"150 rpm\"]",
                "omega = [\"40 rpm\", \"120 rpm\"]",
            ),
            (
                "method = \"trust_region\"\nmax_evaluations = 30\ngrid = [9, 9]",
                "method = \"grid\"\ngrid = [3, 3]",
            ),
            ("duration = \"1.5 s\"", "duration = \"0.8 s\""),
            ("settling_time = \"0.5 s\"", "settling_time = \"0.3 s\""),
        ],
        "",
    );
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    ok(&drillopt(&["solve", &file, "--quiet", "--out", out]));
    let solution = json(&Path::new(out).join("solution.json"));
    // Every node the solve simulated, written as a driller writes it (6 significant digits).
    let points: Vec<String> = solution["evaluations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            let rpm = e["omega_rpm"].as_f64().unwrap();
            let mph = e["v0_m_per_h"].as_f64().unwrap();
            format!(
                "{}rpm,{}m/h",
                (rpm * 1e4).round() / 1e4,
                (mph * 1e4).round() / 1e4
            )
        })
        .collect();
    assert!(points.contains(&"80rpm,11m/h".to_string()), "{points:?}");
    let optimum = &solution["optimum"];
    assert!(optimum.is_object(), "{solution}");
    let mut args = vec![
        "compare",
        file.as_str(),
        "--quiet",
        "--out",
        out,
        "--resume",
    ];
    for p in &points {
        args.extend(["--point", p.as_str()]);
    }
    ok(&drillopt(&args));
    let compare = json(&Path::new(out).join("compare.json"));
    assert_eq!(compare["work"]["simulations_run"], 0, "{}", compare["work"]);
    assert_eq!(
        compare["work"]["simulations_from_cache"].as_u64().unwrap() as usize,
        points.len()
    );
    // The same bits as the solve's evaluation of that node.
    let node = |v: &Value, rpm: f64| {
        v.as_array()
            .unwrap()
            .iter()
            .find(|e| {
                (e["omega_rpm"].as_f64().unwrap() - rpm).abs() < 1e-6
                    && (e["v0_m_per_h"].as_f64().unwrap() - 11.0).abs() < 1e-6
            })
            .map(|e| {
                (
                    e["omega_rad_s"].as_f64().unwrap().to_bits(),
                    e["v0_m_s"].as_f64().unwrap().to_bits(),
                )
            })
            .unwrap()
    };
    assert_eq!(
        node(&solution["evaluations"], 80.0),
        node(&compare["points"], 80.0)
    );
}

/// A malformed count (`many`, `1e3`) names the flag and says what it takes, before any work; clap's
/// own words were "invalid digit found in string".
#[test]
fn a_malformed_count_flag_names_the_flag_and_what_it_takes() {
    for (command, flag) in [
        ("solve", "--samples"),
        ("solve", "--budget"),
        ("map", "--threads"),
        ("modes", "--count"),
        ("campbell", "--points"),
    ] {
        for bad in ["many", "1e3"] {
            let out = drillopt(&[command, TINY, flag, bad]);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{command} {flag} {bad}: {err}");
            assert!(
                err.contains(flag) && err.contains(bad) && err.contains("not a whole number"),
                "{command} {flag} {bad}: {err}"
            );
            assert!(out.stdout.is_empty(), "{command} {flag} {bad}");
        }
    }
}

/// Issue 33 item 8: a `--duration` shorter than twice the file's settling time cut the settling
/// to half the run without a word; it still does (short runs are how a file is tried out), and
/// says so, with the window it used, even with --quiet; the summary records that window.
#[test]
fn a_short_duration_says_that_it_cuts_the_settling_time() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let out = drillopt(&[
        "simulate",
        TINY,
        "--duration",
        "0.6",
        "--quiet",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    ok(&out);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--duration 0.6 s is shorter than twice simulation.settling_time (0.5 s)")
            && stderr.contains("starts at 0.3 s"),
        "{stderr}"
    );
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["settling_time_s"], 0.3);
    // The file's own 1.5 s keep its 0.5 s: no warning.
    let out = drillopt(&[
        "simulate",
        TINY,
        "--quiet",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    ok(&out);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("settling_time"));
}

/// The number after `label` in `text` ("ROP 12.345 m/h" → 12.345) and the unit after it.
fn figure<'a>(text: &'a str, label: &str) -> (f64, &'a str) {
    let at = text
        .find(label)
        .unwrap_or_else(|| panic!("no {label:?} in {text}"))
        + label.len();
    let mut words = text[at..].split_whitespace();
    let value = words.next().unwrap().parse().unwrap();
    (value, words.next().unwrap())
}

#[test]
fn field_units_show_the_same_run_in_feet_klbf_and_psi() {
    // One run, shown twice: --units field changes what a person reads (terminal, plots, CSV),
    // not the run or its SI result files.
    let dir = tempfile::tempdir().unwrap();
    let (metric, field) = (dir.path().join("metric"), dir.path().join("field"));
    let run = |out: &Path, units: &str| {
        let out = drillopt(&[
            "simulate",
            TINY,
            "--quiet",
            "--units",
            units,
            "--out",
            out.to_str().unwrap(),
        ]);
        ok(&out);
        String::from_utf8(out.stdout).unwrap()
    };
    let (m, f) = (run(&metric, "metric"), run(&field, "field"));
    // 0.3048 m per ft, 4.4482216152605 N per lbf, 1.3558179483314 N·m per ft·lbf, 6894.757 Pa
    // per psi (NIST SP 811, B.8); each figure printed to its decimals.
    for (label, metric_unit, field_unit, per, decimals) in [
        ("ROP ", "m/h", "ft/h", 0.3048, 3),
        ("WOB ", "kN", "klbf", 4.448_221_615_260_5, 1),
        ("TOB ", "kN\u{b7}m", "kft\u{b7}lbf", 1.355_817_948_331_4, 2),
        ("von Mises ", "MPa", "psi", 6.894_757_293_168e-3, 1),
    ] {
        let (mv, mu) = figure(&m, label);
        let (fv, fu) = figure(&f, label);
        assert_eq!((mu, fu), (metric_unit, field_unit), "{label}");
        let half = 0.5 * 10f64.powi(-decimals);
        assert!(
            (fv - mv / per).abs() <= half + half / per,
            "{label}{mv} {mu} = {} {fu}, printed {fv}",
            mv / per
        );
    }
    assert!(
        !f.contains(" m/h") && !f.contains(" kN") && !f.contains(" MPa"),
        "{f}"
    );
    // The SI results are the same run.
    let (sm, sf) = (
        json(&metric.join("summary.json")),
        json(&field.join("summary.json")),
    );
    assert_eq!(sm["metrics"], sf["metrics"]);
    let axial = std::fs::read_to_string(field.join("bit_axial.svg")).unwrap();
    assert!(axial.contains("[ft/h]") && !axial.contains("[m/h]"));
    let envelope = std::fs::read_to_string(field.join("stress_envelope.svg")).unwrap();
    assert!(envelope.contains("[psi]") && envelope.contains("[ft]"));
    assert!(
        envelope.contains("torque [kft\u{b7}lbf]") && !envelope.contains("kN\u{b7}m"),
        "the torque-and-drag panel in field units"
    );

    // compare: the table, evaluations.csv and the plots in field units.
    let out = dir.path().join("compare");
    let compare = drillopt(&[
        "compare",
        TINY,
        "--point",
        "100rpm,20m/h",
        "--quiet",
        "--units",
        "oilfield",
        "--out",
        out.to_str().unwrap(),
    ]);
    ok(&compare);
    let table = String::from_utf8(compare.stdout).unwrap();
    assert!(
        table.contains("V0 ft/h") && table.contains("ROP ft/h") && table.contains("WOB klbf"),
        "{table}"
    );
    let csv = std::fs::read_to_string(out.join("evaluations.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
    let cell = |key: &str| -> f64 {
        row[header.iter().position(|h| *h == key).unwrap()]
            .parse()
            .unwrap()
    };
    // 20 m/h = 65.6167979 ft/h; the bit's ROP and WOB are the run's SI values converted.
    assert_eq!(row[1], "65.6167979");
    let si = json(&out.join("compare.json"));
    let sample = &si["points"][0]["samples"][0]["metrics"];
    let rop = sample["mean_rop_m_per_h"].as_f64().unwrap() / 0.3048;
    let wob = sample["mean_wob_n"].as_f64().unwrap() / 4_448.221_615_260_5;
    assert!((cell("mean_rop [ft/h]") - rop).abs() <= 1e-8 * rop, "{csv}");
    assert!((cell("mean_wob [klbf]") - wob).abs() <= 1e-8 * wob, "{csv}");
    assert!(!csv.lines().next().unwrap().contains("[m/h]"));
}
