//! Issue 13 items 8 and 17: an output directory that cannot be made is refused before any work,
//! naming the path and why, each cause once; `drillopt batch` without `--out` writes under
//! `results/batch/`, which git ignores, and not over the committed reports of `results/`.

use crate::common;
use common::drillopt;

const TINY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/regression/tiny_string.toml"
);

/// Every command that writes, with `--out` set to `out`.
fn commands(out: &str) -> Vec<Vec<&str>> {
    vec![
        vec!["simulate", TINY, "--duration", "0.2", "--out", out],
        vec!["campbell", TINY, "--points", "2", "--out", out],
        vec!["solve", TINY, "--threads", "1", "--out", out],
        vec!["map", TINY, "--grid", "2x2", "--threads", "1", "--out", out],
        vec![
            "compare",
            TINY,
            "--point",
            "60rpm,5m/h",
            "--threads",
            "1",
            "--out",
            out,
        ],
    ]
}

#[test]
fn an_output_path_held_by_a_file_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("afile");
    std::fs::write(&file, "not a directory").unwrap();
    let below = file.join("sub");
    let regression = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/regression");
    for (out, why) in [
        (file.to_str().unwrap(), "a file of that name exists"),
        (below.to_str().unwrap(), "cannot be created"),
    ] {
        let mut runs = commands(out);
        runs.push(vec!["batch", regression, "--threads", "1", "--out", out]);
        for args in runs {
            let o = drillopt(&args);
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
            assert!(
                err.contains(&format!("output directory {out}")) && err.contains(why),
                "{args:?}: {err}"
            );
            // Each cause once (the evaluation cache used to print "Not a directory" twice).
            assert!(err.matches("os error").count() <= 1, "{args:?}: {err}");
            assert!(o.stdout.is_empty(), "{args:?}");
        }
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a directory");
}

#[test]
fn batch_writes_its_default_output_where_git_does_not_track() {
    let dir = tempfile::tempdir().unwrap();
    let problems = dir.path().join("problems");
    std::fs::create_dir(&problems).unwrap();
    std::fs::copy(TINY, problems.join("tiny_string.toml")).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["batch", "problems", "--threads", "1", "--quiet"])
        .current_dir(dir.path())
        .output()
        .expect("drillopt runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let results = dir.path().join("results");
    assert!(results.join("batch/tiny_string/solution.json").is_file());
    assert!(!results.join("tiny_string").exists());
    let ignore =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/.gitignore")).unwrap();
    assert!(
        ignore.lines().any(|l| l.trim() == "results/batch/"),
        "{ignore}"
    );
}

#[test]
fn batch_refuses_a_second_problem_of_the_same_name_instead_of_overwriting_the_first() {
    // Two files with `name = "tiny_string"`: the first is solved into <out>/tiny_string, the
    // second is a failure that names both files, and the first's report stays.
    let dir = tempfile::tempdir().unwrap();
    let problems = dir.path().join("problems");
    std::fs::create_dir(&problems).unwrap();
    let (a, b) = (problems.join("a.toml"), problems.join("b.toml"));
    std::fs::copy(TINY, &a).unwrap();
    std::fs::copy(TINY, &b).unwrap();
    let out = dir.path().join("out");
    let run = drillopt(&[
        "batch",
        problems.to_str().unwrap(),
        "--threads",
        "1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(!run.status.success(), "{stdout}");
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("tiny_string"))
        .collect();
    assert_eq!(rows.len(), 2, "{stdout}");
    assert!(rows[0].contains("PASS"), "{stdout}");
    assert!(
        rows[1].contains("FAIL")
            && rows[1].contains(&b.display().to_string())
            && rows[1].contains(&format!("also the name of {}", a.display())),
        "{stdout}"
    );
    let solution = std::fs::read_to_string(out.join("tiny_string/solution.json")).unwrap();
    assert!(solution.contains("a.toml") && !solution.contains("b.toml"));
    assert!(!out.join("tiny_string/cache.jsonl.old").exists());
}

#[test]
fn a_second_run_into_the_same_directory_says_that_it_set_the_first_ones_cache_aside() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let args = [
        "compare",
        TINY,
        "--point",
        "60rpm,5m/h",
        "--threads",
        "1",
        "--out",
        out,
    ];
    let first = drillopt(&args);
    assert!(first.status.success());
    assert!(!String::from_utf8_lossy(&first.stderr).contains("cache.jsonl.old"));
    let second = drillopt(&args);
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(second.status.success(), "{err}");
    assert!(
        err.contains("held an earlier run's evaluations; moved to")
            && err.contains("cache.jsonl.old")
            && err.contains("--resume"),
        "{err}"
    );
    assert!(dir.path().join("cache.jsonl.old").exists());
    // With --quiet the move is made and not said.
    let quiet = drillopt(&[&args[..], &["--quiet"]].concat());
    assert!(!String::from_utf8_lossy(&quiet.stderr).contains("moved to"));
}
