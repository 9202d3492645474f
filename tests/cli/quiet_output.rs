//! Issue 13 item 10: `--quiet` drops the progress bars and messages, not the result: solve, map
//! and compare print their table (and the optimum or best node), as simulate prints its summary.

use crate::common;
use common::drillopt;

const TINY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/regression/tiny_string.toml"
);

fn quiet_stdout(args: &[&str]) -> String {
    let o = drillopt(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{args:?}: {err}");
    // No progress bar or message on stderr either.
    assert!(err.trim().is_empty(), "{args:?}: {err}");
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn quiet_study_commands_still_print_their_result() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_owned();
    let (map, compare, solve) = (out("map"), out("compare"), out("solve"));
    let common = ["--threads", "1", "--quiet", "--out"];

    let text = quiet_stdout(&[&["map", TINY, "--grid", "2x2"], &common[..], &[&map]].concat());
    // A header, the four nodes (one outside the depth-of-cut limit), the best node and where the
    // results are.
    assert!(text.contains("feasible"), "{text}");
    assert_eq!(
        text.lines()
            .filter(|l| l
                .split_whitespace()
                .next()
                .is_some_and(|w| w.parse::<f64>().is_ok()))
            .count(),
        4,
        "{text}"
    );
    assert!(text.contains("best grid point"), "{text}");

    let text = quiet_stdout(
        &[
            &["compare", TINY, "--point", "60rpm,5m/h"],
            &common[..],
            &[&compare],
        ]
        .concat(),
    );
    assert!(
        text.contains("feasible") && text.contains("   60.0     5.00"),
        "{text}"
    );

    let text = quiet_stdout(&[&["solve", TINY, "--budget", "3"], &common[..], &[&solve]].concat());
    assert!(text.contains("feasible") && text.contains("Ω ="), "{text}");
}

/// Without a terminal (standard error to a pipe or a log) the bars cannot draw: a plain progress
/// line every few seconds instead, on standard error (none with `--quiet`).
#[test]
fn without_a_terminal_long_work_prints_progress_lines() {
    let dir = tempfile::tempdir().unwrap();
    let seed = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed_mc2014.toml");
    let out = dir.path().join("run");
    // About 7 s of work on the seed (5 s between lines).
    let run = |quiet: bool| {
        let mut args = vec!["simulate", seed, "--duration", "12", "--out"];
        args.push(out.to_str().unwrap());
        if quiet {
            args.push("--quiet");
        }
        let o = drillopt(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stderr).unwrap()
    };
    let err = run(false);
    let line = err
        .lines()
        .find(|l| l.starts_with("simulate: t = "))
        .unwrap_or_else(|| panic!("no progress line: {err}"));
    assert!(line.contains(" / 12 s") && line.ends_with(" s)"), "{line}");
    assert!(!run(true).contains("simulate: t = "));
}
