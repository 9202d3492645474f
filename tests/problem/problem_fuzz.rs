//! Issue 13: the shipped problem files, mutated at random (a line deleted or duplicated, a value
//! replaced by a random string, a huge, negative or non-finite number or a wrong unit, the file
//! truncated), never make the loader panic, and every refusal names the file and a key (or the
//! file and a line, for TOML syntax). Bounded to 256 cases per file so that it runs in seconds
//! in CI (`cargo test`); no failure files are written.

use drillopt::problem::{Problem, ProblemError};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::path::Path;

/// Cases per file in CI; `DRILLOPT_FUZZ_CASES=20000 cargo test --release --test problem --
/// problem_fuzz::`
/// for a deeper local run.
const CASES: u32 = 256;

fn cases() -> u32 {
    std::env::var("DRILLOPT_FUZZ_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(CASES)
}

const SHIPPED: [(&str, &str); 25] = [
    (
        "problems/field/well_a_1km.toml",
        include_str!("../../problems/field/well_a_1km.toml"),
    ),
    (
        "problems/field/well_a_3km.toml",
        include_str!("../../problems/field/well_a_3km.toml"),
    ),
    (
        "problems/field/well_1km.toml",
        include_str!("../../problems/field/well_1km.toml"),
    ),
    (
        "problems/field/lateral_200m.toml",
        include_str!("../../problems/field/lateral_200m.toml"),
    ),
    (
        "problems/long_collars_rgd_stick.toml",
        include_str!("../../problems/long_collars_rgd_stick.toml"),
    ),
    (
        "problems/bha_example.toml",
        include_str!("../../problems/bha_example.toml"),
    ),
    (
        "problems/bench/seed_study_driller.toml",
        include_str!("../../problems/bench/seed_study_driller.toml"),
    ),
    (
        "problems/regression/slim_pipe_hook_load.toml",
        include_str!("../../problems/regression/slim_pipe_hook_load.toml"),
    ),
    (
        "problems/regression/seed_power_stability.toml",
        include_str!("../../problems/regression/seed_power_stability.toml"),
    ),
    (
        "problems/regression/seed_power_limit.toml",
        include_str!("../../problems/regression/seed_power_limit.toml"),
    ),
    (
        "problems/regression/slim_pipe_autodriller.toml",
        include_str!("../../problems/regression/slim_pipe_autodriller.toml"),
    ),
    (
        "problems/seed_rgd.toml",
        include_str!("../../problems/seed_rgd.toml"),
    ),
    (
        "problems/seed_rgd_bounce.toml",
        include_str!("../../problems/seed_rgd_bounce.toml"),
    ),
    (
        "problems/seed_mc2014.toml",
        include_str!("../../problems/seed_mc2014.toml"),
    ),
    (
        "problems/regression/slim_pipe_fatigue.toml",
        include_str!("../../problems/regression/slim_pipe_fatigue.toml"),
    ),
    (
        "problems/seed_mc2014_paper.toml",
        include_str!("../../problems/seed_mc2014_paper.toml"),
    ),
    (
        "problems/seed_robust.toml",
        include_str!("../../problems/seed_robust.toml"),
    ),
    (
        "problems/seed_detournay.toml",
        include_str!("../../problems/seed_detournay.toml"),
    ),
    (
        "problems/seed_autodriller.toml",
        include_str!("../../problems/seed_autodriller.toml"),
    ),
    (
        "problems/long_collars.toml",
        include_str!("../../problems/long_collars.toml"),
    ),
    (
        "problems/regression/tiny_string.toml",
        include_str!("../../problems/regression/tiny_string.toml"),
    ),
    (
        "problems/regression/slim_pipe_buckling.toml",
        include_str!("../../problems/regression/slim_pipe_buckling.toml"),
    ),
    (
        "problems/regression/slim_pipe_wide_hole.toml",
        include_str!("../../problems/regression/slim_pipe_wide_hole.toml"),
    ),
    (
        "problems/bench/seed_study.toml",
        include_str!("../../problems/bench/seed_study.toml"),
    ),
    (
        "problems/bench/tiny_multi_fidelity.toml",
        include_str!("../../problems/bench/tiny_multi_fidelity.toml"),
    ),
];

/// Every `*.toml` under `problems/` (recursively, as `drillopt batch` searches), relative to the
/// crate root.
fn problem_files(dir: &Path, out: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            problem_files(&path, out);
        } else if path.extension().is_some_and(|x| x == "toml") {
            let root = Path::new(env!("CARGO_MANIFEST_DIR"));
            out.push(path.strip_prefix(root).unwrap().display().to_string());
        }
    }
}

#[test]
fn every_shipped_problem_is_fuzzed() {
    let mut files = Vec::new();
    problem_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("problems"),
        &mut files,
    );
    for f in files {
        assert!(
            SHIPPED.iter().any(|(path, _)| *path == f),
            "{f} is not in SHIPPED: add it, so that the loader is fuzzed on it"
        );
    }
}

/// One edit of a file's text; line indices and byte offsets are taken modulo the file's size.
#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Duplicate(usize),
    /// The value of a `key = value` line (a whole line if the file has none).
    Replace(usize, String),
    Truncate(usize),
}

/// A value a user (or a fuzzer) might type.
fn value() -> impl Strategy<Value = String> {
    let unit = prop::sample::select(vec![
        "",
        " m",
        " mm",
        " rpm",
        " m/h",
        " kN",
        " GPa",
        " psi",
        " ppg",
        " s",
        " ms",
        " Hz",
        " furlongs",
        " RPM",
        " kg/m^3",
        " N/m",
    ]);
    prop_oneof![
        // A random string, quoted or bare.
        "[a-zA-Z0-9 _.,/-]{0,12}".prop_map(|s| format!("\"{s}\"")),
        "[a-z_]{1,8}",
        // Huge, tiny, negative, non-finite, with or without a unit.
        (
            prop::sample::select(vec![
                "1e308", "1e999", "-1e308", "1e-300", "-1", "-0.5", "0", "nan", "inf", "-inf",
                "2.5e11", "1e9",
                // Issue 34: inside the old ranges, absurd in their consequences.
                "5e-324", "1e-160", "1e-163", "1e12", "2e8",
            ]),
            unit.clone()
        )
            .prop_map(|(n, u)| if u.is_empty() {
                n.to_string()
            } else {
                format!("\"{n}{u}\"")
            }),
        (any::<f64>(), unit).prop_map(|(x, u)| format!("\"{x:e}{u}\"")),
        any::<i64>().prop_map(|n| n.to_string()),
        // Wrong shapes: an array, a table, a boolean.
        Just("[1, 2, 3]".to_string()),
        Just("{ a = 1 }".to_string()),
        Just("true".to_string()),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        1 => any::<usize>().prop_map(Mutation::Delete),
        1 => any::<usize>().prop_map(Mutation::Duplicate),
        3 => (any::<usize>(), value()).prop_map(|(i, v)| Mutation::Replace(i, v)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return String::new();
    }
    let n = lines.len();
    match m {
        Mutation::Delete(i) => {
            lines.remove(i % n);
        }
        Mutation::Duplicate(i) => {
            let l = lines[i % n].clone();
            lines.insert(i % n, l);
        }
        Mutation::Replace(i, v) => {
            // A `key = value` line when there is one (else any line, replaced whole).
            let keyed: Vec<usize> = (0..n)
                .filter(|&k| lines[k].contains('=') && !lines[k].trim_start().starts_with('#'))
                .collect();
            let k = if keyed.is_empty() {
                i % n
            } else {
                keyed[i % keyed.len()]
            };
            let l = &mut lines[k];
            *l = match l.split_once('=') {
                Some((key, _)) => format!("{key}= {v}"),
                None => v.clone(),
            };
        }
        Mutation::Truncate(at) => {
            let mut cut = at % (text.len() + 1);
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            return text[..cut].to_string();
        }
    }
    lines.join("\n") + "\n"
}

/// Loading never panics (a panic fails the case); a refusal names the file and a key or a line.
fn check(path: &str, text: &str) -> Result<(), TestCaseError> {
    let err = match Problem::from_toml(text, Path::new(path)) {
        // A problem that loads draws only admissible values (issue 34: the gamma sampler
        // panicked on a cov of 1e-163, and out-of-range draws were refused at run time only).
        Ok(p) => {
            prop_assert!(
                p.study.inadmissible_draw(&p.model).is_none(),
                "{} loads but draws an inadmissible value",
                path
            );
            return Ok(());
        }
        Err(e) => e,
    };
    let msg = err.to_string();
    match &err {
        ProblemError::Syntax { file, line, .. } => {
            prop_assert_eq!(file.to_str(), Some(path));
            prop_assert!(*line >= 1, "no line: {}", msg);
            prop_assert!(msg.starts_with(&format!("{path}:{line}:")), "{}", msg);
        }
        ProblemError::Invalid { file, errors } => {
            prop_assert_eq!(file.to_str(), Some(path));
            prop_assert!(!errors.is_empty());
            for e in errors {
                prop_assert!(
                    !e.key.is_empty() && !e.key.starts_with('('),
                    "not a key: {:?} in {}",
                    e.key,
                    msg
                );
                prop_assert!(
                    msg.contains(&format!("{path}: key `{}`: ", e.key)),
                    "{}",
                    msg
                );
            }
        }
        ProblemError::Io { .. } => prop_assert!(false, "no I/O here: {}", msg),
    }
    Ok(())
}

#[test]
fn mutated_shipped_problems_never_panic_and_every_refusal_names_file_and_key() {
    for (path, text) in SHIPPED {
        let config = Config {
            cases: cases(),
            failure_persistence: None,
            ..Config::default()
        };
        let mut runner = TestRunner::new(config);
        let edits = prop::collection::vec(mutation(), 1..4);
        runner
            .run(&edits, |edits| {
                let mutated = edits.iter().fold(text.to_string(), |t, m| apply(&t, m));
                check(path, &mutated)
            })
            .unwrap_or_else(|e| panic!("{path}: {e}"));
    }
}

/// The seeds of issue 34, as a deterministic sweep: every `key = value` line of every shipped
/// file set to each value the campaign found absurd inside the old ranges (5e-324, 1e-300, the
/// gamma law's vanishing cov, the bounds' 1e12 and 2e8 m/h), with and without a unit. Loading
/// never panics, every refusal names the file and a key, and a file that loads draws only
/// admissible values.
#[test]
fn issue_34_seeds_never_panic_and_are_refused_naming_file_and_key() {
    let values = [
        "5e-324",
        "1e-300",
        "\"1e-300 rpm\"",
        "\"1e-300 m/h\"",
        "1e-163",
        "1e-160",
        "1e12",
        "\"2e8 m/h\"",
        "[\"30 rpm\", 1e12]",
        "[\"1e-300 rpm\", \"150 rpm\"]",
        "[\"2 m/h\", \"2e8 m/h\"]",
    ];
    for (path, text) in SHIPPED {
        let lines = text.lines().count();
        for i in 0..lines {
            for v in values {
                let mutated = apply(text, &Mutation::Replace(i, v.to_string()));
                check(path, &mutated).unwrap_or_else(|e| panic!("{path}, line {i} = {v}: {e}"));
            }
        }
    }
}

/// The command line's quantities, fuzzed as the files are: any `--point` text (numbers huge,
/// tiny, negative, subnormal, non-finite, with right, wrong or no units, and the campaigns'
/// seeds) never panics; a point that is accepted lies in the operating point's ranges, and a
/// refusal names the flag and the key.
#[test]
fn command_line_points_never_panic_and_accepted_ones_are_admissible() {
    use drillopt::model::SetPoint;
    use drillopt::problem::keys::range_of;
    let config = Config {
        cases: 8 * cases(),
        failure_persistence: None,
        ..Config::default()
    };
    let seeds = prop::sample::select(vec![
        "5e-324m/h",
        "-0",
        "1e-300rpm",
        "1e308rpm",
        "-60rpm",
        "60rpm",
        "10m/h",
        "0m/h",
        "nan",
        "inf m/h",
        "2e8 m/h",
        "30 ft/h",
        "60 RPM",
        "",
    ]);
    let part = prop_oneof![
        value().prop_map(|v| v.trim_matches('"').to_string()),
        seeds.prop_map(str::to_string),
    ];
    let mut runner = TestRunner::new(config);
    runner
        .run(&(part.clone(), part), |(a, b)| {
            let text = format!("{a},{b}");
            for kind in [SetPoint::Feed, SetPoint::Wob] {
                match drillopt::cli::parse_point(&text, kind) {
                    Ok(op) => {
                        prop_assert!(
                            range_of("operating_point.omega")
                                .unwrap()
                                .contains(op.omega)
                        );
                        let key = match kind {
                            SetPoint::Feed => "operating_point.v0",
                            SetPoint::Wob => "operating_point.wob",
                        };
                        let set_point = op.set_point(kind);
                        prop_assert!(
                            range_of(key).unwrap().contains(set_point),
                            "{text}: {set_point} outside {key}"
                        );
                        prop_assert!(set_point.is_sign_positive(), "{text}: a negative zero");
                    }
                    Err(e) => {
                        let msg = format!("{e:#}");
                        prop_assert!(msg.contains("--point"), "{text}: {msg}");
                    }
                }
            }
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
}
